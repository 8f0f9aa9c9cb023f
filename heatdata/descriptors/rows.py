"""Descriptor rows of views: every spec of every view, as the rows of a descriptor table (thesis 3.3-3.4, 5.4).

One row per view x descriptor (x object time scale, for a time-scaled kind, Alg. 5.1-5.2), in the columns of
:data:`heatdata.io.tables.DESCRIPTOR_SCHEMA`. The workflow's describe step and a library's query
(:meth:`heatdata.recognition.library.Library.describe`) both describe views here, so a library is always compared
with rows made the same way.
"""

from __future__ import annotations

import logging
import time

import numpy as np
import pandas as pd

from heatdata.descriptors.base import Descriptor, DescriptorSpec
from heatdata.descriptors.compute import describe
from heatdata.descriptors.heat import color_name
from heatdata.errors import HeatdataError, SpectrumError, ViewError
from heatdata.views.view import View

log = logging.getLogger(__name__)


def _ft_times(
    view: View, split: str, specs: list[DescriptorSpec], time_scales: pd.DataFrame | None
) -> dict[str, pd.Series]:
    """Per time-scaled spec (ft-pvhk), the times to describe ``view`` at, indexed by the object they belong to.

    A library view is described at its own object's time scale; a test view, whose object
    is unknown, at every object's (Alg. 5.2 compares it with each object's library at
    that object's time).
    """
    names = [s.name for s in specs if s.impl.time_scaled]
    if not names:
        return {}
    if time_scales is None:
        raise HeatdataError(f"{', '.join(names)} need(s) the objects' time scales (Alg. 5.1, time_scale_table)")
    times = {}
    for name in names:
        scales = time_scales[time_scales["descriptor"] == name].set_index("object")["time_scale"]
        if split == "train":
            if view.object_id not in scales.index:
                raise HeatdataError(f"{view.name}: no time scale of object {view.object_id!r} for {name}")
            scales = scales.loc[[view.object_id]]
        if scales.empty:
            raise HeatdataError(f"no time scales for {name}")
        times[name] = scales
    return times


def _describe_each(view: View, specs: list[DescriptorSpec], times: dict) -> list[Descriptor]:
    """:func:`describe`, but a spec that fails on this view (e.g. a PVST whose source lies on the
    boundary, a heat solve that does not converge) gives NaN descriptors with the reason in
    ``repairs`` instead of stopping a batch."""
    try:
        return describe(view, specs, times=times)
    except (ViewError, SpectrumError):
        pass
    results = []
    for spec in specs:
        try:
            results += describe(view, [spec], times=times)
        except (ViewError, SpectrumError) as exc:
            log.warning("%s: %s failed: %s", view.name, spec.name, exc)
            results += [
                failed_descriptor(spec, spec.impl.size(spec, view), float(t), f"{spec.name} failed: {exc}")
                for t in np.atleast_1d(times.get(spec.name, np.nan))
            ]
    return results


def failed_descriptor(spec: DescriptorSpec, count: int, time: float, reason: str) -> Descriptor:
    """The NaN descriptor of a view ``spec`` could not describe, with ``reason`` in its repairs."""
    nan = np.full(count, np.nan)
    return Descriptor(
        kind=spec.kind,
        values=nan,
        positions=nan,
        source=-1,
        time=time,
        lambda2=np.nan,
        sampling=spec.get("sampling"),
        color_map=color_name(spec.get("color_map")),
        repairs=(reason,),
    )


def descriptor_row(
    view: View, planned, spec: DescriptorSpec, d: Descriptor, seconds: float, time_object: str = ""
) -> dict:
    """One :data:`heatdata.io.tables.DESCRIPTOR_SCHEMA` row; boundary columns (``n_boundary`` too) are null for kinds
    that do not sample the outline."""
    boundary = "sampling" in spec.options
    return {
        "object": view.object_id,
        "label": view.label,
        "view_id": view.view_id,
        "split": planned.split,
        "azimuth": view.azimuth,
        "elevation": view.elevation,
        "distance": view.distance,
        "seed": planned.seed,
        "n_vertices": view.n_vertices,
        "n_boundary": len(view.boundary) if boundary else None,  # the outline of a large view is not free
        "descriptor": spec.name,
        "kind": spec.kind,
        "sampling": spec.get("sampling"),
        "source_rule": str(spec.source) if boundary else None,
        "color_map": d.color_map or ("" if boundary else None),
        "source": d.source,
        "time": d.time,
        "time_object": time_object,
        "lambda2": d.lambda2,
        "t_global": 1.0 / d.lambda2,
        "values": d.values.tolist(),
        "positions": d.positions.tolist(),
        "weights": None if d.weights is None else d.weights.tolist(),
        "repairs": list(view.repairs) + list(d.repairs),
        "seconds": seconds,
    }


def descriptor_rows(
    views: list[View],
    plan: pd.DataFrame,
    specs: list[DescriptorSpec],
    *,
    time_scales: pd.DataFrame | None = None,
    progress_every: int = 40,
) -> pd.DataFrame:
    """Descriptors of ``specs`` for each view; ``plan`` gives each view's split and seed, in order.

    ``time_scales`` (rows of :func:`time_scale_table` for every object) is needed for
    ``ft-pvhk`` specs: a library view gets one row at its object's time scale, a test
    view one row per object (column ``time_object``).

    Returns
    -------
    pandas.DataFrame
        One row per view x descriptor (x time object), columns of
        :data:`heatdata.io.tables.DESCRIPTOR_SCHEMA`.
    """
    if len(views) != len(plan):
        raise HeatdataError(f"{len(views)} views but {len(plan)} plan rows")
    rows = []
    start = time.perf_counter()
    for count, (view, planned) in enumerate(zip(views, plan.itertuples(), strict=True), 1):
        tic = time.perf_counter()
        ft_times = _ft_times(view, planned.split, specs, time_scales)
        descriptors = _describe_each(view, specs, {name: t.to_numpy() for name, t in ft_times.items()})
        seconds = (time.perf_counter() - tic) / len(descriptors)
        labelled = [
            (spec, obj) for spec in specs for obj in (ft_times[spec.name].index if spec.impl.time_scaled else [""])
        ]
        for (spec, time_object), d in zip(labelled, descriptors, strict=True):
            rows.append(descriptor_row(view, planned, spec, d, seconds, time_object))
        if len(views) > 1 and (count % progress_every == 0 or count == len(views)):
            log.info(
                "%s: %d/%d views described (%.1f s)", view.object_id, count, len(views), time.perf_counter() - start
            )
    return pd.DataFrame(rows)
