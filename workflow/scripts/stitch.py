"""JASNOM on one configured pair of meshes (rule stitch, thesis ch. 7)."""

import json
import logging

import numpy as np

from heatdata.io.models import load_model, save_model
from heatdata.jasnom.seam import stitch
from heatdata.log import setup_logging
from heatdata.reporting.figures.jasnom import plot_stitch

setup_logging(path=snakemake.log[0])
log = logging.getLogger("heatdata")
pair, settings = snakemake.params.pair, snakemake.params.settings
scale = pair.get("scale", 1.0)
motion = None
if "motion" in pair:  # registered cameras: translation in file units, between the files' own frames
    motion = np.array(pair["motion"], float)
    motion[:3, 3] *= scale
first, second = (load_model(path, scale=scale, label=pair.get("label", ""), center=False) for path in snakemake.input)
result = stitch(first, second, **settings, scans=pair.get("scans", False), name=pair["object"], motion=motion)
save_model(result.model, snakemake.output.model)
a = result.alignment
if a.ambiguous:
    log.warning(
        "%s: ambiguous: another pose costs nearly as little (J %.4g against %.4g)", pair["object"], a.runner_up, a.cost
    )
if a.poor:
    log.warning("%s: poor: the seam's mean gap is %.1f%% of the size", pair["object"], 100 * a.gap / a.size)
with open(snakemake.output.summary, "w") as out:
    json.dump(
        {
            "object": pair["object"],
            "first": pair["first"],
            "second": pair["second"],
            "rotation": a.rotation.tolist(),
            "translation": a.translation.tolist(),
            "cost": a.cost,
            "edge_cost": a.edge_cost,
            "crossing_cost": a.crossing_cost,
            "crease_cost": a.crease_cost,
            "runner_up": None if np.isnan(a.runner_up) else a.runner_up,
            "ambiguous": a.ambiguous,
            "mean_gap": a.gap,
            "mean_gap_of_size": a.gap / a.size,
            "poor": a.poor,
            "facing": a.facing,
            "boundaries": [len(result.first.loop), len(result.second.loop)],
            "loop_pairs": result.loop_pairs,
            "open_loops": result.open_loops,
            "welded": result.welded,
            "strip_faces": result.strip_faces,
            "seconds": a.seconds,
            "version": snakemake.params.version,
        },
        out,
        indent=1,
    )
plot_stitch(
    first,
    second,
    result.model,
    result.strip_faces,
    snakemake.output.figure,
    f"JASNOM: {pair['object']} from {len(first.faces)} + {len(second.faces)} faces, {result.loop_pairs} "
    f"boundary pair(s) stitched, {result.open_loops} left open, J = {a.cost:.3g} (runner-up "
    f"{a.runner_up:.3g}{', ambiguous' if a.ambiguous else ''}), mean gap {a.gap / a.size:.2%} of the size",
)
