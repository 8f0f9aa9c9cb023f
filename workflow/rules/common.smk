# Shared helpers: the catalogue of objects, descriptor specs and config checks made before any job runs.
import json
import re
from pathlib import Path

import numpy as np
import pandas as pd

import heatdata
from heatdata.catalog import catalog_from_folder, colour_twins, read_catalog, sh3f_catalogs
from heatdata.depth import find_captures
from heatdata.descriptors import DESCRIPTORS, DescriptorSpec, file_name
from heatdata.descriptors.base import article
from heatdata.errors import HeatdataError
from heatdata.report import CONFUSION_PATTERN, read_ablation
from heatdata.stitch import rigid_motion
from snakemake.exceptions import WorkflowError

RESULTS = config["results"]
VERSION = heatdata.__version__


def _config_error(message):
    raise WorkflowError(f"config error: {message}")


def load_objects():
    """The catalogue rows of the objects this run uses, indexed by object id."""
    sh3f = config["sh3f"]
    if sh3f["files"] and config["models_dir"]:
        _config_error("set models_dir or sh3f.files, not both")
    try:
        if sh3f["files"]:
            missing = [f for f in sh3f["files"] if not Path(f).is_file()]
            if missing:
                _config_error(f"sh3f.files: {', '.join(missing)} do(es) not exist "
                              "(apt-get install sweethome3d-furniture installs the libraries; "
                              "dpkg -L sweethome3d-furniture lists their .sh3f files)")
            table = sh3f_catalogs(sh3f["files"], name_pattern=sh3f["names"] or None, label=sh3f["label"] or None,
                                  exclude_pattern=sh3f["exclude"] or None)
        elif config["models_dir"]:
            table = catalog_from_folder(config["models_dir"], scale=config["models_scale"])
        else:
            table = read_catalog(config["catalog"])
    except HeatdataError as exc:
        _config_error(str(exc))
    if config["objects"]:
        unknown = sorted(set(config["objects"]) - set(table["object"]))
        if unknown:
            _config_error(f"objects: {unknown} are not in the catalogue")
        table = table[table["object"].isin(config["objects"])]
    if table.empty:
        _config_error("no objects to process")
    twins = config["colour_twins"]
    if twins["objects"]:
        try:
            table = pd.concat([table, colour_twins(table, twins["objects"], twins["hue"])], ignore_index=True)
        except HeatdataError as exc:
            _config_error(f"colour_twins: {exc}")
    if sh3f["files"]:  # each object (a twin too) is extracted to its own folder by rule extract_model
        table["path"] = [f"{RESULTS}/models/{o}/{f}" for o, f in zip(table["object"], table["file"])]
    return table.set_index("object", drop=False)


def checked_spec(d, where):
    """A config's descriptor (``where``: its key, for the error) checked against its kind: options, availability."""
    try:
        spec = DescriptorSpec(**d)
    except (HeatdataError, TypeError) as exc:
        _config_error(f"{where}: {exc}")
    if DESCRIPTORS[spec.kind] is not None:
        _config_error(f"{where}: {spec.kind} is not available here: {DESCRIPTORS[spec.kind]}")
    return spec


def descriptor_specs():
    """The configured descriptors, each checked against its kind (options, availability on this machine)."""
    specs = [checked_spec(d, f"descriptors[{k}]") for k, d in enumerate(config["descriptors"])]
    names = [s.name for s in specs]
    if len(set(names)) < len(names):
        _config_error(f"descriptors: the same descriptor twice in {names}")
    if config["primary_descriptor"] not in names:
        _config_error(f"primary_descriptor {config['primary_descriptor']!r} is not one of descriptors {names}")
    return specs


SPECS = descriptor_specs()
# the descriptors by file name (pvhk/polar/center/64 -> pvhk_polar_center_64): the classify jobs' wildcard
SPEC_FILES = {file_name(s.name): s for s in SPECS}
FIXED_TIME = any(s.impl.time_scaled for s in SPECS)  # needs the objects' time scales (Alg. 5.1)


# kinds learned on the library views (SI-HKS's codebook): one fit job each, before any describe job
FITTED = {file_name(s.name): s for s in SPECS if s.impl.fitted}


def stitched_objects(catalog):
    """The config's JASNOM pairs (stitch.pairs) as catalogue rows whose model the rule stitch writes."""
    rows = []
    for k, pair in enumerate(config["stitch"]["pairs"]):
        missing = [pair[key] for key in ("first", "second") if not Path(pair[key]).is_file()]
        if missing:
            _config_error(f"stitch.pairs[{k}]: {', '.join(missing)} do(es) not exist")
        try:
            rigid_motion(pair.get("motion", np.eye(4)))
        except HeatdataError:
            _config_error(f"stitch.pairs[{k}].motion is not a rigid motion (a rotation, no reflection, last row "
                          "0 0 0 1)")
        if pair["object"] in catalog.index or pair["object"] in [r["object"] for r in rows]:
            _config_error(f"stitch.pairs[{k}]: object {pair['object']!r} is already one of the run's objects")
        rows.append({"object": pair["object"], "label": pair.get("label", "") or pair["object"],
                     "file": f"{pair['object']}.ply", "path": f"{RESULTS}/stitched/{pair['object']}.ply"})
    return pd.DataFrame(rows, columns=catalog.columns).fillna("").set_index("object", drop=False)


CATALOG = load_objects()
STITCHED = {pair["object"]: pair for pair in config["stitch"]["pairs"]}
if STITCHED:
    CATALOG = pd.concat([CATALOG, stitched_objects(CATALOG)])
OBJECTS = CATALOG.index.tolist()
if config["compact"]["enabled"]:
    COMPACT_SPEC = checked_spec(config["compact"]["descriptor"], "compact.descriptor")
    if not COMPACT_SPEC.impl.multi_source:
        _config_error(f"compact.descriptor: {article(COMPACT_SPEC.kind)} {COMPACT_SPEC.kind} has no heat source to take candidates of (ch. 6)")
    if min(config["library_sizes"]) < 2:
        _config_error("compact: a compact library needs two or more views around the circle; "
                      f"library_sizes has {min(config['library_sizes'])}")
    if len(OBJECTS) < 2 and min(config["compact"]["alphas"]) < 1:
        _config_error("compact: alpha < 1 rewards distance to other objects (eq. 6.10); give two or more objects")
if config["comparison"]["enabled"]:
    missing = sorted(set(config["comparison"]["isomap_objects"]) - set(OBJECTS))
    if missing:
        _config_error(f"comparison.isomap_objects: {missing} are not among the run's objects")
if config["ablation"]:
    try:
        read_ablation(config["ablation"])
    except HeatdataError as exc:
        _config_error(f"ablation: {exc}")
CAPTURES = {}  # object -> its captures (heatdata.depth.find_captures)
if config["captures"]["dir"]:
    try:
        for capture in find_captures(config["captures"]["dir"]):
            CAPTURES.setdefault(capture["object"], []).append(capture)
    except HeatdataError as exc:
        _config_error(f"captures.dir: {exc}")
    unknown = sorted(set(CAPTURES) - set(OBJECTS))
    if unknown:
        _config_error(f"captures.dir: folder(s) {unknown} are not among the run's objects (a capture's folder names "
                      "the object it shows)")
    depth_range = config["captures"]["depth_range"]
    if depth_range and (len(depth_range) != 2 or depth_range[0] >= depth_range[1]):
        _config_error(f"captures.depth_range must be [near, far] with near < far, got {depth_range}")
MULTIVIEW_DESCRIPTOR = config["multiview"]["descriptor"] or config["primary_descriptor"]
if config["multiview"]["enabled"]:
    if MULTIVIEW_DESCRIPTOR not in [s.name for s in SPECS]:
        _config_error(f"multiview.descriptor {MULTIVIEW_DESCRIPTOR!r} is not one of descriptors")
    if any(s.impl.time_scaled for s in SPECS if s.name == MULTIVIEW_DESCRIPTOR):
        _config_error("multiview.descriptor: a time-scaled kind (ft-pvhk) describes test views once per object; "
                      "choose a descriptor with one row per view")
    if len(OBJECTS) < 2:
        _config_error("multiview: recognition among objects needs two or more objects")
    if config["views"]["test"] < 4:
        _config_error("multiview: needs four or more test views per object (half learn the similarity)")
    large = [n for n in config["multiview"]["library_views"] if n > config["views"]["train"]]
    if large:
        _config_error(f"multiview.library_views {large} exceed views.train = {config['views']['train']}")
if config["people"]["enabled"]:
    for k, d in enumerate(config["people"]["descriptors"]):
        spec = checked_spec(d, f"people.descriptors[{k}]")
        if spec.impl.fitted or spec.impl.time_scaled:
            _config_error(f"people.descriptors[{k}]: {article(spec.kind)} {spec.kind} needs "
                          f"{'fitting' if spec.impl.fitted else 'time scales'}; people are described one view at a time")
    if config["people"]["reallusion"] and not Path(config["people"]["reallusion"]).is_file():
        _config_error(f"people.reallusion: {config['people']['reallusion']} does not exist (apt-get install "
                      "sweethome3d-furniture ships /usr/share/sweethome3d/furniture/Reallusion.sh3f)")
too_large = [s for s in config["library_sizes"] if s > config["views"]["train"]]
if too_large:
    _config_error(f"library_sizes {too_large} exceed views.train = {config['views']['train']} rendered views")


def model_input(obj):
    """What an object's render job needs: its model file, its extracted Sweet Home 3D folder or its stitched model."""
    if obj in STITCHED:
        return CATALOG.loc[obj, "path"]
    if config["sh3f"]["files"]:
        return f"{RESULTS}/models/{obj}"
    return CATALOG.loc[obj, "path"]


def catalog_row(wildcards):
    """The object's catalogue row as JSON: a params value, so editing one row reruns one object."""
    return json.dumps(CATALOG.loc[wildcards.object].to_dict(), sort_keys=True, default=str)
