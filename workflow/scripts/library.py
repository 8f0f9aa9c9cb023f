"""A descriptor's library files, one per library size, which `heatdata recognize` reads, each with its search index
beside it (name.faiss, for a kind with an index space) (rule library)."""

import pandas as pd

from heatdata.descriptors import DescriptorSpec
from heatdata.experiments.describe import load_fitted
from heatdata.io.tables import read_table
from heatdata.log import setup_logging
from heatdata.recognition.library import build_library, write_library
from heatdata.recognition.pose import read_surface

setup_logging(path=snakemake.log[0])
name = snakemake.params.descriptor
(spec,) = [s for s in (DescriptorSpec.from_dict(d) for d in snakemake.params.descriptors) if s.name == name]
(spec,) = load_fitted([spec], {name: snakemake.input.fitted[0]} if snakemake.input.fitted else {})
rows, _ = read_table(snakemake.input.descriptors, filters=[("descriptor", "==", name)])
scales = pd.concat([pd.read_csv(p) for p in snakemake.input.time_scales]) if snakemake.input.time_scales else None
surfaces = {obj: read_surface(p) for obj, p in zip(snakemake.params.objects, snakemake.input.surfaces, strict=True)}
for size, path in zip(snakemake.params.library_sizes, snakemake.output, strict=True):
    library, metadata = build_library(
        rows,
        spec,
        int(size),
        time_scales=scales,
        render=snakemake.params.render,
        time_rule=snakemake.params.time_rule,
        source=snakemake.input.descriptors,
        sizes=snakemake.params.sizes,
        surfaces=surfaces,
    )
    write_library(library, metadata, path, index=True)
