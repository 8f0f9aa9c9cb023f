"""Evaluation: nearest-neighbour recognition of test views against a library (thesis 3.3.2, Alg. 5.2, Alg. 6.1).

Predictions and precision tables; the figures are in :mod:`heatdata.reporting.figures.recognition` and the
report in :mod:`heatdata.reporting.pages`.
"""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np
import pandas as pd

from heatdata.core.distances import SHORTLIST
from heatdata.descriptors import kind_of
from heatdata.errors import HeatdataError
from heatdata.io.tables import iter_matrix_table, iter_table
from heatdata.recognition.index import SearchIndex, build_index, nearest_through_index, object_positions
from heatdata.recognition.nearest import classify_candidates

log = logging.getLogger(__name__)


#: what :func:`classify` reads of a descriptor table
CLASSIFY_COLUMNS = ("object", "label", "view_id", "split", "azimuth", "descriptor", "kind", "values")


#: what it reads besides for a time-scaled kind (Alg. 5.2)
TIME_SCALED_COLUMNS = ("time_object", "time", "t_global", "weights")


#: library views above which :func:`classify` searches through an index by default. Below, the exhaustive search
#: takes less than the index's per-query re-ranking (560 views: 0.6 s against 18 s for the PVHK's 3,360 test views,
#: ``benchmarks/bench_index_agreement.py``); at 10,000 views of the HGD it takes 16 ms a query, the index 2 ms.
INDEX_ROWS = 5_000


#: which objects' time scales a time-scaled test view is compared at (:func:`classify`)
TIME_RULES = ("plausible", "every")


def classify(
    descriptors: pd.DataFrame,
    descriptor: str,
    *,
    library: str = "train",
    queries: str = "test",
    time_rule: str = "plausible",
    exact: bool | None = None,
) -> pd.DataFrame:
    """Nearest-neighbour class of each query view among the library views, by the kind's distance.

    The distance is the descriptor kind's own (eq. 3.1 for boundary curves, chi-square
    for histograms). A time-scaled kind (``ft-pvhk``) is compared object by object
    (Alg. 5.2): the query's row at object o's time scale (``time_object``) against o's
    library views, with the weighted distance of eq. 5.14; the nearest view wins.
    Alg. 5.2 takes the query's own object's time scale, which for a test view is its
    label; ``time_rule`` says which objects a query is compared with instead:
    ``"plausible"`` (default) those whose time scale (Alg. 5.1: the smallest 1/lambda_2
    of their library views) is at most the query's own 1/lambda_2 (``t_global``), as its
    own object's nearly always is - every object when none is; ``"every"`` every object.
    On the 58 chairs at 8 library views ``"plausible"`` gains 4.9 points (``scripts/ft_time_scales.py``).

    Above :data:`INDEX_ROWS` library views, a kind with an index space searches through a search index of them
    (:func:`heatdata.recognition.index.nearest_through_index`): the nearest view among every view of the
    objects the index shortlists, which is the exhaustive search's whenever its object is shortlisted (on the
    embedded objects' and the chairs' runs, for every test view: ``benchmarks/bench_index_agreement.py``).
    Below, the exhaustive search is faster.

    Parameters
    ----------
    descriptors : DataFrame
        A descriptor table (:data:`heatdata.io.tables.DESCRIPTOR_SCHEMA`).
    descriptor : str
        Which descriptor (the ``descriptor`` column) to use.
    library, queries : str
        Values of the ``split`` column.
    time_rule : {"plausible", "every"}
        For a time-scaled kind: which objects' time scales a query is compared at.
    exact : bool or None
        True: compare every library view; False: search through an index; None: through an index above
        :data:`INDEX_ROWS` library views.

    Returns
    -------
    DataFrame
        One row per query view, columns of :data:`heatdata.io.tables.PREDICTION_SCHEMA`.
    """
    if time_rule not in TIME_RULES:
        raise HeatdataError(f"unknown time_rule {time_rule!r} (use {' or '.join(TIME_RULES)})")
    _require_columns(descriptors, CLASSIFY_COLUMNS, descriptor)
    rows = descriptors[descriptors["descriptor"] == descriptor]
    lib, query = rows[rows["split"] == library], rows[rows["split"] == queries]
    if lib.empty or query.empty:
        raise HeatdataError(f"descriptor {descriptor!r}: no {library!r} or no {queries!r} rows to compare")
    _one_kind_and_length(rows, descriptor)
    lib, query, unusable = _usable(lib, query, descriptor)
    if kind_of(rows["kind"].iloc[0]).time_scaled:
        _require_columns(descriptors, TIME_SCALED_COLUMNS, descriptor)
    reference = Reference(lib.drop(columns="values"), np.stack(lib["values"].to_numpy()), descriptor, exact=exact)
    return _predictions(reference, query, unusable, time_rule)


class Reference:
    """A library's views as :func:`classify` compares queries with them: their rows, their values stacked once, and
    a search index when the kind has an index space (:mod:`heatdata.recognition.index`) and ``exact`` asks for one.

    Parameters
    ----------
    rows : pandas.DataFrame
        The library rows (none with NaN values), without their ``values`` column.
    values : (N, M) float
        The rows' values.
    descriptor : str
    exact : bool or None
        As for :func:`classify`.
    """

    def __init__(self, rows: pd.DataFrame, values: np.ndarray, descriptor: str, *, exact: bool | None = None):
        self.rows, self.values, self.descriptor = rows, values, descriptor
        self.kind = kind_of(rows["kind"].iloc[0])
        indexed = len(values) > INDEX_ROWS if exact is None else not exact
        space = self.kind.index_space
        #: an index of ``values``; None: the exhaustive search
        self.search: SearchIndex | None = (
            build_index(values, space, what=descriptor) if indexed and space is not None else None
        )
        self.codes, _, self.positions = object_positions(rows["object"])
        self.size = max(len(views) for views in self.positions)
        #: (N, P) part weights of a time-scaled kind's rows (eq. 5.14), or None
        self.weights = _stack(rows["weights"]) if "weights" in rows else None


def _one_kind_and_length(rows: pd.DataFrame, descriptor: str, lengths: set[int] | None = None) -> None:
    """Refuse rows of several lengths (theirs, or ``lengths``) or kinds."""
    lengths = {len(v) for v in rows["values"]} if lengths is None else lengths
    if len(lengths) > 1:
        raise HeatdataError(f"descriptor {descriptor!r}: descriptors of different lengths {sorted(lengths)}")
    kinds = rows["kind"].unique()
    if len(kinds) != 1:
        raise HeatdataError(f"descriptor {descriptor!r}: rows of several kinds {sorted(kinds)}")


def _predictions(reference: Reference, query: pd.DataFrame, unusable: pd.DataFrame, time_rule: str) -> pd.DataFrame:
    """:func:`classify`'s rows for usable ``query`` rows against ``reference`` (and no prediction for ``unusable``)."""
    lib, descriptor, impl = reference.rows, reference.descriptor, reference.kind
    for rows in (query, unusable):
        if not rows.empty and (len(rows["values"].iloc[0]), rows["kind"].iloc[0]) != (
            reference.values.shape[1],
            lib["kind"].iloc[0],
        ):
            raise HeatdataError(
                f"descriptor {descriptor!r}: test descriptors of {len(rows['values'].iloc[0])} values of "
                f"{rows['kind'].iloc[0]}, library ones of {reference.values.shape[1]} of {lib['kind'].iloc[0]}"
            )
    if query.empty:
        index, distance = np.zeros(0, np.int64), np.zeros(0)
    elif impl.time_scaled:
        query, index, distance = _fixed_time_neighbours(query, reference, time_rule)
    elif reference.search is None:
        index, distance = impl.nearest(np.stack(query["values"].to_numpy()), reference.values)
    else:
        values = np.stack(query["values"].to_numpy())
        index, distance = nearest_through_index(
            impl, reference.search, values, reference.values, reference.codes, reference.positions, reference.size
        )
    match = lib.iloc[index]
    predictions = pd.DataFrame(
        {
            "descriptor": descriptor,
            "object": query["object"].to_numpy(),
            "label": query["label"].to_numpy(),
            "view_id": query["view_id"].to_numpy(),
            "azimuth": query["azimuth"].to_numpy(),
            "predicted_object": match["object"].to_numpy(),
            "predicted_label": match["label"].to_numpy(),
            "predicted_view_id": match["view_id"].to_numpy(),
            "predicted_azimuth": match["azimuth"].to_numpy(),
            "distance": distance,
            "correct": query["object"].to_numpy() == match["object"].to_numpy(),
            "library_size": reference.size,
        }
    )
    if not unusable.empty:  # no prediction: counted as wrong
        failed = unusable.drop_duplicates("view_id")
        predictions = pd.concat(
            [
                predictions,
                pd.DataFrame(
                    {
                        "descriptor": descriptor,
                        "object": failed["object"].to_numpy(),
                        "label": failed["label"].to_numpy(),
                        "view_id": failed["view_id"].to_numpy(),
                        "azimuth": failed["azimuth"].to_numpy(),
                        "predicted_object": "",
                        "predicted_label": "",
                        "predicted_view_id": "",
                        "predicted_azimuth": np.nan,
                        "distance": np.nan,
                        "correct": False,
                        "library_size": reference.size,
                    }
                ),
            ],
            ignore_index=True,
        )
    return predictions


def _require_columns(descriptors: pd.DataFrame, columns, descriptor: str) -> None:
    missing = sorted(set(columns) - set(descriptors.columns))
    if missing:
        raise HeatdataError(f"descriptor {descriptor!r}: the table lacks column(s) {', '.join(missing)}")


def _usable(lib: pd.DataFrame, query: pd.DataFrame, descriptor: str) -> tuple[pd.DataFrame, pd.DataFrame, pd.DataFrame]:
    """Library and query rows without NaN values, and the query rows with some (logged).

    A PVST sample that never reaches its threshold, or a descriptor that failed on a view,
    is NaN. Such library views are left out; such test views get no prediction.
    """
    bad_lib, bad_query = nan_views(lib), nan_views(query)
    if bad_lib or bad_query:
        log.warning(
            "%s: %d library and %d test views have NaN values (see their repairs); the library views "
            "are left out and the test views count as wrong",
            descriptor,
            len(bad_lib),
            len(bad_query),
        )
    unusable = query["view_id"].isin(bad_query)
    return lib[~lib["view_id"].isin(bad_lib)], query[~unusable], query[unusable]


def nan_views(rows: pd.DataFrame, values: np.ndarray | None = None) -> set[str]:
    """The ``view_id`` of rows with a NaN value (a failed descriptor): left out of libraries, counted wrong as queries.

    Parameters
    ----------
    rows : pandas.DataFrame
        Descriptor rows (``view_id``, and ``values`` unless given as a matrix).
    values : (len(rows), M) float64, optional
        The rows' values as one array (:func:`heatdata.io.tables.iter_matrix_table`).

    Returns
    -------
    set of str
    """
    finite = rows["values"].map(lambda v: bool(np.isfinite(v).all())) if values is None else np.isfinite(values).all(1)
    return set(rows.loc[~np.asarray(finite, dtype=bool), "view_id"])


def _stack(column: pd.Series) -> np.ndarray | None:
    """(rows, M) array of a list column; None if any row is null (no part weights)."""
    if column.isna().any():
        return None
    return np.stack(column.to_numpy())


def _fixed_time_neighbours(
    query: pd.DataFrame, reference: Reference, time_rule: str
) -> tuple[pd.DataFrame, np.ndarray, np.ndarray]:
    """Alg. 5.2: per query view, the nearest library view over objects, each at its own time scale.

    Returns the query views (one row each), the positional index of each one's nearest
    library row in ``lib``, and the weighted distance (eq. 5.14). Each object is searched
    only for the views ``time_rule`` lets compare with it (:func:`classify`), and only for
    library views nearer than the best so far (``within`` of :meth:`Kind.nearest`).
    """
    views = query.drop_duplicates("view_id")
    view_of_row = pd.Index(views["view_id"]).get_indexer(query["view_id"])
    allowed = np.ones(len(query), dtype=bool)
    if time_rule == "plausible":
        reachable = (query["time"] <= query["t_global"]).to_numpy()
        allowed = reachable | (np.bincount(view_of_row, reachable, len(views)) == 0)[view_of_row]
    lib, descriptor, impl = reference.rows, reference.descriptor, reference.kind
    values = query["values"].to_numpy()  # (rows,) arrays, stacked object by object (memory)
    weights = None if query["weights"].isna().any() else query["weights"].to_numpy()
    lib_values, lib_weights = reference.values, reference.weights
    if (weights is None) != (lib_weights is None):
        raise HeatdataError(f"descriptor {descriptor!r}: part weights on the test or the library rows only")
    at_time = query.groupby("time_object").indices
    best = np.full(len(views), np.inf)
    index = np.zeros(len(views), dtype=np.int64)
    for obj, positions in lib.groupby("object").indices.items():
        rows = at_time.get(obj, np.zeros(0, dtype=np.int64))
        rows = rows[np.argsort(view_of_row[rows], kind="stable")]  # in the order of ``views``
        if not np.array_equal(view_of_row[rows], np.arange(len(views))):
            counts = np.bincount(view_of_row[rows], minlength=len(views))
            view = views["view_id"].iloc[int(np.flatnonzero(counts != 1)[0])]
            problem = "no row" if counts.min() == 0 else "several rows"
            raise HeatdataError(
                f"descriptor {descriptor!r}: test view {view} has {problem} at the time scale of "
                f"object {obj!r} (time_object); describe test views with every object's"
            )
        searched = np.flatnonzero(allowed[rows])  # rows are in view order: row k is view k's
        if not len(searched):
            continue
        rows = rows[searched]
        nearest, distance = impl.nearest(
            np.stack(values[rows]),
            lib_values[positions],
            query_weights=None if weights is None else np.stack(weights[rows]),
            library_weights=None if lib_weights is None else lib_weights[positions],
            within=best[searched],
        )  # only a nearer one matters
        found = nearest >= 0
        best[searched[found]] = distance[found]
        index[searched[found]] = positions[nearest[found]]
    return views, index, best


def evaluate_library_sizes(
    descriptors: pd.DataFrame,
    descriptor: str,
    sizes: list[int],
    *,
    time_rule: str = "plausible",
    exact: bool | None = None,
) -> pd.DataFrame:
    """Nearest-neighbour predictions of the test views for libraries of several sizes.

    Returns the rows of :func:`classify` (with ``time_rule``) with a ``library_size`` column.

    Parameters
    ----------
    descriptors : pandas.DataFrame
        As for :func:`classify`.
    descriptor : str
        The descriptor's name.
    sizes : list of int
        Library views per object (:func:`library_subset`).
    time_rule : {"plausible", "every"}
        As for :func:`classify`.
    exact : bool or None
        As for :func:`classify`.

    Returns
    -------
    pandas.DataFrame
        :func:`classify`'s rows with ``library_size``.
    """
    rows = descriptors[descriptors["descriptor"] == descriptor]
    tests = rows[rows["split"] == "test"]
    results = []
    for size in sizes:
        subset = pd.concat([library_subset(rows, size), tests])
        results.append(classify(subset, descriptor, time_rule=time_rule, exact=exact).assign(library_size=size))
    return pd.concat(results, ignore_index=True)


def evaluate_table(
    path: str | Path,
    descriptor: str,
    sizes: list[int],
    *,
    library_split: str = "train",
    time_rule: str = "plausible",
    exact: bool | None = None,
) -> pd.DataFrame:
    """:func:`evaluate_library_sizes` on a descriptor table on disk, reading its test rows a row group at a time.

    Memory holds the library's values (read as one array, :func:`heatdata.io.tables.iter_matrix_table`), its search
    index and one row group of test rows, not the whole table (a
    run's table has one row group per object, :func:`heatdata.io.tables.concat_tables`): the
    chairs' FT-PVHK has 406,000 test rows, each test view at every object's time scale
    (Alg. 5.2). A time-scaled test view whose rows are not all in one group waits for the
    next; one still missing a time scale at the end is an error, as in :func:`classify`.

    ``library_split="test"`` is the protocol of thesis 5.5: the library views are chosen
    among the test views (each at its own object's time scale), which are all queried, so
    each library view is also a query that finds itself. The default keeps them apart:
    the library comes from the ``train`` views, rendered at other angles with other noise.
    ``time_rule``: as :func:`classify`.

    Parameters
    ----------
    path : str or Path
        A run's ``descriptors.parquet``.
    descriptor : str
        The descriptor's name.
    sizes : list of int
        Library views per object.
    library_split : {"train", "test"}
        Where the library views are chosen.
    time_rule : {"plausible", "every"}
        As for :func:`classify`.
    exact : bool or None
        As for :func:`classify`.

    Returns
    -------
    pandas.DataFrame
        As :func:`evaluate_library_sizes`.
    """
    columns = [*CLASSIFY_COLUMNS, *TIME_SCALED_COLUMNS]
    rows = [("descriptor", "==", descriptor)]
    frames, blocks = [], []
    for group, values in iter_matrix_table(
        path, "values", columns=columns, filters=[*rows, ("split", "==", library_split)]
    ):
        kept = own_time_scale(group)
        frames.append(kept)
        blocks.append(values[kept.index.to_numpy()])
    if not frames:
        raise HeatdataError(f"{path}: no library ({library_split!r}) rows of descriptor {descriptor!r}")
    train = pd.concat(frames, ignore_index=True).assign(split="train")
    _one_kind_and_length(train, descriptor, {block.shape[1] for block in blocks})
    values = np.concatenate(blocks)
    del frames, blocks
    bad = nan_views(train, values)
    if bad:
        log.warning("%s: %d library views have NaN values (see their repairs) and are left out", descriptor, len(bad))
    libraries = {}
    for size in sizes:
        library = library_subset(train, size)
        library = library[~library["view_id"].isin(bad)]
        libraries[size] = (library, values[library.index.to_numpy()])
    time_scaled = kind_of(train["kind"].iloc[0]).time_scaled
    objects = train["object"].nunique()
    del train, values  # each library size holds its own rows, before the indexes are built
    references = {
        size: Reference(library.reset_index(drop=True), chosen, descriptor, exact=exact)
        for size, (library, chosen) in libraries.items()
    }
    del libraries
    parts: dict[int, list[pd.DataFrame]] = {size: [] for size in sizes}

    def add(tests: pd.DataFrame) -> None:
        _one_kind_and_length(tests, descriptor)
        unusable = tests["view_id"].isin(nan_views(tests))
        if unusable.any():
            log.warning("%s: %d test views have NaN values and count as wrong", descriptor, unusable.sum())
        for size, reference in references.items():
            parts[size].append(_predictions(reference, tests[~unusable], tests[unusable], time_rule))

    pending = None
    for group in iter_table(path, columns=columns, filters=[*rows, ("split", "==", "test")]):
        tests = group if pending is None else pd.concat([pending, group], ignore_index=True)
        if time_scaled:  # a view is whole once it has a row at every object's time scale
            whole = tests.groupby("view_id")["time_object"].transform("nunique") >= objects
            tests, pending = tests[whole], tests[~whole]
        if not tests.empty:
            add(tests)
    if pending is not None and not pending.empty:
        add(pending)  # raises: a test view without a row at some object's time scale
    if not any(parts.values()):
        raise HeatdataError(f"{path}: no test rows of descriptor {descriptor!r}")
    return pd.concat([part for size in sizes for part in parts[size]], ignore_index=True)


def evaluate_compact(
    candidates: pd.DataFrame, libraries: pd.DataFrame, *, shortlist: int | None = SHORTLIST
) -> pd.DataFrame:
    """Alg. 6.1: each test view, described from its candidate sources, against each library.

    Parameters
    ----------
    candidates : pandas.DataFrame
        Test (``split = "test"``) ``candidates`` rows of :func:`heatdata.experiments.describe.candidate_rows`.
    libraries : pandas.DataFrame
        :func:`heatdata.experiments.compact.compact_libraries`.

    Returns
    -------
    pandas.DataFrame
        Rows of :data:`heatdata.io.tables.PREDICTION_SCHEMA`, one per library
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
            row = {
                "descriptor": method,
                "library_size": int(size),
                "object": first["object"],
                "label": first["label"],
                "view_id": first["view_id"],
                "azimuth": first["azimuth"],
            }
            if len(values) == 0:
                out.append(
                    {
                        **row,
                        "predicted_object": "",
                        "predicted_label": "",
                        "predicted_view_id": "",
                        "predicted_azimuth": np.nan,
                        "distance": np.nan,
                        "correct": False,
                    }
                )
                continue
            pair = classify_candidates(values, lib_values, objects, shortlist=shortlist)
            match = lib.iloc[pair.index]
            out.append(
                {
                    **row,
                    "predicted_object": match["object"],
                    "predicted_label": match["label"],
                    "predicted_view_id": match["view_id"],
                    "predicted_azimuth": match["azimuth"],
                    "distance": pair.distance,
                    "correct": match["object"] == first["object"],
                }
            )
        log.info("%s, %d views: %d test views classified", method, size, len(per_view))
    return pd.DataFrame(out)


def own_time_scale(rows: pd.DataFrame) -> pd.DataFrame:
    """The descriptor ``rows`` a view gives as itself: at no time scale, or at its own object's (Alg. 5.2 describes
    a time-scaled kind's views at every object's time scale; ``time_object`` names it)."""
    return rows[rows["time_object"].isin(["", None]) | (rows["time_object"] == rows["object"])]


def library_subset(descriptors: pd.DataFrame, size: int, split: str = "train") -> pd.DataFrame:
    """The ``size`` library views per object evenly spaced in azimuth among the ``split`` views (3.4.1).

    Parameters
    ----------
    descriptors : pandas.DataFrame
        Rows of ``descriptors.parquet`` (``object``, ``split``, ``azimuth``, ...).
    size : int
        Library views per object, >= 1.
    split : str
        The split they are chosen among.

    Returns
    -------
    pandas.DataFrame
        The chosen rows (every descriptor of each chosen view).

    Raises
    ------
    HeatdataError
        ``size`` is not a whole number >= 1, there is no ``split`` view, or an object has fewer than ``size``.
    """
    if isinstance(size, bool) or not isinstance(size, (int, np.integer)) or size < 1:
        raise HeatdataError(f"library size must be a whole number of views per object >= 1, got {size!r}")
    library = descriptors[descriptors["split"] == split]
    if library.empty:
        raise HeatdataError(f"no {split} views to choose a library from")
    views = library[["object", "azimuth"]]
    angles = views.drop_duplicates().sort_values(["object", "azimuth"])
    counts = angles.groupby("object").size()
    few = counts[counts < size]
    if len(few):
        raise HeatdataError(f"library size {size} is larger than the {few.iloc[0]} {split} views of {few.index[0]!r}")
    # an object's n angles, sorted: those of rank floor(k n / size), k = 0 .. size - 1; rank r is one when the
    # least k with k n / size >= r (ceil(r size / n)) is below size and lands on r
    rank = angles.groupby("object").cumcount().to_numpy()
    n = angles["object"].map(counts).to_numpy()
    least = -(-rank * size // n)
    keep = angles[(least < size) & (least * n // size == rank)]
    chosen = library[pd.MultiIndex.from_frame(views).isin(pd.MultiIndex.from_frame(keep))]
    return chosen.sort_values("object", kind="stable")
