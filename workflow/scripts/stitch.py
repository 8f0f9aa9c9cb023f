"""JASNOM on one configured pair of meshes (rule stitch, thesis ch. 7)."""
import json

import numpy as np

from heatdata.figures import plot_stitch
from heatdata.log import setup_logging
from heatdata.models import load_model, save_model
from heatdata.stitch import stitch

setup_logging(path=snakemake.log[0])
pair, settings = snakemake.params.pair, snakemake.params.settings
scale = pair.get("scale", 1.0)
motion = None
if "motion" in pair:  # registered cameras: translation in file units, between the files' own frames
    motion = np.array(pair["motion"], float)
    motion[:3, 3] *= scale
first, second = (load_model(path, scale=scale, label=pair.get("label", ""), center=motion is None)
                 for path in snakemake.input)
result = stitch(first, second, alpha=settings["alpha"], beta=settings["beta"], samples=settings["samples"],
                workers=snakemake.threads, name=pair["object"], motion=motion)
save_model(result.model, snakemake.output.model)
a = result.alignment
strip = len(result.model.faces) - len(first.faces) - len(second.faces)
with open(snakemake.output.summary, "w") as out:
    json.dump({"object": pair["object"], "first": pair["first"], "second": pair["second"],
               "rotation": a.rotation.tolist(), "translation": a.translation.tolist(), "shift": a.shift,
               "cost": a.cost, "edge_cost": a.edge_cost, "crossing_cost": a.crossing_cost, "facing": a.facing,
               "boundaries": [len(result.first.loop), len(result.second.loop)], "loop_pairs": result.loop_pairs,
               "open_loops": result.open_loops, "strip_faces": strip, "seconds": a.seconds,
               "version": snakemake.params.version}, out, indent=1)
plot_stitch(first, second, result.model, strip, snakemake.output.figure,
            f"JASNOM: {pair['object']} from {len(first.faces)} + {len(second.faces)} faces, {result.loop_pairs} "
            f"boundary pair(s) stitched, {result.open_loops} left open, J = {a.cost:.3g}")
