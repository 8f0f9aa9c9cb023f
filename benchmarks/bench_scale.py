"""Libraries of 10^4 to 4 x 10^5 views: load, search and recognize through the index, against the exact search.

10,000 objects do not exist here, so the large libraries are part real, part synthetic, and the numbers say which:

- **Real:** a run's library of the default descriptor (``hgd/color=hue-saturation``, 40 views of 14 objects), and
  the run's own test views as queries (their descriptor rows for the searches, the rendered views for
  ``recognize``).
- **Synthetic distractors**, drawn to match the real descriptors: each distractor takes two real objects a and b
  and a weight w ~ Beta(2, 2); its k-th view is ``w a_k + (1 - w) b_k`` (the two objects' k-th library views, so it
  changes with the azimuth as real objects do), times log-normal noise per bin (sigma 0.1), rescaled to the real
  views' totals (the shape and colour parts stay histograms of the same mass). Mixtures of real objects lie between
  them, nearer the queries than unrelated histograms would: a harder crowd for the index than random ones.

For each size the library file is written (``write_library``) with its index (``write_library_index``); then a
fresh process loads it (timed, FAISS's import included) and measures: the recall@1 of the index against the exact
search on real queries (the nearest library view the same, and its object the same), the search's latency through
the index and exhaustively, the 10,000 test views of a batch answered one by one through the index (the 1,680 real
test views cycled), ``recognize`` warm (describe, search and answer, no pose) through the index, and the process's
peak memory: after its imports and the test descriptors, once the library is loaded and searched through the index,
and at the end (the rendered views read from their large tables, and the exact searches).

A second fresh process runs the classify rule's work (:func:`heatdata.recognition.evaluate.evaluate_table`) on a
descriptor table of the library's views and those 10,000 test views, and measures its time and peak memory.

    .venv/bin/snakemake --cores 2 --configfile config/experiments/household_learned.yaml \\
        results/household_learned/libraries/hgd_color=hue-saturation-40.parquet
    .venv/bin/python benchmarks/bench_scale.py results/household_learned --sizes 10000 100000 400000
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from record import write

DESCRIPTOR = "hgd/color=hue-saturation"
VIEWS = 40
BATCH = 10_000


def distractor_library(run: Path, size: int, path: Path) -> tuple[int, int]:
    """Write a library file of ``size`` library views: the run's own, then synthetic distractors (module docstring);
    returns how many views it holds, and how many of them are synthetic."""
    import pandas as pd

    from heatdata.io.tables import read_table
    from heatdata.recognition.library import LIBRARY_KEY, write_library

    rows, meta = read_table(run / "libraries" / f"{DESCRIPTOR.replace('/', '_')}-{VIEWS}.parquet")
    train = rows[rows["split"] == "train"]
    objects = sorted(train["object"].unique())
    per = {obj: np.stack(train.loc[train["object"] == obj, "values"].to_numpy()) for obj in objects}
    count = max(0, size - len(train)) // VIEWS
    rng = np.random.default_rng(0)
    blocks = []
    for _ in range(count):
        a, b = rng.choice(objects, 2, replace=False)
        w = rng.beta(2, 2)
        mixed = (w * per[a] + (1 - w) * per[b]) * rng.lognormal(0, 0.1, per[a].shape)
        blocks.append(mixed * (per[a].sum(axis=1) / mixed.sum(axis=1))[:, None])
    names = np.repeat([f"distractor-{k:05d}" for k in range(count)], VIEWS)
    synthetic = train.iloc[np.tile(np.arange(VIEWS), count)].reset_index(drop=True)
    synthetic = synthetic.assign(
        object=names,
        label="distractor",
        view_id=[f"{n}/train/{k:03d}" for n, k in zip(names, np.tile(np.arange(VIEWS), count), strict=True)],
        values=list(np.concatenate(blocks)) if blocks else [],
    )
    metadata = dict(meta[LIBRARY_KEY])
    metadata["objects"] = sorted([*objects, *dict.fromkeys(names)])
    write_library(pd.concat([rows, synthetic], ignore_index=True), metadata, path)
    return len(train) + len(synthetic), len(synthetic)


def high_water() -> float:
    """This process's peak resident memory in GB (``VmHWM``; ``ru_maxrss`` counts the parent it was forked from)."""
    status = Path("/proc/self/status").read_text()
    return int(next(line for line in status.splitlines() if line.startswith("VmHWM")).split()[1]) / 1e6


def child(library_path: str, run: str, queries: int, views: int) -> None:
    """Measure one library in this fresh process; prints the figures as JSON."""
    tic = time.perf_counter()
    import heatdata as hd
    from heatdata.io.tables import read_table
    from heatdata.views.frames import frame_to_views

    imported = time.perf_counter() - tic
    tests, _ = read_table(
        Path(run) / "descriptors.parquet", filters=[("descriptor", "==", DESCRIPTOR), ("split", "==", "test")]
    )
    before = high_water()
    tic = time.perf_counter()
    library = hd.load_library(library_path)
    loaded = time.perf_counter() - tic
    picked = tests.iloc[np.linspace(0, len(tests) - 1, queries).astype(int)]
    fast, nearest = [], []  # each query's nearest view and its distance (not its 400,000 distances: 3.2 MB each)
    for k in range(len(picked)):
        tic = time.perf_counter()
        near = library.distances(picked.iloc[[k]])
        fast.append(time.perf_counter() - tic)
        nearest.append((int(np.argmin(near)), float(np.min(near))))
    tic = time.perf_counter()
    for k in range(BATCH):
        library.distances(tests.iloc[[k % len(tests)]])
    batch = time.perf_counter() - tic
    peak = high_water()
    paths = sorted((Path(run) / "views").glob("*.parquet"))
    rendered = []
    for path in paths[:: max(1, len(paths) // views)][:views]:  # after the peak above: their tables are large
        table, _ = read_table(path, filters=[("split", "==", "test")])
        rendered.append(frame_to_views(table.head(1))[0])
        del table
    library.recognize(rendered[0], pose=False)  # warm
    answers = []
    for view in rendered:
        tic = time.perf_counter()
        answer = library.recognize(view, pose=False)
        answers.append((time.perf_counter() - tic, answer.best.object == view.object_id))
    same_view = same_object = 0
    slow = []
    for k, (a, near) in enumerate(nearest):
        tic = time.perf_counter()
        exact = library.distances(picked.iloc[[k]], exact=True)
        slow.append(time.perf_counter() - tic)
        b = int(np.argmin(exact))
        same_view += near == exact[b]
        same_object += library._codes[a] == library._codes[b]
    figures = {
        "import heatdata": imported,
        "load (with the index)": loaded,
        "recall@1, view": same_view / len(picked),
        "recall@1, object": same_object / len(picked),
        "search through the index, median": float(np.median(fast)),
        "exact search, median": float(np.median(slow)),
        "recognize warm, median": float(np.median([t for t, _ in answers])),
        "recognize: right object": float(np.mean([ok for _, ok in answers])),
        "10,000 test views through the index": batch,
        "peak memory, before the library (imports, the test descriptors)": before,
        "peak memory, loaded and searched through the index": peak,
        "peak memory, with rendered views recognized and the exact searches": high_water(),
        "index": library.index.description if library.index is not None else "none",
    }
    print(json.dumps(figures))


def classify_table(library_path: Path, run: Path, path: Path) -> int:
    """Write a descriptor table of the library's views (``train``) and :data:`BATCH` test rows: the run's real test
    views cycled, under numbered view names; returns how many test rows."""
    import pandas as pd

    from heatdata.io.tables import DESCRIPTOR_SCHEMA, read_metadata, read_table, write_table

    library, _ = read_table(library_path)
    tests, _ = read_table(
        run / "descriptors.parquet", filters=[("descriptor", "==", DESCRIPTOR), ("split", "==", "test")]
    )
    tests = tests.iloc[np.arange(BATCH) % len(tests)].reset_index(drop=True)
    tests["view_id"] = [f"{view}#{k:05d}" for k, view in enumerate(tests["view_id"])]
    rows = pd.concat([library[library["split"] == "train"], tests], ignore_index=True)
    write_table(rows, path, DESCRIPTOR_SCHEMA, read_metadata(run / "descriptors.parquet"), row_group_size=16_384)
    return len(tests)


def classify_child(table: str) -> None:
    """The classify rule's work on ``table`` (:func:`classify_table`) in this fresh process; prints JSON."""
    from heatdata.recognition.evaluate import evaluate_table

    before = high_water()
    tic = time.perf_counter()
    predictions = evaluate_table(table, DESCRIPTOR, [VIEWS])
    seconds = time.perf_counter() - tic
    real = ~predictions["object"].str.startswith("distractor")
    figures = {
        f"classify {len(predictions):,} test views": seconds,
        "classify: right object": float(predictions.loc[real, "correct"].mean()),
        "peak memory, classify (before it: imports)": high_water(),
        "peak memory, imports": before,
    }
    print(json.dumps(figures))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run", type=Path, help="a run's results folder with the default descriptor's library")
    parser.add_argument("--sizes", type=int, nargs="+", default=[10_000, 100_000, 400_000])
    parser.add_argument("--queries", type=int, default=300, help="real test views searched both ways")
    parser.add_argument("--views", type=int, default=14, help="rendered test views recognized")
    parser.add_argument("--child", help=argparse.SUPPRESS)
    parser.add_argument("--classify-child", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        child(args.child, str(args.run), args.queries, args.views)
        return
    if args.classify_child:
        classify_child(args.classify_child)
        return
    from heatdata.recognition.library import write_library_index

    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for size in args.sizes:
            path = Path(folder) / f"library-{size}.parquet"
            tic = time.perf_counter()
            views, synthetic = distractor_library(args.run, size, path)
            tic = time.perf_counter()
            write_library_index(path)
            built = time.perf_counter() - tic
            done = subprocess.run(
                [sys.executable, __file__, str(args.run), "--child", str(path), "--queries", str(args.queries),
                 "--views", str(args.views)],
                capture_output=True, text=True, check=True,
            )  # fmt: skip
            figures = json.loads(done.stdout.strip().splitlines()[-1])
            table = Path(folder) / f"descriptors-{size}.parquet"
            classify_table(path, args.run, table)
            done = subprocess.run(
                [sys.executable, __file__, str(args.run), "--classify-child", str(table)],
                capture_output=True, text=True, check=True,
            )  # fmt: skip
            table.unlink()
            figures.update(json.loads(done.stdout.strip().splitlines()[-1]))
            label = f"{views:,} views ({synthetic:,} synthetic), {figures.pop('index')}"
            print(label, figures, flush=True)
            rows.append((f"{label}: index built and written", built * 1e3, "ms"))
            for name, value in figures.items():
                share = "recall" in name or "right" in name
                unit = "GB" if name.startswith("peak memory") else "share" if share else "ms"
                rows.append((f"{label}: {name}", value if unit != "ms" else value * 1e3, unit))
            path.unlink()
    write(rows)


if __name__ == "__main__":
    main()
