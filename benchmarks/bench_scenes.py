"""A scene's latency: a 640 x 480 frame with three objects on a table, from the files on disk to every object's name.

Cold: a fresh process (as `heatdata recognize` is) that imports heatdata, loads the library (rows, then the probe
check), reads the depth and colour PNGs, segments the frame (the support plane, the clusters) and recognizes each
segment; each stage timed, and the whole process's wall time from outside, and `heatdata recognize --json`'s.
Warm: one loaded `Library` answering every three-object scene of the run, each from its files; and the same frames
answered without poses (`pose=False`) and with every object posed (threshold 0), for what the pose and its
verification add per object. The scenes are the workflow's (rendered through the Kinect's sensor profile), so each
answer is checked against the truth.

    .venv/bin/snakemake --cores 2 --configfile config/experiments/scenes.yaml
    .venv/bin/python benchmarks/bench_scenes.py results/scenes_run
"""

import time

START = time.perf_counter()

import argparse  # noqa: E402
import json  # noqa: E402
import resource  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402


def child(frame: str, library_path: str) -> None:
    """The cold path, stage by stage, in this fresh process; prints the stages' seconds as JSON."""
    stages = {}
    import heatdata as hd
    from heatdata.segmentation.segment import segment_frame
    from heatdata.views.depth import read_depth_frame

    stages["import heatdata"] = time.perf_counter() - START
    tic = time.perf_counter()
    library = hd.load_library(library_path)
    stages["load library (rows and probe check)"] = time.perf_counter() - tic
    tic = time.perf_counter()
    depth, rgb, intrinsics = read_depth_frame(frame, frame.replace(".png", ".json"), frame.replace(".png", ".rgb.png"))
    stages["read the depth and colour PNGs"] = time.perf_counter() - tic
    tic = time.perf_counter()
    segmentation = segment_frame(depth, intrinsics, rgb)  # the first call imports open3d and scipy.ndimage
    stages["segment (plane, clusters; imports open3d)"] = time.perf_counter() - tic
    tic = time.perf_counter()
    answer = library.recognize_segments(segmentation)
    stages["describe and search every segment"] = time.perf_counter() - tic
    stages["in all (in the process)"] = time.perf_counter() - START
    print(json.dumps({"stages": stages, "objects": [d.object or "" for d in answer.detections]}))  # "": unknown


def three_object_scenes(run: Path) -> list[tuple[str, list[str]]]:
    """The run's scenes with three objects of at least 1,000 readings each, and those objects."""
    scenes = []
    for truth in sorted((run / "scenes" / "frames").glob("*.truth.json")):
        objects = json.loads(truth.read_text())["objects"]
        if len(objects) == 3 and all(o["pixels"] >= 1000 for o in objects):
            scenes.append((str(truth).replace(".truth.json", ".png"), sorted(o["object"] for o in objects)))
    return scenes


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path, help="a run's results folder holding libraries/ and scenes/frames/")
    parser.add_argument("--library", help="the library file (default: the run's HGD with colour at 40 views)")
    parser.add_argument("--cold", type=int, default=5, help="fresh processes")
    args = parser.parse_args()
    import numpy as np
    from record import write

    import heatdata as hd
    from heatdata.experiments.scenes import read_scene

    library_path = args.library or str(args.run / "libraries" / "hgd_color=hue-saturation-40.parquet")
    scenes = three_object_scenes(args.run)
    if not scenes:
        sys.exit(f"{args.run}: no scene with three objects of 1,000 readings or more")
    cold, command = [], []
    for k in range(args.cold):
        frame, truth = scenes[k % len(scenes)]
        tic = time.perf_counter()
        out = subprocess.run(
            [sys.executable, __file__, "--child", frame, library_path], capture_output=True, text=True, check=True
        )
        wall = time.perf_counter() - tic
        result = json.loads(out.stdout.splitlines()[-1])
        cold.append({**result["stages"], "process wall time": wall, "right": sorted(result["objects"]) == truth})
        tic = time.perf_counter()
        out = subprocess.run(
            [
                str(Path(sys.executable).parent / "heatdata"), "recognize", frame, "--library", library_path,
                "--intrinsics", frame.replace(".png", ".json"), "--rgb", frame.replace(".png", ".rgb.png"), "--json",
            ],
            capture_output=True, text=True, check=True,
        )  # fmt: skip
        named = sorted(o["object"] or "" for o in json.loads(out.stdout)["objects"])  # "": unknown
        command.append((time.perf_counter() - tic, named))
    library = hd.load_library(library_path)
    frames = [(read_scene(frame), truth) for frame, truth in scenes]
    library.recognize_scene(frames[0][0][0], frames[0][0][2], frames[0][0][1])  # warm the imports
    warm, right, added = [], 0, []
    for (depth, rgb, intrinsics, _, _), truth in frames:
        tic = time.perf_counter()
        answer = library.recognize_scene(depth, intrinsics, rgb)
        warm.append(time.perf_counter() - tic)
        right += sorted(d.object or "" for d in answer.detections) == truth
        tic = time.perf_counter()
        plain = library.recognize_scene(depth, intrinsics, rgb, pose=False)
        unposed = time.perf_counter() - tic
        tic = time.perf_counter()
        library.recognize_scene(depth, intrinsics, rgb, threshold=0.0)  # every object posed and verified
        added.append((time.perf_counter() - tic - unposed) / max(len(plain.detections), 1))
    stages = {name: sorted(run[name] for run in cold)[len(cold) // 2] for name in cold[0] if name != "right"}
    stages["`heatdata recognize --json`, wall time"] = sorted(wall for wall, _ in command)[len(command) // 2]
    print(f"{library!r}; {len(scenes)} scenes of three objects; {args.cold} cold processes (median)")
    for name, seconds in stages.items():
        print(f"  cold: {name:45s} {seconds * 1e3:7.0f} ms")
    print(
        f"  warm: per frame, median {np.median(warm) * 1e3:.0f} ms, 90th percentile "
        f"{np.quantile(warm, 0.9) * 1e3:.0f} ms, slowest {max(warm) * 1e3:.0f} ms"
    )
    print(
        f"  the pose and its verification, per object (every object posed): median {np.median(added) * 1e3:.0f} ms, "
        f"90th percentile {np.quantile(added, 0.9) * 1e3:.0f} ms"
    )
    print(
        f"  every object named right and said (none unknown): cold {sum(r['right'] for r in cold)} of {len(cold)}, "
        "the command "
        f"{sum(objects == scenes[k % len(scenes)][1] for k, (_, objects) in enumerate(command))} of "
        f"{len(command)}, warm {right} of {len(warm)}"
    )
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    write(
        [
            (f"library views ({library.descriptor})", len(library.views), "views"),
            ("scenes of three objects", len(scenes), "scenes"),
            *((f"cold: {name}", seconds * 1e3, "ms") for name, seconds in stages.items()),
            ("warm: per frame, median", float(np.median(warm)) * 1e3, "ms"),
            ("warm: per frame, 90th percentile", float(np.quantile(warm, 0.9)) * 1e3, "ms"),
            ("warm: per frame, slowest", max(warm) * 1e3, "ms"),
            ("warm: every object named right and said (none unknown)", right / len(warm), "share"),
            ("warm: the pose and its verification per object, median", float(np.median(added)) * 1e3, "ms"),
            (
                "warm: the pose and its verification per object, 90th percentile",
                float(np.quantile(added, 0.9)) * 1e3,
                "ms",
            ),
            ("peak RSS of the warm process", peak, "MB"),
        ]
    )


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "--child":
        child(sys.argv[2], sys.argv[3])
    else:
        main()
