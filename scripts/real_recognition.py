"""Recognition on real RGB-D frames with hand-drawn boxes (:mod:`heatdata.experiments.real_recognition`): how many
of the library's objects are named right, how many objects it lacks are answered unknown, and how many detections of
nothing name an object.

    .venv/bin/python scripts/real_recognition.py ../shared/realdata/ycb/frames \\
        --library results/ycb/libraries/hgd_color=hue-saturation-40.parquet --out docs/results/real_ycb.csv

The folder holds ``<name>-depth.png`` (uint16 millimetres), ``<name>-color.png``, ``meta.yml`` (a camera matrix)
and ``truth.json``. The table has one row per box and per detection of nothing; the frames themselves are not
copied anywhere (the YCB frames' licence forbids committing them).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from heatdata.experiments.real_recognition import score_folder, summary
from heatdata.log import setup_logging
from heatdata.recognition.library import load_library


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder", type=Path, help="a folder of frames with meta.yml and truth.json")
    parser.add_argument("--library", type=Path, required=True, help="a library file with surface samples")
    parser.add_argument("--threshold", type=float, help="the confidence threshold (default: the library's rule)")
    parser.add_argument("--out", type=Path, help="the table of boxes and answers to write (.csv)")
    args = parser.parse_args()
    setup_logging()
    start = time.perf_counter()
    library = load_library(args.library)
    scores = score_folder(library, args.folder, threshold=args.threshold)
    if args.out:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        scores.to_csv(args.out, index=False)
    print(scores.to_string(index=False))
    print(json.dumps({**summary(scores), "wall_seconds": round(time.perf_counter() - start, 1)}))


if __name__ == "__main__":
    main()
