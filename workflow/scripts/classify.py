"""Nearest-neighbour predictions of one descriptor for one library size (rule classify)."""
from heatdata.log import setup_logging
from heatdata.evaluate import evaluate_library_sizes
from heatdata.tables import PREDICTION_SCHEMA, read_table, write_table

setup_logging(path=snakemake.log[0])
name = snakemake.params.descriptor
descriptors, meta = read_table(snakemake.input[0], filters=[("descriptor", "==", name)],
                               columns=["object", "label", "view_id", "split", "azimuth", "descriptor", "kind",
                                        "time_object", "values", "weights"])
predictions = evaluate_library_sizes(descriptors, name, [int(snakemake.wildcards.size)])
write_table(predictions, snakemake.output[0], PREDICTION_SCHEMA, meta)
