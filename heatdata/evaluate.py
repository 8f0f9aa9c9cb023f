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
from .distance import SHORTLIST, mhd_matrix  # noqa: E402
from .recognition import classify_candidates, confusion_matrix, nearest_neighbours  # noqa: E402

log = logging.getLogger(__name__)

RENDERED_NOTE = "Views are rendered from 3D models with simulated Kinect noise, not real sensor data."


def classify(descriptors: pd.DataFrame, descriptor: str, *, library: str = "train", queries: str = "test"
             ) -> pd.DataFrame:
    """Nearest-neighbour class of each query view among the library views (eq. 3.1, Alg. 5.2).

    An ``ft-pvhk`` descriptor is compared object by object (Alg. 5.2): the query's row at
    object o's time scale (``time_object``) against o's library views, with the weighted
    distance of eq. 5.14; the nearest view over all objects wins.

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
        One row per query view, columns of :data:`heatdata.tables.PREDICTION_SCHEMA`.
    """
    rows = descriptors[descriptors["descriptor"] == descriptor]
    lib, query = rows[rows["split"] == library], rows[rows["split"] == queries]
    if lib.empty or query.empty:
        raise HeatdataError(f"descriptor {descriptor!r}: no {library!r} or no {queries!r} rows to compare")
    lengths = {len(v) for v in rows["values"]}
    if len(lengths) > 1:
        raise HeatdataError(f"descriptor {descriptor!r}: descriptors of different lengths {sorted(lengths)}")
    lib, query, unusable = _usable(lib, query, descriptor)
    if (rows["kind"] == "ft-pvhk").all():
        query, index, distance = _fixed_time_neighbours(query, lib, descriptor)
    else:
        nn = nearest_neighbours(np.stack(query["values"].to_numpy()), np.stack(lib["values"].to_numpy()))
        index, distance = nn.index, nn.distance
    match = lib.iloc[index]
    predictions = pd.DataFrame({
        "descriptor": descriptor,
        "object": query["object"].to_numpy(), "label": query["label"].to_numpy(),
        "view_id": query["view_id"].to_numpy(), "azimuth": query["azimuth"].to_numpy(),
        "predicted_object": match["object"].to_numpy(), "predicted_label": match["label"].to_numpy(),
        "predicted_view_id": match["view_id"].to_numpy(), "predicted_azimuth": match["azimuth"].to_numpy(),
        "distance": distance, "correct": query["object"].to_numpy() == match["object"].to_numpy(),
        "library_size": int(lib.groupby("object").size().max()),
    })
    if not unusable.empty:  # no prediction: counted as wrong
        failed = unusable.drop_duplicates("view_id")
        predictions = pd.concat([predictions, pd.DataFrame({
            "descriptor": descriptor, "object": failed["object"].to_numpy(), "label": failed["label"].to_numpy(),
            "view_id": failed["view_id"].to_numpy(), "azimuth": failed["azimuth"].to_numpy(),
            "predicted_object": "", "predicted_label": "", "predicted_view_id": "", "predicted_azimuth": np.nan,
            "distance": np.nan, "correct": False, "library_size": predictions["library_size"].iloc[0]})],
            ignore_index=True)
    return predictions


def _usable(lib: pd.DataFrame, query: pd.DataFrame, descriptor: str
            ) -> tuple[pd.DataFrame, pd.DataFrame, pd.DataFrame]:
    """Library and query rows without NaN values, and the query rows with some (logged).

    A PVST sample that never reaches its threshold, or a descriptor that failed on a view,
    is NaN. Such library views are left out; such test views get no prediction.
    """
    def bad_views(rows):
        return set(rows.loc[~rows["values"].map(lambda v: bool(np.isfinite(v).all())), "view_id"])

    bad_lib, bad_query = bad_views(lib), bad_views(query)
    if bad_lib or bad_query:
        log.warning("%s: %d library and %d test views have NaN values (see their repairs); the library views "
                    "are left out and the test views count as wrong", descriptor, len(bad_lib), len(bad_query))
    unusable = query["view_id"].isin(bad_query)
    return lib[~lib["view_id"].isin(bad_lib)], query[~unusable], query[unusable]


def _stack(column: pd.Series) -> np.ndarray | None:
    """(rows, M) array of a list column; None if any row is null (no part weights)."""
    if column.isna().any():
        return None
    return np.stack(column.to_numpy())


def _fixed_time_neighbours(query: pd.DataFrame, lib: pd.DataFrame, descriptor: str
                           ) -> tuple[pd.DataFrame, np.ndarray, np.ndarray]:
    """Alg. 5.2: per query view, the nearest library view over objects, each at its own time scale.

    Returns the query views (one row each), the positional index of each one's nearest
    library row in ``lib``, and the weighted distance (eq. 5.14).
    """
    views = query.drop_duplicates("view_id")
    best = np.full(len(views), np.inf)
    index = np.zeros(len(views), dtype=np.int64)
    for obj, positions in lib.groupby("object").indices.items():
        at_time = query[query["time_object"] == obj].set_index("view_id").reindex(views["view_id"])
        if at_time["values"].isna().any():
            missing = at_time.index[at_time["values"].isna()][0]
            raise HeatdataError(f"descriptor {descriptor!r}: test view {missing} has no row at the time scale "
                                f"of object {obj!r} (time_object); describe test views with every object's")
        candidates = lib.iloc[positions]
        q_weights, l_weights = _stack(at_time["weights"]), _stack(candidates["weights"])
        if (q_weights is None) != (l_weights is None):
            raise HeatdataError(f"descriptor {descriptor!r}: part weights on the test or the library rows only")
        d = mhd_matrix(np.stack(at_time["values"].to_numpy()), np.stack(candidates["values"].to_numpy()),
                       query_weights=q_weights, library_weights=l_weights)
        nearest = np.argmin(d, axis=1)
        distance = d[np.arange(len(views)), nearest]
        closer = distance < best
        best[closer] = distance[closer]
        index[closer] = positions[nearest[closer]]
    return views, index, best


def library_subset(descriptors: pd.DataFrame, size: int, split: str = "train") -> pd.DataFrame:
    """The ``size`` library views per object evenly spaced in azimuth among the ``split`` views (3.4.1).

    Raises
    ------
    HeatdataError
        An object has fewer library views than ``size``.
    """
    library = descriptors[descriptors["split"] == split]
    chosen = []
    for obj, views in library.groupby("object")["azimuth"]:
        angles = np.sort(views.unique())
        if size > len(angles):
            raise HeatdataError(f"library size {size} is larger than the {len(angles)} {split} views of {obj!r}")
        keep = angles[np.floor(np.arange(size) * len(angles) / size).astype(int)]
        chosen.append(library[(library["object"] == obj) & library["azimuth"].isin(keep)])
    return pd.concat(chosen)


def evaluate_library_sizes(descriptors: pd.DataFrame, descriptor: str, sizes: list[int]) -> pd.DataFrame:
    """Nearest-neighbour predictions of the test views for libraries of several sizes.

    Returns the rows of :func:`classify` with a ``library_size`` column.
    """
    rows = descriptors[descriptors["descriptor"] == descriptor]
    tests = rows[rows["split"] == "test"]
    results = []
    for size in sizes:
        subset = pd.concat([library_subset(rows, size), tests])
        results.append(classify(subset, descriptor).assign(library_size=size))
    return pd.concat(results, ignore_index=True)


def evaluate_compact(candidates: pd.DataFrame, libraries: pd.DataFrame, *, shortlist: int | None = SHORTLIST
                     ) -> pd.DataFrame:
    """Alg. 6.1: each test view, described from its candidate sources, against each library.

    Parameters
    ----------
    candidates : pandas.DataFrame
        Test (``split = "test"``) ``candidates`` rows of :func:`heatdata.dataset.candidate_rows`.
    libraries : pandas.DataFrame
        :func:`heatdata.library.compact_libraries`.

    Returns
    -------
    pandas.DataFrame
        Rows of :data:`heatdata.tables.PREDICTION_SCHEMA`, one per library
        (``descriptor`` = method, ``library_size``) and test view, ready for
        :func:`precision_table`. A test view that could not be described counts as
        wrong (``predicted_object`` empty).
    """
    tests = candidates[(candidates["split"] == "test") & (candidates["source_rule"] == "candidates")]
    per_view = []
    for _, rows in tests.groupby("view_id", sort=False):
        values = np.stack(rows["values"].to_numpy())
        usable = np.all(np.isfinite(values), axis=1)
        first = rows.iloc[0]
        per_view.append((first, values[usable]))
    failed = sum(len(v) == 0 for _, v in per_view)
    if failed:
        log.warning("%d test views have no usable candidate descriptor and count as wrong", failed)
    out = []
    for (method, size), lib in libraries.groupby(["descriptor", "library_size"], sort=False):
        lib_values = np.stack(lib["values"].to_numpy())
        objects = lib["object"].to_numpy()
        for first, values in per_view:
            row = {"descriptor": method, "library_size": int(size), "object": first["object"],
                   "label": first["label"], "view_id": first["view_id"], "azimuth": first["azimuth"]}
            if len(values) == 0:
                out.append({**row, "predicted_object": "", "predicted_label": "", "predicted_view_id": "",
                            "predicted_azimuth": np.nan, "distance": np.nan, "correct": False})
                continue
            _, _, item, distance = classify_candidates(values, lib_values, objects, shortlist=shortlist)
            match = lib.iloc[item]
            out.append({**row, "predicted_object": match["object"], "predicted_label": match["label"],
                        "predicted_view_id": match["view_id"], "predicted_azimuth": match["azimuth"],
                        "distance": distance, "correct": match["object"] == first["object"]})
        log.info("%s, %d views: %d test views classified", method, size, len(per_view))
    return pd.DataFrame(out)


def precision_table(predictions: pd.DataFrame) -> pd.DataFrame:
    """Precision per descriptor, library size and object, and per class (Fig. 3.7, 3.8, 5.13).

    Object precision: the fraction of an object's test views whose nearest library view
    is of that object. Class precision: the fraction whose nearest view has its class.
    Rows with ``group = "all"`` aggregate every test view.
    """
    frames = []
    keys = ["descriptor", "library_size"]
    for level, column, truth in (("object", "object", "predicted_object"), ("class", "label", "predicted_label")):
        hit = predictions[column] == predictions[truth]
        per = hit.groupby([predictions[k] for k in keys] + [predictions[column]]).mean().rename("precision")
        per = per.reset_index().rename(columns={column: "group"})
        overall = hit.groupby([predictions[k] for k in keys]).mean().rename("precision").reset_index()
        frames += [per.assign(level=level), overall.assign(group="all", level=level)]
    return pd.concat(frames, ignore_index=True)[["level", "group", "descriptor", "library_size", "precision"]]


def plot_precision(precision: pd.DataFrame, path: str | Path) -> None:
    """Precision against library size: all views per descriptor, and per object (Fig. 3.7, 5.13)."""
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.5))
    overall = precision[(precision["group"] == "all") & (precision["level"] == "object")]
    for name, rows in overall.groupby("descriptor"):
        rows = rows.sort_values("library_size")
        left.plot(rows["library_size"], rows["precision"], "o-", label=name)
    left.set_xlabel("library views per object")
    left.set_ylabel("precision (all test views)")
    left.legend(fontsize=7)
    left.grid(alpha=0.3)
    best = overall.sort_values("precision").iloc[-1]["descriptor"]
    objects = precision[(precision["level"] == "object") & (precision["group"] != "all")
                        & (precision["descriptor"] == best)]
    right.set_prop_cycle(color=plt.cm.tab20.colors)
    for name, rows in objects.groupby("group"):
        rows = rows.sort_values("library_size")
        right.plot(rows["library_size"], rows["precision"], ".-", label=name)
    right.set_xlabel("library views per object")
    right.set_ylabel(f"precision per object ({best})")
    right.legend(fontsize=6, ncol=2)
    right.grid(alpha=0.3)
    _save(fig, path)


def plot_isomap(descriptors: pd.DataFrame, descriptor: str, path: str | Path, n_neighbors: int = 8) -> None:
    """2D Isomap of the library descriptors under eq. 3.1, neighbouring view angles joined (Fig. 2.11)."""
    from sklearn.manifold import Isomap

    rows = descriptors[(descriptors["descriptor"] == descriptor) & (descriptors["split"] == "train")]
    rows = rows.sort_values(["object", "azimuth"])
    if len(rows) < 4:
        raise HeatdataError(f"Isomap needs at least 4 library views, got {len(rows)}")
    n_neighbors = min(n_neighbors, len(rows) - 2)
    values = np.stack(rows["values"].to_numpy())
    distances = mhd_matrix(values, values)
    distances = np.minimum(distances, distances.T)  # exact symmetry for the neighbour graph
    embedding = Isomap(n_neighbors=n_neighbors, n_components=2, metric="precomputed").fit_transform(distances)
    fig, ax = plt.subplots(figsize=(7, 6))
    ax.set_prop_cycle(color=plt.cm.tab20.colors)
    for obj in rows["object"].unique():
        mask = (rows["object"] == obj).to_numpy()
        closed = np.vstack([embedding[mask], embedding[mask][:1]])  # azimuth wraps around
        ax.plot(closed[:, 0], closed[:, 1], "o-", ms=3, lw=0.8, label=obj)
    ax.set_title(f"Isomap (modified Hausdorff distance) of {descriptor} library descriptors;\n"
                 "lines join neighbouring view angles", fontsize=9)
    ax.legend(fontsize=6, ncol=2)
    _save(fig, path)


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
    counts = confusion_matrix(predictions["object"], predictions["predicted_object"], objects).to_numpy()
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


TEMPERATURE_HEADING = "Temperature at t_s = 1/lambda_2 (equilibrium = 1); star: source, dot: boundary origin"
DERIVATIVE_HEADING = ("Source-position global derivative (eq. 5.12) at t_global = 1/lambda_2: large where a source "
                      "would heat a loosely connected part (Fig. 5.7); star: the PVHK source")


def plot_views(views: list, values: list, sources: list, path: str | Path, titles: list[str], *,
               heading: str = TEMPERATURE_HEADING, cmap: str = "inferno") -> None:
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
        fig.colorbar(collection, ax=ax, fraction=0.04, pad=0.02)
    for ax in axes.ravel()[len(views):]:
        ax.set_axis_off()
    fig.suptitle(f"{heading}\n{RENDERED_NOTE}", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def draw_example_views(catalog: pd.DataFrame, path: str | Path, *, elevation: float = 30.0, distance: float = 1.0,
                       noise: bool = True, seed: int = 0, count: int = 8, image_scale: float = 1.0,
                       derivative_path: str | Path | None = None) -> None:
    """Render up to ``count`` catalogue objects at azimuth 30 deg and draw their PVHK temperatures.

    With ``derivative_path``, also draw the global derivative of the same views (Fig. 5.7)
    on the component holding the source.
    """
    from .catalog import load_catalog_model
    from .descriptors import global_derivative, heat_kernel, pvhk
    from .render import render_view
    from .view import kinect_intrinsics

    views, temps, sources, titles, components, derivatives, local_sources = [], [], [], [], [], [], []
    for _, row in catalog.head(count).iterrows():
        view = render_view(load_catalog_model(row), 30.0, elevation, distance, noise=noise, seed=seed,
                           intrinsics=kinect_intrinsics(image_scale))
        d = pvhk(view, 64, "closest")
        views.append(view)
        temps.append(heat_kernel(view, d.source, [d.time])[0])
        sources.append(d.source)
        titles.append(f"{row['object']} ({view.n_vertices} vertices)")
        if derivative_path is not None:
            component, local = view.component_of(d.source)
            components.append(component)
            local_sources.append(local)
            derivatives.append(global_derivative(component, local))
    plot_views(views, temps, sources, path, titles)
    if derivative_path is not None:
        plot_views(components, derivatives, local_sources, derivative_path, titles, heading=DERIVATIVE_HEADING,
                   cmap="viridis")


def draw_report(descriptors_path, predictions_path, precision_path, catalog_path, output, *, primary: str,
                config: dict) -> None:
    """Workflow step: the report's figures and summary.

    ``output`` has ``precision, confusion, isomap, views, global_derivative, summary``. The
    confusion folder holds one object confusion matrix per descriptor and library size.
    """
    import yaml

    from . import __version__
    from .catalog import read_catalog
    from .tables import read_table

    counts, _ = read_table(descriptors_path, columns=["object", "view_id", "n_vertices"])
    predictions, _ = read_table(predictions_path)
    precision = pd.read_csv(precision_path)
    plot_precision(precision, output.precision)
    Path(output.confusion).mkdir(parents=True, exist_ok=True)
    for (name, size), rows in predictions.groupby(["descriptor", "library_size"]):
        plot_confusion(rows, Path(output.confusion) / f"{name.replace('/', '_')}_{size:03d}_views.png",
                       f"{name}, {size} library views per object")
    chosen = predictions[predictions["descriptor"] == primary]
    largest = chosen[chosen["library_size"] == chosen["library_size"].max()]
    plot_view_confusion(largest, Path(output.confusion) / "view_angles.png", primary)
    library, _ = read_table(descriptors_path, columns=["descriptor", "object", "split", "azimuth", "values"],
                            filters=[("descriptor", "==", primary), ("split", "==", "train")])
    plot_isomap(library, primary, output.isomap)
    views = config["views"]
    draw_example_views(read_catalog(catalog_path), output.views, elevation=views["elevation"],
                       distance=views["distance"], noise=views["noise"], seed=views["seed"],
                       image_scale=views.get("image_scale", 1.0), derivative_path=output.global_derivative)
    table = precision[(precision["group"] == "all")].pivot_table(
        index=["level", "descriptor"], columns="library_size", values="precision")
    Path(output.summary).write_text("\n".join([
        "# heatdata run", "", RENDERED_NOTE, "",
        f"- heatdata {__version__}; {counts['object'].nunique()} objects, "
        f"{counts['view_id'].nunique()} views (mean "
        f"{counts.drop_duplicates('view_id')['n_vertices'].mean():.0f} vertices)",
        f"- views: {views}",
        "", "## Precision (columns: library views per object)", "",
        table.map(lambda v: f"{v:.1%}").to_markdown(), "",
        "## Run parameters", "", "```yaml", yaml.safe_dump(dict(config), sort_keys=False).strip(), "```", "",
    ]))
