"""The hub every descriptor goes through: :func:`describe` asks each spec's kind, sharing one view's work."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from heatdata.descriptors.base import Descriptor, DescriptorSpec
from heatdata.descriptors.work import ViewWork
from heatdata.views.view import View


def describe(
    view: View,
    specs: list[DescriptorSpec],
    *,
    method: str = "krylov",
    modes: int = 30,
    times: Sequence[float] | Mapping[str, Sequence[float]] | None = None,
    part_weights: bool = True,
    t_final: float | None = None,
) -> list[Descriptor]:
    """Several descriptors of one view, sharing the expensive work.

    Heat kinds with the same colour map share one factorization and lambda_2; those
    with the same source share one heat solve; samplings of one solve cost nothing
    more. Histogram kinds share the view's normals and spectrum.

    Parameters
    ----------
    view : View
    specs : list of DescriptorSpec
        Any registered kinds; a fitted kind (SI-HKS) must come from :func:`heatdata.fit_spec`.
    method : {"krylov", "eigen"}
        How heat kinds solve the heat equation (:func:`heatdata.pvhk`).
    modes : int
        Eigenpairs of the ``"eigen"`` method.
    times : sequence of float, or dict from spec name to sequence, optional
        The fixed times of time-scaled specs (``ft-pvhk``; needed if there is one): each
        such spec gives one descriptor per time, all from one Krylov solve. A dict gives
        each spec its own times (e.g. time scales found with its source rule).
    part_weights : bool
        Give ``ft-pvhk`` descriptors their part weights (eq. 5.13), at the cost of a few
        eigenpairs per view.
    t_final : float, optional
        End of the PVST search window (default ``10 / lambda_2``, Alg. 5.3).

    Returns
    -------
    list of Descriptor
        In spec order; a time-scaled spec contributes ``len(times)`` descriptors.
    """
    work = ViewWork(view, method, modes)
    context = dict(times=times, part_weights=part_weights, t_final=t_final)
    return [d for spec in specs for d in spec.impl.compute(work, spec, **context)]
