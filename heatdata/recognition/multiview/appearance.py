"""The appearance model of thesis 4.3 and the learned similarity of 4.4.6."""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import TypeAlias

import numpy as np
import pandas as pd

from heatdata.descriptors import DEFAULT_KIND, Descriptor, kind_of, stack_values
from heatdata.errors import HeatdataError

log = logging.getLogger(__name__)


#: a set of observed descriptors: Descriptors, (M,) arrays, or one (n, M) array
Observations: TypeAlias = Sequence[Descriptor] | Sequence[np.ndarray] | np.ndarray
SIMILARITY_COLUMNS = ["object", "azimuth", "similar_object", "similar_azimuth", "similarity", "similar_alpha"]


def angle_gap(a, b) -> np.ndarray:
    """Absolute circular difference of angles in degrees, in [0, 180]."""
    return np.abs((np.asarray(a, dtype=np.float64) - b + 180.0) % 360.0 - 180.0)


def as_list(observations) -> list:
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

    def distances(self, observations: Observations) -> np.ndarray:
        """(S,) eq. 4.4 between the set of ``observations`` and every label's set Z_s.

        Parameters
        ----------
        observations : list of (M,) arrays or of Descriptor, or an (n, M) array
            The descriptors of the views taken at one stop (a set Z, eq. 4.4).

        Returns
        -------
        (S,) float64
            d(Z, Z_s) for every library label s.
        """
        kinds = {d.kind for d in as_list(observations) if isinstance(d, Descriptor)}
        if kinds - {self.kind}:
            raise HeatdataError(f"observations are {', '.join(sorted(kinds))} descriptors, the library's {self.kind}")
        z = stack_values(observations, "observations")
        if z.shape[1] != self.values.shape[1]:
            raise HeatdataError(
                f"observations have {z.shape[1]} values, the library's {self.kind} descriptors "
                f"{self.values.shape[1]}: describe them with the library's spec"
            )
        d = kind_of(self.kind).distance_matrix(z, self.values)
        starts = np.searchsorted(self.members, np.arange(len(self.labels)))  # members are sorted by label
        forward = np.minimum.reduceat(d, starts, axis=1).sum(axis=0)  # sum over Z of the nearest in Z_s
        backward = np.add.reduceat(d.min(axis=0), starts)  # sum over Z_s of the nearest in Z
        return np.minimum(forward, backward)  # eq. 4.4 for every label at once

    def nearest(self, rows: Observations) -> np.ndarray:
        """(V, S) eq. 4.4 between each single observation and every label's set: its nearest member of Z_s.

        Parameters
        ----------
        rows : list of (M,) arrays or of Descriptor, or a (V, M) array
            Single observations.

        Returns
        -------
        (V, S) float64
            Each observation's distance to every label's set.
        """
        d = kind_of(self.kind).distance_matrix(stack_values(rows, "observations"), self.values)
        return np.minimum.reduceat(d, np.searchsorted(self.members, np.arange(len(self.labels))), axis=1)

    def log_likelihood(self, observations: Observations) -> np.ndarray:
        """(S,) log p(Z | s) = -d(Z, Z_s) / alpha_s - log alpha_s (4.3).

        Parameters
        ----------
        observations : list of (M,) arrays or of Descriptor, or an (n, M) array
            The descriptors of the views taken at one stop (a set Z, eq. 4.4).

        Returns
        -------
        (S,) float64
            log p(Z | s) for every library label s.
        """
        return -self.distances(observations) / self.alpha - np.log(self.alpha)


def appearance_model(
    library: pd.DataFrame, *, alpha: float | None = None, views: pd.DataFrame | None = None
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

    Returns
    -------
    AppearanceModel
        The library's descriptor sets per label and each object's alpha.

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
    return AppearanceModel(
        labels=labels, members=members, values=values, alpha=np.ones(len(labels)), kind=str(kinds[0])
    )


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
    for _obj, group in labels.groupby("object"):
        angles = group["azimuth"].to_numpy()
        for k, angle in zip(group.index, angles, strict=True):
            if np.isnan(scales[k]) and len(group) > 1:
                gaps = angle_gap(angles, angle)
                gaps[gaps == 0] = np.inf
                neighbours = group.index[gaps == gaps.min()]
                scales[k] = min(set_distance(d[np.ix_(members == k, members == j)]) for j in neighbours)
    known = scales[np.isfinite(scales) & (scales > 0)]
    if not len(known):
        raise HeatdataError(
            "alpha cannot be estimated from this library (one view per object, or identical "
            "views): give alpha explicitly"
        )
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
    return pd.DataFrame(
        {
            "object": objects[a],
            "azimuth": azimuths[a],
            "similar_object": objects[b],
            "similar_azimuth": azimuths[b],
            "similarity": mu.ravel(),
            "similar_alpha": model.alpha[b],
        }
    )


def assign_labels(model: AppearanceModel, views: pd.DataFrame) -> pd.DataFrame:
    """``views`` with a ``label`` column: the index of its object's library label at the nearest azimuth."""
    out = views.copy()
    out["label"] = -1
    for obj, group in model.labels.groupby("object"):
        mask = (views["object"] == obj).to_numpy()
        gaps = angle_gap(views.loc[mask, "azimuth"].to_numpy()[:, None], group["azimuth"].to_numpy()[None, :])
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
        ["similar_object", "similar_azimuth"]
    )["similar_alpha"]
    learned = own.reindex(pd.MultiIndex.from_frame(model.labels)).to_numpy(dtype=np.float64)
    if len(own) != len(learned) or not np.isfinite(learned).all():
        raise HeatdataError(
            f"the similarity table ({len(own)} labels) does not match the library "
            f"({len(learned)} labels): learn it on this library"
        )
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
    labels = pd.MultiIndex.from_arrays([model.labels["object"].astype(str), model.labels["azimuth"].astype(float)])
    rows, cols = (  # vectorized: a chairs library has 2,320 labels, so 5.4 million (s, s') rows
        labels.get_indexer(pd.MultiIndex.from_arrays([similarity[o].astype(str), similarity[a].astype(float)]))
        for o, a in (("object", "azimuth"), ("similar_object", "similar_azimuth"))
    )
    whole = len(similarity) == len(labels) ** 2 and len(np.unique(rows[rows >= 0])) == len(labels)
    if not whole or (rows < 0).any() or (cols < 0).any():
        table_labels = similarity[["object", "azimuth"]].drop_duplicates()
        raise HeatdataError(
            f"the similarity table ({len(table_labels)} labels, {len(similarity)} rows) does not "
            f"match the library ({len(labels)} labels): learn it on this library"
        )
    mu = np.zeros((len(labels), len(labels)))
    mu[rows, cols] = np.nan_to_num(similarity["similarity"].to_numpy(dtype=np.float64), nan=0.0)
    return mu
