"""Every scene recognized with one library, each detection scored against the scene's truth (rule recognize_scenes)."""

from threadpoolctl import threadpool_limits

from heatdata.experiments.scenes import recognize_scene_files
from heatdata.io.tables import DETECTION_SCHEMA, write_table
from heatdata.log import setup_logging
from heatdata.recognition.library import load_library

setup_logging(path=snakemake.log[0])
library = load_library(snakemake.input.library)
depths = [path for path in snakemake.input.frames if path.endswith(".png") and path.count(".") == 1]
with threadpool_limits(snakemake.threads):
    table = recognize_scene_files(library, depths)
metadata = {
    "library": snakemake.input.library,
    "library_size": snakemake.params.size,
    "scenes": snakemake.params.settings,
}
write_table(table, snakemake.output[0], DETECTION_SCHEMA, metadata)
