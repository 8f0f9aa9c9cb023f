"""`heatdata recognize`'s latency (issue 33): from a depth PNG on disk to the answer, cold and warm.

Cold: a fresh process that imports heatdata, loads the library (its rows, then the probe check), reads the depth
PNG and its colour image, builds the view, describes it and searches the library; each stage timed, and the whole
process's wall time from outside; and `heatdata recognize --json` on the same frames, which answers a frame as a
scene (the support plane looked for, none found in a frame of one chair, the chair one object). Warm: one loaded
`Library` answering a stream of frames, each from its files on disk. The frames are test views of the library's own
run (rendered, then written as 16-bit depth PNGs with their colour, as a sensor would save them), so each answer can
be checked.

    .venv/bin/snakemake --cores 2 --configfile config/experiments/chairs.yaml config/experiments/chairs_library.yaml \\
        results/chairs_library/libraries/hgd_color=hue-saturation-40.parquet
    .venv/bin/python benchmarks/bench_recognize.py results/chairs_library
"""

import time

START = time.perf_counter()

import argparse  # noqa: E402
import json  # noqa: E402
import resource  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
from pathlib import Path  # noqa: E402


def child(frame: str, library_path: str) -> None:
    """The cold path, stage by stage, in this fresh process; prints the stages' seconds as JSON."""
    stages = {}
    tic = time.perf_counter()
    import heatdata as hd
    from heatdata.views.depth import read_image, read_intrinsics, view_from_depth

    stages["import"] = time.perf_counter() - START
    tic = time.perf_counter()
    library = hd.load_library(library_path)
    stages["load library (rows and probe check)"] = time.perf_counter() - tic
    tic = time.perf_counter()
    depth = read_image(frame, "depth image", "depth") / 1000.0
    rgb = read_image(frame.replace(".png", ".rgb.png"), "colour image", "RGB")
    intrinsics = read_intrinsics(frame.replace(".png", ".json"))
    stages["read the depth and colour PNGs"] = time.perf_counter() - tic
    tic = time.perf_counter()
    view = view_from_depth(depth, intrinsics, rgb)
    stages["build the view"] = time.perf_counter() - tic
    tic = time.perf_counter()
    query = library.describe(view)
    stages["describe"] = time.perf_counter() - tic
    tic = time.perf_counter()
    distances = library.distances(query)
    stages["search"] = time.perf_counter() - tic
    best = library.views.iloc[int(distances.argmin())]["object"]
    stages["in all (in the process)"] = time.perf_counter() - START
    print(json.dumps({"stages": stages, "object": best, "vertices": view.n_vertices}))


def frames(run: Path, folder: Path, count: int) -> list[tuple[str, str]]:
    """``count`` test views of the run, spread over its objects, written as depth and colour PNGs."""
    import numpy as np
    from PIL import Image

    import heatdata as hd
    from heatdata.io.tables import read_table
    from heatdata.views.frames import frame_to_views

    paths = sorted((run / "views").glob("*.parquet"))
    picked = [paths[int(k)] for k in np.linspace(0, len(paths) - 1, count)]
    written = []
    for k, path in enumerate(picked):
        table, _ = read_table(path, filters=[("split", "==", "test")])
        view = frame_to_views(table.head(1))[0]
        png = folder / f"frame{k}.png"
        hd.write_depth(view, png)
        image = np.zeros((view.intrinsics["height"], view.intrinsics["width"], 3), np.uint8)
        pixels = np.round(view.pixels).astype(int)
        image[pixels[:, 1], pixels[:, 0]] = np.round(255 * view.colors).astype(np.uint8)
        Image.fromarray(image).save(folder / f"frame{k}.rgb.png")
        written.append((str(png), view.object_id))
    return written


def _circle(run: Path, obj: str) -> list:
    """Every test view of ``obj`` in the run, in azimuth order."""
    from heatdata.io.tables import read_table
    from heatdata.views.frames import frame_to_views

    table, _ = read_table(run / "views" / f"{obj}.parquet", filters=[("split", "==", "test")])
    return frame_to_views(table.sort_values("azimuth"))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path, help="a run's results folder holding libraries/ and views/")
    parser.add_argument("--library", help="the library file (default: the run's only one)")
    parser.add_argument("--frames", type=int, default=20)
    parser.add_argument("--cold", type=int, default=5, help="fresh processes")
    args = parser.parse_args()
    import numpy as np
    from record import write

    import heatdata as hd

    library_path = args.library or str(next((args.run / "libraries").glob("*.parquet")))
    with tempfile.TemporaryDirectory() as folder:
        stream = frames(args.run, Path(folder), args.frames)
        cold = []
        for k in range(args.cold):
            frame, truth = stream[k % len(stream)]
            tic = time.perf_counter()
            out = subprocess.run(
                [sys.executable, __file__, "--child", frame, library_path], capture_output=True, text=True, check=True
            )
            wall = time.perf_counter() - tic
            result = json.loads(out.stdout.splitlines()[-1])
            cold.append({**result["stages"], "process wall time": wall, "right": result["object"] == truth})
        command = []
        for k in range(args.cold):
            frame, truth = stream[k % len(stream)]
            tic = time.perf_counter()
            out = subprocess.run(
                [
                    str(Path(sys.executable).parent / "heatdata"),
                    "recognize",
                    frame,
                    "--library",
                    library_path,
                    "--intrinsics",
                    frame.replace(".png", ".json"),
                    "--rgb",
                    frame.replace(".png", ".rgb.png"),
                    "--json",
                ],
                capture_output=True,
                text=True,
                check=True,
            )
            found = [o["object"] for o in json.loads(out.stdout)["objects"]]  # the frame of one chair: one object
            command.append((time.perf_counter() - tic, found == [truth]))
        library = hd.load_library(library_path)
        warm, right = [], 0
        for frame, truth in stream:
            tic = time.perf_counter()
            view = hd.read_depth(frame, frame.replace(".png", ".json"), frame.replace(".png", ".rgb.png"))
            answer = library.recognize(view, k=5)
            warm.append(time.perf_counter() - tic)
            right += answer.best.object == truth
        sequence = {}
        for exact in (False, True):  # one object's test views in a row, as a robot circling it would see them
            circle = _circle(args.run, stream[0][1])
            tic = time.perf_counter()
            steps = library.recognize_sequence(circle, [360.0 / len(circle)], exact=exact)
            sequence[exact] = (time.perf_counter() - tic, len(circle), steps[-1].estimate == stream[0][1])
    stages = {name: sorted(run[name] for run in cold)[len(cold) // 2] for name in cold[0] if name != "right"}
    stages["`heatdata recognize --json`, wall time"] = sorted(wall for wall, _ in command)[len(command) // 2]
    print(f"{library!r}; {args.cold} cold processes (median) and {len(warm)} warm frames")
    for name, seconds in stages.items():
        print(f"  cold: {name:40s} {seconds * 1e3:7.0f} ms")
    print(f"  warm: per frame, median {np.median(warm) * 1e3:.0f} ms, slowest {max(warm) * 1e3:.0f} ms")
    for exact, (seconds, count, ok) in sequence.items():
        kind = "exhaustive filter" if exact else "particle filter"
        print(f"  sequence of {count} frames, {kind}: {seconds:.2f} s, right: {ok}")
    print(
        f"  right answers: cold {sum(r['right'] for r in cold)} of {len(cold)}, the command "
        f"{sum(ok for _, ok in command)} of {len(command)}, warm {right} of {len(warm)}"
    )
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    write(
        [
            (f"library views ({library.descriptor})", len(library.views), "views"),
            ("library objects", len(library.objects), "objects"),
            *((f"cold: {name}", seconds * 1e3, "ms") for name, seconds in stages.items()),
            ("warm: per frame, median", float(np.median(warm)) * 1e3, "ms"),
            ("warm: per frame, slowest", max(warm) * 1e3, "ms"),
            ("warm: right answers", right / len(warm), "share"),
            *(
                (f"a sequence of {count} frames, {'exhaustive filter' if exact else 'particle filter'}", seconds, "s")
                for exact, (seconds, count, _) in sequence.items()
            ),
            ("peak RSS of the warm process", peak, "MB"),
        ]
    )


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "--child":
        child(sys.argv[2], sys.argv[3])
    else:
        main()
