"""Scenes of the run's objects on a table, as a depth sensor sees them, and how well each is found and named.

The workflow's scenes steps (config ``scenes``):

- :func:`plan_scene`: 1-4 of the run's objects at random positions and yaw on a table (their footprints apart),
  a wall behind it, and a camera 0.8-1.5 m from a point of the table at 20-50 deg elevation, its azimuth within
  40 deg of the table's front; every draw from one seed per scene;
- :func:`render_planned_scene`: the frame by :func:`heatdata.views.render.render_scene` with the sensor profile
  (the Kinect's by default), and the ground truth: which object each pixel sees, each object's pose in the
  camera frame, how many of its pixels have a reading, how much of it the other objects hide, whether the image
  border cuts it;
- :func:`write_scene`: the frame as a user's capture is written (a 16-bit depth PNG in millimetres,
  ``<name>.rgb.png``, ``<name>.json`` intrinsics) plus ``<name>.labels.png`` (object ``i`` of the truth is
  ``i + 1``) and ``<name>.truth.json``;
- :func:`score_scene`: each detection of :meth:`heatdata.recognition.library.Library.recognize_scene` matched to
  the object whose pixels it overlaps most (mask IoU >= 0.5), and each object no detection matched;
- :func:`scene_summary`: detection recall (objects with at least :data:`MIN_OBJECT_PIXELS` readings), the share of
  segments that match no object, naming accuracy for unoccluded objects and, apart, for partly occluded or cut
  ones, how many right answers are confident enough to be said and how many mistakes are said to be unknown, and
  the latency per frame.

The frames are renderings through a sensor profile, not sensor data.
"""

from __future__ import annotations

import json
import logging
import zlib
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd
from PIL import Image

from heatdata.core.geometry import turn_about_up
from heatdata.errors import HeatdataError
from heatdata.io.files import atomic
from heatdata.io.models import Model, transformed
from heatdata.io.tables import DETECTION_SCHEMA
from heatdata.typing import StrPath
from heatdata.views.depth import back_project
from heatdata.views.sensor import SensorProfile
from heatdata.views.view import kinect_intrinsics

if TYPE_CHECKING:  # the renderer imports open3d: only where a scene is rendered, not where the workflow plans it
    from heatdata.views.render import Placement, SceneFrame

log = logging.getLogger(__name__)

TABLE_HEIGHT = 0.75  # m, the table top above the floor (the scene's y = 0)
TABLE_THICKNESS = 0.03
TABLE_COLOR = (0.55, 0.4, 0.25)
WALL_COLOR = (0.85, 0.85, 0.8)
FLOOR_COLOR = (0.45, 0.42, 0.4)
FLOOR_SIZE = 8.0  # m square: beyond the table's edges the camera sees the floor, as in a room
WALL_SIZE = (3.0, 2.4)  # m, width and height from the floor
EDGE_MARGIN = 0.03  # m between an object's footprint and the table's edge
GAP = 0.02  # m between two objects' footprints (objects do not touch)
AZIMUTH_SPAN = 40.0  # degrees either side of the table's front
TARGET_JITTER = 0.15  # m: where on the table the camera looks, about its centre
MIN_OBJECT_PIXELS = 1000  # objects with fewer readings are not counted in the detection recall
OCCLUDED = 0.05  # an object with more than this share of its pixels hidden by other objects is partly occluded
IOU = 0.5  # a detection matches an object when their masks' intersection over union is at least this

#: the scenes' defaults (config ``scenes``)
SCENE_DEFAULTS = {
    "count": 6,
    "objects": [1, 4],
    "distance": [0.8, 1.5],
    "elevation": [20.0, 50.0],
    "table": [1.2, 0.8],
    "wall_gap": [0.0, 0.2],
    "sensor": "kinect",
    "image_scale": 1.0,
    "seed": 0,
}


def box_model(name: str, extents: tuple[float, float, float], color: tuple[float, float, float]) -> Model:
    """A box of one colour centred at the origin (a table top, a wall).

    Parameters
    ----------
    name : str
        The model's name.
    extents : (3,) float
        Sizes along x, y (up) and z, metres.
    color : (3,) float
        RGB in [0, 1].

    Returns
    -------
    Model
    """
    import trimesh

    box = trimesh.creation.box(extents=extents)
    return Model.untextured(name, np.asarray(box.vertices), np.asarray(box.faces), color, label=name)


def _transform(translation, yaw: float = 0.0) -> np.ndarray:
    """(4, 4): a turn of ``yaw`` degrees about +y, then a translation."""
    pose = np.eye(4)
    pose[:3, :3] = turn_about_up(yaw)
    pose[:3, 3] = translation
    return pose


def scene_seed(seed: int, index: int) -> int:
    """The seed of scene ``index`` of a run seeded ``seed`` (the same scene whatever the count)."""
    return int(np.random.SeedSequence([seed, zlib.crc32(b"scene"), index]).generate_state(1)[0])


def choose_objects(objects: list[str], settings: dict, index: int) -> list[str]:
    """The objects of scene ``index``: 1-4 of ``objects`` (``settings["objects"]``), drawn without repeats."""
    if not objects:
        raise HeatdataError("a scene needs objects: the run has none")
    rng = np.random.default_rng(scene_seed(settings["seed"], index))
    low, high = settings["objects"]
    count = int(rng.integers(low, min(high, len(objects)) + 1)) if low <= len(objects) else len(objects)
    return [str(o) for o in rng.choice(sorted(objects), size=max(1, count), replace=False)]


def fits_table(width: float, depth: float, table: list[float]) -> bool:
    """Whether an object ``width`` x ``depth`` m across (its x and z extents) stands on ``table`` at any yaw.

    Its footprint's circumscribed circle, :data:`EDGE_MARGIN` from each edge, must fit the ``[width, depth]`` top.
    """
    radius = 0.5 * float(np.hypot(width, depth))
    return min(table) / 2 - radius - EDGE_MARGIN > 0


def plan_scene(models: list[Model], settings: dict, index: int) -> dict:
    """Where scene ``index`` puts ``models`` on the table, and where its camera is (seeded, see the module).

    Parameters
    ----------
    models : list of Model
        The scene's objects (:func:`choose_objects`).
    settings : dict
        The config's ``scenes`` (:data:`SCENE_DEFAULTS`).
    index : int
        The scene's number.

    Returns
    -------
    dict
        ``scene`` (its name), ``objects`` (``object, x, z, yaw``: the footprint's centre on the table and the turn
        about +y in degrees), ``camera`` (``distance, elevation, azimuth, target``), ``wall_gap``, ``seed``, and
        ``left_out``: the models not placed, each with its size: too large for the table (:func:`fits_table`), or
        with no room left beside the others.
    """
    rng = np.random.default_rng(scene_seed(settings["seed"], index) + 1)
    width, depth = settings["table"]
    placed: list[dict] = []
    left_out = []
    for model in models:
        radius = 0.5 * float(np.hypot(model.extents[0], model.extents[2]))
        if not fits_table(model.extents[0], model.extents[2], settings["table"]):
            left_out.append(f"{model.name} ({2 * radius:.2f} m across)")
            continue
        half_x, half_z = width / 2 - radius - EDGE_MARGIN, depth / 2 - radius - EDGE_MARGIN
        for _ in range(200):
            x, z = rng.uniform(-half_x, half_x), rng.uniform(-half_z, half_z)
            if all(np.hypot(x - p["x"], z - p["z"]) >= radius + p["radius"] + GAP for p in placed):
                break
        else:
            left_out.append(f"{model.name} ({2 * radius:.2f} m across, no room beside the others)")
            continue
        placed.append({"object": model.name, "x": float(x), "z": float(z), "yaw": float(rng.uniform(0, 360)),
                       "radius": radius})  # fmt: skip
    target = [float(rng.uniform(-TARGET_JITTER, TARGET_JITTER)), TABLE_HEIGHT,
              float(rng.uniform(-TARGET_JITTER, TARGET_JITTER))]  # fmt: skip
    return {
        "scene": f"scene-{index:03d}",
        "objects": [{k: v for k, v in p.items() if k != "radius"} for p in placed],
        "camera": {
            "distance": float(rng.uniform(*settings["distance"])),
            "elevation": float(rng.uniform(*settings["elevation"])),
            "azimuth": float(rng.uniform(-AZIMUTH_SPAN, AZIMUTH_SPAN)),
            "target": target,
        },
        "wall_gap": float(rng.uniform(*settings["wall_gap"])),
        "seed": scene_seed(settings["seed"], index),
        "left_out": left_out,
    }


def room(width: float, depth: float, wall_gap: float) -> list[Placement]:
    """The furniture of every scene: a ``width`` x ``depth`` m table, a wall ``wall_gap`` m behind it, the floor."""
    from heatdata.views.render import Placement

    table = box_model("table", (width, TABLE_THICKNESS, depth), TABLE_COLOR)
    wall = box_model("wall", (WALL_SIZE[0], WALL_SIZE[1], 0.02), WALL_COLOR)
    floor = box_model("floor", (FLOOR_SIZE, 0.02, FLOOR_SIZE), FLOOR_COLOR)
    return [
        Placement(table, _transform([0.0, TABLE_HEIGHT - TABLE_THICKNESS / 2, 0.0])),
        Placement(wall, _transform([0.0, WALL_SIZE[1] / 2, -depth / 2 - wall_gap - 0.01])),
        Placement(floor, _transform([0.0, -0.01, 0.0])),
    ]


def object_pose(model: Model, x: float, z: float, yaw_degrees: float) -> np.ndarray:
    """(4, 4) model-to-scene pose of ``model`` standing on the table top, its footprint centred at ``(x, z)``."""
    low, high = model.vertices.min(axis=0), model.vertices.max(axis=0)
    centre = _transform([-(low[0] + high[0]) / 2, -low[1], -(low[2] + high[2]) / 2])
    return _transform([x, TABLE_HEIGHT, z], yaw_degrees) @ centre


def render_flipped_pair(
    model: Model,
    *,
    elevation: float,
    yaw: float = 0.0,
    flip_axis: float = 0.0,
    distance: float | None = None,
    settings: dict | None = None,
    seed: int = 0,
) -> tuple[SceneFrame, SceneFrame, np.ndarray]:
    """Two frames of ``model`` on the scenes' table, as JASNOM's acquisition takes them (thesis 7.5): standing, then
    flipped upside down where it stood, from one camera in front of the table.

    Parameters
    ----------
    model : Model
        The object.
    elevation : float
        The camera's elevation above the table, degrees.
    yaw : float
        The standing object's turn about +y, degrees.
    flip_axis : float
        How far off the user's flip is, degrees: the object is turned about +y by ``yaw + flip_axis``, then by a
        half-turn about x, the axis across the camera's view. With 0 the flip turns the sides the camera did not
        see towards it.
    distance : float, optional
        Camera to the object's centre, metres (default three times its size, at least 0.6 m).
    settings : dict, optional
        The scenes' settings (:data:`SCENE_DEFAULTS`): the table, the sensor, the image scale.
    seed : int
        The sensor noise's seed (the second frame's is the next).

    Returns
    -------
    standing, flipped : SceneFrame
    motion : (4, 4) float64
        The flipped frame's camera coordinates to the standing frame's: the truth JASNOM looks for.
    """
    from heatdata.views.render import Placement, camera_pose, render_scene

    settings = {**SCENE_DEFAULTS, **(settings or {})}
    standing = object_pose(model, 0.0, 0.0, yaw)
    turn = np.eye(4)
    turn[:3, :3] = turn_about_up(yaw + flip_axis)
    turn[:3, :3] = np.diag([1.0, -1.0, -1.0]) @ turn[:3, :3]  # then a half-turn about x
    flipped = object_pose(transformed(model, turn[:3, :3], np.zeros(3)), 0.0, 0.0, 0.0) @ turn
    size = float(np.linalg.norm(model.extents))
    target = np.array([0.0, TABLE_HEIGHT + model.extents[1] / 2, 0.0])
    camera = camera_pose(target, 0.0, elevation, distance or max(0.6, 3.0 * size))
    k = kinect_intrinsics(settings.get("image_scale", 1.0))
    sensor = SensorProfile.named(settings["sensor"])
    width, depth = settings["table"]
    frames = [
        render_scene(
            [*room(width, depth, 0.1), Placement(model, pose)], camera, intrinsics=k, sensor=sensor, seed=seed + i
        )
        for i, pose in enumerate((standing, flipped))
    ]
    return frames[0], frames[1], np.linalg.inv(camera) @ standing @ np.linalg.inv(flipped) @ camera


def render_planned_scene(plan: dict, models: dict[str, Model], settings: dict) -> tuple[SceneFrame, dict]:
    """The frame of a :func:`plan_scene` plan and its ground truth.

    Parameters
    ----------
    plan : dict
        A plan of :func:`plan_scene`.
    models : dict of str to Model
        Its objects' models by name.
    settings : dict
        The config's ``scenes``.

    Returns
    -------
    frame : SceneFrame
        Depth, colour and which model each pixel sees.
    truth : dict
        ``scene, camera`` (camera-to-scene 4 x 4), ``plane`` (the table top ``a, b, c, d`` in the camera frame, normal
        towards the camera), ``sensor``, ``seed`` and ``objects``: per object ``object, label, pose`` (model to
        camera, 4 x 4; the model frame is the catalogue model's, metres, +y up), ``pixels`` (readings),
        ``visible`` (pixels its rays hit), ``occluded`` (share hidden by other objects), ``cut`` (by the image
        border) and ``centroid`` (mean of its readings' points, camera frame).
    """
    from heatdata.views.render import Placement, camera_pose, render_scene

    width, depth = settings["table"]
    placements = room(width, depth, plan["wall_gap"])
    placements += [
        Placement(models[o["object"]], object_pose(models[o["object"]], o["x"], o["z"], o["yaw"]))
        for o in plan["objects"]
    ]
    cam = plan["camera"]
    camera = camera_pose(np.asarray(cam["target"]), cam["azimuth"], cam["elevation"], cam["distance"])
    intrinsics = kinect_intrinsics(settings.get("image_scale", 1.0))
    sensor = SensorProfile.named(settings["sensor"])
    frame = render_scene(placements, camera, intrinsics=intrinsics, sensor=sensor, seed=plan["seed"])
    to_camera = np.linalg.inv(camera)
    readings = np.isfinite(frame.depth)
    objects = []
    furniture = len(placements) - len(plan["objects"])
    for index, placement in enumerate(placements[furniture:], start=furniture):
        visible = frame.labels == index
        alone = render_scene([*placements[:furniture], placement], camera, intrinsics=intrinsics, sensor="ideal")
        alone_pixels = alone.labels == furniture
        mine = visible & readings
        points = back_project(frame.depth, intrinsics)[mine]
        projected = _project(placement.model.vertices @ placement.pose[:3, :3].T + placement.pose[:3, 3], to_camera,
                             intrinsics)  # fmt: skip
        objects.append(
            {
                "object": placement.model.name,
                "label": placement.model.label,
                "pose": (to_camera @ placement.pose).tolist(),
                "pixels": int(mine.sum()),
                "visible": int(visible.sum()),
                "occluded": float(1.0 - visible.sum() / alone_pixels.sum()) if alone_pixels.any() else 1.0,
                "cut": bool(_cut(projected, intrinsics)),
                "centroid": points.mean(axis=0).tolist() if len(points) else [float("nan")] * 3,
            }
        )
    top = np.array([0.0, 1.0, 0.0, -TABLE_HEIGHT])  # y = TABLE_HEIGHT, normal up, in the scene's frame
    plane = top @ camera  # a plane transforms by the inverse transpose of the point transform
    truth = {
        "scene": plan["scene"],
        "camera": camera.tolist(),
        "plane": (plane / np.linalg.norm(plane[:3])).tolist(),
        "sensor": sensor.to_dict(),
        "seed": plan["seed"],
        "plan": plan,
        "objects": objects,
    }
    return frame, truth


def _project(points: np.ndarray, to_camera: np.ndarray, k: dict) -> np.ndarray:
    p = points @ to_camera[:3, :3].T + to_camera[:3, 3]
    return np.column_stack([k["fx"] * p[:, 0] / p[:, 2] + k["cx"], k["fy"] * p[:, 1] / p[:, 2] + k["cy"], p[:, 2]])


def _cut(projected: np.ndarray, k: dict) -> bool:
    """Whether a model's projected vertices leave the image (or pass behind the camera)."""
    u, v, z = projected.T
    return bool(np.any(z <= 0) or u.min() < 0 or v.min() < 0 or u.max() > k["width"] - 1 or v.max() > k["height"] - 1)


def write_scene(frame: SceneFrame, truth: dict, depth_path: StrPath) -> None:
    """Write a scene as a capture is written, with its truth: ``<name>.png`` (16-bit depth, mm), ``<name>.rgb.png``,
    ``<name>.json`` (intrinsics), ``<name>.labels.png`` (truth object ``i`` is ``i + 1``, 0 the rest) and
    ``<name>.truth.json``.

    Parameters
    ----------
    frame : SceneFrame
        The rendered frame.
    truth : dict
        Its truth (:func:`render_planned_scene`).
    depth_path : str or Path
        The depth PNG's path; the other files go beside it.
    """
    path = Path(depth_path)
    base = path.with_suffix("")
    millimetres = np.nan_to_num(np.round(frame.depth * 1000.0), nan=0.0)
    if millimetres.max() > np.iinfo(np.uint16).max:
        raise HeatdataError(f"{path}: depths beyond 65.5 m cannot be written as a depth PNG")
    labels = np.zeros(frame.labels.shape, np.uint8)
    furniture = len(frame.names) - len(truth["objects"])
    for number in range(len(truth["objects"])):
        labels[frame.labels == furniture + number] = number + 1
    images: dict[Path, np.ndarray] = {
        path: millimetres.astype(np.uint16),
        Path(f"{base}.rgb.png"): np.round(frame.rgb * 255).astype(np.uint8),
        Path(f"{base}.labels.png"): labels,
    }
    for target, image in images.items():
        with atomic(target) as temporary:
            Image.fromarray(image).save(temporary, format="PNG")
    texts = {Path(f"{base}.json"): frame.intrinsics, Path(f"{base}.truth.json"): truth}
    for target, data in texts.items():
        with atomic(target) as temporary:
            temporary.write_text(json.dumps(data, indent=1) + "\n")


def scene_files(depth_path: StrPath) -> dict[str, Path]:
    """The files of a scene written by :func:`write_scene`, by role: ``depth, rgb, intrinsics, labels, truth``."""
    path = Path(depth_path)
    base = path.with_suffix("")
    return {
        "depth": path,
        "rgb": Path(f"{base}.rgb.png"),
        "intrinsics": Path(f"{base}.json"),
        "labels": Path(f"{base}.labels.png"),
        "truth": Path(f"{base}.truth.json"),
    }


def score_scene(
    detections: list, labels: np.ndarray, depth: np.ndarray, truth: dict, surfaces: dict | None = None
) -> pd.DataFrame:
    """Each detection matched to the object its mask overlaps most (IoU >= :data:`IOU`), and each object missed;
    a detection posed as its true object scored against the true pose (:func:`heatdata.recognition.pose.pose_errors`).

    Parameters
    ----------
    detections : list of Detection
        :meth:`heatdata.recognition.library.Library.recognize_scene`'s, with their masks.
    labels : (h, w) int
        The truth's label image (:func:`write_scene`: object ``i`` is ``i + 1``).
    depth : (h, w) float
        The frame's depth (NaN or 0: no reading); an object's mask is its pixels with a reading.
    truth : dict
        The scene's truth.
    surfaces : dict, optional
        ``{object: (Surface, symmetry turns)}`` (:func:`heatdata.recognition.pose.symmetry_turns`): the objects
        whose poses are scored.

    Returns
    -------
    pandas.DataFrame
        One row per detection and per missed object, the columns of :data:`heatdata.io.tables.DETECTION_SCHEMA`
        but ``descriptor``, ``seconds`` and ``seconds_without_pose``: ``detection`` is -1 for a missed object,
        ``object`` "" for none, ``truth`` "" for a detection that matches no object; ``mask`` the detection's
        pixels in its box (:func:`pack_mask`); the pose errors NaN where the pose is not of the true object.
    """
    readings = np.isfinite(depth) & (depth > 0)
    masks = [(labels == i + 1) & readings for i in range(len(truth["objects"]))]
    rows, matched = [], set()
    for number, detection in enumerate(detections):
        ious = [_iou(detection.mask, mask) for mask in masks]
        best = int(np.argmax(ious)) if ious else -1
        hit = best >= 0 and ious[best] >= IOU
        if hit:
            matched.add(best)
        row = _score_row(truth, number, detection, best if hit else None, ious[best] if ious else 0.0)
        rows.append({**row, **_pose_row(detection, truth["objects"][best] if hit else None, surfaces or {})})
    for index in sorted(set(range(len(masks))) - matched):
        rows.append({**_score_row(truth, -1, None, index, 0.0), **_pose_row(None, None, {})})
    timed = ("descriptor", "seconds", "seconds_without_pose")
    return pd.DataFrame(rows, columns=[c for c in DETECTION_SCHEMA.names if c not in timed])


def _pose_row(detection, item: dict | None, surfaces: dict) -> dict:
    """A detection's pose, how it was judged, and its errors when it poses the true object ``item``."""
    from heatdata.recognition.pose import pose_errors

    pose = None if detection is None else detection.pose
    found = detection is not None and detection.recognition is not None
    row = {
        "threshold": detection.recognition.threshold if found else np.nan,
        "verified": bool(found and detection.recognition.verified),
        "posed": "" if pose is None else pose.object,
        "fitness": np.nan if pose is None else pose.fitness,
        "rmse": np.nan if pose is None else pose.rmse,
        "explained": np.nan if pose is None else pose.explained,
        "in_front": np.nan if pose is None else pose.in_front,
        "pose": [] if pose is None else pose.matrix.ravel().tolist(),
        "add_s": np.nan,
        "add_s_ok": False,
        "translation_error": np.nan,
        "rotation_error": np.nan,
        "symmetric": False,
    }
    if pose is not None and item is not None and pose.object == item["object"] and pose.object in surfaces:
        surface, turns = surfaces[pose.object]
        errors = pose_errors(pose.matrix, np.asarray(item["pose"]), surface, turns)
        row.update(
            add_s=errors["add_s"],
            add_s_ok=errors["add_s_ok"],
            translation_error=errors["translation"],
            rotation_error=errors["rotation"],
            symmetric=len(turns) > 1,
        )
    return row


def _iou(a: np.ndarray, b: np.ndarray) -> float:
    union = int((a | b).sum())
    return int((a & b).sum()) / union if union else 0.0


def pack_mask(mask: np.ndarray, bbox) -> bytes:
    """A detection's pixels inside its box ``u0, v0, u1, v1`` as packed bits (:func:`unpack_mask` reads them)."""
    u0, v0, u1, v1 = bbox
    return np.packbits(mask[v0 : v1 + 1, u0 : u1 + 1]).tobytes()


def unpack_mask(data: bytes, bbox, shape: tuple[int, int]) -> np.ndarray:
    """(h, w) bool: the mask :func:`pack_mask` packed, placed in a frame of ``shape``."""
    u0, v0, u1, v1 = (int(b) for b in bbox)
    size = (v1 - v0 + 1, u1 - u0 + 1)
    mask = np.zeros(shape, bool)
    mask[v0 : v1 + 1, u0 : u1 + 1] = np.unpackbits(np.frombuffer(data, np.uint8), count=size[0] * size[1]).reshape(size)
    return mask


def _score_row(truth: dict, number: int, detection, index: int | None, iou: float) -> dict:
    item = truth["objects"][index] if index is not None else {}
    found = detection is not None
    best = detection.recognition.answer if found and detection.recognition is not None else None
    return {
        "scene": truth["scene"],
        "detection": number,
        "object": "" if best is None else best.object,
        "label": "" if best is None else best.label,
        "distance": np.nan if best is None else best.distance,
        "confidence": detection.confidence if found else np.nan,
        "known": bool(found and detection.object is not None),
        "azimuth": np.nan if best is None else best.azimuth,
        "pixels": detection.pixels if found else 0,
        "centroid": list(detection.centroid) if found else [],
        "bbox": list(detection.bbox) if found else [],
        "notes": list(detection.notes) if found else [],
        "mask": pack_mask(detection.mask, detection.bbox) if found else b"",
        "truth": item.get("object", ""),
        "truth_label": item.get("label", ""),
        "iou": float(iou),
        "correct": bool(best is not None and item and best.object == item["object"]),
        "truth_pixels": int(item.get("pixels", 0)),
        "occluded": float(item.get("occluded", 0.0)),
        "cut": bool(item.get("cut", False)),
    }


def scene_summary(scores: pd.DataFrame) -> pd.DataFrame:
    """Detection, naming and latency of each library over the scenes (see the module docstring).

    Parameters
    ----------
    scores : pandas.DataFrame
        :func:`score_scene` rows of every scene, with ``descriptor`` and ``seconds`` (the time
        :meth:`recognize_scene` took on the row's frame).

    Returns
    -------
    pandas.DataFrame
        One row per descriptor: ``scenes, objects`` (with at least :data:`MIN_OBJECT_PIXELS` readings),
        ``recall``, ``segments``, ``false_segments`` (share matching no object), ``named`` and ``naming`` (right
        names among detected unoccluded objects inside the frame), ``named_occluded`` and ``naming_occluded``
        (partly occluded or cut ones), ``named_sure`` (of the unoccluded ones, those named right and confident
        enough not to be unknown), ``mistakes_unknown`` (of the wrong answers and the segments that match no object,
        those said to be unknown), ``median_seconds``, ``p90_seconds`` (per frame); of the detections posed as
        their true object, ``posed``, ``pose_add_s`` (the share with ADD-S within 10% of the diameter),
        ``pose_translation`` (median, metres), ``pose_rotation`` (median, degrees, objects that are not symmetric)
        and ``pose_seconds`` (median time the poses and their verification add per detection).
    """
    rows = []
    for descriptor, table in scores.groupby("descriptor", sort=False):
        countable = table[(table["truth"] != "") & (table["truth_pixels"] >= MIN_OBJECT_PIXELS)]
        truth = countable.drop_duplicates(["scene", "truth"])
        found = countable[countable["detection"] >= 0]
        segments = table[table["detection"] >= 0]
        matched = segments[segments["truth"] != ""]
        clear = matched[(matched["occluded"] <= OCCLUDED) & ~matched["cut"]]
        hidden = matched[(matched["occluded"] > OCCLUDED) | matched["cut"]]
        mistakes = segments[(segments["truth"] == "") | ~segments["correct"]]
        frames = table.drop_duplicates("scene")
        times = frames["seconds"]
        detections = segments.groupby("scene").size().reindex(frames["scene"]).fillna(0).to_numpy()
        added = (frames["seconds"] - frames["seconds_without_pose"]).to_numpy() / np.maximum(detections, 1)
        posed = segments[segments["add_s"].notna()]
        turned = posed[~posed["symmetric"]]
        rows.append(
            {
                "descriptor": descriptor,
                "scenes": int(table["scene"].nunique()),
                "objects": len(truth),
                "recall": len(found.drop_duplicates(["scene", "truth"])) / len(truth) if len(truth) else np.nan,
                "segments": len(segments),
                "false_segments": float((segments["truth"] == "").mean()) if len(segments) else np.nan,
                "named": len(clear),
                "naming": float(clear["correct"].mean()) if len(clear) else np.nan,
                "named_occluded": len(hidden),
                "naming_occluded": float(hidden["correct"].mean()) if len(hidden) else np.nan,
                "named_sure": float((clear["correct"] & clear["known"]).mean()) if len(clear) else np.nan,
                "mistakes_unknown": float((~mistakes["known"]).mean()) if len(mistakes) else np.nan,
                "median_seconds": float(times.median()),
                "p90_seconds": float(times.quantile(0.9)),
                "posed": len(posed),
                "pose_add_s": float(posed["add_s_ok"].mean()) if len(posed) else np.nan,
                "pose_translation": float(posed["translation_error"].median()) if len(posed) else np.nan,
                "pose_rotation": float(turned["rotation_error"].median()) if len(turned) else np.nan,
                "pose_seconds": float(np.median(added[detections > 0])) if (detections > 0).any() else np.nan,
            }
        )
    return pd.DataFrame(rows)


def render_scene_files(rows: list[dict], settings: dict, index: int, depth_path: StrPath) -> dict:
    """Workflow step: scene ``index`` of the objects of catalogue ``rows``, rendered and written (:func:`write_scene`).

    Parameters
    ----------
    rows : list of dict
        The catalogue rows of the scene's objects (:func:`choose_objects`).
    settings : dict
        The config's ``scenes``.
    index : int
        The scene's number.
    depth_path : str or Path
        Where its depth PNG goes; the other files beside it.

    Returns
    -------
    dict
        The scene's truth.
    """
    from heatdata.io.catalog import load_catalog_model

    models = {row["object"]: load_catalog_model(row) for row in rows}
    plan = plan_scene(list(models.values()), settings, index)
    if plan["left_out"]:
        log.warning("%s: left out of the %g x %g m table: %s", plan["scene"], *settings["table"],
                    ", ".join(plan["left_out"]))  # fmt: skip
    frame, truth = render_planned_scene(plan, models, settings)
    write_scene(frame, truth, depth_path)
    seen = ", ".join(f"{o['object']} ({o['pixels']} px)" for o in truth["objects"])
    log.info("%s: %s; camera %.2f m, %.0f deg", plan["scene"], seen, plan["camera"]["distance"],
             plan["camera"]["elevation"])  # fmt: skip
    return truth


def read_scene(depth_path: StrPath) -> tuple[np.ndarray, np.ndarray | None, dict, np.ndarray, dict]:
    """A scene written by :func:`write_scene`: depth (metres, NaN: no reading), colour, intrinsics, labels, truth."""
    from heatdata.views.depth import read_depth_frame, read_image

    files = scene_files(depth_path)
    depth, rgb, intrinsics = read_depth_frame(files["depth"], files["intrinsics"], files["rgb"])
    depth[depth <= 0] = np.nan
    labels = read_image(files["labels"], "label image", "L")
    truth = json.loads(files["truth"].read_text())
    return depth, rgb, intrinsics, labels, truth


def recognize_scene_files(library, depth_paths: list[StrPath]) -> pd.DataFrame:
    """Workflow step: every scene recognized with ``library`` and scored against its truth (:func:`score_scene`).

    Every detection is posed and verified (recognized at threshold 0, so that the known/unknown curve can be drawn
    at any threshold); ``known`` is then judged as ``heatdata recognize`` judges it (:meth:`Library.threshold`: by
    verification alone when the library carries surface samples).
    The first scene is recognized once before the timing, so every ``seconds`` is a warm library's;
    ``seconds_without_pose`` times the same frame without poses or verification.

    Parameters
    ----------
    library : Library
        A loaded library.
    depth_paths : list of str or Path
        The scenes' depth PNGs.

    Returns
    -------
    pandas.DataFrame
        :data:`heatdata.io.tables.DETECTION_SCHEMA` rows.
    """
    import time

    from heatdata.recognition.pose import symmetry_turns

    surfaces = {obj: (surface, symmetry_turns(surface)) for obj, surface in library.surfaces.items()}
    limit = library.threshold(pose=True)
    parts = []
    for number, path in enumerate(depth_paths):
        depth, rgb, intrinsics, labels, truth = read_scene(path)
        if number == 0:
            library.recognize_scene(depth, intrinsics, rgb, name=truth["scene"])  # warm the library and the imports
        tic = time.perf_counter()
        library.recognize_scene(depth, intrinsics, rgb, name=truth["scene"], pose=False)
        unposed = time.perf_counter() - tic
        tic = time.perf_counter()
        answer = library.recognize_scene(depth, intrinsics, rgb, name=truth["scene"], threshold=0.0)
        seconds = time.perf_counter() - tic
        scores = score_scene(answer.detections, labels, depth, truth, surfaces)
        confident = ~(scores["confidence"] < limit)  # NaN (a library of one object) is confident
        scores = scores.assign(known=scores["known"] & confident, threshold=limit)
        parts.append(scores.assign(descriptor=library.descriptor, seconds=seconds, seconds_without_pose=unposed))
        log.info(
            "%s: %d objects found in %.0f ms (%.0f ms without the poses): %s", truth["scene"], len(answer.detections),
            1000 * seconds, 1000 * unposed, ", ".join(d.object or "?" for d in answer.detections),
        )  # fmt: skip
    return pd.concat(parts, ignore_index=True)


def offaxis_precision(
    library_rows: pd.DataFrame, moved_rows: pd.DataFrame, predictions: pd.DataFrame, size: int, time_rule: str
) -> pd.DataFrame:
    """Precision of the test views rendered off the optical axis, and of the control views, against the same views
    centred (:func:`heatdata.experiments.views.render_offaxis_views`), per descriptor.

    Parameters
    ----------
    library_rows : pandas.DataFrame
        The run's descriptor rows of its library views (``split = "train"``).
    moved_rows : pandas.DataFrame
        The descriptor rows of the off-axis views (ids ``<object>/offaxis/<index>``) and of the control views
        (``<object>/reseeded/<index>``).
    predictions : pandas.DataFrame
        The run's predictions of its centred test views (``<object>/test/<index>``).
    size : int
        Library views per object.
    time_rule : str
        As the run classifies.

    Returns
    -------
    pandas.DataFrame
        ``descriptor, views, centred, reseeded, off_axis`` (object precision), ``difference`` (off-axis less
        centred, points), ``same_reseeded`` and ``same_off_axis`` (the shares of views answered as centred).
    """
    from heatdata.recognition.evaluate import evaluate_library_sizes

    columns = ["descriptor", "views", "centred", "reseeded", "off_axis", "difference", "same_reseeded",
               "same_off_axis"]  # fmt: skip
    if moved_rows.empty:
        return pd.DataFrame(columns=columns)
    rows = pd.concat([library_rows, moved_rows], ignore_index=True)
    table = []
    for descriptor in moved_rows["descriptor"].unique():
        answers = evaluate_library_sizes(rows, descriptor, [size], time_rule=time_rule)
        kind = answers["view_id"].str.split("/").str[-2]
        answers = answers.assign(view_id=answers["view_id"].str.replace(r"/(offaxis|reseeded)/", "/test/", regex=True))
        off = answers[kind == "offaxis"].set_index("view_id")
        control = answers[kind == "reseeded"].set_index("view_id").loc[off.index]
        centred = predictions[(predictions["descriptor"] == descriptor) & (predictions["library_size"] == size)]
        centred = centred.set_index("view_id").loc[off.index]
        table.append(
            {
                "descriptor": descriptor,
                "views": len(off),
                "centred": float(centred["correct"].mean()),
                "reseeded": float(control["correct"].mean()),
                "off_axis": float(off["correct"].mean()),
                "difference": 100.0 * float(off["correct"].mean() - centred["correct"].mean()),
                "same_reseeded": float((control["predicted_object"] == centred["predicted_object"]).mean()),
                "same_off_axis": float((off["predicted_object"] == centred["predicted_object"]).mean()),
            }
        )
    return pd.DataFrame(table, columns=columns)
