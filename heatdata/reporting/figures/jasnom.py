"""Two meshes and their JASNOM stitch (thesis ch. 7)."""

from __future__ import annotations

from pathlib import Path

import matplotlib
import matplotlib.pyplot as plt
import numpy as np

from heatdata.io.models import Model
from heatdata.reporting.figures.common import _draw_faces_3d, _save


def plot_stitch(first: Model, second: Model, stitched: Model, strip_faces: int, path: str | Path, title: str) -> None:
    """JASNOM before and after (thesis Fig. 7.9): the two meshes as given, and the stitched model with its strip.

    ``first``, ``second`` and ``stitched`` are :class:`heatdata.io.models.Model`; the last
    ``strip_faces`` faces of ``stitched`` are the strip (drawn in red). Faces are shaded by
    their orientation to a light; at most 6,000 are drawn per mesh.
    """
    fig = plt.figure(figsize=(12, 5.5))
    light = np.array([0.3, 0.8, 0.5]) / np.linalg.norm([0.3, 0.8, 0.5])
    panels: list[tuple[str, list[tuple[Model, str | None]]]] = [
        ("before: the two meshes as given", [(first, "tab:blue"), (second, "tab:orange")]),
        ("after: aligned and stitched (the strip in red, drawn over the mesh)", [(stitched, None)]),
    ]
    for k, (label, meshes) in enumerate(panels):
        ax = fig.add_subplot(1, 2, k + 1, projection="3d")
        points = np.vstack([m.vertices for m, _ in meshes])
        for model, colour in meshes:
            corners = model.vertices[model.faces]
            normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
            shade = 0.35 + 0.65 * np.abs(normal @ light) / np.maximum(np.linalg.norm(normal, axis=1), 1e-30)
            base = np.tile(matplotlib.colors.to_rgb(colour or "tab:blue"), (len(model.faces), 1))
            if colour is None:
                base[: len(model.faces) - strip_faces] = matplotlib.colors.to_rgb("tab:grey")
                base[len(model.faces) - strip_faces :] = matplotlib.colors.to_rgb("tab:red")
            rgba = np.column_stack([base * shade[:, None], np.ones(len(base))])
            _draw_faces_3d(ax, model.vertices, model.faces, rgba)
            if colour is None and strip_faces:  # the strip's triangles are thin: draw their edges over the mesh
                from mpl_toolkits.mplot3d.art3d import Line3DCollection

                strip = model.vertices[model.faces[len(model.faces) - strip_faces :]]
                edges = np.concatenate([strip[:, [0, 1]], strip[:, [1, 2]], strip[:, [2, 0]]])
                ax.computed_zorder = False  # the seam is drawn over the mesh, also where the mesh hides it
                ax.add_collection3d(Line3DCollection(edges, colors="tab:red", linewidths=0.8, zorder=10))
        low, high = points.min(axis=0), points.max(axis=0)
        middle, half = (low + high) / 2, (high - low).max() / 2
        ax.set_xlim(middle[0] - half, middle[0] + half)
        ax.set_ylim(middle[1] - half, middle[1] + half)
        ax.set_zlim(middle[2] - half, middle[2] + half)
        ax.set_title(label, fontsize=9)
        ax.set_axis_off()
    fig.suptitle(title, fontsize=9)
    _save(fig, path, note="")
