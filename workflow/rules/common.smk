# Shared values of the rules: the run's objects, descriptors, pairs and captures, checked before any job runs
# (heatdata.experiments.config, so that the tests call the same checks). No plotting or stitching is imported here.
import json
import sys

import jsonschema

import pandas as pd

import heatdata
from heatdata.descriptors import file_name
from heatdata.errors import ConfigError
from heatdata.experiments.config import (CONFUSION_PATTERN, check_numbers, check_results, check_stages,
                                         confusion_labels, descriptor_specs, multiview_descriptor, run_captures,
                                         run_catalog, run_scenes, stitched_objects)
from heatdata.experiments.real_frames import frame_files, real_frame_folders
from heatdata.io.catalog import catalog_sizes
from snakemake.exceptions import WorkflowError

RESULTS = config["results"]
VERSION = heatdata.__version__

try:
    check_numbers(config)
    SPECS = descriptor_specs(config)
    CATALOG = run_catalog(config)
    check_results(config, CATALOG)  # every output lies under results: none may overwrite an input
    # every row, before any job, by one validator: snakemake's validate reads the schema file again for each row
    # (27 of 97 profiled seconds of planning 1,000 objects: benchmarks/bench_dag.py)
    catalog_rows = jsonschema.Draft202012Validator(load_schema("../schemas/catalog.schema.yaml"))
    for row in CATALOG.drop(columns="path").to_dict("records"):
        error = next(catalog_rows.iter_errors(row), None)
        if error is not None:
            raise schema_message(error, f"catalogue row {row['object']}: ")
    STITCHED = {pair["object"]: pair for pair in config["stitch"]["pairs"]}
    if STITCHED:
        CATALOG = pd.concat([CATALOG, stitched_objects(config, CATALOG)])
    OBJECTS = CATALOG.index.tolist()
    check_stages(config, OBJECTS, SPECS)
    CAPTURES = run_captures(config, OBJECTS)  # object -> its captured frames
    SCENES = run_scenes(config, OBJECTS, SPECS, catalog_sizes(CATALOG))  # the scenes' objects, their libraries
    if SCENES["left_out"]:
        width, depth = config["scenes"]["table"]
        print(f"scenes: {len(SCENES['left_out'])} of {len(OBJECTS)} objects are too large for the {width} x {depth} m "
              f"table and left out of the scenes ({', '.join(SCENES['left_out'][:5])}"
              f"{', ...' if len(SCENES['left_out']) > 5 else ''}){'; no scenes' if not SCENES['scenes'] else ''}",
              file=sys.stderr)
    REAL_FRAMES = real_frame_folders(config["real_frames"]["folders"])  # name -> folder of labelled frames
except ConfigError as exc:
    raise WorkflowError(f"config error: {exc}") from None
# the descriptors by file name (pvhk/polar/center/64 -> pvhk_polar_center_64): the classify jobs' wildcard
SPEC_FILES = {file_name(s.name): s for s in SPECS}
FIXED_TIME = any(s.impl.time_scaled for s in SPECS)  # needs the objects' time scales (Alg. 5.1)
# every object's time scales in one table: each describe job needs them all, and one file per job keeps the DAG's
# edges linear in the objects (N files per job made planning quadratic: benchmarks/bench_dag.py)
TIME_SCALES = [f"{RESULTS}/time_scales.csv"] if FIXED_TIME else []
# kinds learned on the library views (SI-HKS's codebook): one fit job each, before any describe job
FITTED = {file_name(s.name): s for s in SPECS if s.impl.fitted}
MULTIVIEW_DESCRIPTOR = multiview_descriptor(config)
# a library file per descriptor x library size: what `heatdata recognize` reads; the scenes' size is built too
LIBRARY_SIZES = sorted(set(config["library_sizes"]) | ({SCENES["size"]} if SCENES["scenes"] else set()), reverse=True)
LIBRARIES = [f"{RESULTS}/libraries/{name}-{size}.parquet" for name in SPEC_FILES for size in config["library_sizes"]]


# every object's catalogue row as JSON, made once: a params value, so editing one row reruns what uses that object
# (CATALOG.loc in each job's params took 1.7 of 67 profiled seconds of planning 1,000 objects)
CATALOG_ROWS = {
    obj: json.dumps(row, sort_keys=True, default=str) for obj, row in CATALOG.to_dict("index").items()
}


def model_input(obj):
    """What an object's render job needs: its model file, its extracted Sweet Home 3D folder or its stitched model."""
    if config["sh3f"]["files"] and obj not in STITCHED:
        return f"{RESULTS}/models/{obj}"
    return CATALOG.at[obj, "path"]


def catalog_row_of(obj):
    """An object's catalogue row as JSON (CATALOG_ROWS)."""
    return CATALOG_ROWS[obj]


def catalog_row(wildcards):
    """The wildcard object's catalogue row (catalog_row_of)."""
    return catalog_row_of(wildcards.object)
