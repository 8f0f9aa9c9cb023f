"""The rump experiment's population (thesis ch. 8): MakeHuman bodies seen from behind by a virtual Kinect."""

from __future__ import annotations

import numpy as np

from heatdata.io.bodies import body_model, rump_landmark_vertices


def rendered_rumps(
    bodies: list[dict], *, distance: float = 1.2, noise: bool = True, seed: int = 0, intrinsics: dict | None = None
) -> list[tuple]:
    """Each body of :func:`population` seen from behind at hip height by the virtual Kinect, as a goat's rump is
    seen by the corridor camera above it (8.2): ``(view, landmarks)``, the landmarks (4, 3) in the view's camera
    frame (hip left, hip right, pin left, pin right: :func:`rump_landmark_vertices` of the average body)."""
    from heatdata.log import progress
    from heatdata.views.render import render_view

    template = rump_landmark_vertices(body_model())
    out = []
    for k, body in enumerate(progress(bodies, desc="render rumps", unit="body")):
        model = body_model(**body)
        view = render_view(model, 180.0, 0.0, distance, noise=noise, seed=seed + k, intrinsics=intrinsics)
        rotation, position = view.pose[:3, :3], view.pose[:3, 3]
        out.append((view, (model.vertices[template] - position) @ rotation))
    return out


def population_table(bodies: list[dict], descriptors: np.ndarray, embedding: np.ndarray):
    """One row per body: ``weight, muscle, isomap1`` (the Isomap's first axis) and the descriptor ``z0 .. z{K-1}``."""
    import pandas as pd

    table = pd.DataFrame(descriptors, columns=[f"z{k}" for k in range(descriptors.shape[1])])
    table.insert(0, "isomap1", embedding[:, 0])
    table.insert(0, "muscle", [b["muscle"] for b in bodies])
    table.insert(0, "weight", [b["weight"] for b in bodies])
    return table
