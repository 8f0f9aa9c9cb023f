"""Descriptor rows of a run's views: every spec of every view, the candidates, time scales, fitted kinds.

The workflow's describe, candidates, time_scale and fit steps (thesis 3.3-3.4, 5.4, 6.2): views of
:mod:`heatdata.experiments.views` in, rows of ``descriptors.parquet`` out
(:func:`heatdata.descriptors.rows.descriptor_rows` makes the rows).
"""

from __future__ import annotations

import logging
import time
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from heatdata.descriptors import (
    CANDIDATES_RULE,
    DescriptorSpec,
    fit_spec,
    object_time_scale,
    source_vertex,
)
from heatdata.descriptors.rows import descriptor_row, descriptor_rows, failed_descriptor
from heatdata.descriptors.sources import candidate_descriptors, candidate_sources
from heatdata.errors import HeatdataError, SpectrumError, ViewError
from heatdata.io.files import atomic
from heatdata.views.view import View

if TYPE_CHECKING:
    from heatdata.io.models import Model  # trimesh: only to load a model

log = logging.getLogger(__name__)


def candidate_rows(
    views: list[View],
    plan: pd.DataFrame,
    spec: DescriptorSpec,
    *,
    library_count: int | None = 250,
    test_count: int | None = None,
    progress_every: int = 40,
) -> pd.DataFrame:
    """Descriptors from many candidate sources per view, and from the spec's own source rule (thesis 6.2).

    Every view gets one row per candidate source (descriptor name with source
    ``candidates``, e.g. ``pvhk/polar/candidates/64``) and one row for ``spec``'s own
    rule (the initial library of 6.4, e.g. ``pvhk/polar/center/64``), all from one
    eigen-decomposition (:func:`heatdata.descriptors.sources.candidate_descriptors`). Library views take
    ``library_count`` candidates by mesh simplification, test views ``test_count``
    (None: every vertex off the outline, as in the thesis). A view that cannot be
    described gets one NaN candidate row with the reason in ``repairs``.
    """
    if len(views) != len(plan):
        raise HeatdataError(f"{len(views)} views but {len(plan)} plan rows")
    multi = spec.replace(source=CANDIDATES_RULE)
    rows = []
    start = time.perf_counter()
    for count, (view, planned) in enumerate(zip(views, plan.itertuples(), strict=True), 1):
        tic = time.perf_counter()
        try:
            sources = candidate_sources(view, library_count if planned.split == "train" else test_count)
            own = source_vertex(view, spec.source)
            described = candidate_descriptors(view, np.append(sources, own), spec)
        except (ViewError, SpectrumError) as exc:
            log.warning("%s: candidate descriptors failed: %s", view.name, exc)
            failed = failed_descriptor(spec, spec.impl.size(spec, view), np.nan, f"candidate descriptors failed: {exc}")
            rows.append(descriptor_row(view, planned, multi, failed, time.perf_counter() - tic))
            continue
        seconds = (time.perf_counter() - tic) / len(described)
        rows += [descriptor_row(view, planned, multi, d, seconds) for d in described[:-1]]
        rows.append(descriptor_row(view, planned, spec, described[-1], seconds))
        if len(views) > 1 and (count % progress_every == 0 or count == len(views)):
            log.info(
                "%s: %d/%d views described from %d candidate sources (%.1f s)",
                view.object_id,
                count,
                len(views),
                len(described) - 1,
                time.perf_counter() - start,
            )
    return pd.DataFrame(rows)


def time_scale_table(views: list[View], plan: pd.DataFrame, specs: list[DescriptorSpec]) -> pd.DataFrame:
    """The time scale of each object for each ``ft-pvhk`` spec (Alg. 5.1, from the library views).

    Returns
    -------
    pandas.DataFrame
        Columns ``object, descriptor, source_rule, time_scale, n_views``; no rows without
        an ft-pvhk spec.
    """
    library: dict[str, list[View]] = {}
    for view, planned in zip(views, plan.itertuples(), strict=True):
        if planned.split == "train":
            library.setdefault(view.object_id, []).append(view)
    rows, scales = [], {}
    for spec in specs:
        if not spec.impl.time_scaled:
            continue
        for obj, object_views in library.items():
            key = (obj, str(spec.source))
            if key not in scales:
                scales[key] = object_time_scale(object_views, spec.source)
            rows.append(
                {
                    "object": obj,
                    "descriptor": spec.name,
                    "source_rule": str(spec.source),
                    "time_scale": scales[key],
                    "n_views": len(object_views),
                }
            )
    return pd.DataFrame(rows, columns=["object", "descriptor", "source_rule", "time_scale", "n_views"])


def describe_object(
    model: Model, plan: pd.DataFrame, specs: list[DescriptorSpec], *, noise: bool = True
) -> pd.DataFrame:
    """Render the planned views of ``model`` and describe them (see :func:`descriptor_rows`)."""
    from heatdata.experiments.views import render_views  # open3d: only for rendering

    return descriptor_rows(render_views(model, plan, noise=noise), plan, specs)


def describe_view_table(
    frame: pd.DataFrame, specs: list[DescriptorSpec], time_scales: pd.DataFrame | None = None
) -> pd.DataFrame:
    """Workflow step: descriptor rows of the views of a :data:`VIEW_SCHEMA` frame."""
    from heatdata.views.frames import frame_to_views

    return descriptor_rows(frame_to_views(frame), frame[["split", "seed"]], specs, time_scales=time_scales)


def describe_library_and_tests(frames: list[pd.DataFrame], spec: DescriptorSpec, size: int) -> pd.DataFrame:
    """Descriptor rows of each object's library of ``size`` views (as :func:`library_subset` chooses them) and of
    its test views: a run's :data:`VIEW_SCHEMA` frames (one per object) described again with one spec."""
    from heatdata.recognition.evaluate import library_subset

    rows = []
    for frame in frames:
        library = library_subset(frame[frame["split"] == "train"], size)
        rows.append(describe_view_table(pd.concat([library, frame[frame["split"] == "test"]]), [spec]))
    return pd.concat(rows, ignore_index=True)


def candidate_view_table(
    frame: pd.DataFrame, spec: DescriptorSpec, *, library_count: int | None, test_count: int | None
) -> pd.DataFrame:
    """Workflow step: :func:`candidate_rows` of the views of a :data:`VIEW_SCHEMA` frame."""
    from heatdata.views.frames import frame_to_views

    return candidate_rows(
        frame_to_views(frame), frame[["split", "seed"]], spec, library_count=library_count, test_count=test_count
    )


def view_table_time_scales(frame: pd.DataFrame, specs: list[DescriptorSpec]) -> pd.DataFrame:
    """Workflow step: :func:`time_scale_table` of the library views of a :data:`VIEW_SCHEMA` frame."""
    from heatdata.views.frames import frame_to_views

    library = frame[frame["split"] == "train"]
    return time_scale_table(frame_to_views(library), library[["split"]], specs)


FIT_VIEWS_PER_OBJECT = 10  # library views per object a fitted kind (SI-HKS's codebook) learns from


def fit_view_tables(
    frames: list[pd.DataFrame], spec: DescriptorSpec, *, per_object: int = FIT_VIEWS_PER_OBJECT
) -> DescriptorSpec:
    """Workflow step: fit ``spec`` on up to ``per_object`` library views of each object, evenly spaced in azimuth
    (a kind with a ``train_views`` option, the pointnet, sets its own count: the views of a library of that size).

    ``frames`` are :data:`VIEW_SCHEMA` tables (one per object); only ``split = "train"`` rows are used.
    """
    from heatdata.recognition.evaluate import library_subset
    from heatdata.views.frames import frame_to_views

    per_object = spec.get("train_views") or per_object
    views = []
    for frame in frames:
        library = frame[frame["split"] == "train"]
        if library.empty:
            continue
        count = min(per_object, library["azimuth"].nunique())
        views += frame_to_views(library_subset(library, count).sort_values("azimuth"))
    log.info("fitting %s on %d library views (%d per object at most)", spec.name, len(views), per_object)
    return fit_spec(spec, views)


def capped_steps(spec: DescriptorSpec, limit: int) -> DescriptorSpec:
    """``spec`` to be trained at most ``limit`` steps (config ``learned_steps_limit``; 0: as it says), for a run
    tried small. Only a kind with a ``steps`` option is changed; its arrays are then stored under the original name.
    """
    names = [option.name for option in spec.impl.options]
    if not limit or "steps" not in names or spec.get("steps") <= limit:
        return spec
    log.warning("%s: trained %d steps, not %d (learned_steps_limit)", spec.name, limit, spec.get("steps"))
    return DescriptorSpec(spec.kind, **{**spec.options, "steps": limit})


def save_fitted(spec: DescriptorSpec, path) -> None:
    """What a fitted spec learned, as a ``.npz`` of its named arrays."""
    with atomic(path) as temporary:
        np.savez(temporary, **spec.fitted)


def load_fitted(specs: list[DescriptorSpec], paths: dict) -> list[DescriptorSpec]:
    """``specs`` with the fitted kinds' learned arrays read from ``paths`` (spec name -> ``.npz``)."""
    out = []
    for spec in specs:
        if spec.impl.fitted:
            if spec.name not in paths:
                raise HeatdataError(f"{spec.name} must be fitted on the library views first (no fitted file given)")
            with np.load(paths[spec.name]) as arrays:
                spec = spec.with_fitted({k: arrays[k] for k in arrays.files})
        out.append(spec)
    return out
