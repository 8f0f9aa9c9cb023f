"""The JASNOM stitch (thesis 7.4): the second mesh moved onto the first and the gap between their loops triangulated."""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.spatial import cKDTree

from heatdata.errors import StitchError
from heatdata.io.models import Model, reversed_faces, rigid_motion, transformed, vertex_colors, welded
from heatdata.jasnom.align import Alignment, align, alignment_at, checked_samples
from heatdata.jasnom.boundary import (
    Boundary,
    _longest,
    _moved,
    _overfull_edges,
    _pair_loops,
    _unit,
    boundaries,
)
from heatdata.jasnom.cost import ScanSurface
from heatdata.jasnom.defaults import ALONG, ALPHA, BETA, GAMMA, SCAN_ALONG, SCAN_ROBUST, TABLE
from heatdata.jasnom.scans import scan_loops
from heatdata.jasnom.table import TableContact, TableScan

log = logging.getLogger(__name__)


def nearest_targets(first: Boundary, second: Boundary) -> np.ndarray:
    """(N,) int64: for each vertex of ``second`` (already in ``first``'s frame), the nearest vertex of ``first``."""
    return cKDTree(first.points).query(second.points)[1].astype(np.int64)


def strip_faces(first: Boundary, second: Boundary, targets: np.ndarray, offset: int) -> np.ndarray:
    """7.4: the triangle strip between two boundaries in one frame, from each second vertex's target on the first.

    The second boundary is walked backwards (the boundaries run in opposite directions on
    a consistently oriented surface, 7.3) from the vertex nearest its target; the targets
    are made monotone along the walk (the order constraint of eq. 7.7: steps of more than
    half the first loop are read as steps back, and steps back are held). Each step
    advances on one boundary and adds one triangle, so the strip has ``K + N`` triangles,
    no two of its edges cross, and each boundary edge is used once against its own face:
    the union is a consistently oriented 2-manifold. Vertices of the first boundary
    without an assignment share the previous target (7.4).

    Parameters
    ----------
    first, second : Boundary
    targets : (N,) int
        A vertex index into ``first.loop`` for each vertex of ``second.loop``.
    offset : int
        Added to the second mesh's vertex indices (its vertices follow the first's).

    Returns
    -------
    (K + N, 3) int64
    """
    k, n = len(first.loop), len(second.loop)
    gaps = np.linalg.norm(first.points[targets] - second.points, axis=1)
    origin = int(np.argmin(gaps))
    walk = (origin - np.arange(n)) % n  # the second boundary, backwards from its best-matched vertex
    steps = (np.diff(targets[walk]) + k // 2) % k - k // 2
    unwrapped = targets[walk[0]] + np.concatenate([[0], np.cumsum(steps)])
    unwrapped = np.minimum(np.maximum.accumulate(unwrapped), targets[walk[0]] + k)
    x = lambda j: int(first.loop[j % k])
    y = lambda i: int(second.loop[i]) + offset
    faces = []
    p = int(unwrapped[0])
    for step in range(n):
        q = walk[step]
        goal = int(unwrapped[step + 1]) if step + 1 < n else int(unwrapped[0]) + k
        while p < goal:  # advance on the first boundary while the second stays at q
            faces.append((x(p + 1), x(p), y(q)))
            p += 1
        following = walk[(step + 1) % n]
        faces.append((y(q), y(following), x(p)))  # advance on the second boundary
    return np.array(faces, dtype=np.int64)


def _weld(
    vertices: np.ndarray, faces: np.ndarray, strip: np.ndarray, offset: int, tolerance: float
) -> tuple[np.ndarray, np.ndarray, int]:
    """The strip's coincident pairs welded: a strip edge between the meshes no longer than ``tolerance`` joins its
    ends, each vertex to at most one, shortest first; the triangles this degenerates are dropped.

    Returns the faces with welded indices (the second mesh's vertex becomes the first's), the mask of faces kept
    and how many pairs were welded. If welding would leave an edge of more than two faces, nothing is welded.
    """
    edges = np.concatenate([strip[:, [0, 1]], strip[:, [1, 2]], strip[:, [2, 0]]])
    cross = np.unique(np.sort(edges[(edges[:, 0] < offset) != (edges[:, 1] < offset)], axis=1), axis=0)
    lengths = np.linalg.norm(vertices[cross[:, 0]] - vertices[cross[:, 1]], axis=1)
    index = np.arange(len(vertices))
    taken: set[int] = set()
    for k in np.argsort(lengths, kind="stable"):
        if lengths[k] > tolerance:
            break
        a, b = (int(v) for v in cross[k])
        if a not in taken and b not in taken:
            taken.update((a, b))
            index[b] = a
    joined = index[faces]
    keep = (joined[:, 0] != joined[:, 1]) & (joined[:, 1] != joined[:, 2]) & (joined[:, 2] != joined[:, 0])
    if taken and _overfull_edges(joined[keep]):
        log.warning(
            "welding the seam's coincident vertices would make an edge of more than two faces: the strip is kept whole"
        )
        return faces, np.ones(len(faces), dtype=bool), 0
    return joined, keep, len(taken) // 2


def _same_direction(first: Boundary, second: Boundary) -> bool:
    """Whether two boundaries in one frame run the same way (their nearest vertices' tangents agree on average):
    on one consistently oriented surface they run opposite ways (7.3)."""

    def tangents(b: Boundary) -> np.ndarray:
        return _unit(np.roll(b.points, -1, axis=0) - np.roll(b.points, 1, axis=0))

    targets = nearest_targets(first, second)
    return float(np.mean(np.einsum("ij,ij->i", tangents(first)[targets], tangents(second)))) > 0


@dataclass(frozen=True)
class Stitched:
    """What :func:`stitch` returns: the stitched model, the alignment, the two longest boundaries (the second moved),
    how many loop pairs were stitched, how many loops stay open, how many vertex pairs were welded, how many
    strip triangles the model keeps (its last faces) and, for scans, how many loops are holes inside the
    silhouettes rather than a silhouette (:mod:`heatdata.jasnom.scans`)."""

    model: Model
    alignment: Alignment
    first: Boundary
    second: Boundary
    loop_pairs: int
    open_loops: int
    welded: int
    strip_faces: int
    holes: int

    def summary(self) -> dict[str, Any]:
        """What ``heatdata stitch`` prints and rule ``stitch`` records: the motion, J and its terms, the
        runner-up, the seam's gap and what was stitched (JSON types; ``runner_up`` None when nothing else was
        tried).

        Returns
        -------
        dict
        """
        a = self.alignment
        return {
            "rotation": a.rotation.tolist(),
            "translation": a.translation.tolist(),
            "cost": a.cost,
            "edge_cost": a.edge_cost,
            "crossing_cost": a.crossing_cost,
            "crease_cost": a.crease_cost,
            "table_cost": a.table_cost,
            "free_space_cost": a.free_space_cost,
            "runner_up": None if np.isnan(a.runner_up) else a.runner_up,
            "ambiguous": a.ambiguous,
            "mean_gap": a.gap,
            "mean_gap_of_size": a.gap / a.size,
            "poor": a.poor,
            "facing": a.facing,
            "boundaries": [len(self.first.loop), len(self.second.loop)],
            "loop_pairs": self.loop_pairs,
            "open_loops": self.open_loops,
            "welded": self.welded,
            "strip_faces": self.strip_faces,
            "holes": self.holes,
            "seconds": a.seconds,
        }


def stitch(
    first: Model,
    second: Model,
    *,
    alpha: float = ALPHA,
    beta: float = BETA,
    gamma: float = GAMMA,
    along: float | None = None,
    robust: float | None = None,
    samples: int = 128,
    scans: bool = False,
    name: str | None = None,
    motion: np.ndarray | None = None,
    contact: TableContact | None = None,
    table: float = TABLE,
    free_space: float | None = None,
) -> Stitched:
    """JASNOM: align ``second`` onto ``first`` by their longest boundaries and stitch them into one model.

    The longest loops align the meshes (7.2-7.3, 7.5; module docstring). Beyond the
    thesis, the other loops (a cut through a concave object leaves several) are paired by
    their mean distance and similar length and stitched at that alignment.

    Parameters
    ----------
    first, second : Model
        Two meshes that together cover an object without overlapping, each a 2-manifold
        with a boundary, both wound the same way about the object (both outwards, or both
        inwards as two of heatdata's views are, whose faces point away from their cameras).
        Coincident vertices (an STL file's, or a cut's duplicated ones) are merged first
        (:func:`heatdata.io.models.welded`), and the merge is recorded in the model's
        ``repairs``.
    alpha, beta, gamma, along, robust, samples
        As for :func:`align`; ``along`` and ``robust`` default to :data:`ALONG` and 0, or
        for scans to :data:`SCAN_ALONG` and :data:`SCAN_ROBUST`.
    scans : bool
        Each mesh is a depth scan in its own camera's frame (the camera at the origin, as
        a sensor writes it), the two taken from roughly opposite sides (the object
        flipped, 7.5). Poses are then allowed where each scan lies on the far side of
        the object from the other's camera (:class:`ScanSurface`), instead of where the
        boundary normals face each other, which silhouettes cut at depth jumps do not.
    name : str, optional
        The stitched model's name (default: ``first.name + "+" + second.name``).
    motion : (4, 4) float, optional
        A known rigid motion of ``second`` into ``first``'s frame (registered cameras, a
        turntable): nothing is searched (:func:`alignment_at`), and boundaries that do not
        face each other there (a gap of grazing surface between two opposite scans) are
        stitched anyway, with a warning.
    contact : TableContact, optional
        The scans' tables (the object scanned standing, then flipped, on a table;
        :func:`stitch_scans` gives them): J gains the support-plane term and the search the
        flip candidates (:mod:`heatdata.jasnom.table`).
    table : float
        The support-plane term's weight (default :data:`heatdata.jasnom.defaults.TABLE`).
    free_space : float, optional
        The free-space term's weight (:class:`heatdata.jasnom.align.Witnesses`; default
        :func:`heatdata.jasnom.align.free_space_weight`'s: :data:`heatdata.jasnom.defaults.FREE_SPACE` for scans
        without tables, else 0).

    Returns
    -------
    Stitched
        ``model`` is in ``first``'s frame: the first mesh's vertices, then the second's
        moved there (less those welded to the first's), and the strip's triangles last
        (coloured by their corners' vertex colours); both meshes' textures are kept.

    Raises
    ------
    StitchError
        As :func:`boundary` and :func:`align` (no pose where the meshes face each other);
        the same mesh twice.
    """
    checked_samples(samples)
    if (
        first.vertices.shape == second.vertices.shape
        and first.faces.shape == second.faces.shape
        and np.array_equal(first.faces, second.faces)
        and np.allclose(first.vertices, second.vertices)
    ):
        raise StitchError(
            f"{first.name} and {second.name} are the same mesh: JASNOM joins two different parts of an object"
        )
    first, second = welded(first), welded(second)
    loops1, loops2 = boundaries(first), boundaries(second)
    b1, b2 = _longest(loops1, first.name), _longest(loops2, second.name)
    # every loop aligns, as a cut's do: a scan's loops other than its silhouette, though most are what the scanner
    # missed, align two opposite bunny scans better than the silhouettes alone (6 deg off against 10;
    # docs/chapters/jasnom.md); they are counted
    in_camera_frames = scans and all(np.all(model.vertices[:, 2] > 0) for model in (first, second))
    holes = (
        sum(len(scan_loops(model, loops).holes) for model, loops in ((first, loops1), (second, loops2)))
        if in_camera_frames
        else 0
    )
    weights: dict[str, Any] = {
        "alpha": alpha,
        "beta": beta,
        "gamma": gamma,
        "samples": samples,
        "along": (SCAN_ALONG if scans else ALONG) if along is None else along,
        "robust": (SCAN_ROBUST if scans else 0.0) if robust is None else robust,
    }
    if contact is not None:
        weights |= {"contact": contact, "table": table}
    surfaces = (ScanSurface.of(first), ScanSurface.of(second)) if scans else None
    weights |= {"scans": surfaces, "free_space": free_space}
    if motion is None:
        alignment = align(loops1, loops2, **weights)
    else:
        motion = rigid_motion(motion)
        alignment = alignment_at(loops1, loops2, motion[:3, :3], motion[:3, 3], **weights)
    if alignment.facing > 0 and motion is not None and not scans:  # a found motion faces them (align's constraint)
        log.warning(
            "%s and %s do not face each other across their boundaries at the given motion (mean cosine of "
            "the boundary normals %+.2f): the strip spans a gap the scans did not see",
            first.name,
            second.name,
            alignment.facing,
        )
    if _same_direction(b1, _moved(b2, alignment.rotation, alignment.translation)):
        log.warning(
            "%s is wound the other way round the object from %s (their boundaries run the same way at the "
            "seam): its faces are reversed",
            second.name,
            first.name,
        )
        second = reversed_faces(second)
        loops2 = boundaries(second)
    moved = transformed(second, alignment.rotation, alignment.translation)
    moved_loops = [_moved(b, alignment.rotation, alignment.translation) for b in loops2]
    moved_b2 = moved_loops[0]
    offset = len(first.vertices)
    pairs = [(b1, moved_b2), *_pair_loops(loops1[1:], moved_loops[1:])]
    strip = np.vstack([strip_faces(l1, l2, nearest_targets(l1, l2), offset) for l1, l2 in pairs])
    open_loops = b1.loops + moved_b2.loops - 2 * len(pairs)
    if open_loops:
        log.warning(
            "%d boundary loop(s) of %s and %s have no partner and stay open%s",
            open_loops,
            first.name,
            second.name,
            f", {holes} of them holes inside the scans' silhouettes (what the scanners missed)" if holes else "",
        )
    vertices = np.vstack([first.vertices, moved.vertices])
    colors = np.vstack([vertex_colors(first), vertex_colors(moved)])
    faces = np.vstack([first.faces, moved.faces + offset, strip])
    seam = np.concatenate(
        [np.linalg.norm(np.roll(b.points, -1, axis=0) - b.points, axis=1) for pair in pairs for b in pair]
    )
    faces, keep, seam_welds = _weld(vertices, faces, strip, offset, 0.01 * float(np.median(seam)))
    faces = faces[keep]
    used = np.unique(faces)
    index = np.full(len(vertices), -1, np.int64)
    index[used] = np.arange(len(used))
    model = Model(
        name=name or f"{first.name}+{second.name}",
        vertices=vertices[used],
        faces=index[faces],
        corner_colors=np.concatenate([first.corner_colors, moved.corner_colors, colors[strip].astype(np.float32)])[
            keep
        ],
        corner_uv=np.concatenate([first.corner_uv, moved.corner_uv, np.zeros((len(strip), 3, 2), np.float32)])[keep],
        face_texture=np.concatenate(
            [
                first.face_texture,
                np.where(moved.face_texture >= 0, moved.face_texture + len(first.textures), -1),
                np.full(len(strip), -1),
            ]
        ).astype(np.int32)[keep],
        textures=list(first.textures) + list(moved.textures),
        label=first.label or second.label,
        source=f"JASNOM of {first.source or first.name} and {second.source or second.name}",
        repairs=list(first.repairs) + list(second.repairs),
    )
    strip_kept = int(keep[len(first.faces) + len(second.faces) :].sum())
    log.info(
        "stitched %s: J %.4g (J1 %.3g, J2 %.3g, J3 %.3g; runner-up %.4g), mean gap %.3g, %d loop pair(s), "
        "%d vertex pair(s) welded, %d strip triangles, %.1f s",
        model.name,
        alignment.cost,
        alignment.edge_cost,
        alignment.crossing_cost,
        alignment.crease_cost,
        alignment.runner_up,
        alignment.gap,
        len(pairs),
        seam_welds,
        strip_kept,
        alignment.seconds,
    )
    return Stitched(
        model=model,
        alignment=alignment,
        first=b1,
        second=moved_b2,
        loop_pairs=len(pairs),
        open_loops=open_loops,
        welded=seam_welds,
        strip_faces=strip_kept,
        holes=holes,
    )


def stitch_scans(first: TableScan, second: TableScan, **options: Any) -> Stitched:
    """JASNOM on an object scanned standing on a table, then flipped upside down on it (thesis 7.5): :func:`stitch`
    of the two scans' objects (``scans=True``) with their tables as witnesses (:mod:`heatdata.jasnom.table`).

    Parameters
    ----------
    first, second : TableScan
        The standing scan (the output is in its camera's frame) and the flipped one
        (:func:`heatdata.jasnom.table.table_scan`).
    **options
        :func:`stitch`'s other options (``samples``, ``table``, ``motion``, ``name``...).

    Returns
    -------
    Stitched

    Raises
    ------
    StitchError
        As :func:`stitch`; objects whose heights above their tables differ (not one object).
    """
    return stitch(first.model, second.model, scans=True, contact=TableContact.of_scans(first, second), **options)
