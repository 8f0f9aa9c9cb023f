"""Recognition figures (thesis 3.3, Fig. 3.5, 3.7): precision, confusion, misclassified views, Isomaps."""

from __future__ import annotations

from pathlib import Path

import matplotlib
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.ticker import PercentFormatter

from heatdata.descriptors import kind_of
from heatdata.errors import HeatdataError
from heatdata.recognition.metrics import confusion_matrix
from heatdata.reporting.figures.common import (
    MAX_LEGEND_OBJECTS,
    _draw_counts,
    _draw_mesh,
    _save,
)

matplotlib.use("Agg")


MARKERS = "osD^vPX<>*"
DODGE = 0.035  # of the step between library sizes: lines of equal precision drawn side by side, not over each other


def plot_precision(precision: pd.DataFrame, path: str | Path, primary: str | None = None) -> None:
    """Object precision (%) against library size: every test view per descriptor, and per object (Fig. 3.7, 5.13).

    The left panel draws each descriptor's line a little apart (:data:`DODGE`) with its own marker, so that equal
    precisions stay visible, and names them in a legend below the axes. The right panel shows ``primary`` (default:
    the descriptor with the best precision) per object: a grid of numbers for up to
    :data:`~heatdata.reporting.figures.common.MAX_LEGEND_OBJECTS` objects, else every object's grey line and their
    median. Precision axes run within [0, 100%].
    """
    fig, (left, right) = plt.subplots(1, 2, figsize=(12, 5.2))
    overall = precision[(precision["group"] == "all") & (precision["level"] == "object")]
    sizes = sorted(overall["library_size"].unique())
    at = {size: k for k, size in enumerate(sizes)}
    names = list(dict.fromkeys(overall["descriptor"]))
    for k, name in enumerate(names):
        rows = overall[overall["descriptor"] == name].sort_values("library_size")
        x = rows["library_size"].map(at) + DODGE * (k - (len(names) - 1) / 2)
        left.plot(x, 100 * rows["precision"], marker=MARKERS[k % len(MARKERS)], label=name, clip_on=False)
    left.set_ylabel("object precision, all test views (%)")
    left.set_ylim(_percent_floor(overall["precision"]), 100)
    left.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2, frameon=False)
    primary = primary or overall.sort_values("precision").iloc[-1]["descriptor"]
    objects = precision[
        (precision["level"] == "object") & (precision["group"] != "all") & (precision["descriptor"] == primary)
    ]
    count = objects["group"].nunique()
    if count <= MAX_LEGEND_OBJECTS:
        grid = objects.pivot_table(index="group", columns="library_size", values="precision").reindex(columns=sizes)
        image = right.imshow(100 * grid.to_numpy(), cmap="RdYlGn", vmin=_percent_floor(grid.stack()), vmax=100,
                             aspect="auto")  # fmt: skip
        for (row, column), value in np.ndenumerate(100 * grid.to_numpy()):
            if np.isfinite(value):
                right.text(column, row, f"{value:.0f}", ha="center", va="center", fontsize=7)
        right.set_yticks(range(len(grid)), grid.index, fontsize=7)
        right.set_title(f"object precision per object (%): {primary}", fontsize=9)
        fig.colorbar(image, ax=right, format=PercentFormatter(100, decimals=0), fraction=0.05)
    else:
        for _, rows in objects.groupby("group"):
            rows = rows.sort_values("library_size")
            right.plot(rows["library_size"].map(at), 100 * rows["precision"], ".-", color="grey", alpha=0.35, lw=0.8,
                       clip_on=False)  # fmt: skip
        median = objects.groupby("library_size")["precision"].median()
        right.plot(median.index.map(at), 100 * median, "o-", color="black", lw=2, clip_on=False,
                   label=f"median of {count} objects (grey: each)")  # fmt: skip
        right.set_ylabel(f"object precision per object (%)\n{primary}", fontsize=9)
        right.set_ylim(_percent_floor(objects["precision"]), 100)
        right.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.14), frameon=False)
        right.yaxis.set_major_formatter(PercentFormatter(100, decimals=0))
        right.grid(alpha=0.3)
    for ax in (left, right):
        ax.set_xticks(range(len(sizes)), [str(s) for s in sizes])
        ax.set_xlabel("library views per object")
    left.set_xlim(-0.5, len(sizes) - 0.5)
    left.yaxis.set_major_formatter(PercentFormatter(100, decimals=0))
    left.grid(alpha=0.3)
    _save(fig, path)


def _percent_floor(shares: pd.Series) -> float:
    """The bottom of a precision axis in %: 5 points below the least share, down to a multiple of 5, at least 0."""
    least = 100 * float(np.nanmin(shares)) if len(shares) else 0.0
    return max(0.0, 5 * np.floor((least - 5) / 5))


POSITION_LABELS = {
    "polar": "polar angle / 2 pi (counter-clockwise from +x in the image)",
    "arclength": "arc length from the boundary origin / boundary length",
    None: "bin / number of bins",
}


def plot_descriptor_curves(
    descriptors: pd.DataFrame,
    descriptor: str,
    path: str | Path,
    *,
    objects: int = 8,
    azimuths: tuple = (0.0, 90.0, 180.0, 270.0),
) -> None:
    """A descriptor's values against their positions for library views at a few azimuths (thesis Fig. 2.5, 3.3).

    For a boundary kind the curve is the temperature (or PVST time) along the boundary;
    for a histogram kind, the histogram.
    """
    rows = descriptors[(descriptors["descriptor"] == descriptor) & (descriptors["split"] == "train")]
    if rows.empty:
        raise HeatdataError(f"no library views of {descriptor} to draw")
    names = rows["object"].drop_duplicates().tolist()[:objects]
    impl = kind_of(rows["kind"].iloc[0])
    cols = min(4, len(names))
    lines = int(np.ceil(len(names) / cols))
    fig, axes = plt.subplots(lines, cols, figsize=(3.3 * cols, 2.8 * lines), squeeze=False, sharey=True)
    sampling = rows["sampling"].iloc[0]
    for ax, obj in zip(axes.ravel(), names, strict=False):
        views = rows[rows["object"] == obj]
        for azimuth in azimuths:
            nearest = views.iloc[int(np.argmin(np.abs((views["azimuth"] - azimuth + 180) % 360 - 180)))]
            ax.plot(nearest["positions"], nearest["values"], lw=1, label=f"{nearest['azimuth']:.0f} deg")
        ax.set_title(obj, fontsize=8)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=6, title="azimuth", title_fontsize=6)
    for ax in axes[-1]:
        ax.set_xlabel(POSITION_LABELS.get(sampling, POSITION_LABELS[None]), fontsize=7)
    for ax in axes[:, 0]:
        ax.set_ylabel(impl.value_label, fontsize=7)
    for ax in axes.ravel()[len(names) :]:
        ax.set_axis_off()
    fig.suptitle(f"{descriptor} of library views at four azimuths", fontsize=9)
    _save(fig, path)


def plot_misclassified(
    predictions: pd.DataFrame,
    descriptors: pd.DataFrame,
    views: dict,
    path: str | Path,
    descriptor: str,
    *,
    count: int = 6,
) -> None:
    """Misclassified test views beside their nearest library view, and both descriptors.

    Parameters
    ----------
    predictions : DataFrame
        One descriptor's predictions at one library size.
    descriptors : DataFrame
        The descriptor rows (``view_id``, ``positions``, ``values``) of those views.
    views : dict from view id to View
        At least the misclassified test views and their nearest library views.
    """
    wrong = predictions[~predictions["correct"]].sort_values(["object", "azimuth"])
    wrong = pd.concat([wrong.groupby("object").head(1), wrong]).drop_duplicates("view_id").head(count)
    if wrong.empty:
        fig, ax = plt.subplots(figsize=(6, 1.5))
        ax.text(
            0.5,
            0.5,
            f"{descriptor}: every test view's nearest library view is its own object",
            ha="center",
            va="center",
            fontsize=9,
        )
        ax.set_axis_off()
        _save(fig, path)
        return
    curves = descriptors[descriptors["descriptor"] == descriptor].drop_duplicates("view_id").set_index("view_id")
    impl = kind_of(curves["kind"].iloc[0])
    fig, axes = plt.subplots(
        len(wrong), 3, figsize=(10, 2.6 * len(wrong)), squeeze=False, gridspec_kw={"width_ratios": [1, 1, 1.6]}
    )
    for (left, middle, right), (_, row) in zip(axes, wrong.iterrows(), strict=True):
        test, nearest = row["view_id"], row["predicted_view_id"]
        _draw_mesh(left, views[test], f"test: {row['object']} at {row['azimuth']:.1f} deg")
        _draw_mesh(middle, views[nearest], f"nearest: {row['predicted_object']} at {row['predicted_azimuth']:.0f} deg")
        for view_id, colour, label in ((test, "black", "test view"), (nearest, "tab:red", "nearest library view")):
            right.plot(curves.loc[view_id, "positions"], curves.loc[view_id, "values"], color=colour, lw=1, label=label)
        right.set_ylabel(impl.value_label, fontsize=7)
        right.set_title(f"distance {row['distance']:.4g} ({impl.distance_name})", fontsize=8)
        right.legend(fontsize=6)
        right.grid(alpha=0.3)
    axes[-1, 2].set_xlabel(POSITION_LABELS.get(curves["sampling"].iloc[0], POSITION_LABELS[None]), fontsize=7)
    fig.suptitle(
        f"{descriptor}: misclassified test views ({(~predictions['correct']).sum()} of {len(predictions)}; "
        f"{len(wrong)} shown, one per object first)",
        fontsize=9,
    )
    _save(fig, path)


def _draw_isomap(ax, descriptors: pd.DataFrame, descriptor: str, n_neighbors: int = 8) -> str:
    """Draw the 2D Isomap of ``descriptor``'s library views on ``ax``; returns the distance's name."""
    from sklearn.manifold import Isomap

    rows = descriptors[(descriptors["descriptor"] == descriptor) & (descriptors["split"] == "train")]
    rows = rows.sort_values(["object", "azimuth"])
    if len(rows) < 4:
        raise HeatdataError(f"Isomap needs at least 4 library views, got {len(rows)}")
    n_neighbors = min(n_neighbors, len(rows) - 2)
    values = np.stack(rows["values"].to_numpy())
    impl = kind_of(rows["kind"].iloc[0])
    distances = impl.distance_matrix(values, values)
    distances = np.minimum(distances, distances.T)  # exact symmetry for the neighbour graph
    embedding = Isomap(n_neighbors=n_neighbors, n_components=2, metric="precomputed").fit_transform(distances)
    objects = rows["object"].unique()
    ax.set_prop_cycle(color=(plt.cm.tab10 if len(objects) <= 10 else plt.cm.tab20).colors)
    for obj in objects:
        mask = (rows["object"] == obj).to_numpy()
        closed = np.vstack([embedding[mask], embedding[mask][:1]])  # azimuth wraps around
        ax.plot(closed[:, 0], closed[:, 1], "o-", ms=3, lw=0.8, label=obj)
    return impl.distance_name


def plot_isomap(descriptors: pd.DataFrame, descriptor: str, path: str | Path, n_neighbors: int = 8) -> None:
    """2D Isomap of the library descriptors under their kind's distance, neighbouring view angles joined (Fig. 2.11).

    ``descriptors`` needs the columns ``descriptor, kind, object, split, azimuth, values``.
    """
    fig, ax = plt.subplots(figsize=(7, 6))
    name = _draw_isomap(ax, descriptors, descriptor, n_neighbors)
    ax.set_title(
        f"Isomap ({name}) of {descriptor} library descriptors;\nlines join neighbouring view angles", fontsize=9
    )
    ax.legend(fontsize=6, ncol=2)
    _save(fig, path)


def plot_isomaps(
    descriptors: pd.DataFrame, names: list[str], objects: list[str], path: str | Path, n_neighbors: int = 8
) -> None:
    """Fig. 3.13: one 2D Isomap per descriptor of the library views of ``objects``, each under its own distance."""
    chosen = descriptors[descriptors["object"].isin(objects)]
    cols = min(4, len(names))
    rows = int(np.ceil(len(names) / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(3.6 * cols, 3.4 * rows), squeeze=False)
    for ax, name in zip(axes.ravel(), names, strict=False):
        distance_name = _draw_isomap(ax, chosen, name, n_neighbors)
        ax.set_title(f"{name}\n({distance_name})", fontsize=8)
        ax.tick_params(labelsize=6)
    for ax in axes.ravel()[len(names) :]:
        ax.set_axis_off()
    handles, labels = axes.ravel()[0].get_legend_handles_labels()
    spare = axes.ravel()[len(names) :]
    if len(spare):
        spare[0].legend(handles, labels, loc="center", fontsize=9, title="object")
    else:
        axes.ravel()[0].legend(fontsize=6)
    fig.suptitle(
        f"Library views of {len(objects)} objects, one Isomap per descriptor, neighbouring view angles "
        "joined (cf. thesis Fig. 3.13)",
        fontsize=9,
    )
    _save(fig, path)


def plot_confusion(predictions: pd.DataFrame, path: str | Path, title: str, level: str = "object") -> None:
    """Confusion matrix of objects (or of classes, ``level="class"``): rows true, columns predicted, with precision."""
    true, predicted = ("object", "predicted_object") if level == "object" else ("label", "predicted_label")
    names = sorted(set(predictions[true]) | set(predictions[predicted]) - {""})
    fig, ax = plt.subplots(figsize=(max(5.0, 1.6 + 0.55 * len(names)), max(4.5, 0.8 + 0.5 * len(names))))
    image = _draw_counts(ax, confusion_matrix(predictions[true], predictions[predicted], names).to_numpy(), names)
    ax.set_xlabel(f"predicted {level} (nearest library view)")
    ax.set_ylabel(f"true {level} ({level} precision)")
    hit = (predictions[true] == predictions[predicted]).mean()
    ax.set_title(f"{title}\n{level} precision {hit:.1%}; numbers: test views", fontsize=9)
    fig.colorbar(image, ax=ax, fraction=0.04, pad=0.02, format=PercentFormatter(100, decimals=0)).set_label(
        "share of the true row's test views", fontsize=8
    )
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
