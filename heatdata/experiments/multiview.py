"""Algorithm 4.1's trials (thesis 4.5): starts at the most ambiguous test views, runs and their summary."""

from __future__ import annotations

import logging
from typing import Any

import numpy as np
import pandas as pd

from heatdata.errors import HeatdataError
from heatdata.recognition.multiview.appearance import (
    _sets,
    filter_model,
    learn_similarity,
    similarity_matrix,
)
from heatdata.recognition.multiview.filters import (
    ExhaustiveFilter,
    HypothesisFilter,
    ParticleFilter,
)
from heatdata.recognition.multiview.robot import TableRobot, recognize

log = logging.getLogger(__name__)


def ambiguous_starts(library: pd.DataFrame, tests: pd.DataFrame, count: int = 3) -> pd.DataFrame:
    """Each object's ``count`` most ambiguous test views: smallest margin between another object and its own.

    The margin is ``d(z, nearest view of another object) - d(z, nearest view of its own)``
    under the appearance model's distance (eq. 4.4 with one observation); a negative
    margin is a view that single-view recognition gets wrong. Returns ``object``,
    ``azimuth``, ``margin``, ``nearest_other``.
    """
    model = _sets(library)  # the margins are distances: alpha does not enter them
    if len(model.objects) < 2:
        raise HeatdataError("ambiguity needs two or more library objects")
    d = model.nearest(list(tests["values"]))
    own = tests["object"].to_numpy()[:, None] == model.labels["object"].to_numpy()[None, :]
    other = np.where(own, np.inf, d).argmin(axis=1)
    rows = np.arange(len(tests))
    table = pd.DataFrame(
        {
            "object": tests["object"].to_numpy(),
            "azimuth": tests["azimuth"].to_numpy(),
            "margin": d[rows, other] - np.where(own, d, np.inf).min(axis=1),
            "nearest_other": model.labels["object"].to_numpy()[other],
        }
    ).sort_values(["object", "margin"])
    return table.groupby("object").head(count).reset_index(drop=True)


def multiview_trials(
    library: pd.DataFrame,
    similarity: pd.DataFrame,
    tests: pd.DataFrame,
    starts: pd.DataFrame,
    *,
    particles=(10, 50, 100),
    bootstraps=("similarity", "angular"),
    policies=("fixed",),
    repetitions: int = 30,
    exhaustive: bool = True,
    seed: int = 0,
    per_stop: int = 2,
    step: float = 15.0,
    candidates: tuple[float, ...] = (-90.0, -45.0, -15.0, 15.0, 45.0, 90.0),
    max_degrees: float = 720.0,
    filter_options: dict[str, Any] | None = None,
) -> pd.DataFrame:
    """The experiments of 4.5: every start view x particle count x bootstrap x policy x repetition.

    ``starts`` has ``object`` and ``azimuth`` (e.g. :func:`ambiguous_starts`); ``tests``
    holds each object's test views (observations are the ``per_stop`` nearest each stop).
    ``step``, ``candidates`` and ``max_degrees`` go to
    :func:`~heatdata.recognition.multiview.robot.recognize`, and ``filter_options`` to every
    :class:`~heatdata.recognition.multiview.filters.ParticleFilter` (``tau_boot``, ``sigma_min``, ``alpha``,
    ``newcomer``, ...).
    The active policy runs with the similarity bootstrap only. With ``exhaustive``, each
    start also runs once with :class:`ExhaustiveFilter` (``bootstrap`` "exhaustive",
    fixed steps, ``particles`` its number of hypotheses): the exact answer of the
    appearance model, which the particles approximate.

    Returns
    -------
    DataFrame
        One row per run: ``object, start, particles, bootstrap, policy, repetition,
        estimate, correct, identified, converged, degrees, stops, restarts, comparisons,
        seconds``; ``correct``: converged on the true object; ``identified``: the most
        probable object at the end is the true one, converged or not (how 4.5.4 scores
        the chairs after one circle);
        ``comparisons`` counts particle evaluations (particles x stops; the exhaustive
        filter's are its labels x stops) and ``exhaustive`` the library labels x stops an
        exhaustive search would compare.
    """
    import time

    from heatdata.log import progress

    filter_options = dict(filter_options or {})
    model = filter_model(library, similarity, filter_options.get("alpha"))
    mu = similarity_matrix(model, similarity)
    robots = {obj: TableRobot(model, rows, per_stop) for obj, rows in tests.groupby("object")}
    missing = sorted(set(starts["object"]) - set(robots))
    if missing:
        raise HeatdataError(f"no test views of start object(s) {missing}")
    labels = len(model.labels)
    jobs = [
        (s, n, b, p, r)
        for s in starts.itertuples()
        for n in particles
        for b in bootstraps
        for p in policies
        if not (p == "active" and b != "similarity")
        for r in range(repetitions)
    ]
    jobs += [(s, 0, "exhaustive", "fixed", 0) for s in starts.itertuples()] if exhaustive else []
    rows = []
    for k, (start, n, boot, policy, rep) in enumerate(progress(jobs, desc="multi-view trials", unit="run")):
        begin = time.perf_counter()
        f: HypothesisFilter
        if boot == "exhaustive":
            f = ExhaustiveFilter(model)
            n = len(f.object)
        else:
            f = ParticleFilter(model, mu, particles=n, bootstrap=boot, seed=seed + k, **filter_options)
        result = recognize(
            f,
            robots[start.object],
            start.azimuth,
            policy=policy,
            step=step,
            candidates=candidates,
            max_degrees=max_degrees,
        )
        rows.append(
            {
                "object": start.object,
                "start": start.azimuth,
                "particles": n,
                "bootstrap": boot,
                "policy": policy,
                "repetition": rep,
                **result,
                "correct": result["converged"] and result["estimate"] == start.object,
                "identified": result["estimate"] == start.object,
                "comparisons": (labels if boot == "exhaustive" else n) * result["stops"],
                "exhaustive": labels * result["stops"],
                "seconds": time.perf_counter() - begin,
            }
        )
    return pd.DataFrame(rows)


def split_tests(rows: pd.DataFrame) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Each object's test views split by azimuth rank: even ranks learn the similarity, odd ranks are observed.

    The two halves interleave in angle and have their own noise, so the similarity of
    eq. 4.6 is learned from views independent of both the library and the test views.
    """
    ranked = rows.sort_values(["object", "azimuth"], kind="stable")
    rank = ranked.groupby("object").cumcount().to_numpy()
    return ranked[rank % 2 == 0], ranked[rank % 2 == 1]


def multiview_experiment(
    descriptors: pd.DataFrame, descriptor: str, settings: dict
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Workflow step: the trials of 4.5 for one descriptor of a run, for each library size in ``settings``.

    Parameters
    ----------
    descriptors : DataFrame
        Rows of ``descriptors.parquet`` (``split`` train: the library, test: split by
        :func:`split_tests` into similarity and observed views).
    settings : dict
        The config's ``multiview`` section: ``library_views``, ``particles``,
        ``repetitions``, ``starts``, ``policies``, ``step``, ``per_stop``,
        ``max_degrees``, ``candidates``, ``tau_boot``, ``sigma_min``, ``alpha``, ``seed``.

    Returns
    -------
    trials, similarity : DataFrame
        :func:`multiview_trials` with a ``library_views`` column; the learned similarity
        tables with the same column.
    """
    from heatdata.recognition.evaluate import library_subset

    rows = descriptors[descriptors["descriptor"] == descriptor]
    if rows.empty:
        raise HeatdataError(f"multiview: no rows of descriptor {descriptor!r}")
    if not np.isfinite(np.stack(rows["values"].to_numpy())).all():
        raise HeatdataError(f"multiview: {descriptor} failed on some views (NaN); choose another descriptor")
    similar_views, tests = split_tests(rows[rows["split"] == "test"])
    trials, similarities = [], []
    for size in settings["library_views"]:
        library = library_subset(rows, size)
        similarity = learn_similarity(library, similar_views, alpha=settings["alpha"])
        starts = ambiguous_starts(library, tests, settings["starts"])
        log.info(
            "%d library views per object: %d start views, margins %s",
            size,
            len(starts),
            np.round(starts["margin"].to_numpy(), 3).tolist(),
        )
        table = multiview_trials(
            library,
            similarity,
            tests,
            starts,
            particles=settings["particles"],
            policies=settings["policies"],
            repetitions=settings["repetitions"],
            seed=settings["seed"],
            candidates=tuple(settings["candidates"]),
            step=settings["step"],
            per_stop=settings["per_stop"],
            max_degrees=settings["max_degrees"],
            filter_options={k: settings[k] for k in ("tau_boot", "sigma_min", "alpha")},
        )
        trials.append(table.assign(library_views=size, descriptor=descriptor))
        similarities.append(similarity.assign(library_views=size))
    return pd.concat(trials, ignore_index=True), pd.concat(similarities, ignore_index=True)


def trial_summary(trials: pd.DataFrame) -> pd.DataFrame:
    """Accuracy (converged on the true object), identified (true object most probable at the end), degrees
    travelled and comparisons per setting."""
    keys = ["library_views", "policy", "bootstrap", "particles"]
    summary = trials.groupby(keys).agg(
        runs=("correct", "size"),
        accuracy=("correct", "mean"),
        identified=("identified", "mean"),
        converged=("converged", "mean"),
        degrees=("degrees", "mean"),
        stops=("stops", "mean"),
        comparisons=("comparisons", "mean"),
        exhaustive=("exhaustive", "mean"),
        seconds=("seconds", "mean"),
    )
    return summary.reset_index()
