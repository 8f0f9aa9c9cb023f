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
    pair_names = {"object": pair["object"], "first": pair["first"], "second": pair["second"]}
    json.dump({**pair_names, **result.summary(), "version": snakemake.params.version}, out, indent=1)
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
