"""View sets: which views of which objects to render, and their descriptor rows (thesis 3.3-3.4).

A view plan lists, per object, the training views (the library, evenly spaced in
azimuth) and the test views (offset by half a test step, so no test view repeats a
library angle), each with its own noise seed derived from the object id, split and
index - the same plan always renders the same views.
"""

from __future__ import annotations

import logging
import time
import zlib

import numpy as np
import pandas as pd

from .descriptors import DescriptorSpec, describe
from .errors import HeatdataError
from .models import Model
from .render import render_view
from .view import View

log = logging.getLogger(__name__)


def view_plan(objects: list[str], n_train: int = 40, n_test: int = 120, *, elevation: float = 30.0,
              distance: float = 1.0, seed: int = 0) -> pd.DataFrame:
    """One row per view to render: ``object, split, index, azimuth, elevation, distance, seed``.

    Training azimuths are ``360 k / n_train``; test azimuths ``360 (k + 1/2) / n_test``.
    """
    if n_train < 1 or n_test < 0:
        raise HeatdataError(f"need at least one training view and no negative test count ({n_train}, {n_test})")
    rows = []
    for obj in objects:
        for split, count in (("train", n_train), ("test", n_test)):
            offset = 0.0 if split == "train" else 0.5
            for k in range(count):
                view_seed = np.random.SeedSequence([seed, zlib.crc32(obj.encode()), int(split == "test"), k])
                rows.append({"object": obj, "split": split, "index": k,
                             "azimuth": round(360.0 * (k + offset) / count, 6), "elevation": float(elevation),
                             "distance": float(distance), "seed": int(view_seed.generate_state(1)[0])})
    return pd.DataFrame(rows)


def render_views(model: Model, plan: pd.DataFrame, *, noise: bool = True, progress_every: int = 40) -> list[View]:
    """Render every planned view of ``model`` (rows of :func:`view_plan` for this object)."""
    views = []
    start = time.perf_counter()
    for count, row in enumerate(plan.itertuples(), 1):
        views.append(render_view(model, row.azimuth, row.elevation, row.distance, noise=noise, seed=row.seed,
                                 view_id=f"{model.name}/{row.split}/{row.index:03d}"))
        if count % progress_every == 0 or count == len(plan):
            log.info("%s: %d/%d views rendered (%.1f s)", model.name, count, len(plan), time.perf_counter() - start)
    repaired = [v for v in views if v.repairs]
    if repaired:
        log.info("%s: %d of %d views repaired (see the repairs column), e.g. %s", model.name, len(repaired),
                 len(views), "; ".join(repaired[0].repairs))
    return views


def descriptor_rows(views: list[View], plan: pd.DataFrame, specs: list[DescriptorSpec], *,
                    progress_every: int = 40) -> pd.DataFrame:
    """Descriptors of ``specs`` for each view; ``plan`` gives each view's split and seed, in order.

    Returns
    -------
    pandas.DataFrame
        One row per view x descriptor, columns of :data:`heatdata.tables.DESCRIPTOR_SCHEMA`.
    """
    if len(views) != len(plan):
        raise HeatdataError(f"{len(views)} views but {len(plan)} plan rows")
    rows = []
    start = time.perf_counter()
    for count, (view, planned) in enumerate(zip(views, plan.itertuples(), strict=True), 1):
        tic = time.perf_counter()
        descriptors = describe(view, specs)
        seconds = (time.perf_counter() - tic) / len(specs)
        for spec, d in zip(specs, descriptors, strict=True):
            rows.append({
                "object": view.object_id, "label": view.label, "view_id": view.view_id, "split": planned.split,
                "azimuth": view.azimuth, "elevation": view.elevation, "distance": view.distance,
                "seed": planned.seed, "n_vertices": view.n_vertices, "n_boundary": len(view.boundary),
                "descriptor": spec.name, "kind": spec.kind, "sampling": spec.sampling,
                "source_rule": str(spec.source), "color_map": d.color_map or "", "source": d.source,
                "time": d.time, "lambda2": d.lambda2, "values": d.values.tolist(),
                "positions": d.positions.tolist(), "repairs": list(view.repairs) + list(d.repairs),
                "seconds": seconds,
            })
        if count % progress_every == 0 or count == len(views):
            log.info("%s: %d/%d views described (%.1f s)", view.object_id, count, len(views),
                     time.perf_counter() - start)
    return pd.DataFrame(rows)


def describe_object(model: Model, plan: pd.DataFrame, specs: list[DescriptorSpec], *, noise: bool = True
                    ) -> pd.DataFrame:
    """Render the planned views of ``model`` and describe them (see :func:`descriptor_rows`)."""
    return descriptor_rows(render_views(model, plan, noise=noise), plan, specs)


def render_object_views(row: dict, views: dict) -> pd.DataFrame:
    """Workflow step: the planned views of one catalogue object as a :data:`VIEW_SCHEMA` frame.

    ``views`` holds ``train, test, elevation, distance, noise, seed`` (config ``views``).
    """
    from .catalog import load_catalog_model
    from .tables import views_to_frame

    model = load_catalog_model(row)
    plan = view_plan([model.name], views["train"], views["test"], elevation=views["elevation"],
                     distance=views["distance"], seed=views["seed"])
    return views_to_frame(render_views(model, plan, noise=views["noise"]), plan)


def describe_view_table(frame: pd.DataFrame, specs: list[DescriptorSpec]) -> pd.DataFrame:
    """Workflow step: descriptor rows of the views of a :data:`VIEW_SCHEMA` frame."""
    from .tables import frame_to_views

    return descriptor_rows(frame_to_views(frame), frame[["split", "seed"]], specs)
