"""HBRD on the proxy population of MakeHuman bodies (rule rump, thesis ch. 8)."""

import numpy as np

from heatdata.experiments.rump import population_table, rendered_rumps
from heatdata.io.bodies import population
from heatdata.log import setup_logging
from heatdata.reporting.figures.common import PROXY_NOTE
from heatdata.reporting.figures.rump import plot_rumps
from heatdata.reporting.pages import rump_page
from heatdata.rump import condition_measures, population_hbrd
from heatdata.views.view import kinect_intrinsics

setup_logging(path=snakemake.log[0])
s = snakemake.params.settings
bodies = population(s["bodies"], seed=s["seed"], gender=s["gender"], muscle_range=tuple(s["muscle"]))
scans = rendered_rumps(
    bodies, distance=s["distance"], noise=s["noise"], seed=s["seed"], intrinsics=kinect_intrinsics(s["image_scale"])
)
heats = population_hbrd(scans, extent=s["extent"])
descriptors = np.array([h.descriptor for h in heats])
weights = np.array([b["weight"] for b in bodies])
measures = condition_measures(descriptors, weights, n_neighbors=s["n_neighbors"])
population_table(bodies, descriptors, measures["embedding"]).to_csv(snakemake.output.descriptors, index=False)
plot_rumps(
    heats,
    weights,
    measures["embedding"],
    measures["thin"],
    snakemake.output.figure,
    f"HBRD of {len(bodies)} MakeHuman bodies (a proxy, not goats): Spearman {measures['spearman_isomap']:.2f} "
    f"with the weight (Isomap's first axis)",
    note=PROXY_NOTE,
)
with open(snakemake.output.page, "w") as out:
    out.write(rump_page(measures, s, [len(h.vertices) for h in heats]))
