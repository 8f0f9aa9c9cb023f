"""What every figure shares: its notes, mesh drawing and saving."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from heatdata.io.files import atomic

MAX_LEGEND_OBJECTS = 20  # the per-object precision panel names at most this many objects


RENDERED_NOTE = "Views are rendered from 3D models with simulated Kinect noise, not real sensor data."


PROXY_NOTE = (
    "Bodies are MakeHuman models rendered with simulated Kinect noise: a proxy for goats' rumps, not goats, "
    "not real sensor data."
)


def _draw_mesh(ax, view, title: str) -> None:
    """A partial view in image coordinates, faces in their vertices' mean colour."""
    from matplotlib.collections import PolyCollection

    p = view.pixels
    colours = np.clip(view.colors[view.faces].mean(axis=1), 0, 1)
    ax.add_collection(PolyCollection(p[view.faces], facecolors=colours, edgecolors=colours, linewidths=0.3))
    b = np.append(view.boundary, view.boundary[0])
    ax.plot(p[b, 0], p[b, 1], color="tab:cyan", lw=0.8)
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.invert_yaxis()
    ax.set_axis_off()
    ax.set_title(title, fontsize=8)


def _save(fig, path: str | Path, note: str = RENDERED_NOTE) -> None:
    """Sign the figure as rendered data, save it and free it."""
    fig.text(0.01, 0.005, note, fontsize=6, color="grey")
    fig.tight_layout()
    with atomic(path) as temporary:
        fig.savefig(temporary, dpi=110)
    plt.close(fig)


def _draw_counts(ax, counts: np.ndarray, names: list[str]):
    """A confusion matrix of ``counts`` (true rows, predicted columns) shaded by row share, each true row's
    precision in its label; returns the image (for a colour bar)."""
    fraction = counts / np.maximum(counts.sum(axis=1, keepdims=True), 1)
    image = ax.imshow(100 * fraction, cmap="Blues", vmin=0, vmax=100)
    for (i, j), n in np.ndenumerate(counts):
        if n:
            ax.text(
                j, i, str(n), ha="center", va="center", fontsize=7, color="white" if fraction[i, j] > 0.5 else "black"
            )
    ax.set_xticks(range(len(names)), names, rotation=60, ha="right", fontsize=8)
    ax.set_yticks(
        range(len(names)), [f"{o} ({a:.0%})" for o, a in zip(names, np.diag(fraction), strict=True)], fontsize=8
    )
    return image


def _draw_faces_3d(ax, vertices: np.ndarray, faces: np.ndarray, colors: np.ndarray, max_faces: int = 6000) -> None:
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    step = max(1, len(faces) // max_faces)
    shown = faces[::step]
    ax.add_collection3d(Poly3DCollection(vertices[shown], facecolors=colors[::step], edgecolors="none"))
