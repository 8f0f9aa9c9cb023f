"""Two scans of one object joined into one model, by registration where they overlap and by JASNOM where they do not.

JASNOM's premise (thesis 7.1) is two scans that share almost nothing; many real pairs share part of their surface,
and there the field's answer is registration by the overlap. :func:`join` registers the pair first
(:func:`heatdata.jasnom.register.register`: FPFH + RANSAC, then ICP) and measures what the motion found says: how
much of the smaller scan lies on the other, and how much of either lies in the space the other's camera saw empty.
A pair that overlaps, without either scan in front of the other, keeps the registration; any other pair is
stitched by JASNOM (:func:`heatdata.jasnom.seam.stitch` with ``scans=True``). Either way :class:`Joined` says which
ran and why.

An object with a symmetry registers as overlapping even from opposite sides: a cup's back, turned, is its front.
That registration is as right as the shape can tell; a handle or a label that breaks the symmetry is too small a
part of the surface for the overlap to see.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Any

import numpy as np

from heatdata.io.models import Model, transformed
from heatdata.jasnom.register import MAX_IN_FRONT, MIN_OVERLAP, Registration, register
from heatdata.jasnom.seam import Stitched, stitch

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class Joined:
    """What :func:`join` returns.

    Attributes
    ----------
    model : Model
        In the first scan's frame: the stitched model (JASNOM), or both scans as one mesh (registration; the
        overlap keeps both sheets).
    method : {"registration", "jasnom"}
    why : str
        The measurements that chose the method, as a sentence.
    rotation : (3, 3) float64
    translation : (3,) float64
        The motion of the second scan into the first's frame.
    registration : Registration
        The registration tried first, with its overlap and in-front shares.
    stitched : Stitched or None
        JASNOM's stitch, when it ran.
    """

    model: Model
    method: str
    why: str
    rotation: np.ndarray
    translation: np.ndarray
    registration: Registration
    stitched: Stitched | None

    def summary(self) -> dict[str, Any]:
        """The method, why, the motion and the registration's measures (JSON types); with JASNOM, its summary too."""
        r = self.registration
        found = {
            "method": self.method,
            "why": self.why,
            "overlap": r.overlap,
            "in_front": r.in_front,
            "rotation": self.rotation.tolist(),
            "translation": self.translation.tolist(),
        }
        return (self.stitched.summary() if self.stitched is not None else {}) | found


def join(first: Model, second: Model, *, seed: int = 0, name: str | None = None, **options: Any) -> Joined:
    """Register ``second`` onto ``first`` where they overlap, else stitch them by JASNOM (module docstring).

    Parameters
    ----------
    first, second : Model
        Two scans of one object, each in its camera's frame (camera at the origin:
        :func:`heatdata.jasnom.scans.read_scan`).
    seed : int
        RANSAC's seed.
    name : str, optional
        The joined model's name (default: ``first.name + "+" + second.name``).
    **options
        :func:`heatdata.jasnom.seam.stitch`'s options for JASNOM (``samples``, ``along``, ``robust``...).

    Returns
    -------
    Joined
    """
    name = name or f"{first.name}+{second.name}"
    registration = register(first.vertices, second.vertices, seed=seed)
    measured = (
        f"after registration {100 * registration.overlap:.0f}% of the smaller scan lies on the other (an overlap "
        f"needs {100 * MIN_OVERLAP:.0f}%) and {100 * registration.in_front:.0f}% of a scan in front of the other's "
        f"surface (at most {100 * MAX_IN_FRONT:.0f}%)"
    )
    if registration.overlapping:
        moved = transformed(second, registration.rotation, registration.translation)
        model = Model.untextured(
            name,
            np.vstack([first.vertices, moved.vertices]),
            np.vstack([first.faces, moved.faces + len(first.vertices)]),
            np.concatenate([first.corner_colors, moved.corner_colors]),
            label=first.label or second.label,
            source=f"registration of {first.source or first.name} and {second.source or second.name}",
        )
        joined = Joined(
            model,
            "registration",
            f"the scans overlap: {measured}",
            registration.rotation,
            registration.translation,
            registration,
            None,
        )
    else:
        stitched = stitch(first, second, scans=True, name=name, **options)
        joined = Joined(
            stitched.model,
            "jasnom",
            f"the scans do not overlap: {measured}",
            stitched.alignment.rotation,
            stitched.alignment.translation,
            registration,
            stitched,
        )
    log.info("%s joined by %s: %s", name, joined.method, joined.why)
    return joined
