"""Evaluation: nearest-neighbour recognition of test views against a library (thesis 3.3.2).

Also draws the figures a person would rather look at than read: the object confusion
matrix, the view-angle confusion of Fig. 3.5, and partial views coloured by
temperature with the source marked (Fig. 2.3/2.4).
"""

from __future__ import annotations

import logging
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from .errors import HeatdataError  # noqa: E402
from .recognition import nearest_neighbours  # noqa: E402

log = logging.getLogger(__name__)

RENDERED_NOTE = "Views are rendered from 3D models with simulated Kinect noise, not real sensor data."


def classify(descriptors: pd.DataFrame, descriptor: str, *, library: str = "train", queries: str = "test"
             ) -> pd.DataFrame:
    """Nearest-neighbour class of each query view among the library views (eq. 3.1).

    Parameters
    ----------
    descriptors : DataFrame
        A descriptor table (:data:`heatdata.tables.DESCRIPTOR_SCHEMA`).
    descriptor : str
        Which descriptor (the ``descriptor`` column) to use.
    library, queries : str
        Values of the ``split`` column.

    Returns
    -------
    DataFrame
        One row per query, columns of :data:`heatdata.tables.PREDICTION_SCHEMA`.
    """
    rows = descriptors[descriptors["descriptor"] == descriptor]
    lib, query = rows[rows["split"] == library], rows[rows["split"] == queries]
    if lib.empty or query.empty:
        raise HeatdataError(f"descriptor {descriptor!r}: no {library!r} or no {queries!r} rows to compare")
    lengths = {len(v) for v in rows["values"]}
    if len(lengths) > 1:
        raise HeatdataError(f"descriptor {descriptor!r}: descriptors of different lengths {sorted(lengths)}")
    nn = nearest_neighbours(np.stack(query["values"].to_numpy()), np.stack(lib["values"].to_numpy()))
    match = lib.iloc[nn.index]
    return pd.DataFrame({
        "descriptor": descriptor,
        "object": query["object"].to_numpy(), "label": query["label"].to_numpy(),
        "view_id": query["view_id"].to_numpy(), "azimuth": query["azimuth"].to_numpy(),
        "predicted_object": match["object"].to_numpy(), "predicted_label": match["label"].to_numpy(),
        "predicted_view_id": match["view_id"].to_numpy(), "predicted_azimuth": match["azimuth"].to_numpy(),
        "distance": nn.distance, "correct": query["object"].to_numpy() == match["object"].to_numpy(),
    })


def accuracy_table(predictions: pd.DataFrame) -> pd.DataFrame:
    """Per-object accuracy (rows) for each descriptor (columns), with an ``all`` row."""
    per = predictions.pivot_table(index="object", columns="descriptor", values="correct", aggfunc="mean")
    per.loc["all"] = predictions.groupby("descriptor")["correct"].mean()
    return per


def _save(fig, path: str | Path) -> None:
    """Sign the figure as rendered data, save it and free it."""
    fig.text(0.01, 0.005, RENDERED_NOTE, fontsize=6, color="grey")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_confusion(predictions: pd.DataFrame, path: str | Path, title: str) -> None:
    """Object confusion matrix, rows true, columns predicted, with per-object accuracy."""
    objects = sorted(set(predictions["object"]) | set(predictions["predicted_object"]))
    counts = pd.crosstab(pd.Categorical(predictions["object"], objects),
                         pd.Categorical(predictions["predicted_object"], objects), dropna=False).to_numpy()
    fraction = counts / np.maximum(counts.sum(axis=1, keepdims=True), 1)
    fig, ax = plt.subplots(figsize=(max(5.0, 1.0 + 0.55 * len(objects)), max(4.5, 0.8 + 0.5 * len(objects))))
    ax.imshow(fraction, cmap="Blues", vmin=0, vmax=1)
    for (i, j), n in np.ndenumerate(counts):
        if n:
            ax.text(j, i, str(n), ha="center", va="center", fontsize=7,
                    color="white" if fraction[i, j] > 0.5 else "black")
    accuracy = np.diag(fraction)
    ax.set_xticks(range(len(objects)), objects, rotation=60, ha="right", fontsize=8)
    ax.set_yticks(range(len(objects)), [f"{o} ({a:.0%})" for o, a in zip(objects, accuracy, strict=True)], fontsize=8)
    ax.set_xlabel("predicted object (nearest library view)")
    ax.set_ylabel("true object (accuracy)")
    ax.set_title(f"{title}\noverall accuracy {predictions['correct'].mean():.1%}", fontsize=9)
    _save(fig, path)


def plot_view_confusion(predictions: pd.DataFrame, path: str | Path, title: str) -> None:
    """Fig. 3.5: true (object, azimuth) against the (object, azimuth) of the nearest library view."""
    objects = sorted(set(predictions["object"]) | set(predictions["predicted_object"]))
    position = {o: i for i, o in enumerate(objects)}
    x = predictions["object"].map(position) + predictions["azimuth"] / 360.0
    y = predictions["predicted_object"].map(position) + predictions["predicted_azimuth"] / 360.0
    fig, ax = plt.subplots(figsize=(7.5, 7))
    ax.scatter(x, y, s=2, c=np.where(predictions["correct"], "tab:blue", "tab:red"))
    for k in range(len(objects) + 1):
        ax.axhline(k, color="0.85", lw=0.5)
        ax.axvline(k, color="0.85", lw=0.5)
    ticks = np.arange(len(objects)) + 0.5
    ax.set_xticks(ticks, objects, rotation=60, ha="right", fontsize=7)
    ax.set_yticks(ticks, objects, fontsize=7)
    ax.set_xlim(0, len(objects))
    ax.set_ylim(0, len(objects))
    ax.set_xlabel("true object, azimuth 0-360 deg within each cell")
    ax.set_ylabel("nearest library view: object and azimuth")
    ax.set_title(f"{title}: view-angle confusion (red: wrong object)", fontsize=9)
    _save(fig, path)


def plot_views(views: list, temperatures: list, sources: list, path: str | Path, titles: list[str]) -> None:
    """Partial views coloured by temperature at t_s, with the source and boundary marked."""
    if not views:
        raise HeatdataError("no views to draw")
    cols = min(4, len(views))
    rows = int(np.ceil(len(views) / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 3.2 * rows), squeeze=False)
    for ax, view, temp, source, title in zip(axes.ravel(), views, temperatures, sources, titles, strict=False):
        p = view.pixels
        collection = ax.tripcolor(p[:, 0], p[:, 1], view.faces, temp, shading="gouraud", cmap="inferno")
        b = np.append(view.boundary, view.boundary[0])
        ax.plot(p[b, 0], p[b, 1], color="cyan", lw=0.8)
        ax.plot(*p[view.boundary[0]], "o", color="cyan", ms=4)
        ax.plot(*p[source], "*", color="lime", ms=12, mec="black")
        ax.set_aspect("equal")
        ax.invert_yaxis()
        ax.set_axis_off()
        ax.set_title(title, fontsize=8)
        fig.colorbar(collection, ax=ax, fraction=0.04, pad=0.02)
    for ax in axes.ravel()[len(views):]:
        ax.set_axis_off()
    fig.suptitle("Temperature at t_s = 1/lambda_2 (equilibrium = 1); star: source, dot: boundary origin\n"
                 + RENDERED_NOTE, fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
