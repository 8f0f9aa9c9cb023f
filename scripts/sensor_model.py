"""The depth sensor measured on real frames beside the renderer's profiles measured the same way
(:mod:`heatdata.experiments.sensor_model`): noise and quantization against depth, the ring round each object
(holes, flying pixels, the halo at the base) and holes on dark surfaces.

    .venv/bin/python scripts/sensor_model.py --kinect ../shared/realdata/mosd/frames \\
        --realsense ../shared/realdata/ycb/frames --out docs/results/sensor_model.csv \\
        --figure docs/images/sensor_noise.png --crops docs/images/sensor_crops.png

``--kinect`` is a folder of mOSD's layout (``<name>.depth.png``, ``<name>.rgb.png``, ``<name>.labels.png``,
``intrinsics.json``),
``--realsense`` one of the YCB frames' (``<name>-depth.png``, ``<name>-color.png``, ``meta.yml``). Each is compared
with frames rendered through its profile (``kinect``, ``realsense``): the 14 embedded objects, three at a time on a
table, at the distances and elevations of the real ones, stored as whole millimetres as the real PNGs are. The
crops figure shows mOSD's frames only (the YCB frames' licence forbids copying them).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
import pandas as pd

import heatdata as hd
from heatdata.experiments.real_frames import read_labelled_frames
from heatdata.experiments.real_recognition import frame_files
from heatdata.experiments.scenes import TABLE_HEIGHT, object_pose, room
from heatdata.experiments.sensor_model import fit_tau, measure_frame, pooled
from heatdata.log import setup_logging
from heatdata.views.depth import read_depth_frame
from heatdata.views.render import Placement, camera_pose, render_scene

#: the rendered frames per sensor, and their cameras: distance (m), elevation (degrees) and intrinsics
RENDERED_FRAMES = 12
CAMERAS = {
    "kinect": ((0.7, 1.3), (35.0, 55.0), {"fx": 525.0, "fy": 525.0, "cx": 319.5, "cy": 239.5}),
    "realsense": ((0.55, 1.0), (45.0, 60.0), {"fx": 618.0, "fy": 618.0, "cx": 312.4, "cy": 232.4}),
}


def real_frames(folder: Path, sensor: str):
    """``(depth, intrinsics, rgb)`` of each frame of a folder in its sensor's layout (mOSD's labelled frames, or the
    YCB frames' ``<name>-depth.png`` with ``meta.yml``)."""
    if sensor == "kinect":
        for frame in read_labelled_frames(folder):
            yield frame.depth, frame.intrinsics, frame.rgb
    else:
        for _, depth_path, color_path in frame_files(folder):
            depth, rgb, k = read_depth_frame(depth_path, folder / "meta.yml", color_path)
            yield depth, k, rgb


def rendered_frames(sensor: str, count: int):
    """Frames of the embedded objects rendered through ``sensor``'s profile, rounded to millimetres."""
    models = [hd.load_catalog_model(row) for row in hd.read_catalog(hd.embedded_catalog()).to_dict("records")]
    distances, elevations, camera = CAMERAS[sensor]
    intrinsics = {**camera, "width": 640, "height": 480}
    rng = np.random.default_rng(0)
    for seed in range(count):
        chosen = rng.choice(len(models), 3, replace=False)
        placed = [
            Placement(models[j], object_pose(models[j], x, rng.uniform(-0.1, 0.1), rng.uniform(0, 360)))
            for j, x in zip(chosen, (-0.25, 0.0, 0.25), strict=True)
        ]
        pose = camera_pose(
            np.array([0.0, TABLE_HEIGHT, 0.0]), rng.uniform(-20, 20), rng.uniform(*elevations), rng.uniform(*distances)
        )
        frame = render_scene([*room(1.2, 0.8, 0.05), *placed], pose, sensor=sensor, seed=seed, intrinsics=intrinsics)
        yield np.round(frame.depth, 3), frame.intrinsics, frame.rgb


def noise_figure(noise: pd.DataFrame, path: Path) -> None:
    """Noise against depth, real and rendered, one panel per sensor."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    sensors = list(dict.fromkeys(noise["sensor"]))
    fig, axes = plt.subplots(1, len(sensors), figsize=(5 * len(sensors), 3.6), squeeze=False)
    for ax, sensor in zip(axes[0], sensors, strict=True):
        for source, style in (("real", "o"), ("rendered", "s--")):
            rows = noise[(noise["sensor"] == sensor) & (noise["source"] == source) & (noise["windows"] >= 20)]
            ax.plot(rows["depth"], 1000 * rows["sigma"], style, label=f"{source}: noise")
            ax.plot(rows["depth"], 1000 * rows["step"], style, alpha=0.4, label=f"{source}: depth step")
        ax.set(title=sensor, xlabel="depth (m)", ylabel="mm")
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def crops_figure(real: tuple, rendered: tuple, path: Path) -> None:
    """The depth round one object, real (a mOSD cylinder) and rendered (an embedded can), side by side."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(8, 3.8))
    for ax, (title, crop) in zip(axes, (("real (Kinect, mOSD)", real), ("rendered (kinect profile)", rendered))):
        shown = np.where(np.isfinite(crop) & (crop > 0), crop, np.nan)
        image = ax.imshow(shown, cmap="viridis")
        ax.imshow(np.where(np.isnan(shown), 1.0, np.nan), cmap="Reds", vmin=0, vmax=1.5)  # holes in red
        ax.set(title=title, xticks=[], yticks=[])
        fig.colorbar(image, ax=ax, label="depth (m)", shrink=0.8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def object_crop(depth: np.ndarray, intrinsics: dict, rgb, size: int = 90) -> np.ndarray:
    """The depth in a square round the frame's largest object."""
    segments = hd.segment_frame(depth, intrinsics, rgb).segments
    u0, v0, u1, v1 = segments[0].bbox
    cu, cv = (u0 + u1) // 2, (v0 + v1) // 2
    return depth[max(cv - size, 0) : cv + size, max(cu - size, 0) : cu + size]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--kinect", type=Path, help="real Kinect frames (mOSD's layout)")
    parser.add_argument("--realsense", type=Path, help="real RealSense frames (the YCB frames' layout)")
    parser.add_argument("--out", type=Path, required=True, help="the measures (.csv; the noise table beside it)")
    parser.add_argument("--figure", type=Path, help="noise against depth (.png)")
    parser.add_argument("--crops", type=Path, help="a real and a rendered object's depth (.png; needs --kinect)")
    args = parser.parse_args()
    setup_logging()
    start = time.perf_counter()
    noise, rows = [], []
    for sensor, folder in (("kinect", args.kinect), ("realsense", args.realsense)):
        if folder is None:
            continue
        for source, frames in (
            ("real", real_frames(folder, sensor)),
            ("rendered", rendered_frames(sensor, RENDERED_FRAMES)),
        ):
            measures = [measure_frame(depth, k, rgb) for depth, k, rgb in frames]
            found = pooled(measures, sensor)
            noise.append(found["noise"].assign(source=source))
            dark = found["dark"]
            darkest = dark[dark["luminance"] < 0.05]
            rows.append(
                {
                    **found["ring"],
                    "source": source,
                    "frames": len(measures),
                    "tau": fit_tau(found["noise"], unit=0.001),
                    "dark_holes": float(darkest["holes"].sum() / max(darkest["pixels"].sum(), 1)),
                    "bright_holes": float(dark.loc[dark["luminance"] >= 0.2, "holes"].sum())
                    / max(float(dark.loc[dark["luminance"] >= 0.2, "pixels"].sum()), 1.0),
                }
            )
            print(rows[-1], flush=True)
    table = pd.DataFrame(rows)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    table.round(5).to_csv(args.out, index=False)
    noise_table = pd.concat(noise, ignore_index=True)
    noise_table.round(6).to_csv(args.out.with_name(args.out.stem + "_noise.csv"), index=False)
    if args.figure:
        noise_figure(noise_table, args.figure)
    if args.crops and args.kinect:
        real = next(iter(real_frames(args.kinect, "kinect")))
        rendered = next(iter(rendered_frames("kinect", 1)))
        crops_figure(object_crop(*real), object_crop(*rendered), args.crops)
    print(table.to_string(index=False))
    print(f"wall {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
