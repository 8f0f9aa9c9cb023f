"""Figures a person would rather look at than read (thesis Fig. 2.3/2.4, 2.11, 3.5, 3.7, 5.7).

The object confusion matrix, the view-angle confusion of Fig. 3.5, precision against
library size, Isomaps of the library descriptors, and partial views coloured by
temperature with the source marked.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.ticker import PercentFormatter  # noqa: E402
import pandas as pd  # noqa: E402

from .descriptors import kind_of  # noqa: E402
from .errors import HeatdataError  # noqa: E402
from .recognition import confusion_matrix  # noqa: E402

MAX_LEGEND_OBJECTS = 20  # the per-object precision panel names at most this many objects
RENDERED_NOTE = "Views are rendered from 3D models with simulated Kinect noise, not real sensor data."
PROXY_NOTE = ("Bodies are MakeHuman models rendered with simulated Kinect noise: a proxy for goats' rumps, not goats, "
              "not real sensor data.")


def plot_precision(precision: pd.DataFrame, path: str | Path, primary: str | None = None) -> None:
    """Object precision (%) against library size: every test view per descriptor, and per object (Fig. 3.7, 5.13).

    The per-object panel shows ``primary`` (default: the descriptor with the best precision).
    """
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.5))
    overall = precision[(precision["group"] == "all") & (precision["level"] == "object")]
    sizes = sorted(overall["library_size"].unique())
    for name, rows in overall.groupby("descriptor"):
        rows = rows.sort_values("library_size")
        left.plot(rows["library_size"], 100 * rows["precision"], "o-", label=name)
    left.set_ylabel("object precision, all test views (%)")
    left.legend(fontsize=7)
    primary = primary or overall.sort_values("precision").iloc[-1]["descriptor"]
    objects = precision[(precision["level"] == "object") & (precision["group"] != "all")
                        & (precision["descriptor"] == primary)]
    right.set_prop_cycle(color=plt.cm.tab20.colors)
    count = objects["group"].nunique()
    many = count > MAX_LEGEND_OBJECTS  # then grey lines and their median, no legend of names
    for name, rows in objects.groupby("group"):
        rows = rows.sort_values("library_size")
        style = {"color": "grey", "alpha": 0.35, "lw": 0.8} if many else {"label": name}
        right.plot(rows["library_size"], 100 * rows["precision"], ".-", **style)
    if many:
        median = objects.groupby("library_size")["precision"].median()
        right.plot(median.index, 100 * median, "o-", color="black", lw=2,
                   label=f"median of {count} objects (grey: each)")
    right.set_ylabel(f"object precision per object (%)\n{primary}", fontsize=9)
    right.legend(fontsize=6 if not many else 8, ncol=1 if many else 2)
    for ax in (left, right):
        ax.set_xticks(sizes, [str(s) for s in sizes])
        ax.set_xlabel("library views per object")
        ax.yaxis.set_major_formatter(PercentFormatter(100, decimals=0))
        ax.grid(alpha=0.3)
    _save(fig, path)


POSITION_LABELS = {"polar": "polar angle / 2 pi (counter-clockwise from +x in the image)",
                   "arclength": "arc length from the boundary origin / boundary length",
                   None: "bin / number of bins"}


def plot_descriptor_curves(descriptors: pd.DataFrame, descriptor: str, path: str | Path, *, objects: int = 8,
                           azimuths: tuple = (0.0, 90.0, 180.0, 270.0)) -> None:
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
    for ax in axes.ravel()[len(names):]:
        ax.set_axis_off()
    fig.suptitle(f"{descriptor} of library views at four azimuths", fontsize=9)
    _save(fig, path)


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


def plot_misclassified(predictions: pd.DataFrame, descriptors: pd.DataFrame, views: dict, path: str | Path,
                       descriptor: str, *, count: int = 6) -> None:
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
        ax.text(0.5, 0.5, f"{descriptor}: every test view's nearest library view is its own object",
                ha="center", va="center", fontsize=9)
        ax.set_axis_off()
        _save(fig, path)
        return
    curves = descriptors[descriptors["descriptor"] == descriptor].drop_duplicates("view_id").set_index("view_id")
    impl = kind_of(curves["kind"].iloc[0])
    fig, axes = plt.subplots(len(wrong), 3, figsize=(10, 2.6 * len(wrong)), squeeze=False,
                             gridspec_kw={"width_ratios": [1, 1, 1.6]})
    for (left, middle, right), (_, row) in zip(axes, wrong.iterrows(), strict=True):
        test, nearest = row["view_id"], row["predicted_view_id"]
        _draw_mesh(left, views[test], f"test: {row['object']} at {row['azimuth']:.1f} deg")
        _draw_mesh(middle, views[nearest], f"nearest: {row['predicted_object']} at {row['predicted_azimuth']:.0f} deg")
        for view_id, colour, label in ((test, "black", "test view"), (nearest, "tab:red", "nearest library view")):
            right.plot(curves.loc[view_id, "positions"], curves.loc[view_id, "values"], color=colour, lw=1,
                       label=label)
        right.set_ylabel(impl.value_label, fontsize=7)
        right.set_title(f"distance {row['distance']:.4g} ({impl.distance_name})", fontsize=8)
        right.legend(fontsize=6)
        right.grid(alpha=0.3)
    axes[-1, 2].set_xlabel(POSITION_LABELS.get(curves["sampling"].iloc[0], POSITION_LABELS[None]), fontsize=7)
    fig.suptitle(f"{descriptor}: misclassified test views ({(~predictions['correct']).sum()} of {len(predictions)}; "
                 f"{len(wrong)} shown, one per object first)", fontsize=9)
    _save(fig, path)


def plot_multiview(summary: pd.DataFrame, path: str | Path, title: str) -> None:
    """Thesis Fig. 4.8, 4.10: accuracy, identification, degrees travelled and comparisons against particles.

    ``summary`` is :func:`heatdata.multiview.trial_summary`; one line per library size,
    bootstrap and policy, and a black reference line for the exhaustive filter's rows.
    """
    fig, (acc, ident, deg, comp) = plt.subplots(1, 4, figsize=(18, 4.2))
    styles = {size: style for size, style in zip(sorted(summary["library_views"].unique()), ["-", "--", ":", "-."])}
    colours = {("similarity", "fixed"): "tab:blue", ("angular", "fixed"): "tab:orange",
               ("similarity", "active"): "tab:green", ("angular", "active"): "tab:red"}
    exact = summary[summary["bootstrap"] == "exhaustive"]
    summary = summary[summary["bootstrap"] != "exhaustive"]
    for row in exact.itertuples():  # the exact filter has no particle count: a reference line
        style = dict(color="black", ls=styles[row.library_views], lw=1)
        acc.axhline(100 * row.accuracy, **style, label=f"exhaustive filter ({row.particles} hypotheses), "
                                                       f"{row.library_views} library views")
        ident.axhline(100 * row.identified, **style)
        deg.axhline(row.degrees, **style)
    for (size, boot, policy), rows in summary.groupby(["library_views", "bootstrap", "policy"]):
        rows = rows.sort_values("particles")
        label = f"{boot} bootstrap, {policy} steps, {size} library views"
        style = dict(color=colours[(boot, policy)], ls=styles[size], marker="o", ms=3, label=label)
        acc.plot(rows["particles"], 100 * rows["accuracy"], **style)
        ident.plot(rows["particles"], 100 * rows["identified"], **style)
        deg.plot(rows["particles"], rows["degrees"], **style)
        comp.plot(rows["particles"], rows["comparisons"], **style)
        if boot == "similarity" and policy == "fixed":
            comp.plot(rows["particles"], rows["exhaustive"], color="grey", ls=styles[size], lw=1,
                      label=f"exhaustive search, {size} library views")
    acc.set_ylabel("accuracy: converged on the true object (%)")
    ident.set_ylabel("identified: true object most probable at the end (%)")
    for ax in (acc, ident):
        ax.yaxis.set_major_formatter(PercentFormatter(100, decimals=0))
    deg.set_ylabel("degrees travelled (mean)")
    comp.set_ylabel("view comparisons (particles x stops, mean)")
    for ax in (acc, ident, deg, comp):
        ax.set_xscale("log")
        ticks = sorted(summary["particles"].unique())
        ax.set_xticks(ticks, [str(t) for t in ticks])
        ax.set_xlabel("particles")
        ax.grid(alpha=0.3)
    acc.legend(fontsize=6)
    comp.legend(fontsize=6)
    fig.suptitle(title, fontsize=9)
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
    ax.set_title(f"Isomap ({name}) of {descriptor} library descriptors;\n"
                 "lines join neighbouring view angles", fontsize=9)
    ax.legend(fontsize=6, ncol=2)
    _save(fig, path)


def plot_isomaps(descriptors: pd.DataFrame, names: list[str], objects: list[str], path: str | Path,
                 n_neighbors: int = 8) -> None:
    """Fig. 3.13: one 2D Isomap per descriptor of the library views of ``objects``, each under its own distance."""
    chosen = descriptors[descriptors["object"].isin(objects)]
    cols = min(4, len(names))
    rows = int(np.ceil(len(names) / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(3.6 * cols, 3.4 * rows), squeeze=False)
    for ax, name in zip(axes.ravel(), names, strict=False):
        distance_name = _draw_isomap(ax, chosen, name, n_neighbors)
        ax.set_title(f"{name}\n({distance_name})", fontsize=8)
        ax.tick_params(labelsize=6)
    for ax in axes.ravel()[len(names):]:
        ax.set_axis_off()
    handles, labels = axes.ravel()[0].get_legend_handles_labels()
    spare = axes.ravel()[len(names):]
    if len(spare):
        spare[0].legend(handles, labels, loc="center", fontsize=9, title="object")
    else:
        axes.ravel()[0].legend(fontsize=6)
    fig.suptitle(f"Library views of {len(objects)} objects, one Isomap per descriptor, neighbouring view angles "
                 "joined (cf. thesis Fig. 3.13)", fontsize=9)
    _save(fig, path)


def plot_holes(summary: pd.DataFrame, path: str | Path) -> None:
    """Fig. 3.14-3.15: holed boxes recognized among solid boxes, and how far holes move each descriptor."""
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 0.9 + 0.42 * len(summary)))
    y = np.arange(len(summary))
    left.barh(y, 100 * summary["precision"], color="tab:blue")
    left.set_yticks(y, summary["descriptor"], fontsize=8)
    left.set_xlim(0, 100)
    left.set_xlabel("holed-box views whose nearest solid view is their own box (%)")
    right.barh(y, summary["median_ratio"], color="tab:orange")
    right.axvline(1.0, color="0.3", lw=0.8, ls="--")
    right.set_xscale("log")
    right.set_yticks(y, [])
    right.set_xlabel("median d(solid, holed) / d(solid, next view angle)")
    for ax in (left, right):
        ax.invert_yaxis()
        ax.grid(axis="x", alpha=0.3)
    fig.suptitle("Boxes with a round hole cut in every face, against the same boxes solid (cf. thesis Fig. 3.15)",
                 fontsize=9)
    _save(fig, path, note="Views are rendered from 3D models without sensor noise, not real sensor data.")


def _save(fig, path: str | Path, note: str = RENDERED_NOTE) -> None:
    """Sign the figure as rendered data, save it and free it."""
    fig.text(0.01, 0.005, note, fontsize=6, color="grey")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


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
        "share of the true row's test views", fontsize=8)
    _save(fig, path)


def _draw_counts(ax, counts: np.ndarray, names: list[str]):
    """A confusion matrix of ``counts`` (true rows, predicted columns) shaded by row share, each true row's
    precision in its label; returns the image (for a colour bar)."""
    fraction = counts / np.maximum(counts.sum(axis=1, keepdims=True), 1)
    image = ax.imshow(100 * fraction, cmap="Blues", vmin=0, vmax=100)
    for (i, j), n in np.ndenumerate(counts):
        if n:
            ax.text(j, i, str(n), ha="center", va="center", fontsize=7,
                    color="white" if fraction[i, j] > 0.5 else "black")
    ax.set_xticks(range(len(names)), names, rotation=60, ha="right", fontsize=8)
    ax.set_yticks(range(len(names)), [f"{o} ({a:.0%})" for o, a in zip(names, np.diag(fraction), strict=True)],
                  fontsize=8)
    return image


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


TEMPERATURE_LABEL = "temperature (equilibrium = 1)"
DERIVATIVE_LABEL = "global derivative (eq. 5.12), 1/m^2"
DERIVATIVE_HEADING = ("Source-position global derivative (eq. 5.12) at t_global = 1/lambda_2: large where a source "
                      "would heat a loosely connected part (Fig. 5.7); star: the source")


def plot_views(views: list, values: list, sources: list, path: str | Path, titles: list[str], *, heading: str,
               colorbar_label: str = TEMPERATURE_LABEL, cmap: str = "inferno") -> None:
    """Partial views coloured by per-vertex ``values`` (e.g. temperature at t_s), source and boundary marked."""
    if not views:
        raise HeatdataError("no views to draw")
    cols = min(4, len(views))
    rows = int(np.ceil(len(views) / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 3.2 * rows), squeeze=False)
    for ax, view, value, source, title in zip(axes.ravel(), views, values, sources, titles, strict=False):
        p = view.pixels
        collection = ax.tripcolor(p[:, 0], p[:, 1], view.faces, value, shading="gouraud", cmap=cmap)
        b = np.append(view.boundary, view.boundary[0])
        ax.plot(p[b, 0], p[b, 1], color="cyan", lw=0.8)
        ax.plot(*p[view.boundary[0]], "o", color="cyan", ms=4)
        ax.plot(*p[source], "*", color="lime", ms=12, mec="black")
        ax.set_aspect("equal")
        ax.invert_yaxis()
        ax.set_axis_off()
        ax.set_title(title, fontsize=8)
        fig.colorbar(collection, ax=ax, fraction=0.04, pad=0.02).set_label(colorbar_label, fontsize=7)
    for ax in axes.ravel()[len(views):]:
        ax.set_axis_off()
    fig.suptitle(f"{heading}\n{RENDERED_NOTE}", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def draw_example_views(catalog: pd.DataFrame, path: str | Path, *, elevation: float = 30.0, distance: float = 1.0,
                       noise: bool = True, seed: int = 0, count: int = 8, image_scale: float = 1.0,
                       source: str = "closest", derivative_path: str | Path | None = None) -> None:
    """Render up to ``count`` catalogue objects at azimuth 30 deg and draw the temperature of a PVHK.

    ``source`` is the PVHK's source rule (the report passes its primary descriptor's). With
    ``derivative_path``, also draw the global derivative of the same views (Fig. 5.7) on the
    component holding the source.
    """
    from .catalog import load_catalog_model
    from .descriptors import global_derivative, heat_kernel, pvhk
    from .render import render_view
    from .view import kinect_intrinsics

    views, temps, sources, titles, components, derivatives, local_sources = [], [], [], [], [], [], []
    for _, row in catalog.head(count).iterrows():
        view = render_view(load_catalog_model(row), 30.0, elevation, distance, noise=noise, seed=seed,
                           intrinsics=kinect_intrinsics(image_scale))
        d = pvhk(view, 64, source)
        views.append(view)
        temps.append(heat_kernel(view, d.source, [d.time])[0])
        sources.append(d.source)
        titles.append(f"{row['object']} ({view.n_vertices} vertices)")
        if derivative_path is not None:
            component, local = view.component_of(d.source)
            components.append(component)
            local_sources.append(local)
            derivatives.append(global_derivative(component, local))
    plot_views(views, temps, sources, path, titles,
               heading=f"Temperature at t_s = 1/lambda_2 after a pulse at the {source!r} source (star); "
                       "dot: boundary origin")
    if derivative_path is not None:
        plot_views(components, derivatives, local_sources, derivative_path, titles, heading=DERIVATIVE_HEADING,
                   colorbar_label=DERIVATIVE_LABEL, cmap="viridis")


def _draw_faces_3d(ax, vertices: np.ndarray, faces: np.ndarray, colors: np.ndarray, max_faces: int = 6000) -> None:
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    step = max(1, len(faces) // max_faces)
    shown = faces[::step]
    ax.add_collection3d(Poly3DCollection(vertices[shown], facecolors=colors[::step], edgecolors="none"))


def plot_stitch(first, second, stitched, strip_faces: int, path: str | Path, title: str) -> None:
    """JASNOM before and after (thesis Fig. 7.9): the two meshes as given, and the stitched model with its strip.

    ``first``, ``second`` and ``stitched`` are :class:`heatdata.models.Model`; the last
    ``strip_faces`` faces of ``stitched`` are the strip (drawn in red). Faces are shaded by
    their orientation to a light; at most 6,000 are drawn per mesh.
    """
    fig = plt.figure(figsize=(12, 5.5))
    light = np.array([0.3, 0.8, 0.5]) / np.linalg.norm([0.3, 0.8, 0.5])
    panels = [("before: the two meshes as given", [(first, "tab:blue"), (second, "tab:orange")]),
              ("after: aligned and stitched (the strip in red, drawn over the mesh)", [(stitched, None)])]
    for k, (label, meshes) in enumerate(panels):
        ax = fig.add_subplot(1, 2, k + 1, projection="3d")
        points = np.vstack([m.vertices for m, _ in meshes])
        for model, colour in meshes:
            corners = model.vertices[model.faces]
            normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
            shade = 0.35 + 0.65 * np.abs(normal @ light) / np.maximum(np.linalg.norm(normal, axis=1), 1e-30)
            base = np.tile(matplotlib.colors.to_rgb(colour or "tab:blue"), (len(model.faces), 1))
            if colour is None:
                base[:len(model.faces) - strip_faces] = matplotlib.colors.to_rgb("tab:grey")
                base[len(model.faces) - strip_faces:] = matplotlib.colors.to_rgb("tab:red")
            rgba = np.column_stack([base * shade[:, None], np.ones(len(base))])
            _draw_faces_3d(ax, model.vertices, model.faces, rgba)
            if colour is None and strip_faces:  # the strip's triangles are thin: draw their edges over the mesh
                from mpl_toolkits.mplot3d.art3d import Line3DCollection

                strip = model.vertices[model.faces[len(model.faces) - strip_faces:]]
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


def plot_rumps(heats: list, weights: np.ndarray, embedding: np.ndarray, thin: np.ndarray, path: str | Path,
               title: str, note: str = RENDERED_NOTE) -> None:
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
        image = ax.tripcolor(x, y, heat.faces, heat.difference[0], cmap="magma", shading="gouraud",
                             vmin=0.0, vmax=max(float(heat.difference[0].max()), 1e-12))
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


def plot_pose_isomap(embeddings: list[tuple], examples: list[tuple], path: str | Path, title: str) -> None:
    """Fig. 3.11: 2D Isomaps of people's descriptors coloured by pose, and example views.

    Parameters
    ----------
    embeddings : list of (embedding (N, 2), groups (N,), title)
        One panel each, e.g. one body's pose sequence and Reallusion's posed people.
    examples : list of (View, title)
        Views drawn beside them (e.g. two frames of each group).
    """
    if not embeddings:
        raise HeatdataError("no Isomap to draw")
    fig = plt.figure(figsize=(4.6 * len(embeddings) + 1.7 * len(examples), 4.6))
    grid = fig.add_gridspec(1, 2 * len(embeddings) + len(examples), width_ratios=[2.7] * (2 * len(embeddings))
                            + [2.0] * len(examples))
    for k, (embedding, groups, heading) in enumerate(embeddings):
        ax = fig.add_subplot(grid[0, 2 * k:2 * k + 2])
        groups = np.asarray(groups)
        for colour, group in zip(plt.get_cmap("tab10").colors, dict.fromkeys(groups), strict=False):
            chosen = groups == group
            ax.scatter(*embedding[chosen].T, s=22, color=colour, label=f"{group} ({chosen.sum()})",
                       edgecolors="black", linewidths=0.3)
        ax.legend(fontsize=7)
        ax.set_title(heading, fontsize=8)
        ax.set_xlabel("Isomap 1", fontsize=7)
        ax.set_ylabel("Isomap 2", fontsize=7)
    for k, (view, heading) in enumerate(examples):
        _draw_mesh(fig.add_subplot(grid[0, 2 * len(embeddings) + k]), view, heading)
    fig.suptitle(title, fontsize=9)
    _save(fig, path)


def plot_twins(predictions: pd.DataFrame, examples: dict, path: str | Path, title: str) -> None:
    """Fig. 3.12: for each twin pair, its people's views and one person confusion matrix per descriptor.

    Parameters
    ----------
    predictions : pandas.DataFrame
        ``pair, descriptor, person, predicted`` per test view
        (:func:`heatdata.people.twin_predictions` with a ``pair`` column).
    examples : dict
        Pair -> list of (View, title): a view of each of its people.
    """
    pairs = list(dict.fromkeys(predictions["pair"]))
    names = list(dict.fromkeys(predictions["descriptor"]))
    shown = max(len(examples.get(pair, [])) for pair in pairs)
    fig, axes = plt.subplots(len(pairs), shown + len(names), figsize=(2.0 * shown + 3.3 * len(names),
                                                                       3.4 * len(pairs)), squeeze=False)
    for row, pair in enumerate(pairs):
        for k, ax in enumerate(axes[row, :shown]):
            if k < len(examples.get(pair, [])):
                _draw_mesh(ax, *examples[pair][k])
            else:
                ax.set_axis_off()
        for ax, name in zip(axes[row, shown:], names, strict=True):
            rows = predictions[(predictions["pair"] == pair) & (predictions["descriptor"] == name)]
            people = list(dict.fromkeys(rows["person"]))
            _draw_counts(ax, confusion_matrix(rows["person"], rows["predicted"], people).to_numpy(), people)
            ax.set_title(f"{pair}:\n{name}\nprecision {rows['correct'].mean():.0%} of {len(rows)} test views",
                         fontsize=8)
            ax.set_xlabel("predicted (nearest library view)", fontsize=7)
    fig.suptitle(title, fontsize=9)
    _save(fig, path)
