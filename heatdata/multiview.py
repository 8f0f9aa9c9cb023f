"""Multi-view recognition (thesis ch. 4): appearance models, the learned similarity and the particle filter.

A robot circling an object collects views one stop at a time and knows only how far it
moved (odometry). Algorithm 4.1 keeps hypotheses ``s = (object, view angle)`` as
particles, weighs them by the appearance model of 4.3, and, when it drops unlikely
particles, re-populates them at the library views that *look like* the survivors
(the similarity bootstrap of 4.4.6), so that an object whose views resemble another's
never vanishes while the observations are ambiguous. Beyond the thesis,
:meth:`ParticleFilter.best_move` chooses the next step that is expected to reduce the
posterior entropy over objects most (active recognition), and :class:`ExhaustiveFilter`
scores every object at every degree: the exact posterior the particles approximate.

Every distance is the descriptor kind's own (:meth:`heatdata.descriptors.Kind.distance_matrix`),
so any kind works; library tables are rows of ``descriptors.parquet`` (columns
``object``, ``azimuth``, ``values`` and optionally ``kind``).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, replace

import numpy as np
import pandas as pd
from scipy.special import logsumexp

from .descriptors import DEFAULT_KIND, Descriptor, kind_of, stack_values
from .errors import HeatdataError

log = logging.getLogger(__name__)

SIMILARITY_COLUMNS = ["object", "azimuth", "similar_object", "similar_azimuth", "similarity", "similar_alpha"]


def _angle_gap(a, b) -> np.ndarray:
    """Absolute circular difference of angles in degrees, in [0, 180]."""
    return np.abs((np.asarray(a, dtype=np.float64) - b + 180.0) % 360.0 - 180.0)


def _as_list(observations) -> list:
    return [observations] if isinstance(observations, Descriptor) else list(observations)


def set_distance(d: np.ndarray) -> float:
    """Eq. 4.4 from the matrix of distances between the members of two sets Z (rows) and Z' (columns).

    ``d(Z, Z') = min(sum_{x in Z} inf_{y in Z'} d(x, y), sum_{y in Z'} inf_{x in Z} d(x, y))``.
    """
    return float(min(d.min(axis=1).sum(), d.min(axis=0).sum()))


@dataclass(frozen=True)
class AppearanceModel:
    """p(Z | s) of thesis 4.3 for every partial-view label s = (object, azimuth) of a library.

    Attributes
    ----------
    labels : DataFrame
        One row per label: ``object``, ``azimuth``, in order; a label's index is its row.
    members : (N,) int
        The label of each library descriptor, non-decreasing (each set Z_s is contiguous).
    values : (N, M) float64
        The library descriptors Z_s, stacked.
    alpha : (S,) float64
        The scale of each label's exponential (eq. 4.5).
    kind : str
        The descriptor kind whose distance compares observations.
    """

    labels: pd.DataFrame
    members: np.ndarray
    values: np.ndarray
    alpha: np.ndarray
    kind: str

    @property
    def objects(self) -> list[str]:
        return sorted(self.labels["object"].unique())

    def distances(self, observations) -> np.ndarray:
        """(S,) eq. 4.4 between the set of ``observations`` and every label's set Z_s."""
        kinds = {d.kind for d in _as_list(observations) if isinstance(d, Descriptor)}
        if kinds - {self.kind}:
            raise HeatdataError(f"observations are {', '.join(sorted(kinds))} descriptors, the library's {self.kind}")
        z = stack_values(observations, "observations")
        if z.shape[1] != self.values.shape[1]:
            raise HeatdataError(f"observations have {z.shape[1]} values, the library's {self.kind} descriptors "
                                f"{self.values.shape[1]}: describe them with the library's spec")
        d = kind_of(self.kind).distance_matrix(z, self.values)
        starts = np.searchsorted(self.members, np.arange(len(self.labels)))  # members are sorted by label
        forward = np.minimum.reduceat(d, starts, axis=1).sum(axis=0)  # sum over Z of the nearest in Z_s
        backward = np.add.reduceat(d.min(axis=0), starts)  # sum over Z_s of the nearest in Z
        return np.minimum(forward, backward)  # eq. 4.4 for every label at once

    def nearest(self, rows) -> np.ndarray:
        """(V, S) eq. 4.4 between each single observation and every label's set: its nearest member of Z_s."""
        d = kind_of(self.kind).distance_matrix(stack_values(rows, "observations"), self.values)
        return np.minimum.reduceat(d, np.searchsorted(self.members, np.arange(len(self.labels))), axis=1)

    def log_likelihood(self, observations) -> np.ndarray:
        """(S,) log p(Z | s) = -d(Z, Z_s) / alpha_s - log alpha_s (4.3)."""
        return -self.distances(observations) / self.alpha - np.log(self.alpha)


def appearance_model(library: pd.DataFrame, *, alpha: float | None = None, views: pd.DataFrame | None = None
                     ) -> AppearanceModel:
    """The appearance model of a library table (thesis 4.3).

    Parameters
    ----------
    library : DataFrame
        One row per library descriptor: ``object``, ``azimuth``, ``values`` (and ``kind``;
        default the PVHK's). Rows with one (object, azimuth) form the set Z_s.
    alpha : float, optional
        One scale for every label (the thesis's chairs used 0.08, on its distance scale).
    views : DataFrame, optional
        Views independent of the library (as for :func:`learn_similarity`). alpha_s is then
        eq. 4.5 with them as the other descriptors of s: the mean distance
        ``d({z'}, Z_s)`` over the independent views z' whose nearest library label is s
        (labels no view falls on take the median). Without ``views`` or ``alpha``, alpha_s
        is eq. 4.5 inside the library, the mean leave-one-out distance in Z_s; a label with
        a single descriptor takes the distance to the nearest neighbouring library angle of
        its object (how much the appearance changes over one library step; not in the
        thesis), or, for an object with one view, the median of the others.

    Raises
    ------
    HeatdataError
        Missing columns, several kinds, NaN descriptors or a non-positive alpha.
    """
    model = _sets(library)
    if alpha is not None:
        if not alpha > 0:
            raise HeatdataError(f"alpha must be positive, got {alpha}")
        return replace(model, alpha=np.full(len(model.labels), float(alpha)))
    if views is not None:
        return replace(model, alpha=_alpha_from_views(model, views))
    return replace(model, alpha=_alpha(model.values, model.members, model.labels, model.kind))


def _sets(library: pd.DataFrame) -> AppearanceModel:
    """A library's labels and sets Z_s, checked; alpha is 1 until :func:`appearance_model` or :func:`filter_model`
    sets it (the set distances do not depend on it)."""
    missing = sorted({"object", "azimuth", "values"} - set(library.columns))
    if missing:
        raise HeatdataError(f"library table lacks column(s) {', '.join(missing)}")
    if library.empty:
        raise HeatdataError("library table is empty")
    kinds = library["kind"].unique() if "kind" in library.columns else [DEFAULT_KIND]
    if len(kinds) != 1:
        raise HeatdataError(f"library holds several descriptor kinds {sorted(kinds)}; use one descriptor")
    library = library.sort_values(["object", "azimuth"], kind="stable")
    values = stack_values(list(library["values"]), "library")
    if not np.isfinite(values).all():
        raise HeatdataError("library descriptors hold NaN (failed descriptors): drop those rows first")
    labels = library[["object", "azimuth"]].drop_duplicates().reset_index(drop=True)
    index = {(o, a): k for k, (o, a) in enumerate(zip(labels["object"], labels["azimuth"], strict=True))}
    members = np.array([index[(o, a)] for o, a in zip(library["object"], library["azimuth"], strict=True)])
    return AppearanceModel(labels=labels, members=members, values=values, alpha=np.ones(len(labels)),
                           kind=str(kinds[0]))


def _alpha_from_views(model: AppearanceModel, views: pd.DataFrame) -> np.ndarray:
    """alpha_s of eq. 4.5 with independent views as the other descriptors of each partial view s."""
    labelled = assign_labels(model, views)
    own = model.nearest(list(labelled["values"]))[np.arange(len(labelled)), labelled["label"].to_numpy()]
    scales = np.full(len(model.labels), np.nan)
    for k, distances in pd.Series(own).groupby(labelled["label"].to_numpy()):
        scales[k] = distances.mean()
    usable = np.isfinite(scales) & (scales > 0)
    if not usable.any():
        raise HeatdataError("alpha cannot be estimated from these views (identical to the library): give alpha")
    return np.where(usable, scales, np.median(scales[usable]))


def _alpha(values: np.ndarray, members: np.ndarray, labels: pd.DataFrame, kind: str) -> np.ndarray:
    """alpha_s of eq. 4.5, with the neighbouring-angle fallback of :func:`appearance_model` for single views."""
    d = kind_of(kind).distance_matrix(values, values)
    scales = np.full(len(labels), np.nan)
    for k in range(len(labels)):
        rows = np.flatnonzero(members == k)
        if len(rows) > 1:  # eq. 4.5: d_H({z'}, Z_s \ {z'}) averaged over z'
            inner = d[np.ix_(rows, rows)]
            np.fill_diagonal(inner, np.inf)
            scales[k] = inner.min(axis=1).mean()
    for obj, group in labels.groupby("object"):
        angles = group["azimuth"].to_numpy()
        for k, angle in zip(group.index, angles, strict=True):
            if np.isnan(scales[k]) and len(group) > 1:
                gaps = _angle_gap(angles, angle)
                gaps[gaps == 0] = np.inf
                neighbours = group.index[gaps == gaps.min()]
                scales[k] = min(set_distance(d[np.ix_(members == k, members == j)]) for j in neighbours)
    known = scales[np.isfinite(scales) & (scales > 0)]
    if not len(known):
        raise HeatdataError("alpha cannot be estimated from this library (one view per object, or identical "
                            "views): give alpha explicitly")
    fallback = float(np.median(known))
    return np.where(np.isfinite(scales) & (scales > 0), scales, fallback)


def learn_similarity(library: pd.DataFrame, views: pd.DataFrame, *, alpha: float | None = None) -> pd.DataFrame:
    """mu(s, s') = p(Z_s | s') of eq. 4.6, learned from views independent of the library.

    Each independent view is labelled with the library label of its object at the
    nearest azimuth; Z_s is the set of views so labelled, and ``p(Z_s | s')`` the
    appearance model of the library with alpha learned from the same views
    (:func:`appearance_model` with ``views``), unless ``alpha`` is given.

    Parameters
    ----------
    library, views : DataFrame
        Tables of one descriptor (``object``, ``azimuth``, ``values``); ``views`` must
        cover every library object.

    Returns
    -------
    DataFrame
        :data:`SIMILARITY_COLUMNS`, one row per pair of library labels (s, s'):
        ``similarity`` = p(Z_s | s'), NaN where no independent view has label s, and
        ``similar_alpha``, the alpha of s' (the filter's appearance model takes it).
    """
    lacking = sorted({"object", "azimuth", "values"} - set(views.columns))
    if lacking:
        raise HeatdataError(f"similarity views lack column(s) {', '.join(lacking)}")
    missing = sorted(set(library["object"]) - set(views["object"]))
    if missing:
        raise HeatdataError(f"the similarity views lack library object(s) {missing}")
    model = appearance_model(library, alpha=alpha, views=None if alpha is not None else views)
    mu = np.full((len(model.labels),) * 2, np.nan)
    for k, labelled in assign_labels(model, views).groupby("label"):
        mu[k] = np.exp(model.log_likelihood(list(labelled["values"])))
    a, b = np.divmod(np.arange(mu.size), len(model.labels))
    log.info("similarity of %d labels learned from %d independent views", len(model.labels), len(views))
    objects, azimuths = model.labels["object"].to_numpy(), model.labels["azimuth"].to_numpy()
    return pd.DataFrame({"object": objects[a], "azimuth": azimuths[a], "similar_object": objects[b],
                         "similar_azimuth": azimuths[b], "similarity": mu.ravel(), "similar_alpha": model.alpha[b]})


def assign_labels(model: AppearanceModel, views: pd.DataFrame) -> pd.DataFrame:
    """``views`` with a ``label`` column: the index of its object's library label at the nearest azimuth."""
    out = views.copy()
    out["label"] = -1
    for obj, group in model.labels.groupby("object"):
        mask = (views["object"] == obj).to_numpy()
        gaps = _angle_gap(views.loc[mask, "azimuth"].to_numpy()[:, None], group["azimuth"].to_numpy()[None, :])
        out.loc[mask, "label"] = group.index.to_numpy()[gaps.argmin(axis=1)]
    return out


def filter_model(library: pd.DataFrame, similarity: pd.DataFrame, alpha: float | None = None) -> AppearanceModel:
    """The appearance model a filter uses: the library's, with the alpha learned with the similarity (or ``alpha``)."""
    if alpha is not None:
        return appearance_model(library, alpha=alpha)
    model = _sets(library)
    if "similar_alpha" not in similarity.columns:
        raise HeatdataError("similarity table lacks column(s) similar_alpha")
    own = similarity.drop_duplicates(["similar_object", "similar_azimuth"]).set_index(
        ["similar_object", "similar_azimuth"])["similar_alpha"]
    learned = own.reindex(pd.MultiIndex.from_frame(model.labels)).to_numpy(dtype=np.float64)
    if len(own) != len(learned) or not np.isfinite(learned).all():
        raise HeatdataError(f"the similarity table ({len(own)} labels) does not match the library "
                            f"({len(learned)} labels): learn it on this library")
    return replace(model, alpha=learned)


def similarity_matrix(model: AppearanceModel, similarity: pd.DataFrame) -> np.ndarray:
    """(S, S) mu[s, s'] of a :func:`learn_similarity` table, in the model's label order; NaN rows become 0.

    Raises
    ------
    HeatdataError
        The table's labels are not the library's.
    """
    missing = sorted(set(SIMILARITY_COLUMNS) - set(similarity.columns))
    if missing:
        raise HeatdataError(f"similarity table lacks column(s) {', '.join(missing)}")
    keys = list(zip(model.labels["object"], model.labels["azimuth"], strict=True))
    table_keys = set(zip(similarity["object"], similarity["azimuth"], strict=True))
    if table_keys != set(keys) or len(similarity) != len(keys) ** 2:
        raise HeatdataError(f"the similarity table ({len(table_keys)} labels, {len(similarity)} rows) does not "
                            f"match the library ({len(keys)} labels): learn it on this library")
    position = {key: k for k, key in enumerate(keys)}
    mu = np.zeros((len(keys), len(keys)))
    rows = [position[k] for k in zip(similarity["object"], similarity["azimuth"], strict=True)]
    cols = [position[k] for k in zip(similarity["similar_object"], similarity["similar_azimuth"], strict=True)]
    mu[rows, cols] = np.nan_to_num(similarity["similarity"].to_numpy(dtype=np.float64), nan=0.0)
    return mu


def stochastic_universal_sampling(weights: np.ndarray, count: int, rng: np.random.Generator) -> np.ndarray:
    """``count`` indices drawn in proportion to ``weights`` with one random offset (Baker 1987)."""
    cumulative = np.cumsum(weights / weights.sum())
    pointers = (rng.random() + np.arange(count)) / count
    return np.minimum(np.searchsorted(cumulative, pointers, side="right"), len(weights) - 1)


def _object_angles(model: AppearanceModel) -> list[tuple[np.ndarray, np.ndarray]]:
    """Per object (in ``model.objects`` order): its labels' indices and azimuths."""
    labels = model.labels
    return [(labels.index[labels["object"] == o].to_numpy(), labels["azimuth"].to_numpy()[labels["object"] == o])
            for o in model.objects]


def _nearest_labels(angles: list, obj: np.ndarray, azimuth: np.ndarray) -> np.ndarray:
    """The library label of each hypothesis (object index, azimuth): its object's view at the nearest azimuth."""
    out = np.empty(len(obj), dtype=np.int64)
    for i, (index, azimuths) in enumerate(angles):
        mask = obj == i
        if mask.any():
            out[mask] = index[_angle_gap(azimuth[mask, None], azimuths[None, :]).argmin(axis=1)]
    return out


def _label_cells(labels: pd.DataFrame) -> np.ndarray:
    """(S, 2) degrees below and above each label's azimuth to the midpoints with its object's neighbouring labels."""
    cells = np.full((len(labels), 2), 180.0)
    for _, group in labels.groupby("object"):
        if len(group) < 2:
            continue
        order = group.sort_values("azimuth")
        angles = order["azimuth"].to_numpy()
        gap_up = (np.roll(angles, -1) - angles) % 360.0 / 2.0
        cells[order.index.to_numpy()] = np.column_stack([np.roll(gap_up, 1), gap_up])
    return cells


class _Hypotheses:
    """What both filters share: hypotheses (``object`` index, ``azimuth``) with log-weights ``log_w``, moved by the
    odometry (eq. 4.7) and summed per object (eq. 4.1-4.2). Subclasses set ``model``, ``objects``, ``object``,
    ``azimuth``, ``log_w`` and ``steps``, and define ``update``."""

    def step(self, observations, displacement_deg: float = 0.0) -> None:
        """One stop: propagate by the odometry and weigh by the new observations (:meth:`update`).

        Parameters
        ----------
        observations : list of (M,) arrays or of Descriptor, or an (n, M) array
            The descriptors of the views taken at this stop (a set Z_t, eq. 4.4).
        displacement_deg : float
            The azimuth the robot moved since the last stop (odometry); any real number.
        """
        self.update(self.model.log_likelihood(observations), displacement_deg)

    def _move(self, displacement_deg: float) -> None:
        """Eq. 4.7: every hypothesis turns with the robot; angles wrap."""
        if not np.isfinite(displacement_deg):
            raise HeatdataError(f"displacement must be a finite angle in degrees, got {displacement_deg}")
        self.azimuth = (self.azimuth + displacement_deg) % 360.0
        self.steps += 1

    @property
    def weights(self) -> np.ndarray:
        return np.exp(self.log_w)

    def posterior(self) -> dict[str, float]:
        """p(object | Z_1:t, Delta_1:t-1): the summed weight of each object's hypotheses (eq. 4.1-4.2)."""
        mass = np.bincount(self.object, weights=self.weights, minlength=len(self.objects))
        return {o: float(m) for o, m in zip(self.objects, mass / mass.sum(), strict=True)}

    @property
    def estimate(self) -> str:
        """The most probable object."""
        posterior = self.posterior()
        return max(posterior, key=posterior.get)


class ParticleFilter(_Hypotheses):
    """Algorithm 4.1: multiple hypotheses (object, view angle) over multiple views, seeded.

    Parameters
    ----------
    library : DataFrame or AppearanceModel
        Library descriptors (``object``, ``azimuth``, ``values``; one kind), or their model
        (:func:`appearance_model`, to share it between filters).
    similarity : DataFrame or (S, S) array
        :func:`learn_similarity` on this library, or its :func:`similarity_matrix`.
    particles : int
        N, the number of particles.
    bootstrap : {"similarity", "angular"}
        The re-population of 4.4.6, or the baseline of 4.5: random angles within
        ``neighbourhood`` degrees of a surviving particle, of its object.
    tau_boot : float in [0, 1]
        Particles whose hypothesis (their label's summed weight) weighs below ``tau_boot``
        times the best hypothesis are replaced.
    sigma_min : float in [0, 1)
        Labels whose similarity to the survivors (eq. 4.9, as a fraction of the largest)
        is below this are not re-populated.
    restart : float
        Restart (4.4.4) when the particles explain an observation this many times worse
        than the library's best label: ``sum_i w_i p(Z|s_i) < restart * max_s p(Z|s)``.
    max_restarts : int
        Draws of new particles for one observation before the step gives up (logged).
    newcomer : {"mean", "least"}
        The weight a re-populated particle starts at: the survivors' mean, or the least
        survivor's (the thesis does not say; "mean" keeps look-alikes of the best
        hypothesis competitive, so one ambiguous stop does not erase an object's evidence).
    repopulate : {"cell", "view"}
        Where a re-populated particle of label s starts: uniformly in s's cell (the
        azimuths whose nearest library view is s), or at s's own azimuth. With sparse
        libraries (7 views, 51 deg apart) "view" leaves only 7 phases per object.
    alpha : float, optional
        A fixed alpha for the appearance model (default: the one learned with the
        similarity, :func:`learn_similarity`).
    seed : int
    """

    def __init__(self, library: pd.DataFrame, similarity: pd.DataFrame, particles: int = 100, *,
                 bootstrap: str = "similarity", tau_boot: float = 0.5, sigma_min: float = 0.2,
                 neighbourhood: float = 30.0, restart: float = 1e-3, max_restarts: int = 10,
                 newcomer: str = "mean", repopulate: str = "cell", alpha: float | None = None, seed: int = 0):
        if particles < 1 or int(particles) != particles:
            raise HeatdataError(f"particles must be a whole number >= 1, got {particles}")
        if bootstrap not in ("similarity", "angular"):
            raise HeatdataError(f"bootstrap is 'similarity' (4.4.6) or 'angular' (the baseline of 4.5), "
                                f"got {bootstrap!r}")
        if not 0.0 <= tau_boot <= 1.0 or not 0.0 <= sigma_min < 1.0:
            raise HeatdataError(f"tau_boot must be in [0, 1] and sigma_min in [0, 1), got {tau_boot}, {sigma_min}")
        if newcomer not in ("mean", "least"):
            raise HeatdataError(f"newcomer is 'mean' or 'least' (the survivors' weight a re-populated particle "
                                f"starts at), got {newcomer!r}")
        if repopulate not in ("cell", "view"):
            raise HeatdataError(f"repopulate is 'cell' or 'view' (where in its label a re-populated particle "
                                f"starts), got {repopulate!r}")
        if isinstance(library, AppearanceModel):
            self.model = library
        elif isinstance(similarity, np.ndarray):
            self.model = appearance_model(library, alpha=alpha)
        else:
            self.model = filter_model(library, similarity, alpha)
        if isinstance(similarity, np.ndarray):
            if similarity.shape != (len(self.model.labels),) * 2:
                raise HeatdataError(f"a similarity matrix must be {len(self.model.labels)} x {len(self.model.labels)} "
                                    f"(the library's labels), got {similarity.shape}")
            self.mu = similarity
        else:
            self.mu = similarity_matrix(self.model, similarity)
        self.n = int(particles)
        self.bootstrap_rule, self.tau_boot, self.sigma_min = bootstrap, tau_boot, sigma_min
        self.neighbourhood, self.restart, self.max_restarts = neighbourhood, restart, max_restarts
        self.newcomer, self.repopulate = newcomer, repopulate
        self.rng = np.random.default_rng(seed)
        self.objects = self.model.objects
        self._object_index = self.model.labels["object"].map({o: i for i, o in enumerate(self.objects)}).to_numpy()
        self._angles = _object_angles(self.model)
        self._cells = _label_cells(self.model.labels)
        self.position, self.visited = 0.0, []  # the robot's azimuth by odometry, relative to its first stop
        self.steps = 0
        self.restarts = 0
        self._draw()

    # --- state -----------------------------------------------------------------------------------------------------
    def _draw(self) -> None:
        """Uniform particles over objects and view angles, equal weights (4.4.1)."""
        self.object = self.rng.integers(len(self.objects), size=self.n)
        self.azimuth = self.rng.uniform(0.0, 360.0, size=self.n)
        self.log_w = np.full(self.n, -np.log(self.n))

    def labels(self, obj: np.ndarray | None = None, azimuth: np.ndarray | None = None) -> np.ndarray:
        """The library label of each particle: its object's library view at the nearest azimuth."""
        return _nearest_labels(self._angles, self.object if obj is None else obj,
                               self.azimuth if azimuth is None else azimuth)

    @property
    def converged(self) -> bool:
        """All particles agree on the object (4.4.7)."""
        return bool(np.all(self.object == self.object[0]))

    # --- Algorithm 4.1 ----------------------------------------------------------------------------------------------
    def update(self, log_p: np.ndarray, displacement_deg: float = 0.0) -> None:
        """:meth:`step` from the observations' log p(Z | s) of every library label (precomputed, e.g. cached)."""
        self._move(displacement_deg)
        self.position = (self.position + displacement_deg) % 360.0
        self.visited.append(self.position)
        for attempt in range(self.max_restarts + 1):
            prior = self.log_w + log_p[self.labels()]  # 4.4.3: w_t = w_t-1 p(Z_t | s_t)
            explained = logsumexp(prior) - log_p.max()
            if explained >= np.log(self.restart):
                break
            if attempt == self.max_restarts:
                log.warning("no particles explain the observation after %d restarts; keeping the last draw",
                            self.max_restarts)
                break
            self.restarts += 1  # 4.4.4: new uniform particles, the robot waits
            log.debug("restart %d: the particles explain the observation %.1e times the best label", attempt + 1,
                      np.exp(explained))
            self._draw()
        self.log_w = prior - logsumexp(prior)  # eq. 4.8
        if not self.converged:
            self._bootstrap()

    def _bootstrap(self) -> None:
        """4.4.6: replace particles far below the best hypothesis by views that resemble the survivors."""
        labels = self.labels()
        w = self.weights
        hypothesis = np.bincount(labels, weights=w, minlength=len(self.model.labels))
        drop = hypothesis[labels] / hypothesis.max() < self.tau_boot  # the best hypothesis always survives
        if not drop.any():
            return
        keep = ~drop
        count = int(drop.sum())
        if self.bootstrap_rule == "similarity":
            # eq. 4.9: mu(s, S_remain) = sum_i w_i mu(s | s_i) over the survivors
            score = self.mu[:, labels[keep]] @ w[keep]
            score = np.where(score >= self.sigma_min * score.max(), score, 0.0) if score.max() > 0 else score
            if score.sum() <= 0:
                score = np.bincount(labels[keep], weights=w[keep], minlength=len(score))
            chosen = stochastic_universal_sampling(score, count, self.rng)
            new_object = self._object_index[chosen]
            new_azimuth = self.model.labels["azimuth"].to_numpy()[chosen]
            if self.repopulate == "cell":  # anywhere the label's view is its object's nearest library view
                low, high = self._cells[chosen].T
                new_azimuth = (new_azimuth + self.rng.uniform(-low, high)) % 360.0
        else:  # the baseline of 4.5: near a survivor, in angle only
            parents = np.flatnonzero(keep)[stochastic_universal_sampling(w[keep], count, self.rng)]
            new_object = self.object[parents]
            new_azimuth = (self.azimuth[parents] + self.rng.uniform(-self.neighbourhood, self.neighbourhood, count)
                           ) % 360.0
        self.object = np.concatenate([self.object[keep], new_object])
        self.azimuth = np.concatenate([self.azimuth[keep], new_azimuth])
        # survivors keep the evidence of every stop so far (w_t = w_t-1 p(Z_t | s), 4.4.3); a newcomer has none of
        # its own: it starts at the survivors' mean weight (it looks like them) or at the least one's
        survivors = self.log_w[keep]
        start = logsumexp(survivors) - np.log(len(survivors)) if self.newcomer == "mean" else survivors.min()
        log_w = np.concatenate([survivors, np.full(count, start)])
        self.log_w = log_w - logsumexp(log_w)

    # --- beyond the thesis: where to look next ----------------------------------------------------------------------
    def best_move(self, candidates_deg=(-90.0, -45.0, -15.0, 15.0, 45.0, 90.0), *, per_degree: bool = True,
                  revisit: float = 7.5) -> float:
        """The step whose expected observation most reduces the posterior entropy over objects.

        For each candidate step and each particle's hypothesis, the observation expected
        there is the library label the hypothesis moves to, and its likelihood under every
        particle's moved label is the learned similarity mu (eq. 4.6, from independent
        views). The expected entropy averages the resulting posteriors by the particle
        weights. With ``per_degree`` the step maximizes the expected reduction per degree
        travelled (the robot's effort), else the reduction itself; ties go to the shorter
        step, and when no step is expected to help, the shortest forward one is taken.
        A step back to within ``revisit`` degrees of a stop already made (by odometry) is
        expected to teach nothing: the views there were seen, and seeing them again is
        not independent evidence.
        """
        candidates = np.asarray(list(candidates_deg), dtype=np.float64)
        if not len(candidates) or not np.isfinite(candidates).all():
            raise HeatdataError(f"candidate steps must be finite angles in degrees, got {list(candidates_deg)}")
        w = self.weights
        expected = []
        for step in candidates:
            moved = self.labels(self.object, (self.azimuth + step) % 360.0)
            # p(observation from moved[j] | particle i at moved[i]): mu[moved[j], moved[i]]
            likelihood = self.mu[np.ix_(moved, moved)]
            posterior = w[None, :] * likelihood
            total = posterior.sum(axis=1, keepdims=True)
            # an outcome no particle explains (no similarity learned for its label) teaches nothing: the prior
            posterior = np.where(total > 0, posterior / np.where(total > 0, total, 1.0), w[None, :])
            per_object = np.zeros((self.n, len(self.objects)))
            np.add.at(per_object.T, self.object, posterior.T)
            entropy = -np.sum(np.where(per_object > 0, per_object * np.log(np.maximum(per_object, 1e-300)), 0.0),
                              axis=1)
            expected.append(float(w @ entropy))
        now = np.bincount(self.object, weights=w, minlength=len(self.objects))
        gain = -np.sum(now[now > 0] * np.log(now[now > 0])) - np.array(expected)
        fresh = np.ones(len(candidates), dtype=bool)
        if self.visited:
            seen = _angle_gap((self.position + candidates)[:, None], np.array(self.visited)[None, :]).min(axis=1)
            fresh = seen > revisit
            gain = np.where(fresh, gain, 0.0)
        if gain.max() <= 1e-9:  # no step is expected to tell the objects apart: keep circling, to new views if any
            pool = candidates[fresh] if fresh.any() else candidates
            forward = pool[pool > 0]
            return float(forward.min() if len(forward) else pool[np.argmin(np.abs(pool))])
        score = gain / np.maximum(np.abs(candidates), 1e-9) if per_degree else gain
        best = np.flatnonzero(score >= score.max() - 1e-12)
        return float(candidates[best[np.argmin(np.abs(candidates[best]))]])


class ExhaustiveFilter(_Hypotheses):
    """The exact Bayes filter of eq. 4.1-4.2: every object at every start azimuth of a grid, none ever dropped.

    The reference the particles approximate: hypotheses ``(object, start azimuth)`` on a
    ``resolution``-degree grid, each moved by the odometry (eq. 4.7) and weighed by the
    appearance model at its object's nearest library view, every stop (exhaustive search:
    every library label is compared with every observation). Its errors are the
    appearance model's, not the sampling's.

    Parameters
    ----------
    library : DataFrame or AppearanceModel
        As for :class:`ParticleFilter`.
    resolution : float
        Degrees between start azimuths (360 / resolution per object).
    confidence : float in (0.5, 1)
        :attr:`converged` when one object holds this much of the posterior.
    alpha : float, optional
        A fixed alpha (default: the library's own, :func:`appearance_model`).
    """

    def __init__(self, library, *, resolution: float = 1.0, confidence: float = 0.99, alpha: float | None = None):
        if not 0.0 < resolution <= 360.0:
            raise HeatdataError(f"resolution must be in (0, 360] degrees, got {resolution}")
        if not 0.5 < confidence < 1.0:
            raise HeatdataError(f"confidence must be in (0.5, 1), got {confidence}")
        self.model = library if isinstance(library, AppearanceModel) else appearance_model(library, alpha=alpha)
        self.objects = self.model.objects
        self.confidence = confidence
        grid = np.arange(0.0, 360.0, resolution)
        self.object = np.repeat(np.arange(len(self.objects)), len(grid))
        self.azimuth = np.tile(grid, len(self.objects))
        self.log_w = np.full(len(self.object), -np.log(len(self.object)))
        self._angles = _object_angles(self.model)
        self.steps = 0
        self.restarts = 0  # never: no hypothesis is ever dropped

    def update(self, log_p: np.ndarray, displacement_deg: float = 0.0) -> None:
        """As :meth:`ParticleFilter.update`: move every hypothesis, weigh it, normalize (eq. 4.8)."""
        self._move(displacement_deg)
        log_w = self.log_w + log_p[_nearest_labels(self._angles, self.object, self.azimuth)]
        self.log_w = log_w - logsumexp(log_w)

    @property
    def converged(self) -> bool:
        """One object holds ``confidence`` of the posterior."""
        return max(self.posterior().values()) >= self.confidence


# --- the robot and the experiments of 4.5 -------------------------------------------------------------------------
def robot_views(model, start_azimuth: float, moves, spec, *, per_stop: int = 2, elevation: float = 30.0,
                distance: float = 1.0, noise: bool = True, seed: int = 0) -> list[tuple[list, float]]:
    """A simulated robot circling ``model`` (4.5.4): rendered noisy views along its path, with the odometry.

    Parameters
    ----------
    model : Model
    start_azimuth : float
        Where the robot starts, degrees.
    moves : sequence of float
        The azimuth steps between stops (e.g. ``[15] * 23``); the first stop is the start.
    spec : DescriptorSpec
        How each view is described.
    per_stop : int
        Views taken at each stop, each with its own noise (two in the thesis).

    Returns
    -------
    list of (descriptors, displacement)
        Per stop: the ``per_stop`` descriptors and the azimuth moved since the last stop
        (0 at the start), ready for :meth:`ParticleFilter.step`.
    """
    from .descriptors import describe
    from .render import render_view

    path, azimuth = [], float(start_azimuth)
    for k, move in enumerate([0.0, *moves]):
        azimuth += move
        views = [render_view(model, azimuth % 360.0, elevation, distance, noise=noise, seed=seed + 1000 * k + j)
                 for j in range(per_stop)]
        path.append(([describe(v, [spec])[0] for v in views], float(move)))
    return path


class TableRobot:
    """The robot of the experiments: at each stop it observes the ``per_stop`` test views nearest its azimuth.

    The log-likelihoods of each stop's observations under the appearance model are
    cached, so many runs over the same test views cost one comparison per stop.
    """

    def __init__(self, model: AppearanceModel, tests: pd.DataFrame, per_stop: int = 2):
        if tests["object"].nunique() != 1:
            raise HeatdataError(f"a robot observes one object, got {sorted(tests['object'].unique())}")
        if per_stop < 1 or per_stop > len(tests):
            raise HeatdataError(f"per_stop must be in 1..{len(tests)} (the test views), got {per_stop}")
        self.model, self.per_stop = model, per_stop
        self.azimuths = tests["azimuth"].to_numpy(dtype=np.float64)
        self.values = list(tests["values"])
        self._cache: dict[tuple, np.ndarray] = {}

    def views(self, azimuth: float) -> tuple:
        """Indices of the test views seen from ``azimuth``: the nearest ones."""
        order = np.argsort(_angle_gap(self.azimuths, azimuth % 360.0), kind="stable")
        return tuple(sorted(order[:self.per_stop].tolist()))

    def log_likelihood(self, azimuth: float) -> np.ndarray:
        """log p(Z | s) of the observations at ``azimuth`` for every library label."""
        key = self.views(azimuth)
        if key not in self._cache:
            self._cache[key] = self.model.log_likelihood([self.values[i] for i in key])
        return self._cache[key]


def recognize(f: ParticleFilter | ExhaustiveFilter, robot: TableRobot, start: float, *, policy: str = "fixed",
              step: float = 15.0, candidates=(-90.0, -45.0, -15.0, 15.0, 45.0, 90.0), max_degrees: float = 720.0
              ) -> dict:
    """Run Algorithm 4.1 (or the exhaustive filter) with ``robot`` from ``start`` until it converges or travels
    ``max_degrees``.

    ``policy`` is ``"fixed"`` (``step`` degrees each time, as in 4.5.4) or ``"active"``
    (:meth:`ParticleFilter.best_move` among ``candidates``). Returns the estimate,
    whether it converged, the degrees travelled, the stops and the restarts.
    """
    if policy not in ("fixed", "active"):
        raise HeatdataError(f"policy is 'fixed' or 'active', got {policy!r}")
    if policy == "active" and not hasattr(f, "best_move"):
        raise HeatdataError(f"the active policy needs a ParticleFilter, got {type(f).__name__}")
    azimuth, travelled = float(start), 0.0
    f.update(robot.log_likelihood(azimuth), 0.0)
    while not f.converged:
        move = step if policy == "fixed" else f.best_move(candidates)
        if travelled + abs(move) > max_degrees:
            break
        azimuth += move
        travelled += abs(move)
        f.update(robot.log_likelihood(azimuth), move)
    return {"estimate": f.estimate, "converged": f.converged, "degrees": travelled, "stops": f.steps,
            "restarts": f.restarts}


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
    table = pd.DataFrame({"object": tests["object"].to_numpy(), "azimuth": tests["azimuth"].to_numpy(),
                          "margin": d[rows, other] - np.where(own, d, np.inf).min(axis=1),
                          "nearest_other": model.labels["object"].to_numpy()[other]}).sort_values(["object", "margin"])
    return table.groupby("object").head(count).reset_index(drop=True)


def multiview_trials(library: pd.DataFrame, similarity: pd.DataFrame, tests: pd.DataFrame, starts: pd.DataFrame, *,
                     particles=(10, 50, 100), bootstraps=("similarity", "angular"), policies=("fixed",),
                     repetitions: int = 30, exhaustive: bool = True, seed: int = 0, **options) -> pd.DataFrame:
    """The experiments of 4.5: every start view x particle count x bootstrap x policy x repetition.

    ``starts`` has ``object`` and ``azimuth`` (e.g. :func:`ambiguous_starts`); ``tests``
    holds each object's test views (observations are the two nearest each stop).
    ``options`` go to :class:`ParticleFilter` (``tau_boot``, ``sigma_min``, ``alpha``, ...)
    and to :func:`recognize` (``step``, ``candidates``, ``max_degrees``, ``per_stop``).
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

    from .log import progress

    run_keys = {"step", "candidates", "max_degrees"}
    run_options = {k: v for k, v in options.items() if k in run_keys}
    per_stop = options.pop("per_stop", 2)
    filter_options = {k: v for k, v in options.items() if k not in run_keys}
    model = filter_model(library, similarity, filter_options.get("alpha"))
    mu = similarity_matrix(model, similarity)
    robots = {obj: TableRobot(model, rows, per_stop) for obj, rows in tests.groupby("object")}
    missing = sorted(set(starts["object"]) - set(robots))
    if missing:
        raise HeatdataError(f"no test views of start object(s) {missing}")
    labels = len(model.labels)
    jobs = [(s, n, b, p, r) for s in starts.itertuples() for n in particles for b in bootstraps for p in policies
            if not (p == "active" and b != "similarity") for r in range(repetitions)]
    jobs += [(s, 0, "exhaustive", "fixed", 0) for s in starts.itertuples()] if exhaustive else []
    rows = []
    for k, (start, n, boot, policy, rep) in enumerate(progress(jobs, desc="multi-view trials", unit="run")):
        begin = time.perf_counter()
        if boot == "exhaustive":
            f = ExhaustiveFilter(model)
            n = len(f.object)
        else:
            f = ParticleFilter(model, mu, particles=n, bootstrap=boot, seed=seed + k, **filter_options)
        result = recognize(f, robots[start.object], start.azimuth, policy=policy, **run_options)
        rows.append({"object": start.object, "start": start.azimuth, "particles": n, "bootstrap": boot,
                     "policy": policy, "repetition": rep, **result,
                     "correct": result["converged"] and result["estimate"] == start.object,
                     "identified": result["estimate"] == start.object,
                     "comparisons": (labels if boot == "exhaustive" else n) * result["stops"],
                     "exhaustive": labels * result["stops"],
                     "seconds": time.perf_counter() - begin})
    return pd.DataFrame(rows)


def split_tests(rows: pd.DataFrame) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Each object's test views split by azimuth rank: even ranks learn the similarity, odd ranks are observed.

    The two halves interleave in angle and have their own noise, so the similarity of
    eq. 4.6 is learned from views independent of both the library and the test views.
    """
    ranked = rows.sort_values(["object", "azimuth"], kind="stable")
    rank = ranked.groupby("object").cumcount().to_numpy()
    return ranked[rank % 2 == 0], ranked[rank % 2 == 1]


def multiview_experiment(descriptors: pd.DataFrame, descriptor: str, settings: dict
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
    from .library import library_subset

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
        log.info("%d library views per object: %d start views, margins %s", size, len(starts),
                 np.round(starts["margin"].to_numpy(), 3).tolist())
        options = {k: settings[k] for k in ("step", "per_stop", "max_degrees", "tau_boot", "sigma_min", "alpha")}
        table = multiview_trials(library, similarity, tests, starts, particles=settings["particles"],
                                 policies=settings["policies"], repetitions=settings["repetitions"],
                                 seed=settings["seed"], candidates=tuple(settings["candidates"]), **options)
        trials.append(table.assign(library_views=size, descriptor=descriptor))
        similarities.append(similarity.assign(library_views=size))
    return pd.concat(trials, ignore_index=True), pd.concat(similarities, ignore_index=True)


def trial_summary(trials: pd.DataFrame) -> pd.DataFrame:
    """Accuracy (converged on the true object), identified (true object most probable at the end), degrees
    travelled and comparisons per setting."""
    keys = ["library_views", "policy", "bootstrap", "particles"]
    summary = trials.groupby(keys).agg(runs=("correct", "size"), accuracy=("correct", "mean"),
                                       identified=("identified", "mean"),
                                       converged=("converged", "mean"), degrees=("degrees", "mean"),
                                       stops=("stops", "mean"), comparisons=("comparisons", "mean"),
                                       exhaustive=("exhaustive", "mean"), seconds=("seconds", "mean"))
    return summary.reset_index()
