"""Views as table rows and back: the ``views.parquet`` columns of :data:`heatdata.io.tables.VIEW_SCHEMA`."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd


def views_to_frame(views: list, plan: pd.DataFrame) -> pd.DataFrame:
    """Views as rows of :data:`VIEW_SCHEMA` (flattened arrays); ``plan`` gives split and seed in order.

    Parameters
    ----------
    views : list of View
        Rendered or captured views, in the plan's order.
    plan : pandas.DataFrame
        Their plan rows (:func:`heatdata.experiments.views.view_plan`).

    Returns
    -------
    pandas.DataFrame
        One row per view.
    """
    return pd.DataFrame(
        [
            {
                "view_id": v.view_id,
                "object": v.object_id,
                "label": v.label,
                "split": p.split,
                "seed": p.seed,
                "azimuth": v.azimuth,
                "elevation": v.elevation,
                "distance": v.distance,
                "n_vertices": v.n_vertices,
                "vertices": v.vertices.ravel(),
                "faces": v.faces.ravel().astype(np.int32),
                "colors": v.colors.ravel().astype(np.float32),
                "pose": v.pose.ravel(),
                "intrinsics": json.dumps(v.intrinsics),
                "repairs": list(v.repairs),
            }
            for v, p in zip(views, plan.itertuples(), strict=True)
        ]
    )


def frame_to_views(frame: pd.DataFrame) -> list:
    """The views of a :data:`VIEW_SCHEMA` table, in row order.

    Parameters
    ----------
    frame : pandas.DataFrame
        Rows of ``views.parquet``.

    Returns
    -------
    list of View
    """
    from heatdata.views.view import View

    return [
        View(
            vertices=np.asarray(r.vertices, np.float64).reshape(-1, 3),
            faces=np.asarray(r.faces, np.int64).reshape(-1, 3),
            colors=np.asarray(r.colors, np.float64).reshape(-1, 3),
            intrinsics=json.loads(r.intrinsics),
            view_id=r.view_id,
            object_id=r.object,
            label=r.label,
            azimuth=r.azimuth,
            elevation=r.elevation,
            distance=r.distance,
            pose=np.asarray(r.pose).reshape(4, 4),
            repairs=list(r.repairs),
        )
        for r in frame.itertuples()
    ]
