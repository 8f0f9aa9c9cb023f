"""The filters of thesis ch. 4: Algorithm 4.1's particle filter with its similarity bootstrap, and the exact grid."""

from __future__ import annotations

import logging
from abc import ABC, abstractmethod
from collections.abc import Sequence

import numpy as np
import pandas as pd
from scipy.special import logsumexp

from heatdata.errors import HeatdataError
from heatdata.recognition.multiview.appearance import (
    AppearanceModel,
    angle_gap,
    appearance_model,
    filter_model,
    similarity_matrix,
)

log = logging.getLogger(__name__)

#: the most particles a filter draws: a million (hypotheses of object and azimuth) fit in well under 1 GB
MAX_PARTICLES = 1_000_000


def stochastic_universal_sampling(weights: np.ndarray, count: int, rng: np.random.Generator) -> np.ndarray:
    """``count`` indices drawn in proportion to ``weights`` with one random offset (Baker 1987)."""
    cumulative = np.cumsum(weights / weights.sum())
    pointers = (rng.random() + np.arange(count)) / count
    return np.minimum(np.searchsorted(cumulative, pointers, side="right"), len(weights) - 1)


def _object_angles(model: AppearanceModel) -> list[tuple[np.ndarray, np.ndarray]]:
    """Per object (in ``model.objects`` order): its labels' indices and azimuths."""
    labels = model.labels
    return [
        (labels.index[labels["object"] == o].to_numpy(), labels["azimuth"].to_numpy()[labels["object"] == o])
        for o in model.objects
    ]


def _nearest_labels(angles: list, obj: np.ndarray, azimuth: np.ndarray) -> np.ndarray:
    """The library label of each hypothesis (object index, azimuth): its object's view at the nearest azimuth."""
    out = np.empty(len(obj), dtype=np.int64)
    for i, (index, azimuths) in enumerate(angles):
        mask = obj == i
        if mask.any():
            out[mask] = index[angle_gap(azimuth[mask, None], azimuths[None, :]).argmin(axis=1)]
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


class HypothesisFilter(ABC):
    """What both filters share: hypotheses (``object`` index, ``azimuth``) with log-weights ``log_w``, moved by the
    odometry (eq. 4.7) and summed per object (eq. 4.1-4.2). Subclasses set the attributes below and define
    :meth:`update` and :attr:`converged`."""

    #: the appearance model the hypotheses are weighed by (eq. 4.5)
    model: AppearanceModel
    #: the library's objects; ``object`` indexes them
    objects: list[str]
    #: (H,) int: each hypothesis's object
    object: np.ndarray
    #: (H,) float: each hypothesis's view angle, degrees
    azimuth: np.ndarray
    #: (H,) float: log-weights, normalized
    log_w: np.ndarray
    #: stops so far, and restarts (4.4.4; the exhaustive filter never restarts)
    steps: int
    restarts: int
    #: log of the probability that the object is none of the library's (None: no such hypothesis, the thesis's)
    log_unknown: float | None = None

    def expect_unknown(self, prior: float) -> None:
        """Add the hypothesis "an object the library lacks", with prior probability ``prior`` in (0, 1).

        Its evidence at each stop is the library's calibrated confidence (:meth:`weigh_unknown`). With the prior at
        the library's confidence threshold, a single view is unknown exactly when its confidence is below the
        threshold, as :meth:`heatdata.recognition.library.Library.recognize` says.
        """
        if not 0.0 < prior < 1.0:
            raise HeatdataError(f"the unknown hypothesis's prior must be in (0, 1), got {prior}")
        self.log_unknown = float(np.log(prior))
        self._log_known = float(np.log1p(-prior))

    def weigh_unknown(self, confidence: float) -> None:
        """One stop's evidence for the unknown hypothesis: ``confidence`` in [0, 1], how likely the stop's view is of
        an object of the library (:class:`heatdata.recognition.confidence.Confidence`), weighs the library's objects
        together by ``confidence`` and the unknown object by ``1 - confidence`` (views independent, as eq. 4.3)."""
        if self.log_unknown is None:
            raise HeatdataError("this filter has no unknown hypothesis (expect_unknown first)")
        if not 0.0 <= confidence <= 1.0:
            raise HeatdataError(f"a confidence is in [0, 1], got {confidence}")
        sure = float(np.clip(confidence, 1e-12, 1.0 - 1e-12))
        known, unknown = self._log_known + np.log(sure), self.log_unknown + np.log1p(-sure)
        total = np.logaddexp(known, unknown)
        self._log_known, self.log_unknown = known - total, unknown - total

    @property
    def unknown(self) -> float:
        """The probability that the object is none of the library's (0 without the hypothesis)."""
        return 0.0 if self.log_unknown is None else float(np.exp(self.log_unknown))

    @abstractmethod
    def update(self, log_p: np.ndarray, displacement_deg: float = 0.0) -> None:
        """One stop from the observations' log p(Z | s) of every library label (precomputed, e.g. cached)."""

    @property
    @abstractmethod
    def converged(self) -> bool:
        """Whether the filter has settled on one object."""

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
        """p(object | Z_1:t, Delta_1:t-1): the summed weight of each object's hypotheses (eq. 4.1-4.2), times the
        probability that the object is one of the library's (:attr:`unknown` holds the rest)."""
        mass = np.bincount(self.object, weights=self.weights, minlength=len(self.objects))
        known = 1.0 - self.unknown
        return {o: float(m) * known for o, m in zip(self.objects, mass / mass.sum(), strict=True)}

    @property
    def estimate(self) -> str | None:
        """The most probable object; None when an object the library lacks is more probable than each of its."""
        posterior = self.posterior()
        best = max(posterior, key=lambda o: posterior[o])
        return None if self.unknown > posterior[best] else best


class ParticleFilter(HypothesisFilter):
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

    def __init__(
        self,
        library: pd.DataFrame,
        similarity: pd.DataFrame,
        particles: int = 100,
        *,
        bootstrap: str = "similarity",
        tau_boot: float = 0.5,
        sigma_min: float = 0.2,
        neighbourhood: float = 30.0,
        restart: float = 1e-3,
        max_restarts: int = 10,
        newcomer: str = "mean",
        repopulate: str = "cell",
        alpha: float | None = None,
        seed: int = 0,
    ):
        if not (1 <= particles <= MAX_PARTICLES and int(particles) == particles):
            raise HeatdataError(f"particles must be a whole number in [1, {MAX_PARTICLES:,}], got {particles}")
        if bootstrap not in ("similarity", "angular"):
            raise HeatdataError(
                f"bootstrap is 'similarity' (4.4.6) or 'angular' (the baseline of 4.5), got {bootstrap!r}"
            )
        if not 0.0 <= tau_boot <= 1.0 or not 0.0 <= sigma_min < 1.0:
            raise HeatdataError(f"tau_boot must be in [0, 1] and sigma_min in [0, 1), got {tau_boot}, {sigma_min}")
        if newcomer not in ("mean", "least"):
            raise HeatdataError(
                f"newcomer is 'mean' or 'least' (the survivors' weight a re-populated particle "
                f"starts at), got {newcomer!r}"
            )
        if repopulate not in ("cell", "view"):
            raise HeatdataError(
                f"repopulate is 'cell' or 'view' (where in its label a re-populated particle "
                f"starts), got {repopulate!r}"
            )
        if isinstance(library, AppearanceModel):
            self.model = library
        elif isinstance(similarity, np.ndarray):
            self.model = appearance_model(library, alpha=alpha)
        else:
            self.model = filter_model(library, similarity, alpha)
        if isinstance(similarity, np.ndarray):
            if similarity.shape != (len(self.model.labels),) * 2:
                raise HeatdataError(
                    f"a similarity matrix must be {len(self.model.labels)} x {len(self.model.labels)} "
                    f"(the library's labels), got {similarity.shape}"
                )
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
        self.position = 0.0  # the robot's azimuth by odometry, relative to its first stop
        self.visited: list[float] = []
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
        """The library label of each particle: its object's library view at the nearest azimuth.

        Parameters
        ----------
        obj : (N,) int, optional
            Objects (default the particles').
        azimuth : (N,) float, optional
            View angles in degrees (default the particles').

        Returns
        -------
        (N,) int
            The library label (row of the model's ``labels``) of each.
        """
        return _nearest_labels(
            self._angles, self.object if obj is None else obj, self.azimuth if azimuth is None else azimuth
        )

    @property
    def converged(self) -> bool:
        """All particles agree on the object (4.4.7)."""
        return bool(np.all(self.object == self.object[0]))

    # --- Algorithm 4.1 ----------------------------------------------------------------------------------------------
    def update(self, log_p: np.ndarray, displacement_deg: float = 0.0) -> None:
        """:meth:`step` from the observations' log p(Z | s) of every library label (precomputed, e.g. cached).

        Parameters
        ----------
        log_p : (S,) float
            log p(Z | s) of the stop's observations for every library label
            (:meth:`AppearanceModel.log_likelihood`).
        displacement_deg : float
            The azimuth moved since the last stop (odometry).
        """
        self._move(displacement_deg)
        self.position = (self.position + displacement_deg) % 360.0
        self.visited.append(self.position)
        for attempt in range(self.max_restarts + 1):
            prior = self.log_w + log_p[self.labels()]  # 4.4.3: w_t = w_t-1 p(Z_t | s_t)
            explained = logsumexp(prior) - log_p.max()
            if explained >= np.log(self.restart):
                break
            if attempt == self.max_restarts:
                log.warning(
                    "no particles explain the observation after %d restarts; keeping the last draw", self.max_restarts
                )
                break
            self.restarts += 1  # 4.4.4: new uniform particles, the robot waits
            log.debug(
                "restart %d: the particles explain the observation %.1e times the best label",
                attempt + 1,
                np.exp(explained),
            )
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
            new_object, new_azimuth = self._similar_newcomers(labels[keep], w[keep], count)
        else:
            new_object, new_azimuth = self._angular_newcomers(keep, w[keep], count)
        self.object = np.concatenate([self.object[keep], new_object])
        self.azimuth = np.concatenate([self.azimuth[keep], new_azimuth])
        # survivors keep the evidence of every stop so far (w_t = w_t-1 p(Z_t | s), 4.4.3); a newcomer has none of
        # its own: it starts at the survivors' mean weight (it looks like them) or at the least one's
        survivors = self.log_w[keep]
        start = logsumexp(survivors) - np.log(len(survivors)) if self.newcomer == "mean" else survivors.min()
        log_w = np.concatenate([survivors, np.full(count, start)])
        self.log_w = log_w - logsumexp(log_w)

    def _similar_newcomers(self, survivors: np.ndarray, w: np.ndarray, count: int) -> tuple[np.ndarray, np.ndarray]:
        """4.4.6: ``count`` newcomers at labels that resemble the survivors' (their labels, weights ``w``)."""
        # eq. 4.9: mu(s, S_remain) = sum_i w_i mu(s | s_i) over the survivors
        score = self.mu[:, survivors] @ w
        score = np.where(score >= self.sigma_min * score.max(), score, 0.0) if score.max() > 0 else score
        if score.sum() <= 0:
            score = np.bincount(survivors, weights=w, minlength=len(score))
        chosen = stochastic_universal_sampling(score, count, self.rng)
        azimuth = self.model.labels["azimuth"].to_numpy()[chosen]
        if self.repopulate == "cell":  # anywhere the label's view is its object's nearest library view
            low, high = self._cells[chosen].T
            azimuth = (azimuth + self.rng.uniform(-low, high)) % 360.0
        return self._object_index[chosen], azimuth

    def _angular_newcomers(self, keep: np.ndarray, w: np.ndarray, count: int) -> tuple[np.ndarray, np.ndarray]:
        """The baseline of 4.5: ``count`` newcomers near a survivor (mask ``keep``, weights ``w``), in angle only."""
        parents = np.flatnonzero(keep)[stochastic_universal_sampling(w, count, self.rng)]
        azimuth = self.azimuth[parents] + self.rng.uniform(-self.neighbourhood, self.neighbourhood, count)
        return self.object[parents], azimuth % 360.0

    # --- beyond the thesis: where to look next ----------------------------------------------------------------------
    def best_move(
        self,
        candidates_deg: Sequence[float] = (-90.0, -45.0, -15.0, 15.0, 45.0, 90.0),
        *,
        per_degree: bool = True,
        revisit: float = 7.5,
    ) -> float:
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

        Parameters
        ----------
        candidates_deg : sequence of float
            The steps to choose among, degrees (any sign).
        per_degree : bool
            Maximize the expected reduction per degree travelled, else the reduction itself.
        revisit : float
            Degrees within which a stop already made teaches nothing.

        Returns
        -------
        float
            The chosen step, degrees.
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
            entropy = -np.sum(
                np.where(per_object > 0, per_object * np.log(np.maximum(per_object, 1e-300)), 0.0), axis=1
            )
            expected.append(float(w @ entropy))
        now = np.bincount(self.object, weights=w, minlength=len(self.objects))
        gain = -np.sum(now[now > 0] * np.log(now[now > 0])) - np.array(expected)
        fresh = np.ones(len(candidates), dtype=bool)
        if self.visited:
            seen = angle_gap((self.position + candidates)[:, None], np.array(self.visited)[None, :]).min(axis=1)
            fresh = seen > revisit
            gain = np.where(fresh, gain, 0.0)
        if gain.max() <= 1e-9:  # no step is expected to tell the objects apart: keep circling, to new views if any
            pool = candidates[fresh] if fresh.any() else candidates
            forward = pool[pool > 0]
            return float(forward.min() if len(forward) else pool[np.argmin(np.abs(pool))])
        score = gain / np.maximum(np.abs(candidates), 1e-9) if per_degree else gain
        best = np.flatnonzero(score >= score.max() - 1e-12)
        return float(candidates[best[np.argmin(np.abs(candidates[best]))]])


class ExhaustiveFilter(HypothesisFilter):
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

    def __init__(
        self,
        library: pd.DataFrame | AppearanceModel,
        *,
        resolution: float = 1.0,
        confidence: float = 0.99,
        alpha: float | None = None,
    ):
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
        """As :meth:`ParticleFilter.update`: move every hypothesis, weigh it, normalize (eq. 4.8).

        Parameters
        ----------
        log_p : (S,) float
            log p(Z | s) of the stop's observations for every library label.
        displacement_deg : float
            The azimuth moved since the last stop.
        """
        self._move(displacement_deg)
        log_w = self.log_w + log_p[_nearest_labels(self._angles, self.object, self.azimuth)]
        self.log_w = log_w - logsumexp(log_w)

    @property
    def converged(self) -> bool:
        """One object, or the unknown one, holds ``confidence`` of the posterior."""
        return max(*self.posterior().values(), self.unknown) >= self.confidence
