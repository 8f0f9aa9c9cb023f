"""What recognition answers: the nearest objects of a view, a sequence's belief, and the objects of a scene.

Plain frozen dataclasses with a ``to_dict`` each, the shape of ``heatdata recognize --json``. Made by
:class:`heatdata.recognition.library.Library`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from heatdata.recognition.pose import Pose


@dataclass(frozen=True)
class Match:
    """One object a view is nearest: its distance, and the library view nearest to the query (whose azimuth
    estimates the angle the query is seen from)."""

    object: str
    label: str
    distance: float
    azimuth: float
    elevation: float
    view_id: str


@dataclass(frozen=True)
class Recognition:
    """What :meth:`Library.recognize` answers: the nearest objects, nearest first, the query's repairs, and how
    confident the answer is that the nearest object is the one seen.

    Attributes
    ----------
    descriptor : str
        The library's descriptor.
    matches : list of Match
        The nearest objects, nearest first.
    repairs : list of str
        What describing the query repaired or warned of.
    confidence : float
        In [0, 1]: how likely the object seen is in the library (:mod:`heatdata.recognition.confidence`); NaN for
        a library of one object.
    threshold : float
        The confidence it was judged at: below it, the object is unknown.
    pose : Pose or None
        The accepted candidate's pose, or, when none is accepted, the nearest candidate's; None when no pose was
        estimated (the confidence below the threshold, a library without surface samples, or not asked for).
    """

    descriptor: str
    matches: list[Match]
    repairs: list[str] = field(default_factory=list)
    confidence: float = float("nan")
    threshold: float = 0.0
    pose: Pose | None = None

    @property
    def confident(self) -> bool:
        """Whether the confidence reached the threshold (a library of one object: always)."""
        return bool(np.isnan(self.confidence) or self.confidence >= self.threshold)

    @property
    def verified(self) -> bool:
        """Whether a candidate's pose explains the view (True when no pose was estimated)."""
        return self.pose is None or self.pose.accepted

    @property
    def known(self) -> bool:
        """Whether the object is named: confident and verified."""
        return self.confident and self.verified

    @property
    def best(self) -> Match:
        """The nearest object."""
        return self.matches[0]

    @property
    def answer(self) -> Match:
        """The object the answer names when it is known: the candidate whose pose was accepted, else the nearest."""
        if self.pose is not None:
            for match in self.matches:
                if match.object == self.pose.object:
                    return match
        return self.best

    @property
    def object(self) -> str | None:
        """The object seen; None when it is unknown."""
        return self.answer.object if self.known else None

    def to_dict(self) -> dict:
        """The answer as plain types (``heatdata recognize --json``).

        Returns
        -------
        dict
            ``descriptor, object, label, confidence, azimuth`` of the answer (``object`` and ``label`` None when
            it is unknown), its ``pose`` (:meth:`Pose.to_dict`, or None), ``matches`` (the nearest objects all the
            same) and ``repairs``.
        """
        return {
            "descriptor": self.descriptor,
            "object": self.object,
            "label": self.answer.label if self.known else None,
            "confidence": _plain_confidence(self.confidence),
            "azimuth": self.answer.azimuth,
            "pose": None if self.pose is None else self.pose.to_dict(),
            "matches": [m.__dict__ for m in self.matches],
            "repairs": list(self.repairs),
        }


@dataclass(frozen=True)
class SequenceStep:
    """The filter's belief after one frame of a sequence (Alg. 4.1): the posterior over objects, and the probability
    that the object is none of the library's.

    Attributes
    ----------
    frame : int
        The frame's index.
    move : float
        Degrees moved since the last frame.
    posterior : dict of str to float
        Each object's probability (with ``unknown``, they sum to 1).
    estimate : str or None
        The most probable object; None when the unknown object is more probable.
    converged : bool
        Whether the filter settled: on ``estimate``, or, when it is None, on the object being unknown.
    unknown : float
        The probability that the object is none of the library's (0 for a library without a confidence).
    """

    frame: int
    move: float
    posterior: dict[str, float]
    estimate: str | None
    converged: bool
    unknown: float = 0.0

    def to_dict(self) -> dict:
        """The step as plain types (``heatdata recognize --json``).

        Returns
        -------
        dict
            ``frame, move, posterior, estimate, converged, unknown``.
        """
        return dict(self.__dict__)


@dataclass(frozen=True)
class Detection:
    """One object of a scene: where it is in the frame and what the library takes it for.

    Attributes
    ----------
    recognition : Recognition or None
        The nearest objects of its view, nearest first; None when its view could not be described (the reason is
        in ``notes``).
    centroid : (3,) float
        The mean of its points in the camera frame, metres (x right, y down, z forward).
    pixels : int
        Its readings.
    bbox : (4,) int
        ``u0, v0, u1, v1``: the bounding box of its pixels, inclusive.
    notes : list of str
        What a user should know: cut by the image border, in several pieces, larger than the object it is taken
        for (objects touching each other form one segment), not described.
    mask : (h, w) bool
        Its pixels (not in :meth:`to_dict`).
    """

    recognition: Recognition | None
    centroid: tuple[float, float, float]
    pixels: int
    bbox: tuple[int, int, int, int]
    notes: list[str] = field(default_factory=list)
    mask: np.ndarray | None = field(default=None, repr=False, compare=False)

    @property
    def object(self) -> str | None:
        """The object it is, or None: unknown, or not described."""
        return None if self.recognition is None else self.recognition.object

    @property
    def label(self) -> str | None:
        """Its object's class, or None."""
        return None if self.object is None or self.recognition is None else self.recognition.answer.label

    @property
    def pose(self) -> Pose | None:
        """Its pose (:attr:`Recognition.pose`), or None."""
        return None if self.recognition is None else self.recognition.pose

    @property
    def confidence(self) -> float:
        """How likely it is an object of the library, in [0, 1] (NaN when it was not described)."""
        return float("nan") if self.recognition is None else self.recognition.confidence

    @property
    def distance(self) -> float:
        """The distance to the answer's nearest library view, as :meth:`to_dict` gives it (NaN when there is none)."""
        return float("nan") if self.recognition is None else self.recognition.answer.distance

    def to_dict(self) -> dict:
        """The detection as plain types (one of ``heatdata recognize --json``'s ``objects``).

        Returns
        -------
        dict
            ``object, label, confidence, distance, centroid, pixels, bbox, notes``, the answer's nearest library
            view's ``azimuth``, its ``pose`` (:meth:`Pose.to_dict`, or None) and the ``matches`` (``object`` and
            ``label`` None when it is unknown or not described).
        """
        best = None if self.recognition is None else self.recognition.answer
        return {
            "object": self.object,
            "label": self.label,
            "confidence": _plain_confidence(self.confidence),
            "distance": None if best is None else best.distance,
            "centroid": [float(c) for c in self.centroid],
            "pixels": int(self.pixels),
            "bbox": [int(b) for b in self.bbox],
            "notes": list(self.notes),
            "azimuth": None if best is None else best.azimuth,
            "pose": None if self.pose is None else self.pose.to_dict(),
            "matches": [] if self.recognition is None else [m.__dict__ for m in self.recognition.matches],
        }


@dataclass(frozen=True)
class SceneRecognition:
    """What :meth:`heatdata.recognition.library.Library.recognize_scene` answers: every object found in a frame.

    Attributes
    ----------
    descriptor : str
        The library's descriptor.
    detections : list of Detection
        One per segment, largest first.
    plane : (4,) float or None
        The support plane ``a, b, c, d`` in the camera frame (unit normal towards the camera), or None.
    repairs : list of str
        What the frame showed (the plane, or why there is none; clusters dropped) and warnings (no colour).
    """

    descriptor: str
    detections: list[Detection]
    plane: np.ndarray | None
    repairs: list[str] = field(default_factory=list)

    def to_dict(self) -> dict:
        """The answer as plain types (``heatdata recognize --json``).

        Returns
        -------
        dict
            ``descriptor``, ``objects`` (:meth:`Detection.to_dict` each), ``plane`` (a list, or None) and
            ``repairs``.
        """
        return {
            "descriptor": self.descriptor,
            "objects": [d.to_dict() for d in self.detections],
            "plane": None if self.plane is None else [float(x) for x in self.plane],
            "repairs": list(self.repairs),
        }


def _plain_confidence(value: float) -> float | None:
    """A confidence for JSON: None for NaN."""
    return None if np.isnan(value) else float(value)
