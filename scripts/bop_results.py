"""heatdata's poses on a BOP scene, written as BOP's results CSV for ``bop_toolkit``'s evaluation beside the
field's methods (:mod:`heatdata.frames.bop`).

    .venv/bin/snakemake --cores 2 results/ycbv/libraries/hgd_color=hue-saturation-40.parquet \\
        --config models_dir=/data/bop/ycbv/models models_units=mm models_up_axis=z results=results/ycbv
    .venv/bin/python scripts/bop_results.py /data/bop/ycbv/test/000048 \\
        --library results/ycbv/libraries/hgd_color=hue-saturation-40.parquet \\
        --models /data/bop/ycbv/models --units mm --up-axis z --out heatdata_ycbv-test.csv

The library's objects are the model files' names (``obj_000005``), whose numbers are BOP's object ids; ``--units``
and ``--up-axis`` are those the library was built with, so that each pose is put back in the model file's own
frame. Each object named and posed (its pose accepted) is one row, its score what the pose explains less what it
contradicts; ``time`` is the image's whole recognition, segmentation included.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from heatdata.frames.bop import bop_object_id, file_frame_pose, read_bop_scene, write_bop_results
from heatdata.io.catalog import UNITS
from heatdata.io.models import SUPPORTED_SUFFIXES, UP_AXES, load_model
from heatdata.log import setup_logging
from heatdata.recognition.library import load_library


def model_frames(models: Path, objects: list[str], up_axis: str, scale: float) -> dict[str, np.ndarray]:
    """Each library object's turned file's bounding-box centre, in file units (what the loader took off)."""
    centres = {}
    for obj in objects:
        path = next((models / f"{obj}{s}" for s in SUPPORTED_SUFFIXES if (models / f"{obj}{s}").is_file()), None)
        if path is None:
            raise SystemExit(f"{models}: no model file of {obj}")
        vertices = load_model(path, scale=scale, up_axis=up_axis, center=False).vertices / scale
        centres[obj] = 0.5 * (vertices.min(axis=0) + vertices.max(axis=0))
    return centres


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene", type=Path, help="a BOP scene folder (<dataset>/test/000048)")
    parser.add_argument("--library", type=Path, required=True, help="a library built from the dataset's models")
    parser.add_argument("--models", type=Path, required=True, help="the dataset's models folder (obj_000001.ply)")
    parser.add_argument("--units", choices=tuple(UNITS), default="mm", help="the models' units (BOP: mm)")
    parser.add_argument("--up-axis", choices=tuple(UP_AXES), default="y", help="the up axis the library was built with")
    parser.add_argument("--out", type=Path, required=True, help="the results CSV")
    args = parser.parse_args()
    setup_logging()
    library = load_library(args.library)
    ids = {obj: bop_object_id(obj) for obj in library.objects}
    centres = model_frames(args.models, library.objects, args.up_axis, UNITS[args.units])
    rows = []
    for image in read_bop_scene(args.scene):
        depth, rgb = image.read()
        start = time.perf_counter()
        scene = library.recognize_scene(depth, image.intrinsics, rgb, name=f"{image.scene_id}/{image.im_id}")
        seconds = time.perf_counter() - start
        for detection in scene.detections:
            pose = detection.pose
            if detection.object is None or pose is None or not pose.accepted:
                continue
            file_pose = file_frame_pose(pose.matrix, UP_AXES[args.up_axis], centres[pose.object], UNITS[args.units])
            score = max(pose.explained - pose.in_front - pose.unseen - pose.below, 0.0)
            rows.append(
                {
                    "scene_id": image.scene_id,
                    "im_id": image.im_id,
                    "obj_id": ids[pose.object],
                    "score": score,
                    "pose": file_pose,
                    "time": seconds,
                }
            )
        print(f"{image.scene_id}/{image.im_id}: {len(scene.detections)} objects, {seconds:.2f} s", flush=True)
    write_bop_results(rows, args.out)
    print(f"{args.out}: {len(rows)} poses")


if __name__ == "__main__":
    main()
