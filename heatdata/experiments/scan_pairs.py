"""Pairs of real range scans with the scanner's true poses: each pair joined from random starting motions, and scored.

The scans are read as ``heatdata stitch`` reads them (:func:`heatdata.jasnom.scans.read_scan`: each in its camera's
frame), the second moved by a random start (:func:`random_motion`, seeded: the scanner rolled about its axis by any
angle and shifted; the files' own frames are nearly aligned already, so a method that did nothing would look right
there), and joined by :func:`heatdata.jasnom.join.join`, which registers
overlapping pairs and stitches the rest with JASNOM. The answer is scored against the truth from the scanner's
``.conf`` file: the rotation error in degrees, and the distance between where the found and the true motion put the
second scan's centroid, over the size (the bounding-box diagonal of both scans at the truth).
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation

from heatdata.errors import HeatdataError
from heatdata.io.models import Model
from heatdata.typing import StrPath

log = logging.getLogger(__name__)

#: the file frame of a Cyberware grid against heatdata's camera frame (:mod:`heatdata.frames.range_grid`)
FLIP = np.diag([1.0, -1.0, -1.0])


def read_conf(path: StrPath) -> dict[str, np.ndarray]:
    """A Stanford ``.conf`` file's scan poses: ``bmesh NAME tx ty tz qx qy qz qw``, where a scan's point ``p`` lies
    at ``R(q)^T p + t`` in the object's frame (the repository's convention).

    Returns
    -------
    dict
        Scan file name (as the file writes it, e.g. ``bun000.ply``) to its (4, 4) motion into the object's frame.
    """
    poses = {}
    for number, line in enumerate(Path(path).read_text().splitlines(), 1):
        words = line.split()
        if not words or words[0] != "bmesh":
            continue
        if len(words) != 9:
            raise HeatdataError(f"{path}:{number}: a bmesh line has a name, 3 translations and 4 quaternion values")
        t, q = np.array(words[2:5], float), np.array(words[5:9], float)
        motion = np.eye(4)
        motion[:3, :3] = Rotation.from_quat(q).as_matrix().T
        motion[:3, 3] = t
        poses[words[1]] = motion
    return poses


def camera_offset(model: Model, raw: np.ndarray) -> np.ndarray:
    """The shift along z that :func:`heatdata.frames.range_grid.read_range_grid` gave a scan: ``model``'s vertices
    are ``FLIP @ p + offset`` of the file's points ``raw`` (n, 3), matched by their x and y."""
    _, nearest = cKDTree((raw @ FLIP)[:, :2]).query(model.vertices[:, :2])
    offset = np.median(model.vertices[:, 2] - (raw @ FLIP)[nearest, 2])
    return np.array([0.0, 0.0, offset])


def true_motion(conf: dict[str, np.ndarray], names: tuple[str, str], offsets: tuple[np.ndarray, np.ndarray]):
    """The (4, 4) motion of the second scan's camera frame into the first's, from the scanner's poses."""
    camera = []
    for name, offset in zip(names, offsets, strict=True):
        frame = np.eye(4)  # camera = FLIP @ file + offset
        frame[:3, :3], frame[:3, 3] = FLIP, offset
        camera.append(frame @ np.linalg.inv(conf[name]))  # object frame -> camera frame
    return camera[0] @ np.linalg.inv(camera[1])


def random_motion(rng: np.random.Generator, size: float) -> np.ndarray:
    """A random start for a scan in its camera's frame: a turn by a uniform angle about the optical axis (the
    scanner rolled), then a shift across the view of up to a tenth of ``size`` in each direction. The scan stays in
    front of its camera, as JASNOM's scan constraint needs (the camera at the origin)."""
    motion = np.eye(4)
    motion[:3, :3] = Rotation.from_rotvec([0.0, 0.0, rng.uniform(0.0, 2 * np.pi)]).as_matrix()
    motion[:2, 3] = rng.uniform(-0.1, 0.1, 2) * size
    return motion


@dataclass(frozen=True)
class Trial:
    """One pair joined from one random start, against the truth."""

    pair: str
    start: int
    method: str
    rotation_error: float
    translation_error: float
    overlap: float
    in_front: float
    seconds: float
    ambiguous: bool
    poor: bool
    free_space: float
    cost: float
    free_space_cost: float
    cost_at_truth: float


def errors(found: np.ndarray, truth: np.ndarray, points: np.ndarray, size: float) -> tuple[float, float]:
    """Degrees between two motions' rotations, and the distance between where they put ``points``' centroid over
    ``size``."""
    angle = float(np.degrees(Rotation.from_matrix(found[:3, :3] @ truth[:3, :3].T).magnitude()))
    centre = points.mean(axis=0)
    shift = float(np.linalg.norm(found[:3, :3] @ centre + found[:3, 3] - truth[:3, :3] @ centre - truth[:3, 3]))
    return angle, shift / size


def read_pair(folder: StrPath, names: tuple[str, str], conf: dict[str, np.ndarray]):
    """Two scans of a folder (``NAME.ply``, or ``NAME.ply.xz`` as the data ships) read as :func:`read_scan` reads
    them, and the true motion of the second's camera frame into the first's."""
    import lzma
    import tempfile

    import trimesh

    from heatdata.jasnom.scans import read_scan

    models, offsets = [], []
    for name in names:
        path = Path(folder) / name
        with tempfile.TemporaryDirectory() as temporary:
            if not path.is_file() and path.with_name(path.name + ".xz").is_file():
                plain = Path(temporary) / name
                plain.write_bytes(lzma.decompress(path.with_name(path.name + ".xz").read_bytes()))
                path = plain
            model = read_scan(path)
            raw = np.asarray(trimesh.load(path, process=False).vertices, np.float64)
        models.append(model)
        offsets.append(camera_offset(model, raw))
    return models, true_motion(conf, names, (offsets[0], offsets[1]))


def pair_trials(
    first: Model,
    second: Model,
    truth: np.ndarray,
    pair: str,
    starts: int,
    seed: int = 0,
    free_space: float | None = None,
) -> list[Trial]:
    """``first`` and ``second`` joined from ``starts`` random starting motions of ``second`` (:func:`join`), each
    scored against ``truth`` (module docstring); ``free_space`` is JASNOM's free-space weight (default: the
    stitch's)."""
    from heatdata.io.models import transformed
    from heatdata.jasnom.join import join

    size = float(
        np.linalg.norm(np.ptp(np.vstack([first.vertices, second.vertices @ truth[:3, :3].T + truth[:3, 3]]), axis=0))
    )
    rng = np.random.default_rng(seed)
    trials = []
    for start in range(starts):
        motion = random_motion(rng, size)
        moved = transformed(second, motion[:3, :3], motion[:3, 3])
        begin = time.perf_counter()
        joined = join(first, moved, seed=start, free_space=free_space)
        seconds = time.perf_counter() - begin
        found = np.eye(4)
        found[:3, :3], found[:3, 3] = joined.rotation, joined.translation
        angle, shift = errors(found, truth @ np.linalg.inv(motion), moved.vertices, size)
        alignment = joined.stitched.alignment if joined.stitched is not None else None
        trials.append(
            Trial(
                pair=pair,
                start=start,
                method=joined.method,
                rotation_error=angle,
                translation_error=shift,
                overlap=joined.registration.overlap,
                in_front=joined.registration.in_front,
                seconds=seconds,
                ambiguous=bool(alignment is not None and alignment.ambiguous),
                poor=bool(alignment is not None and alignment.poor),
                **_costs(first, moved, alignment, truth @ np.linalg.inv(motion), free_space),
            )
        )
        log.info(
            "%s start %d: %s, %.2f deg, %.2f%% of the size, %.1f s",
            pair,
            start,
            joined.method,
            angle,
            100 * shift,
            seconds,
        )
    return trials


def _costs(first: Model, moved: Model, alignment, truth: np.ndarray, free_space: float | None) -> dict[str, float]:
    """JASNOM's weight of F, its J and F at the answer, and J at the truth (NaN where the pair was registered)."""
    from heatdata.jasnom.defaults import FREE_SPACE
    from heatdata.jasnom.seam import stitch

    if alignment is None:
        return {"free_space": np.nan, "cost": np.nan, "free_space_cost": np.nan, "cost_at_truth": np.nan}
    weight = FREE_SPACE if free_space is None else free_space
    at_truth = stitch(first, moved, scans=True, motion=truth, free_space=weight).alignment
    return {
        "free_space": weight,
        "cost": alignment.cost,
        "free_space_cost": alignment.free_space_cost,
        "cost_at_truth": at_truth.cost,
    }
