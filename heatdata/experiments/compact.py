"""Workflow step of compact libraries (thesis ch. 6): the sources chosen for every object, size and alpha."""

from __future__ import annotations

import logging
import time

import numpy as np
import pandas as pd

from heatdata.errors import HeatdataError
from heatdata.recognition.compact import (
    CONSECUTIVE_DISTANCES,
    RHO_NORMS,
    combined_costs,
    consecutive_costs,
    cyclic_dp,
    other_object_distances,
    select_sources,
)
from heatdata.recognition.evaluate import library_subset

log = logging.getLogger(__name__)


def compact_libraries(
    candidates: pd.DataFrame,
    sizes: list[int],
    alphas: list[float],
    *,
    solver: str = "lp",
    distance: str = "l1",
    norm: str = "l1",
) -> pd.DataFrame:
    """Alg. 6.3 for every object, library size and alpha, and the initial library for comparison.

    Parameters
    ----------
    candidates : pandas.DataFrame
        Library (``split = "train"``) rows of :func:`heatdata.experiments.describe.candidate_rows`:
        the ``candidates`` descriptor rows (one per view and candidate source) and the
        single-source rows of the initial rule.
    sizes : list of int
        Library views per object (evenly spaced in azimuth, :func:`library_subset`).
    alphas : list of float
        Mixing parameters of eq. 6.11.
    solver : {"lp", "dp"}
        ``"lp"``: :func:`select_sources` (cvxpy, the LP of eq. 6.7-6.9 on the edges its
        bounds keep). ``"dp"``: :func:`cyclic_dp`, the same optimum (the tests compare them)
        without an LP solver.
    distance : {"l1", "mhd"}
        d of eq. 6.6 (:func:`consecutive_costs`).
    norm : {"l1", "l2"}
        The norm of eq. 6.4 and 6.10 (:func:`other_object_distances`).

    Returns
    -------
    pandas.DataFrame
        One row per object, library size, method and library view: ``object, label,
        library_size, descriptor`` (the method: ``initial <rule>`` or ``compact alpha=<a>``),
        ``view_id, azimuth, source, values, cost`` (the object's summed g around the
        circle; NaN for the initial library) and ``seconds`` (building g and selecting).
    """

    if solver not in ("lp", "dp"):
        raise HeatdataError(f"unknown solver {solver!r} (use 'lp' or 'dp')")
    if distance not in CONSECUTIVE_DISTANCES or norm not in RHO_NORMS:
        raise HeatdataError(
            f"unknown distance {distance!r} or norm {norm!r} (use one of {CONSECUTIVE_DISTANCES} "
            f"for c, of {RHO_NORMS} for rho)"
        )
    train = candidates[candidates["split"] == "train"]
    failed = train.loc[[not np.all(np.isfinite(v)) for v in train["values"]], "view_id"].unique()
    if len(failed):
        log.warning(
            "%d library views could not be described and are left out of the circle: %s",
            len(failed),
            ", ".join(failed[:5]),
        )
    multi = train[train["source_rule"] == "candidates"]
    initial = train[(train["source_rule"] != "candidates") & ~train["view_id"].isin(failed)]
    if multi.empty or initial.empty:
        raise HeatdataError(
            "compact libraries need candidate rows and initial-rule rows of library views "
            "(heatdata.experiments.describe.candidate_rows)"
        )
    columns = ["object", "label", "view_id", "azimuth", "source", "values"]
    out = []
    for size in sizes:
        subset = library_subset(multi, size)  # chosen among all views, then the failed ones left out
        subset = subset[~subset["view_id"].isin(failed)]
        views = {obj: [g for _, g in rows.groupby("azimuth", sort=True)] for obj, rows in subset.groupby("object")}
        stacked = {obj: [np.stack(g["values"].to_numpy()) for g in groups] for obj, groups in views.items()}
        tic = time.perf_counter()
        rho = other_object_distances(stacked, norm=norm) if min(alphas) < 1.0 else None
        if rho is not None:
            log.info(
                "%d views per object: distances to the other objects' candidates in %.1f s",
                size,
                time.perf_counter() - tic,
            )
        chosen = initial[initial["view_id"].isin(subset["view_id"])]
        out.append(
            chosen[columns].assign(
                library_size=size, descriptor=f"initial {chosen['source_rule'].iloc[0]}", cost=np.nan, seconds=0.0
            )
        )
        for obj, groups in views.items():
            name = f"{obj} ({size} views)"
            if len(groups) < 2:
                raise HeatdataError(f"{name}: a compact library needs two or more views around the circle")
            start = time.perf_counter()
            consecutive = consecutive_costs(stacked[obj], distance)
            for alpha in alphas:
                tic = time.perf_counter()
                costs = consecutive if rho is None or alpha == 1.0 else combined_costs(consecutive, rho[obj], alpha)
                choice, cost = (
                    select_sources(costs, name=f"{name}, alpha {alpha:g}") if solver == "lp" else cyclic_dp(costs)
                )
                rows = pd.DataFrame([g.iloc[k] for g, k in zip(groups, choice, strict=True)])[columns]
                out.append(
                    rows.assign(
                        library_size=size,
                        descriptor=f"compact alpha={alpha:g}",
                        cost=cost,
                        seconds=time.perf_counter() - tic,
                    )
                )
            log.info("%s: sources selected for alpha in %s (%.1f s)", name, alphas, time.perf_counter() - start)
    return pd.concat(out, ignore_index=True)
