"""Built libraries (thesis ch. 3-5): a run's library views in one self-describing file, and recognition.

A library file is a Parquet table of :data:`heatdata.io.tables.DESCRIPTOR_SCHEMA` rows: the library views of one
descriptor at one library size (``split = "train"``), and views independent of them (``split = "similarity"``)
from which the particle filter learns which views look alike (eq. 4.6). Its metadata holds what describing a new
view the same way needs: the descriptor spec with its options and anything fitted, the objects' time scales
(Alg. 5.1, for the FT-PVHK), the run's render settings, the time rule of Alg. 5.2 and heatdata's version, and a
*probe*: the descriptor of a fixed synthetic view. :func:`load_library` describes the probe again and refuses a
library whose probe this heatdata describes differently, so a library is never compared with descriptors made
another way.

:meth:`Library.recognize` answers the thesis's question for one view (Alg. 3.1; Alg. 5.2 for a time-scaled kind):
which objects it is nearest, and from which azimuth it is seen, the nearest library view's.
:meth:`Library.recognize_sequence` follows a robot's views with their odometry (Alg. 4.1, or the exact filter).
The workflow writes ``results/libraries/{descriptor}-{size}.parquet``; ``heatdata recognize`` reads them.
"""

from __future__ import annotations

import logging
import os
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd
from scipy import ndimage

from heatdata.descriptors import COLOR_KIND, DescriptorSpec, describe, kind_of
from heatdata.descriptors.rows import descriptor_rows
from heatdata.errors import HeatdataError, LibraryError
from heatdata.io.files import check_output
from heatdata.io.tables import DESCRIPTOR_SCHEMA, read_matrix_table, write_table
from heatdata.recognition.answers import Detection, Match, Recognition, SceneRecognition, SequenceStep
from heatdata.recognition.confidence import (
    Confidence,
    calibrate,
    calibration_rows,
    checked_threshold,
    default_side,
    nearest_two,
)
from heatdata.recognition.evaluate import TIME_RULES, library_subset, nan_views, own_time_scale
from heatdata.recognition.index import (
    SearchIndex,
    build_index,
    candidate_count,
    index_path,
    object_positions,
    read_index,
    shortlist,
)
from heatdata.recognition.library_check import check_library, shortened, spec_of
from heatdata.recognition.pose import STARTS, Pose, Surface, depth_image, pose_candidates
from heatdata.segmentation.segment import Segment, Segmentation, SegmentSettings, segment_frame
from heatdata.typing import StrPath
from heatdata.version import __version__
from heatdata.views.depth import checked_depth, view_from_depth
from heatdata.views.view import View, has_colour, joined_view

log = logging.getLogger(__name__)

#: the library file's layout; a file of another layout is refused
LIBRARY_FORMAT = 1
#: the metadata key of a library file
LIBRARY_KEY = "library"
#: how far this heatdata's probe descriptor may lie from the one stored (largest absolute difference)
PROBE_TOLERANCE = 1e-6
#: the fixed time a time-scaled kind describes the probe at
PROBE_TIME = 2e-4
#: independent views per library view kept for the particle filter's similarity (eq. 4.6)
SIMILARITY_PER_VIEW = 1
#: a scene's segment wider than this times the object it is taken for gets a note (objects touching each other); the
#: segments of single objects in the scenes experiment measure at most 0.98 times their object
TOUCHING = 1.15
#: a sequence has settled on an object the library lacks when the unknown hypothesis holds this much of the posterior
UNKNOWN_SETTLED = 0.99
#: the nearest objects of an answer whose poses are checked against the view (verification)
CANDIDATES = 5
#: two unknown segments touch when one, grown by this many pixels, meets the other; at most this many pairs are tried
JOIN_GAP, JOIN_PAIRS = 3, 4
#: columns of a library file that no search reads (where the values lie, how the rows were made), left unread
UNREAD = ("positions", "repairs", "seconds")
#: rows per row group of a library file (groups are decoded in parallel when it loads)
ROW_GROUP = 16_384


def probe_view() -> View:
    """A fixed synthetic view (an 80 x 60 depth image of a coloured, asymmetric bump): what a library's probe
    descriptor is computed on, through the same triangulation as a depth frame."""
    height, width = 60, 80
    intrinsics = {"fx": 75.0, "fy": 75.0, "cx": 39.5, "cy": 29.5, "width": width, "height": height}
    v, u = np.mgrid[0:height, 0:width]
    x, y = (u - 40.0) / 25.0, (v - 30.0) / 20.0
    inside = x**2 + y**2 < 1.0
    inside &= ~((x > 0.2) & (np.abs(y) < 0.15))  # a notch: the outline is not symmetric
    depth = np.where(inside, 1.0 - 0.12 * np.exp(-2.0 * ((x + 0.2) ** 2 + y**2)) - 0.03 * x, np.nan)
    rgb = np.stack([0.2 + 0.6 * (u / width), 0.3 + 0.5 * (v / height), 0.5 + 0.3 * np.sin(3 * x)], axis=-1)
    depth_log = logging.getLogger("heatdata.views.depth")
    level = depth_log.level
    depth_log.setLevel(logging.WARNING)  # the probe is not the user's frame: its segmentation note is noise
    try:
        return view_from_depth(depth, intrinsics, np.clip(rgb, 0.0, 1.0), view_id="probe")
    finally:
        depth_log.setLevel(level)


def probe_values(spec: DescriptorSpec) -> np.ndarray:
    """The descriptor of ``spec`` on :func:`probe_view` (a time-scaled kind at :data:`PROBE_TIME`)."""
    times = {spec.name: [PROBE_TIME]} if spec.impl.time_scaled else None
    return np.asarray(describe(probe_view(), [spec], times=times)[0].values, dtype=np.float64)


def _spec_metadata(spec: DescriptorSpec) -> dict:
    """A library file's ``spec``: :meth:`DescriptorSpec.to_dict` with the options under their own key, and the name
    (the layout every library file has, read back by :func:`heatdata.recognition.library_check.spec_of`)."""
    options = spec.to_dict()
    kind, fitted = options.pop("kind"), options.pop("fitted", None)
    return {"kind": kind, "options": options, "fitted": fitted, "name": spec.name}


def uses_colour(spec: DescriptorSpec) -> bool:
    """Whether ``spec`` compares the views' colours (a C-PVHK, a kind's colour option, a combined kind's part)."""
    if spec.kind == COLOR_KIND or spec.get("color") not in (None, "none"):
        return True
    return any(uses_colour(part) for part in spec.get("parts") or ())


def build_library(
    descriptors: pd.DataFrame,
    spec: DescriptorSpec,
    size: int,
    *,
    time_scales: pd.DataFrame | None = None,
    render: dict | None = None,
    time_rule: str = "plausible",
    source: str = "",
    sizes: dict | None = None,
    surfaces: dict[str, Surface] | None = None,
) -> tuple[pd.DataFrame, dict]:
    """A library's rows and metadata from a run's descriptor table (the workflow's rule ``library``).

    Parameters
    ----------
    descriptors : pandas.DataFrame
        A run's descriptor rows of ``spec`` (:data:`~heatdata.io.tables.DESCRIPTOR_SCHEMA`).
    spec : DescriptorSpec
        The descriptor, with what it learned if its kind is fitted.
    size : int
        Library views per object (:func:`heatdata.recognition.evaluate.library_subset`).
    time_scales : pandas.DataFrame, optional
        The objects' time scales (``object, descriptor, source_rule, time_scale, n_views``), for a time-scaled kind.
    render : dict, optional
        The run's view settings (intrinsics, distance, elevation, noise), kept for the reader.
    time_rule : {"plausible", "every"}
        Which objects' time scales a time-scaled query is compared at (Alg. 5.2, as ``classify``).
    source : str
        Where the rows came from (the run's table), for the reader.
    sizes : dict, optional
        Each object's real size, ``{object: [width, height, depth]}`` in metres (the catalogue's), by which a scene's
        segment larger than the object it is taken for gets a note (objects touching each other).
    surfaces : dict, optional
        Each object's surface samples (:func:`heatdata.recognition.pose.sample_surface`), by which a view's pose is
        found and its answer verified; an object without them is answered without a pose.

    Returns
    -------
    rows : pandas.DataFrame
        The library views (``split = "train"``, at their own object's time scale) and the independent views
        (``split = "similarity"``).
    metadata : dict
        What :func:`load_library` needs besides the rows.
    """
    if time_rule not in TIME_RULES:
        raise HeatdataError(f"unknown time_rule {time_rule!r} (use {' or '.join(TIME_RULES)})")
    rows = descriptors[descriptors["descriptor"] == spec.name]
    if rows.empty:
        raise HeatdataError(f"no rows of descriptor {spec.name} to build a library from")
    own = own_time_scale(rows)
    library = library_subset(own[own["split"] == "train"], size)  # as classify chooses them
    tests = own[own["split"] == "test"]
    independent = library_subset(tests.assign(split="train"), min(SIMILARITY_PER_VIEW * size, _views(tests)))
    library, independent = _finite(library, spec), _finite(independent, spec)
    if spec.impl.time_scaled and (time_scales is None or time_scales.empty):
        raise HeatdataError(f"{spec.name}: a time-scaled kind's library needs the objects' time scales")
    scales = None
    if spec.impl.time_scaled and time_scales is not None:
        scales = time_scales[time_scales["descriptor"] == spec.name][["object", "time_scale"]].to_dict("records")
    metadata = {
        "format": LIBRARY_FORMAT,
        "heatdata_version": __version__,
        "spec": _spec_metadata(spec),
        "library_size": int(size),
        "objects": sorted(library["object"].unique()),
        "time_scales": scales,
        "time_rule": time_rule,
        "render": render or {},
        "probe": probe_values(spec).tolist(),
        "source": source,
        "sizes": _checked_sizes(sizes or {}),
        "confidence": _calibration(library, spec),
        "surfaces": {
            obj: surface.to_dict() for obj, surface in (surfaces or {}).items() if obj in set(library["object"])
        },
    }
    frame = pd.concat([library.assign(split="train"), independent.assign(split="similarity")], ignore_index=True)
    return frame, metadata


def _calibration(views: pd.DataFrame, spec: DescriptorSpec) -> dict | None:
    """The library's calibrated confidence (:func:`heatdata.recognition.confidence.calibrate`) as metadata; None
    for a library of one object."""
    if views["object"].nunique() < 2:
        log.warning("%s: a library of one object cannot tell an unknown object: every answer is its object", spec.name)
        return None
    values = np.stack(views["values"].to_numpy())
    weights = views["weights"]
    weighted = spec.impl.time_scaled and not weights.isna().any()
    stacked = np.stack(weights.to_numpy()) if weighted else None
    rows = calibration_rows(len(views))
    distance = kind_of(spec.kind).distance_matrix(
        values[rows],
        values,
        query_weights=None if stacked is None else stacked[rows],
        library_weights=stacked,
    )
    confidence = calibrate(distance, views["object"].to_numpy(), rows, side=default_side(spec.impl.learned))
    log.info("%s: confidence calibrated on %d views (AUROC %.3f)", spec.name, len(rows), confidence.auroc)
    return confidence.to_dict()


def _checked_sizes(sizes: dict) -> dict:
    """``{object: [width, height, depth]}`` in metres, finite and positive (objects without a size left out)."""
    checked = {}
    for obj, size in sizes.items():
        values = np.asarray(size, dtype=np.float64)
        if values.shape == (3,) and np.all(np.isfinite(values)) and np.all(values > 0):
            checked[str(obj)] = values.tolist()
    return checked


def _finite(rows: pd.DataFrame, spec: DescriptorSpec) -> pd.DataFrame:
    """The rows without NaN values: as ``classify`` leaves such library views out (logged)."""
    bad = nan_views(rows)
    if bad:
        log.warning("%s: %d views with NaN values (see their repairs) are left out", spec.name, len(bad))
    return rows[~rows["view_id"].isin(bad)]


def _views(rows: pd.DataFrame) -> int:
    """Views per object of the object with the fewest (at least 1)."""
    return max(1, int(rows.groupby("object")["view_id"].nunique().min())) if len(rows) else 1


def _rows_of(values, keep: np.ndarray):
    """``values[keep]`` of an array or a frame, a slice (no copy) when the kept rows are consecutive (a library
    file's library views come first)."""
    kept = np.flatnonzero(keep)
    rows = values.iloc if isinstance(values, pd.DataFrame) else values
    if len(kept) and kept[-1] - kept[0] + 1 == len(kept):
        return rows[kept[0] : kept[-1] + 1]
    return rows[kept]


def write_library(rows: pd.DataFrame, metadata: dict, path: StrPath, *, index: bool = False) -> None:
    """Write a library file (Parquet; written whole, then renamed), its library views first.

    Parameters
    ----------
    rows, metadata
        As :func:`~heatdata.recognition.library.build_library` returns them.
    path : str or Path
        The ``.parquet`` to write.
    index : bool
        Also write its search index beside it (``name.faiss``; :mod:`heatdata.recognition.index`), for a kind with an
        index space.

    Raises
    ------
    OutputError
        With ``index``, a library file named like its own index (``name.faiss``).
    """
    rows = rows.iloc[np.argsort((rows["split"] != "train").to_numpy(), kind="stable")]
    space = spec_of(metadata["spec"]).impl.index_space if index else None
    if space is not None:
        beside = check_output(index_path(path), inputs=[path], what="the index")  # a library named name.faiss
        views = np.stack(rows.loc[rows["split"] == "train", "values"].to_numpy())
        build_index(views, space, what=str(path)).write(beside)
    write_table(rows, Path(path), DESCRIPTOR_SCHEMA, {LIBRARY_KEY: metadata}, row_group_size=ROW_GROUP)


class Library:
    """A built library: the library views of one descriptor, and how to describe and recognize a new view.

    Made by :func:`load_library`.

    Parameters
    ----------
    rows : pandas.DataFrame
        The rows of :func:`~heatdata.recognition.library.build_library`: library views (``split = "train"``) and
        independent views (``split = "similarity"``).
    metadata : dict
        Its metadata (:func:`~heatdata.recognition.library.build_library`).
    path : str or Path
        Where it was read from, for messages.
    values : (len(rows), M) float64, optional
        The rows' values as one array (:func:`heatdata.io.tables.read_matrix_table`), so that they are not stacked
        again.
    """

    def __init__(
        self, rows: pd.DataFrame, metadata: dict, path: StrPath = "library", *, values: np.ndarray | None = None
    ):
        self.path = str(path)
        self.metadata = dict(metadata)
        self.spec = spec_of(metadata["spec"])
        self.descriptor = self.spec.name
        self.time_rule = metadata["time_rule"]
        self.library_size = int(metadata["library_size"])
        self.render = metadata.get("render", {})
        self.sizes = _checked_sizes(metadata.get("sizes") or {})
        scales = metadata.get("time_scales")
        self.time_scales = (
            None
            if scales is None
            else pd.DataFrame(scales).assign(descriptor=self.descriptor, source_rule=str(self.spec.get("source")))
        )
        train = (rows["split"] == "train").to_numpy()
        self.views = _rows_of(rows, train).reset_index(drop=True)
        self.independent = rows[~train].reset_index(drop=True)
        if self.views.empty:
            raise LibraryError(f"{self.path}: the library holds no library view")
        self._codes, self.objects, self._positions = object_positions(self.views["object"])
        self._values = np.stack(self.views["values"].to_numpy()) if values is None else _rows_of(values, train)
        weights = self.views["weights"]
        self._weights = None if weights.isna().any() else np.stack(weights.to_numpy())
        self._by_object = dict(zip(self.objects, self._positions))
        #: the search index beside the exact search (:mod:`heatdata.recognition.index`); None: exact search only
        self.index: SearchIndex | None = None
        self._similarity: pd.DataFrame | None = None
        if "confidence" not in self.metadata:  # a file written before calibration: learned now, not stored
            self.metadata["confidence"] = _calibration(self.views, self.spec)
        calibrated = self.metadata["confidence"]
        self.confidence: Confidence | None = None if calibrated is None else Confidence.from_dict(calibrated)
        stored = self.metadata.get("surfaces") or {}
        self.surfaces = {obj: Surface.from_dict(data, f"{self.path}: {obj}") for obj, data in stored.items()}
        #: the objects whose models had no colour, when the kind compares colours: a query's colour is left out
        #: against their views (rendered in the untextured grey)
        self.colourless = (
            sorted(o for o, s in self.surfaces.items() if not s.coloured) if uses_colour(self.spec) else []
        )
        self._colourless = np.isin(self.views["object"].to_numpy(), self.colourless)

    def __repr__(self) -> str:
        return (
            f"Library({self.descriptor}, {len(self.objects)} objects x {self.library_size} views, "
            f"heatdata {self.metadata['heatdata_version']}, {self.path})"
        )

    def without(self, objects: Sequence[str]) -> Library:
        """This library without some of its objects, its confidence learned again from the views left: how it
        answers an object it lacks (the open-set evaluation).

        Parameters
        ----------
        objects : sequence of str
            Objects to leave out.

        Returns
        -------
        Library
        """
        unknown = sorted(set(objects) - set(self.objects))
        if unknown:
            raise HeatdataError(f"{self.path} holds no {', '.join(unknown)}")
        left = set(objects)
        rows = pd.concat([self.views, self.independent], ignore_index=True)
        metadata = {key: value for key, value in self.metadata.items() if key != "confidence"}
        metadata["objects"] = [obj for obj in self.objects if obj not in left]
        metadata["surfaces"] = {
            obj: data for obj, data in (self.metadata.get("surfaces") or {}).items() if obj not in left
        }
        return Library(rows[~rows["object"].isin(left)], metadata, f"{self.path} without {', '.join(sorted(left))}")

    def describe(self, view: View) -> pd.DataFrame:
        """The query rows of ``view``, described as the run described its test views.

        Parameters
        ----------
        view : View
            Any view.

        Returns
        -------
        pandas.DataFrame
            :data:`~heatdata.io.tables.DESCRIPTOR_SCHEMA` rows: one, or one per object's time scale for a
            time-scaled kind.
        """
        plan = pd.DataFrame({"split": ["test"], "seed": [0]})
        rows = descriptor_rows([view], plan, [self.spec], time_scales=self.time_scales)
        if nan_views(rows):  # as classify, which gives such a test view no prediction
            reasons = "; ".join(sorted({r for rs in rows["repairs"] for r in rs if "failed" in r})) or "NaN values"
            raise HeatdataError(f"{view.name}: {self.descriptor} cannot describe this view ({reasons})")
        return rows

    def query_distances(self, view: View, *, exact: bool = False) -> tuple[pd.DataFrame, np.ndarray]:
        """The query rows of ``view`` (:meth:`describe`) and their distance to each library view (:meth:`distances`).

        The views of the objects whose models had no colour (:attr:`colourless`) are compared with the query
        described in their grey, its colour left out: a frame's colours would set every such object far from it.

        Parameters
        ----------
        view : View
        exact : bool
            As :meth:`distances`'s.

        Returns
        -------
        query : pandas.DataFrame
            The rows of :meth:`describe` (of the grey query when no library object has colour).
        distance : (N,) ndarray
        """
        if not self.colourless:
            query = self.describe(view)
            return query, self.distances(query, exact=exact)
        from heatdata.io.models import DEFAULT_GREY  # trimesh's loader, only for a library of colourless models

        grey = self.describe(replace(view, colors=np.full_like(view.colors, DEFAULT_GREY[0])))
        distance = self.distances(grey, exact=exact)
        if self._colourless.all():
            return grey, distance
        query = self.describe(view)
        return query, np.where(self._colourless, distance, self.distances(query, exact=exact))

    def use_index(self, index: SearchIndex | None) -> None:
        """Search through ``index`` (None: the exact search alone).

        Parameters
        ----------
        index : SearchIndex or None
            An index of this library's views in their order, in its kind's space
            (:func:`heatdata.recognition.index.build_index`).
        """
        if index is not None and (len(index) != len(self.views) or index.space != self.spec.impl.index_space):
            raise LibraryError(
                f"{self.path}: an index of {len(index)} views in the {index.space} space does not fit "
                f"{len(self.views)} library views of {self.descriptor}"
            )
        self.index = index

    def distances(self, query: pd.DataFrame, *, exact: bool = False) -> np.ndarray:
        """The query's distance to each library view, by the kind's own distance (eq. 3.1, 5.14, chi-square).

        Through the library's index (:mod:`heatdata.recognition.index`) unless ``exact``: every library view of the
        objects its candidates name is compared, the others are inf.

        Parameters
        ----------
        query : pandas.DataFrame
            The rows of :meth:`describe`.
        exact : bool
            Compare every library view (Alg. 3.1 as written), whether or not the library has an index.

        Returns
        -------
        (N,) ndarray
            One distance per row of :attr:`views`; inf where Alg. 5.2's time rule does not compare them, or the
            index did not shortlist their object.
        """
        impl = kind_of(self.spec.kind)
        if not impl.time_scaled:
            values = np.stack(query["values"].to_numpy())[:1]
            if exact or self.index is None:
                return impl.distance_matrix(values, self._values)[0]
            candidates = self.index.candidates(values, candidate_count(self.library_size))[0]
            positions = shortlist(candidates, self._codes, self._positions)
            distance = np.full(len(self.views), np.inf)
            distance[positions] = impl.distance_matrix(values, self._values[positions])[0]
            return distance
        distance = np.full(len(self.views), np.inf)
        at = query.set_index("time_object")
        allowed = set(at.index)
        if self.time_rule == "plausible":
            reachable = set(at.index[at["time"] <= at["t_global"]])
            allowed = reachable or allowed
        for obj, positions in self._by_object.items():
            if obj not in allowed:
                continue
            row = at.loc[obj]
            weights = row["weights"]
            distance[positions] = impl.distance_matrix(
                np.asarray(row["values"], dtype=np.float64)[None],
                self._values[positions],
                query_weights=None if weights is None else np.asarray(weights, dtype=np.float64)[None],
                library_weights=None if self._weights is None else self._weights[positions],
            )[0]
        return distance

    def recognize(
        self,
        view: View,
        k: int = 5,
        *,
        threshold: float | None = None,
        pose: bool = True,
        exact: bool = False,
        depth: np.ndarray | None = None,
    ) -> Recognition:
        """The ``k`` objects nearest ``view`` (Alg. 3.1; Alg. 5.2 for a time-scaled kind), nearest first, how
        confident the answer is that the nearest is the object seen, and where it is.

        Each object's distance is that of its library view nearest the query; that view's azimuth estimates the
        angle ``view`` is seen from. The first match is what ``classify`` predicts for the same view. The confidence
        (:mod:`heatdata.recognition.confidence`) is learned by the library from its own views; below ``threshold``
        the answer is unknown (:attr:`Recognition.object` is None). Above it, the nearest objects are posed in turn
        (:func:`heatdata.recognition.pose.estimate_pose`: ICP from their nearest library views) until a pose
        explains the view; when none does, the answer is unknown too.

        Parameters
        ----------
        view : View
            A rendered view, a depth frame's or an organized cloud's.
        k : int
            How many objects to return.
        threshold : float in [0, 1], optional
            The confidence below which the object is unknown (default: none where the answer is verified, else the
            library's, :func:`heatdata.recognition.confidence.calibrate`; :meth:`threshold`).
        pose : bool
            Estimate the pose and verify the answer (a library without surface samples says so and answers
            without).
        exact : bool
            Compare the view with every library view, not through the library's index (:meth:`distances`).
        depth : (h, w) float, optional
            The depth image ``view`` was cut from (its intrinsics' size; NaN, infinite or <= 0 where no reading),
            which verification compares the posed model with. By default the view's own vertices: where the view
            holds nothing counts as measured empty, so a part of the object the view dropped (a rendered view keeps
            its largest connected component; a face seen edge-on breaks into depth steps) reads as unseen.

        Returns
        -------
        Recognition

        Raises
        ------
        ViewError
            ``depth`` is not a 2-D image of the view's size (:func:`heatdata.views.depth.checked_depth`).
        """
        notes = self._colour_note(has_colour(view.colors), view.name)
        if pose and not self.surfaces:
            notes.append(self.no_surfaces())
        if depth is not None:
            depth, _ = checked_depth(depth, view.intrinsics, view.name)
        answer = self._nearest(view, k, threshold, pose=pose, exact=exact, depth=depth)
        return replace(answer, repairs=answer.repairs + notes)

    def no_surfaces(self) -> str:
        """The line that says this library cannot pose or verify, and how to rebuild it.

        Returns
        -------
        str
        """
        return (
            f"{self.path} holds no surface samples (built before poses): answers have no pose and are not "
            f"verified; rebuild it with the workflow (snakemake --forcerun library {self.path})"
        )

    def threshold(self, threshold: float | None = None, *, pose: bool = False) -> float:
        """The confidence threshold in use.

        Where answers are posed and verified (``pose`` and a library with surface samples), verification alone
        decides by default what is unknown: the threshold is 0. The confidence is learned from rendered views, and a
        real sensor's segments lie 10-100 times farther from their library views than rendered ones do, so that
        every real object fell under the library's threshold; hypothesis verification reads the frame itself
        (``docs/chapters/confidence.md`` measures both, on rendered and real frames).

        Parameters
        ----------
        threshold : float, optional
            The user's, checked to lie in [0, 1].
        pose : bool
            Whether the answers are posed and verified.

        Returns
        -------
        float
            ``threshold``; else 0 when the answers are verified, or the library's (0 when it has none: a library of
            one object).
        """
        if threshold is not None:
            return checked_threshold(threshold)
        if (pose and self.surfaces) or self.confidence is None:
            return 0.0
        return self.confidence.threshold

    def _nearest(
        self,
        view: View,
        k: int,
        threshold: float | None = None,
        *,
        pose: bool = False,
        depth: np.ndarray | None = None,
        plane: np.ndarray | None = None,
        exact: bool = False,
    ) -> Recognition:
        """:meth:`recognize` without its notes; ``depth`` is the frame's (default the view's own) and ``plane`` the
        support plane, for the pose."""
        if k < 1 or int(k) != k:
            raise HeatdataError(f"k must be a whole number >= 1, got {k}")
        limit = self.threshold(threshold, pose=pose)
        query, distance = self.query_distances(view, exact=exact)
        confidence = float("nan")
        if self.confidence is not None:
            _, nearest, other = nearest_two(distance[None], self._codes)
            confidence = float(self.confidence(nearest, other)[0])
        matches = []
        for best in self._nearest_views(distance)[: max(int(k), CANDIDATES)]:
            row = self.views.iloc[best]
            matches.append(
                Match(
                    str(row["object"]),
                    str(row["label"]),
                    float(distance[best]),
                    float(row["azimuth"]),
                    float(row["elevation"]),
                    str(row["view_id"]),
                )
            )
        repairs = sorted({r for rs in query["repairs"] for r in rs})
        answer = Recognition(self.descriptor, matches[: int(k)], repairs, confidence, limit)
        if not (pose and self.surfaces and answer.confident):
            return answer
        found = self._pose(view, matches, distance, depth, plane)
        kept = answer.matches
        if found is not None and found.object not in {m.object for m in kept}:  # a candidate beyond the k listed
            kept = [*kept, next(m for m in matches if m.object == found.object)]
        return replace(answer, matches=kept, pose=found)

    def _nearest_views(self, distance: np.ndarray) -> np.ndarray:
        """Each compared object's nearest library view (the first of equals), nearest objects first (equals by
        name)."""
        finite = np.flatnonzero(np.isfinite(distance))
        codes = self._codes[finite]
        order = finite[np.lexsort((distance[finite], codes))]
        ordered = self._codes[order]
        firsts = order[np.r_[True, ordered[1:] != ordered[:-1]]] if len(order) else order
        return firsts[np.lexsort((self._codes[firsts], distance[firsts]))]

    def _pose(
        self,
        view: View,
        matches: list[Match],
        distance: np.ndarray,
        depth: np.ndarray | None,
        plane: np.ndarray | None,
    ) -> Pose | None:
        """Hypothesis verification of the :data:`CANDIDATES` nearest objects
        (:func:`heatdata.recognition.pose.pose_candidates`): the accepted pose that explains ``view`` best, else the
        nearest object's pose (rejected)."""
        depth = depth_image(view.vertices, view.intrinsics) if depth is None else depth
        candidates = []
        for match in matches[:CANDIDATES]:
            surface = self.surfaces.get(match.object)
            if surface is None:
                continue
            positions = self._by_object[match.object]
            nearest = self.views.iloc[positions[np.argsort(distance[positions], kind="stable")[:STARTS]]]
            views = list(zip(nearest["azimuth"], nearest["elevation"], nearest["distance"], strict=True))
            candidates.append((match.object, surface, views))
        return pose_candidates(candidates, view.vertices, view.canonical_rotation, depth, view.intrinsics, plane)

    def _colour_note(self, coloured: bool, what: str) -> list[str]:
        """A warning when this library compares colours and a view (``what``, for the message) has none (a depth
        frame without its RGB); a note when some of its models have none (:meth:`query_distances`)."""
        if self.colourless:
            some = "" if len(self.colourless) == len(self.objects) else f" ({', '.join(self.colourless)})"
            note = (
                f"the library's models{some} have no colour: {what}'s colour is not compared with them, only its shape"
            )
            log.info("%s", note)
            return [note]
        if coloured or not uses_colour(self.spec):
            return []
        note = (
            f"{what} has no colour, and {self.descriptor} compares colours: the answer may be wrong "
            "(give the frame's colour image, --rgb, or use a shape-only library)"
        )
        log.warning("%s", note)
        return [note]

    def recognize_scene(
        self,
        depth: np.ndarray,
        intrinsics: dict,
        rgb: np.ndarray | None = None,
        *,
        k: int = 5,
        settings: SegmentSettings | None = None,
        mask: np.ndarray | None = None,
        depth_range: tuple[float, float] | None = None,
        name: str = "frame",
        threshold: float | None = None,
        pose: bool = True,
        exact: bool = False,
    ) -> SceneRecognition:
        """Every object of a depth frame: the support plane, the objects on it, and what each is nearest.

        The frame is segmented (:func:`heatdata.segmentation.segment.segment_frame`: the plane by RANSAC, surfaces
        cut at depth steps and concave creases) and each segment's view recognized (:meth:`recognize`); what a
        robot needs of each, where it is and what it is, is a :class:`Detection`. A frame of one isolated object
        (no support plane) gives one detection, as :meth:`recognize` does for its view.

        Parameters
        ----------
        depth : (h, w) float
            z-depth in metres; NaN, infinite or <= 0 where there is no reading.
        intrinsics : dict
            ``fx, fy, cx, cy, width, height``.
        rgb : (h, w, 3) uint8 or float in [0, 1], optional
            The colour registered to the depth image (give it to a library that compares colours).
        k : int
            Objects to list per detection.
        settings : SegmentSettings, optional
            The segmentation's settings.
        mask : (h, w) bool, optional
            The pixels to look at (objects cut out by the user; each object in it is still one answer).
        depth_range : (near, far) metres, optional
            The depths to look at (with a mask too: the pixels both keep).
        name : str
            The frame's name, for messages.
        threshold : float in [0, 1], optional
            The confidence below which an object is unknown (default: none where the answers are verified, else the
            library's; :meth:`threshold`).
        pose : bool
            Estimate each object's pose and verify its answer against the frame's depth (:meth:`recognize`).
        exact : bool
            Compare each object with every library view, not through the library's index (:meth:`distances`).

        Returns
        -------
        SceneRecognition
            The detections, largest first (none when nothing stands on the plane), the plane and notes.

        Raises
        ------
        ViewError
            An empty frame (no reading), intrinsics or a colour image that do not fit the depth image.
        """
        segmentation = segment_frame(depth, intrinsics, rgb, settings, mask=mask, depth_range=depth_range, name=name)
        return self.recognize_segments(segmentation, k=k, threshold=threshold, pose=pose, exact=exact)

    def recognize_segments(
        self,
        segmentation: Segmentation,
        *,
        k: int = 5,
        threshold: float | None = None,
        pose: bool = True,
        exact: bool = False,
    ) -> SceneRecognition:
        """:meth:`recognize_scene` of a frame already segmented (:func:`heatdata.segmentation.segment.segment_points`).

        Parameters
        ----------
        segmentation : Segmentation
            The frame's plane and segments.
        k : int
            Objects to list per detection.
        threshold : float in [0, 1], optional
            The confidence below which an object is unknown (default: none where the answers are verified, else the
            library's; :meth:`threshold`).
        pose : bool
            Estimate each object's pose and verify its answer against the frame's depth (:meth:`recognize`).
        exact : bool
            As :meth:`recognize_scene`'s.

        Returns
        -------
        SceneRecognition
        """
        limit = self.threshold(threshold, pose=pose)
        repairs = list(segmentation.notes)
        if pose and not self.surfaces and segmentation.segments:
            repairs.append(self.no_surfaces())
        detections = []
        for segment in segmentation.segments:
            notes = list(segment.notes)
            try:
                answer: Recognition | None = self._nearest(
                    segment.view, k, limit, pose=pose, depth=segmentation.depth, plane=segmentation.plane, exact=exact
                )
            except HeatdataError as exc:  # a segment the descriptor cannot describe is still a detection
                answer = None
                notes.append(f"not described: {exc}")
            if answer is not None:
                notes += self._size_note(segment, answer, segmentation.plane is not None)
                notes += [] if answer.pose is None else answer.pose.notes
            detections.append(
                Detection(
                    answer,
                    (float(segment.centroid[0]), float(segment.centroid[1]), float(segment.centroid[2])),
                    segment.pixels,
                    segment.bbox,
                    notes,
                    segment.mask,
                )
            )
        if pose and self.surfaces:
            detections = self._join_pieces(detections, segmentation, k, limit, exact)
        if segmentation.segments:
            repairs += self._colour_note(segmentation.coloured, "the frame")
        if detections and all(d.object is None for d in detections):
            repairs.append(
                f"every object of the frame is unknown to this library ({len(self.objects)} objects): is it the right "
                "library, and are the frame's depth unit and intrinsics (its focal length) right?"
            )
        return SceneRecognition(self.descriptor, detections, segmentation.plane, repairs)

    def _join_pieces(
        self, detections: list[Detection], segmentation: Segmentation, k: int, limit: float, exact: bool
    ) -> list[Detection]:
        """Two touching segments that are each unknown, joined where one object's pose explains them together: an
        object the segmentation cut at its own concave seam (a drill's handle from its body). At most
        :data:`JOIN_PAIRS` pairs are tried, the largest first; each segment joins once."""
        masks: dict[int, np.ndarray] = {
            i: segment.mask
            for i, (segment, detection) in enumerate(zip(segmentation.segments, detections, strict=True))
            if detection.recognition is not None and detection.object is None and segment.mask is not None
        }
        grown = {i: ndimage.binary_dilation(mask, iterations=JOIN_GAP) for i, mask in masks.items()}
        pairs = [(a, b) for a in masks for b in masks if a < b and (grown[a] & masks[b]).any()]
        joined: dict[int, Detection] = {}
        for a, b in pairs[:JOIN_PAIRS]:
            if a in joined or b in joined:
                continue
            first, second = segmentation.segments[a], segmentation.segments[b]
            view = joined_view(first.view, second.view)
            try:
                answer = self._nearest(view, k, limit, pose=True, depth=segmentation.depth, plane=segmentation.plane,
                                       exact=exact)  # fmt: skip
            except HeatdataError:
                continue
            if not answer.known:
                continue
            mask = masks[a] | masks[b]
            rows, cols = np.nonzero(mask)
            weights = np.array([first.pixels, second.pixels], float)
            centroid = np.average([first.centroid, second.centroid], axis=0, weights=weights)
            note = f"two touching pieces joined: the {answer.object}'s pose explains them together"
            joined[a] = joined[b] = Detection(
                answer,
                (float(centroid[0]), float(centroid[1]), float(centroid[2])),
                int(mask.sum()),
                (int(cols.min()), int(rows.min()), int(cols.max()), int(rows.max())),
                [note, *([] if answer.pose is None else answer.pose.notes)],
                mask,
            )
        kept: list[Detection] = []
        for i, detection in enumerate(detections):
            piece = joined.get(i, detection)
            if not any(piece is other for other in kept):
                kept.append(piece)
        return sorted(kept, key=lambda d: -d.pixels)

    def _size_note(self, segment: Segment, answer: Recognition, on_plane: bool) -> list[str]:
        """A note when ``segment`` is larger than the object it is taken for: objects touching, or one the library
        lacks."""
        obj = answer.answer.object
        if obj not in self.sizes:
            return []
        width, height, depth = self.sizes[obj]
        size = np.hypot(width, depth) if on_plane else float(np.linalg.norm([width, height, depth]))
        if segment.extent <= TOUCHING * size:
            return []
        return [
            f"{segment.extent * 100:.0f} cm across, larger than the {obj} it is "
            f"{'taken for' if answer.known else 'nearest'} ({size * 100:.0f} cm): "
            "several objects touching each other form one segment, or the object is not in the library"
        ]

    def _table(self, rows: pd.DataFrame) -> pd.DataFrame:
        return rows[["object", "azimuth", "values"]].assign(kind=self.spec.kind)

    def similarity(self) -> pd.DataFrame:
        """mu of eq. 4.6 between the library's views, learned from its independent views (computed once).

        Returns
        -------
        pandas.DataFrame
            As :func:`heatdata.recognition.multiview.appearance.learn_similarity`.
        """
        from heatdata.recognition.multiview.appearance import learn_similarity

        if self._similarity is None:
            if self.independent.empty:
                raise LibraryError(f"{self.path}: no independent views to learn which views look alike (eq. 4.6)")
            self._similarity = learn_similarity(self._table(self.views), self._table(self.independent))
        return self._similarity

    def recognize_sequence(
        self,
        views: Sequence[View],
        moves: Sequence[float],
        *,
        exact: bool = False,
        particles: int = 100,
        seed: int = 0,
        threshold: float | None = None,
    ) -> list[SequenceStep]:
        """Follow views taken around an object (Alg. 4.1): the posterior over objects after each, and how likely
        the object is one the library lacks.

        Beside the thesis's hypotheses (object, view angle), the filter holds one for "an object the library lacks"
        (:meth:`heatdata.recognition.multiview.filters.HypothesisFilter.expect_unknown`), weighed at each frame by
        the view's calibrated confidence, its prior the confidence threshold: a sequence of one frame is unknown
        exactly when :meth:`recognize` says so, and a sequence of an object the library lacks does not settle on
        one of its objects.

        Parameters
        ----------
        views : sequence of View
            The frames, in the order they were taken.
        moves : sequence of float
            The azimuth (degrees) the sensor moved between consecutive frames: one per gap, or one for all.
        exact : bool
            The exhaustive filter (every object at every degree) instead of the particle filter.
        particles : int
            The particle filter's particles.
        seed : int
            Its seed.
        threshold : float in [0, 1], optional
            The unknown hypothesis's prior (default: the library's confidence threshold; 0: no unknown hypothesis).

        Returns
        -------
        list of SequenceStep
            One per frame.
        """
        from heatdata.recognition.multiview.filters import ExhaustiveFilter, ParticleFilter

        if self.spec.impl.time_scaled:
            raise HeatdataError(
                f"{self.descriptor}: a time-scaled kind describes a view per object, which Alg. 4.1's appearance "
                "model does not take; use a library of another descriptor for a sequence"
            )
        if not views:
            raise HeatdataError("a sequence needs at least one frame")
        gaps = list(moves)
        if len(gaps) == 1 and len(views) > 2:
            gaps = gaps * (len(views) - 1)
        if len(gaps) != len(views) - 1 and not (len(views) == 1 and len(gaps) <= 1):
            raise HeatdataError(
                f"{len(views)} frames need {len(views) - 1} moves (or one for every gap), got {len(gaps)}"
            )
        if not all(np.isfinite(gaps)):
            raise HeatdataError(f"moves must be finite angles in degrees, got {gaps}")
        table = self._table(self.views)
        belief = ExhaustiveFilter(table) if exact else ParticleFilter(table, self.similarity(), particles, seed=seed)
        prior = self.threshold(threshold)
        if self.confidence is not None and prior > 0:
            belief.expect_unknown(min(prior, 1.0 - 1e-9))
        steps = []
        for frame, view in enumerate(views):
            self._colour_note(has_colour(view.colors), view.name)
            move = float(gaps[frame - 1]) if frame else 0.0
            query, distance = self.query_distances(view)
            belief.step([np.asarray(query["values"].iloc[0], dtype=np.float64)], move)
            if belief.log_unknown is not None and self.confidence is not None:
                _, nearest, other = nearest_two(distance[None], self._codes)
                belief.weigh_unknown(float(self.confidence(nearest, other)[0]))
            estimate = belief.estimate
            settled = belief.unknown >= UNKNOWN_SETTLED if estimate is None else bool(belief.converged)
            steps.append(SequenceStep(frame, move, belief.posterior(), estimate, settled, belief.unknown))
        return steps


def load_library(path: StrPath, *, index: bool = True) -> Library:
    """Read a library file and check that this heatdata describes views as the one that built it.

    Parameters
    ----------
    path : str or Path
        A file the workflow wrote (``results/libraries/{descriptor}-{size}.parquet``).
    index : bool
        Search through the index beside it (:func:`library_index`); False: the exact search alone.

    Returns
    -------
    Library

    Raises
    ------
    LibraryError
        Not a library file, another layout, or a probe this heatdata describes differently.
    """
    try:
        rows, values, run = read_matrix_table(
            Path(path), "values", schema=DESCRIPTOR_SCHEMA, skip=UNREAD, first=("split", "train")
        )
    except HeatdataError as exc:
        raise LibraryError(str(exc)) from None
    rows = rows.assign(**dict.fromkeys(UNREAD))
    metadata = run.get(LIBRARY_KEY)
    if not isinstance(metadata, dict):
        raise LibraryError(f"{path}: not a library file (build one with the workflow: results/libraries/)")
    if metadata.get("format") != LIBRARY_FORMAT or isinstance(metadata.get("format"), bool):
        raise LibraryError(
            f"{path}: a library of layout {shortened(repr(metadata.get('format')))}; this heatdata reads layout "
            f"{LIBRARY_FORMAT}"
        )
    spec = check_library(rows, metadata, path, values)
    try:
        library = Library(rows, metadata, path, values=values)
        now = probe_values(spec)
    except LibraryError:
        raise
    except Exception as exc:  # what the checks above cannot foresee is still one line naming the file
        raise LibraryError(f"{path}: a damaged library file ({type(exc).__name__}: {shortened(str(exc))})") from None
    probe = np.asarray(metadata["probe"], dtype=np.float64)
    if now.shape != probe.shape or not np.allclose(now, probe, atol=PROBE_TOLERANCE, rtol=0, equal_nan=True):
        gap = np.nanmax(np.abs(now - probe)) if now.shape == probe.shape else float("inf")
        raise LibraryError(
            f"{path}: built by heatdata {metadata['heatdata_version']}, whose {library.descriptor} describes views "
            f"differently from this heatdata {__version__} (probe off by {gap:.2g}): rebuild the library"
        )
    if index:
        library.use_index(library_index(library, path))
    return library


def library_index(library: Library, path: StrPath) -> SearchIndex | None:
    """The index of a library file (:mod:`heatdata.recognition.index`): the one beside it, read and checked, or one
    built in memory when there is none or it is not this library's (said in a log line).

    Parameters
    ----------
    library : Library
        The file's library.
    path : str or Path
        The library file.

    Returns
    -------
    SearchIndex or None
        None for a kind without an index space (a time-scaled or combined kind): the exact search answers.
    """
    space = library.spec.impl.index_space
    if space is None:
        return None
    beside = index_path(path)
    if os.path.lexists(beside):
        try:
            return read_index(beside, library._values, space)
        except Exception as exc:  # a cache, never an authority: whatever is wrong with the file, it is rebuilt
            reason = str(exc) if isinstance(exc, HeatdataError) else f"{beside}: unreadable ({type(exc).__name__})"
            log.warning("%s: building one in memory instead (heatdata index %s rewrites it)", reason, path)
    else:
        log.info("%s has no index beside it: building one in memory (heatdata index %s writes it)", path, path)
    return build_index(library._values, space, what=str(path))


def write_library_index(path: StrPath) -> Path:
    """Build the index of a library file and write it beside it (``name.faiss``).

    Parameters
    ----------
    path : str or Path
        A library file.

    Returns
    -------
    Path
        The index file.

    Raises
    ------
    LibraryError
        Not a library file, or one whose kind answers by the exact search alone (a time-scaled or combined kind).
    """
    library = load_library(path, index=False)
    space = library.spec.impl.index_space
    if space is None:
        raise LibraryError(
            f"{path}: a {library.spec.kind} library answers by the exact search and has no index (a time-scaled "
            "kind describes a query at each object's time scale; a combined kind sums several distances)"
        )
    written = check_output(index_path(path), inputs=[path], what="the index")
    build_index(library._values, space, what=str(path)).write(written)
    log.info("%s: index written (%.1f MB)", written, written.stat().st_size / 1e6)
    return written
