"""``heatdata stitch``: JASNOM on two meshes, or on two depth frames of an object on a table (thesis ch. 7)."""

from __future__ import annotations

import argparse
import logging
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from heatdata.cli.arguments import command_inputs, dump_json, number
from heatdata.errors import HeatdataError
from heatdata.experiments.captures import CAPTURE_SUFFIXES as DEPTH_SUFFIXES
from heatdata.io.files import check_output, require_file
from heatdata.jasnom.defaults import (
    ALONG,
    ALPHA,
    BETA,
    FREE_SPACE,
    GAMMA,
    MAX_SAMPLES,
    MAX_WEIGHT,
    MIN_SAMPLES,
    SCAN_ALONG,
    SCAN_ROBUST,
    TABLE,
)
from heatdata.log import printable

log = logging.getLogger("heatdata")


def cmd_stitch(args: argparse.Namespace) -> None:
    """JASNOM (thesis ch. 7): align the second mesh onto the first by their boundaries and stitch them.

    Two scans on their scanners' grids (PCD, range-grid PLY) are first registered by their overlap (FPFH + RANSAC,
    then ICP); where they overlap the registration stands, and where they do not JASNOM stitches them; the output
    says which ran and why. The output is in the first mesh's frame. It prints the motion, J and its terms, the
    runner-up's J and the seam's mean gap, and warns when another pose is nearly as cheap (ambiguous) or the seam is
    wide (poor).
    """
    from heatdata.io.models import SUPPORTED_SUFFIXES, load_model, save_model
    from heatdata.jasnom.seam import stitch

    beside = [companion for path in (args.first, args.second) for companion in _companions(path)]
    out = check_output(
        args.out, inputs=command_inputs(args, *beside), suffixes=SUPPORTED_SUFFIXES, what="the stitched model"
    )
    motion = None
    if args.motion is not None:
        require_file(args.motion, "motion file (a 4x4 matrix)")
        try:
            motion = np.loadtxt(args.motion, ndmin=2)
        except (OSError, ValueError) as error:
            raise HeatdataError(f"{args.motion}: not a 4x4 matrix of numbers ({error})") from error
        if motion.shape != (4, 4):
            raise HeatdataError(f"{args.motion}: not a 4x4 matrix of numbers (shape {motion.shape})")
        motion[:3, 3] *= args.scale
    options = {
        "alpha": args.alpha,
        "beta": args.beta,
        "gamma": args.gamma,
        "along": args.along,
        "robust": args.robust,
        "free_space": args.free_space,
        "samples": args.samples,
        "name": out.stem,
        "motion": motion,
    }
    joined = None
    if _depth_frames(args):
        from heatdata.jasnom.seam import stitch_scans

        result = stitch_scans(*_table_scans(args), table=args.table, **options)
    elif _scan_files(args):
        from heatdata.jasnom.join import join
        from heatdata.jasnom.scans import read_scan

        first, second = (read_scan(path, scale=args.scale) for path in (args.first, args.second))
        if motion is None:
            del options["motion"]
            joined = join(first, second, **options)
            if joined.stitched is None:  # registered: the scans overlap
                _save_registration(joined, out, args.json, args.close_holes)
                return
            result = joined.stitched
        else:
            result = stitch(first, second, scans=True, **options)
    else:
        if args.intrinsics or args.rgb:
            raise HeatdataError("--intrinsics and --rgb are for two depth frames (heatdata stitch --scans a.png b.png)")
        first, second = (load_model(path, scale=args.scale, center=False) for path in (args.first, args.second))
        result = stitch(first, second, scans=args.scans, **options)
    model, closed = _closed(result.model, args.close_holes)
    save_model(model, out)
    a = result.alignment
    if a.ambiguous:
        log.warning(
            "ambiguous: another pose costs nearly as little (J %.4g against %.4g): check the result, or give --motion",
            a.runner_up,
            a.cost,
        )
    if a.poor:
        log.warning(
            "poor: the seam's mean gap is %.1f%% of the size: the boundaries are not one curve here",
            100 * a.gap / a.size,
        )
    summary = {"model": str(out), "vertices": len(model.vertices), "faces": len(model.faces)}
    summary |= result.summary() | closed | ({"method": "jasnom", "why": joined.why} if joined is not None else {})
    del summary["facing"]  # a found motion always faces away (align's constraint)
    summary |= {
        "rotation": np.round(a.rotation, 6).tolist(),
        "translation": np.round(a.translation, 6).tolist(),
        "seconds": round(a.seconds, 2),
    }
    print(dump_json(summary) if args.json else stitch_table(summary))


def stitch_table(summary: dict) -> str:
    """The terminal's answer of ``heatdata stitch``: what was written, the motion, the costs and the seam, a line
    each (``--json`` prints ``summary`` itself)."""
    runner_up = "none tried" if summary["runner_up"] is None else f"{summary['runner_up']:.4g}"
    verdicts = [word for word in ("ambiguous", "poor") if summary[word]]
    rows = [
        ("model", f"{printable(summary['model'])}: {summary['vertices']} vertices, {summary['faces']} faces"),
        *([("method", f"JASNOM: {summary['why']}")] if "why" in summary else []),
        ("motion", _motion_words(summary)),
        (
            "cost J",
            f"{summary['cost']:.4g} (boundary {summary['edge_cost']:.4g}, interpenetration "
            f"{summary['crossing_cost']:.4g}, crease {summary['crease_cost']:.4g}, table "
            f"{summary['table_cost']:.4g}, free space {summary['free_space_cost']:.4g}); runner-up {runner_up}",
        ),
        (
            "seam",
            f"mean gap {summary['mean_gap']:.4g} m ({100 * summary['mean_gap_of_size']:.2f}% of the size); "
            f"boundary loops {summary['boundaries'][0]} and {summary['boundaries'][1]}; "
            f"{summary['strip_faces']} faces of strip; {summary['holes']} hole(s) inside the scans, "
            + (f"{summary['holes_closed']} loop(s) closed" if "holes_closed" in summary else "left open"),
        ),
        ("verdict", ", ".join(verdicts) + " (see the warnings above)" if verdicts else "clear"),
        ("time", f"{summary['seconds']:.2f} s"),
    ]
    return "\n".join(f"{name:<8} {value}" for name, value in rows)


def _save_registration(joined, out: Path, as_json: bool, close_holes: int | None) -> None:
    """Two overlapping scans registered: the joined model written, and what was done printed."""
    from heatdata.io.models import save_model

    model, closed = _closed(joined.model, close_holes)
    save_model(model, out)
    summary = {"model": str(out), "vertices": len(model.vertices), "faces": len(model.faces)}
    summary |= joined.summary() | closed | {"seconds": round(joined.registration.seconds, 2)}
    print(dump_json(summary) if as_json else registration_table(summary))


def _closed(model, max_edges: int | None):
    """``model`` with its holes of up to ``max_edges`` edges closed (none when None), and the summary's line on it."""
    if max_edges is None:
        return model, {}
    from heatdata.jasnom.scans import close_holes

    closed, filled = close_holes(model, max_edges)
    return closed, {"holes_closed": filled}


def registration_table(summary: dict) -> str:
    """The terminal's answer of ``heatdata stitch`` for two overlapping scans: what was written, the motion, and why
    it was registered (``--json`` prints ``summary`` itself)."""
    rows = [
        ("model", f"{printable(summary['model'])}: {summary['vertices']} vertices, {summary['faces']} faces"),
        ("method", f"registration (FPFH + RANSAC, then ICP): {summary['why']}"),
        ("motion", _motion_words(summary)),
        *([("holes", f"{summary['holes_closed']} closed")] if "holes_closed" in summary else []),
        ("time", f"{summary['seconds']:.2f} s"),
    ]
    return "\n".join(f"{name:<8} {value}" for name, value in rows)


def _motion_words(summary: dict) -> str:
    """A motion as a turn about an axis, then a move."""
    rotation = Rotation.from_matrix(np.asarray(summary["rotation"]))
    axis_angle = rotation.as_rotvec()
    degrees = float(np.degrees(np.linalg.norm(axis_angle)))
    axis = axis_angle / np.linalg.norm(axis_angle) if degrees > 0 else np.array([0.0, 0.0, 1.0])
    return (
        f"turn {degrees:.1f} deg about ({axis[0]:+.3f} {axis[1]:+.3f} {axis[2]:+.3f}), then move "
        "({:+.4f} {:+.4f} {:+.4f}) m".format(*summary["translation"])
    )


def _scan_files(args: argparse.Namespace) -> bool:
    """Whether ``stitch`` was given two scans on their scanners' grids (PCD, range-grid PLY) rather than meshes."""
    from heatdata.jasnom.scans import is_scan_file

    scans = [is_scan_file(path) for path in (args.first, args.second)]
    if any(scans) and not all(scans):
        raise HeatdataError("give two scans (PCD or range-grid PLY files) or two meshes, not one of each")
    return all(scans)


def _depth_frames(args: argparse.Namespace) -> bool:
    """Whether ``stitch`` was given two depth frames (an object on a table, standing and flipped) rather than meshes."""
    frames = [Path(p).suffix.lower() in DEPTH_SUFFIXES for p in (args.first, args.second)]
    if any(frames) and not all(frames):
        raise HeatdataError(
            "give two depth frames (an object on a table, standing and flipped) or two meshes, not one of each"
        )
    if all(frames) and not args.scans:
        raise HeatdataError("two depth frames are stitched as scans of an object on a table: add --scans")
    return all(frames)


def _companions(frame: Path) -> tuple[Path, Path]:
    """The files a depth frame's scan reads beside it when no option names them: ``<name>.json`` (its intrinsics) and
    ``<name>.rgb.png`` (its colour)."""
    base = Path(frame).with_suffix("")
    return Path(f"{base}.json"), Path(f"{base}.rgb.png")


def _table_scans(args: argparse.Namespace):
    """The two frames' objects on their tables: each frame's intrinsics are --intrinsics or its ``<name>.json``, its
    colour the --rgb given or its ``<name>.rgb.png`` when there is one."""
    from heatdata.jasnom.table import read_table_scan

    scans = []
    for k, path in enumerate((args.first, args.second)):
        camera, colour = _companions(path)
        intrinsics = args.intrinsics or camera
        if not Path(intrinsics).is_file():
            raise HeatdataError(
                f"{path}: no intrinsics: give --intrinsics (JSON or YAML with fx, fy, cx, cy, width, height) or "
                f"write {camera}"
            )
        rgb = args.rgb[k] if args.rgb else colour
        scans.append(read_table_scan(path, intrinsics, rgb if Path(rgb).is_file() or args.rgb else None))
    return scans


def add_stitch(sub) -> None:
    """The ``stitch`` command's arguments."""
    join = sub.add_parser(
        "stitch",
        help="one model from two meshes or scans of an object: JASNOM where they do not overlap (thesis ch. 7)",
        description=cmd_stitch.__doc__,
    )
    join.add_argument(
        "first",
        type=Path,
        help="the mesh that stays put: the output is in its frame (PLY, OBJ, OFF, STL, GLB); a scan on its "
        "scanner's grid (PCD, range-grid PLY), registered where the two scans overlap and stitched by JASNOM where "
        "they do not; with --scans, a depth frame (.png in millimetres, .npy in metres) of the object standing on a "
        "table",
    )
    join.add_argument("second", type=Path, help="the mesh moved onto it; with --scans, a frame of the object flipped")
    join.add_argument("-o", "--out", type=Path, required=True, help="the stitched mesh (.ply keeps vertex colours)")
    join.add_argument("--json", action="store_true", help="print the motion, costs and seam as JSON, for programs")
    join.add_argument(
        "--alpha",
        type=number(positive=True, high=MAX_WEIGHT),
        default=ALPHA,
        help=f"steepness of the interpenetration penalty, relative to the sampling (default {ALPHA:g})",
    )
    join.add_argument(
        "--beta",
        type=number(0.0, high=MAX_WEIGHT),
        default=BETA,
        help=f"weight of the interpenetration penalty J2, eq. 7.4; 0 to patch a hole (default {BETA:g})",
    )
    join.add_argument(
        "--gamma",
        type=number(0.0, high=MAX_WEIGHT),
        default=GAMMA,
        help=f"weight of the crease term J3 (default {GAMMA:g})",
    )
    join.add_argument(
        "--scans",
        action="store_true",
        help="the meshes are depth scans, each in its camera's frame (camera at the origin), taken from "
        "opposite sides (the object flipped): the alignment keeps each on the far side from the "
        "other's camera and tolerates the band of surface neither saw",
    )
    join.add_argument(
        "--intrinsics",
        type=Path,
        help="with two depth frames: their camera's fx, fy, cx, cy, width, height (JSON or YAML; default each "
        "frame's <name>.json)",
    )
    join.add_argument(
        "--rgb",
        type=Path,
        nargs=2,
        metavar=("FIRST", "SECOND"),
        help="with two depth frames: their colour images (default each frame's <name>.rgb.png, when there is one)",
    )
    join.add_argument(
        "--table",
        type=number(0.0, high=MAX_WEIGHT),
        default=TABLE,
        help=f"with two depth frames: weight of the support-plane term, the tables as witnesses (default {TABLE:g})",
    )
    join.add_argument(
        "--free-space",
        type=number(0.0, high=MAX_WEIGHT),
        help="with two scans: weight of the free-space term, which keeps each scan out of the space the other's "
        f"camera saw empty (default {FREE_SPACE:g} for scans without tables, else 0)",
    )
    join.add_argument(
        "--along",
        type=number(0.0, high=MAX_WEIGHT),
        help="weight of the gap along the seam's continuation in J1: below 1 tolerates a band of "
        f"unseen surface (default {ALONG:g}; with --scans {SCAN_ALONG:g})",
    )
    join.add_argument(
        "--robust",
        type=number(0.0, high=MAX_WEIGHT),
        help=f"soft-L1 width of the residuals, in boundary radii (default 0: squares; with --scans {SCAN_ROBUST:g})",
    )
    join.add_argument(
        "--close-holes",
        type=int,
        metavar="EDGES",
        help="close the holes of the output of up to EDGES boundary edges (pymeshlab), such as a scanner leaves where "
        "it saw nothing; by default they stay open and are counted",
    )
    join.add_argument(
        "--samples",
        type=number(MIN_SAMPLES, high=MAX_SAMPLES, whole=True),
        default=128,
        help=(
            "boundary samples for the alignment; the coarse search tries twice as many "
            f"(default 128, at most {MAX_SAMPLES})"
        ),
    )
    join.add_argument("--scale", type=number(positive=True), default=1.0, help="file units to metres (default 1)")
    join.add_argument(
        "--motion",
        type=Path,
        help="a known motion of the second mesh into the first's frame (registered cameras): a text "
        "file with a 4x4 matrix, translation in file units; nothing is searched",
    )
    join.set_defaults(func=cmd_stitch)
