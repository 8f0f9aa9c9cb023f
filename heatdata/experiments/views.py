"""View plans and the render loop: which views of each object the run renders, and rendering them.

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

from heatdata.errors import HeatdataError
from heatdata.io.models import Model
from heatdata.views.render import render_view
from heatdata.views.view import View, kinect_intrinsics

log = logging.getLogger(__name__)


def view_plan(
    objects: list[str],
    n_train: int = 40,
    n_test: int = 120,
    *,
    elevation: float = 30.0,
    distance: float = 1.0,
    seed: int = 0,
) -> pd.DataFrame:
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
                rows.append(
                    {
                        "object": obj,
                        "split": split,
                        "index": k,
                        "azimuth": round(360.0 * (k + offset) / count, 6),
                        "elevation": float(elevation),
                        "distance": float(distance),
                        "seed": int(view_seed.generate_state(1)[0]),
                    }
                )
    return pd.DataFrame(rows)


def render_views(
    model: Model,
    plan: pd.DataFrame,
    *,
    noise: bool = True,
    intrinsics: dict | None = None,
    components: str = "largest",
    progress_every: int = 40,
) -> list[View]:
    """Render every planned view of ``model`` (rows of :func:`view_plan` for this object).

    ``intrinsics``: the camera's (default the Kinect's, :func:`heatdata.views.view.kinect_intrinsics`);
    ``components``: ``"largest"`` or ``"all"`` (:func:`heatdata.render_view`).
    """
    views = []
    start = time.perf_counter()
    for count, row in enumerate(plan.itertuples(), 1):
        views.append(
            render_view(
                model,
                row.azimuth,
                row.elevation,
                row.distance,
                noise=noise,
                seed=row.seed,
                intrinsics=intrinsics,
                components=components,
                view_id=f"{model.name}/{row.split}/{row.index:03d}",
            )
        )
        if count % progress_every == 0 or count == len(plan):
            log.info("%s: %d/%d views rendered (%.1f s)", model.name, count, len(plan), time.perf_counter() - start)
    repaired = [v for v in views if v.repairs]
    if repaired:
        log.info(
            "%s: %d of %d views repaired (see the repairs column), e.g. %s",
            model.name,
            len(repaired),
            len(views),
            "; ".join(repaired[0].repairs),
        )
    return views


def render_object_views(row: dict, views: dict) -> pd.DataFrame:
    """Workflow step: the planned views of one catalogue object as a :data:`VIEW_SCHEMA` frame.

    ``views`` holds ``train, test, elevation, distance, noise, seed`` and optionally
    ``image_scale`` and ``components`` (config ``views``).
    """
    from heatdata.io.catalog import load_catalog_model
    from heatdata.views.frames import views_to_frame

    model = load_catalog_model(row)
    plan = view_plan(
        [model.name],
        views["train"],
        views["test"],
        elevation=views["elevation"],
        distance=views["distance"],
        seed=views["seed"],
    )
    intrinsics = kinect_intrinsics(views.get("image_scale", 1.0))
    return views_to_frame(
        render_views(
            model, plan, noise=views["noise"], intrinsics=intrinsics, components=views.get("components", "largest")
        ),
        plan,
    )


def capture_view_table(
    captures: list[dict], label: str = "", *, depth_range=None, max_depth_jump: float | None = None
) -> pd.DataFrame:
    """Workflow step: one object's captures (:func:`heatdata.experiments.captures.find_captures`) as test views of a
    :data:`VIEW_SCHEMA` frame (split ``test``: described as rendered test views are; angles unknown, NaN)."""
    from heatdata.views.depth import MAX_DEPTH_JUMP, read_depth
    from heatdata.views.frames import views_to_frame

    views = [
        read_depth(
            c["depth"],
            c["intrinsics"],
            c["rgb"] or None,
            c["mask"] or None,
            depth_range=depth_range or None,
            max_depth_jump=max_depth_jump or MAX_DEPTH_JUMP,
            view_id=f"{c['object']}/capture/{c['name']}",
            object_id=c["object"],
            label=label,
        )
        for c in captures
    ]
    return views_to_frame(views, pd.DataFrame({"split": "test", "seed": 0}, index=range(len(views))))
