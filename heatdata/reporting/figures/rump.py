"""HBRD of a population of rumps (thesis ch. 8)."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from heatdata.reporting.figures.common import RENDERED_NOTE, _save


def plot_rumps(
    heats: list,
    weights: np.ndarray,
    embedding: np.ndarray,
    thin: np.ndarray,
    path: str | Path,
    title: str,
    note: str = RENDERED_NOTE,
) -> None:
    """HBRD on a population (thesis Fig. 8.6-8.8).

    Parameters
    ----------
    heats : list of :class:`heatdata.rump.RumpHeat`
        Every rump: the thinnest and the heaviest are drawn, their temperature difference
        at the first time with the planar path in black (Fig. 8.6); every descriptor
        (Fig. 8.7) is coloured by ``weights`` (N,).
    embedding : (N, 3) float
        The descriptors' 3D Isomap (Fig. 8.8); ``thin`` (N,) bool marks the thin ones (blue).
    """
    weights = np.asarray(weights, float)
    descriptors = np.array([h.descriptor for h in heats])
    examples = {f"weight {weights[k]:.2f}": heats[k] for k in (int(np.argmin(weights)), int(np.argmax(weights)))}
    fig = plt.figure(figsize=(4.0 * len(examples) + 9.0, 4.2))
    columns = len(examples) + 2
    for k, (label, heat) in enumerate(examples.items()):
        ax = fig.add_subplot(1, columns, k + 1)
        x, y = heat.vertices[:, 0], heat.vertices[:, 1]
        image = ax.tripcolor(
            x,
            y,
            heat.faces,
            heat.difference[0],
            cmap="magma",
            shading="gouraud",
            vmin=0.0,
            vmax=max(float(heat.difference[0].max()), 1e-12),
        )
        ax.plot(x[heat.path], y[heat.path], "k-", lw=1.5)
        ax.plot(*heat.landmarks.T, "c+", ms=9, mew=2)
        ax.set_aspect("equal")
        ax.set_title(f"{label}: T - T_plane at t = {heat.times[0]:.2g}", fontsize=8)
        ax.set_xlabel("canonical x (m)", fontsize=7)
        fig.colorbar(image, ax=ax, fraction=0.046, label="temperature difference (equilibrium = 1)")
    times = next(iter(examples.values())).times
    ax = fig.add_subplot(1, columns, columns - 1)
    colours = plt.get_cmap("viridis")(weights)
    for z, colour in zip(descriptors, colours):
        ax.semilogx(times, z, color=colour, lw=1)
    ax.set_xlabel("time t (m$^2$)")
    ax.set_ylabel("HBRD z(t), eq. 8.1")
    ax.set_title("descriptors, coloured by weight (yellow = heaviest)", fontsize=8)
    ax = fig.add_subplot(1, columns, columns, projection="3d")
    ax.scatter(*embedding[thin].T, c="tab:blue", label="thinnest third", s=18)
    ax.scatter(*embedding[~thin].T, c="tab:red", label="the rest", s=18)
    ax.set_title("3D Isomap of the descriptors (Fig. 8.8)", fontsize=8)
    ax.legend(fontsize=7)
    fig.suptitle(title, fontsize=9)
    _save(fig, path, note=note)
