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
from heatdata.views.render import camera_distance, render_view
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
    sensor: str | None = None,
    intrinsics: dict | None = None,
    components: str = "largest",
    offsets: np.ndarray | None = None,
    split: str | None = None,
    progress_every: int = 40,
) -> list[View]:
    """Render every planned view of ``model`` (rows of :func:`view_plan` for this object).

    ``sensor``: a sensor profile in place of ``noise`` (:class:`heatdata.views.sensor.SensorProfile`);
    ``intrinsics``: the camera's (default the Kinect's, :func:`heatdata.views.view.kinect_intrinsics`);
    ``components``: ``"largest"`` or ``"all"`` (:func:`heatdata.render_view`); ``offsets``: (len(plan), 2) pixels
    at which each view's object stands off the image centre (the camera turned), default none; ``split``: the
    name of the views' split in their ids (default the plan's).
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
                sensor=sensor,
                seed=row.seed,
                intrinsics=intrinsics,
                image_offset=(0.0, 0.0) if offsets is None else tuple(offsets[count - 1]),
                components=components,
                view_id=f"{model.name}/{split or row.split}/{row.index:03d}",
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
    ``sensor``, ``image_scale`` and ``components`` (config ``views``); a ``distance`` of ``"fit"`` is set by the
    object's size (:func:`heatdata.views.render.camera_distance`).
    """
    from heatdata.io.catalog import load_catalog_model
    from heatdata.views.frames import views_to_frame

    model = load_catalog_model(row)
    intrinsics = kinect_intrinsics(views.get("image_scale", 1.0))
    plan = view_plan(
        [model.name],
        views["train"],
        views["test"],
        elevation=views["elevation"],
        distance=camera_distance(model, views["distance"], intrinsics),
        seed=views["seed"],
    )
    return views_to_frame(
        render_views(
            model,
            plan,
            noise=views["noise"],
            sensor=views.get("sensor"),
            intrinsics=intrinsics,
            components=views.get("components", "largest"),
        ),
        plan,
    )


def render_offaxis_views(row: dict, views: dict, count: int) -> pd.DataFrame:
    """Workflow step: ``count`` of one object's test views rendered again, off the optical axis and, as a control,
    centred with another noise draw.

    Each off-axis view is the test view of the same index, azimuth and noise seed, the camera turned (not moved) so
    that the object's centre lands at a random pixel (seeded by the view's seed) that keeps the object inside the
    image; its id is ``<object>/offaxis/<index>``, beside the run's ``<object>/test/<index>``. Each control view
    (``<object>/reseeded/<index>``) is the test view again with the next noise seed: how much an answer changes
    when nothing but the sensor's noise and the pixels that sample the surface change.

    Parameters
    ----------
    row : dict
        The object's catalogue row.
    views : dict
        The config's ``views``.
    count : int
        Test views to render again, evenly spaced among the run's.

    Returns
    -------
    pandas.DataFrame
        A :data:`VIEW_SCHEMA` frame (split ``test``); each off-axis view's pixel offset is in its repairs.
    """
    from heatdata.io.catalog import load_catalog_model
    from heatdata.views.frames import views_to_frame

    model = load_catalog_model(row)
    intrinsics = kinect_intrinsics(views.get("image_scale", 1.0))
    distance = camera_distance(model, views["distance"], intrinsics)
    plan = view_plan([model.name], 1, views["test"], elevation=views["elevation"], distance=distance,
                     seed=views["seed"])  # fmt: skip
    plan = plan[plan["split"] == "test"]
    plan = plan.iloc[np.unique(np.linspace(0, len(plan) - 1, min(count, len(plan))).round().astype(int))]
    radius = intrinsics["fx"] * 0.5 * float(np.linalg.norm(model.extents)) / distance + 4.0
    room = np.array([intrinsics["width"], intrinsics["height"]]) / 2.0 - radius
    offsets = np.array(
        [np.random.default_rng(seed).uniform(-1.0, 1.0, 2) * np.maximum(room, 0.0) for seed in plan["seed"]]
    )
    options = dict(noise=views["noise"], sensor=views.get("sensor"), intrinsics=intrinsics,
                   components=views.get("components", "largest"))  # fmt: skip
    moved = render_views(model, plan, offsets=offsets, split="offaxis", **options)
    for view, (du, dv) in zip(moved, offsets, strict=True):
        view.repairs.append(f"rendered {du:+.0f}, {dv:+.0f} px off the image centre (the camera turned)")
    reseeded = plan.assign(seed=plan["seed"] + 1)
    control = render_views(model, reseeded, split="reseeded", **options)
    return views_to_frame(moved + control, pd.concat([plan, reseeded], ignore_index=True))


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
