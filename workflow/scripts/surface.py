"""An object's surface samples with normals, which its library files carry for the pose (rule surface)."""

import json

from heatdata.io.catalog import load_catalog_model
from heatdata.log import setup_logging
from heatdata.recognition.pose import sample_surface, write_surface

setup_logging(path=snakemake.log[0])
model = load_catalog_model(json.loads(snakemake.params.row))
surface = sample_surface(model.vertices, model.faces, coloured=model.coloured)
write_surface(surface, snakemake.output[0])
