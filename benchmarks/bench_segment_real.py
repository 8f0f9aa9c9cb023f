"""Segmentation of real Kinect table-tops: objects found, leftover pieces and segments of nothing per category, and
the time a 640 x 480 frame takes on this machine (``segment_frame``: the support plane, then the surfaces cut at
depth steps and concave creases), scored as the mOSD benchmark counts them (objects of >= 1000 pixels, found at
mask IoU >= 0.5).

    .venv/bin/python benchmarks/bench_segment_real.py ../shared/realdata/mosd/frames
"""

import argparse
import sys

from record import write

from heatdata.experiments.real_frames import by_category, score_folder


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", help="labelled frames: <name>.depth.png, .rgb.png, .labels.png, intrinsics.json")
    folder = parser.parse_args().folder
    table = by_category(score_folder(folder))
    print(table.to_string(index=False, float_format="%.3f"))
    figures = []
    for row in table.itertuples():
        figures.append((f"{row.category}: objects found", row.found_share * 100, f"% of {row.objects}"))
        figures.append((f"{row.category}: leftover pieces per object", row.leftovers_per_object, "pieces"))
        figures.append((f"{row.category}: segments of nothing", row.of_nothing_share * 100, f"% of {row.segments}"))
    total = table.set_index("category").loc["all"]
    figures.append(("median time a frame", total.median_seconds, "s"))
    write(figures)
    sys.exit(0)


if __name__ == "__main__":
    main()
