"""The workflow's config, checked before any job runs: the run's objects, descriptors, pairs and captures.

``workflow/rules/common.smk`` calls these at parse time and turns a :class:`~heatdata.errors.ConfigError`
into Snakemake's one-line ``config error: ...``; the tests call them directly. The config is the
schema-validated dictionary of ``workflow/schemas/config.schema.yaml`` (its defaults filled in).
"""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from heatdata.descriptors import DESCRIPTORS, DescriptorSpec
from heatdata.descriptors.base import article
from heatdata.errors import ConfigError, HeatdataError, did_you_mean
from heatdata.experiments.captures import find_captures
from heatdata.io.catalog import catalog_from_folder, color_twins, read_catalog, with_model_defaults
from heatdata.io.models import rigid_motion
from heatdata.io.sh3f import sh3f_catalogs
from heatdata.io.tables import read_ablation

#: the confusion figures' paths under ``figures/confusion/`` (rule evaluate's report patterns)
CONFUSION_PATTERN = "{descriptor}/{level}_{size}_views.png"


def confusion_labels(sizes: list[int]):
    """The report's labels of a confusion figure (rule evaluate), as a function of its path's wildcards: the library
    size zero-padded to the widest of ``sizes``, because the report sorts labels as text (12, 40, 5, 8 otherwise)."""
    width = len(str(max(sizes)))
    return lambda wildcards: {"matrix": wildcards.level, "library views": wildcards.size.zfill(width)}


#: config keys spelled another way until 0.1.0 (dotted: a key inside a section), and their one spelling now
ALIASES = {
    "colour_twins": "color_twins",
    "rump.neighbours": "rump.n_neighbors",
    "people.neighbours": "people.n_neighbors",
}


def accept_aliases(config: dict[str, Any]) -> list[str]:
    """Rename the config's old spellings (:data:`ALIASES`) in place, each with a DeprecationWarning.

    Parameters
    ----------
    config : dict
        The config as read, before the schema fills in defaults.

    Returns
    -------
    list of str
        One line per renamed key, for the log.
    """
    notes = []
    for old, new in ALIASES.items():
        *section, key = old.split(".")
        where: Any = config
        for part in section:
            where = where.get(part) if isinstance(where, dict) else None
        if not isinstance(where, dict) or key not in where:
            continue
        renamed = new.split(".")[-1]
        if renamed in where:
            raise ConfigError(f"{old} is the old spelling of {new}: give one of them")
        where[renamed] = where.pop(key)
        notes.append(f"config key {old} is deprecated: spell it {new}")
        warnings.warn(notes[-1], DeprecationWarning, stacklevel=2)
    return notes


def check_numbers(value: Any, where: str = "") -> None:
    """Every number in the config is finite: JSON Schema's ``number`` admits YAML's ``.nan`` and ``.inf``.

    Parameters
    ----------
    value : dict, list or scalar
        The validated config (or a part of it).
    where : str
        The key of ``value``, for the message.

    Raises
    ------
    ConfigError
        A NaN or infinite number, naming its key (``views.distance``).
    """
    if isinstance(value, dict):
        for key, item in value.items():
            check_numbers(item, f"{where}.{key}" if where else str(key))
    elif isinstance(value, list):
        for k, item in enumerate(value):
            check_numbers(item, f"{where}[{k}]")
    elif isinstance(value, float) and not np.isfinite(value):
        raise ConfigError(f"{where}: {value} is not a finite number")


def run_catalog(config: dict[str, Any]) -> pd.DataFrame:
    """The catalogue rows of the objects the run uses, indexed by object id.

    From ``sh3f.files``, ``models_dir`` or ``catalog`` (in that order), kept to ``objects`` and to the first
    ``objects_limit``, with ``color_twins`` of those added. Objects of a Sweet Home 3D library get ``path`` under
    ``results/models/``, where rule ``extract_model`` writes them.

    Parameters
    ----------
    config : dict
        The validated config.

    Returns
    -------
    pandas.DataFrame
        One row per object, indexed by ``object``.

    Raises
    ------
    ConfigError
        A missing library, an unknown object, no objects, a twin of an unknown object.
    """
    sh3f = config["sh3f"]
    if sh3f["files"] and config["models_dir"]:
        raise ConfigError("set models_dir or sh3f.files, not both")
    try:
        if sh3f["files"]:
            missing = [f for f in sh3f["files"] if not Path(f).is_file()]
            if missing:
                raise ConfigError(
                    f"sh3f.files: {', '.join(missing)} do(es) not exist "
                    "(apt-get install sweethome3d-furniture installs the libraries; "
                    "dpkg -L sweethome3d-furniture lists their .sh3f files)"
                )
            table = sh3f_catalogs(
                sh3f["files"],
                name_pattern=sh3f["names"] or None,
                label=sh3f["label"] or None,
                exclude_pattern=sh3f["exclude"] or None,
                classes=sh3f.get("classes", "name"),
            )
        elif config["models_dir"]:
            table = catalog_from_folder(
                config["models_dir"], config["models_scale"], config["models_units"], config["models_up_axis"]
            )
        else:
            table = with_model_defaults(
                read_catalog(config["catalog"]), config["models_units"], config["models_up_axis"]
            )
    except ConfigError:
        raise
    except HeatdataError as exc:
        raise ConfigError(str(exc)) from None
    if config["objects"]:
        unknown = sorted(set(config["objects"]) - set(table["object"]))
        if unknown:
            raise ConfigError(f"objects: {unknown} are not in the catalogue{did_you_mean(unknown[0], table['object'])}")
        table = table[table["object"].isin(config["objects"])]
    if table.empty:
        raise ConfigError("no objects to process")
    twins = config["color_twins"]
    twinned = twins["objects"]
    if config.get("objects_limit"):
        table = table.head(config["objects_limit"])
        twinned = [o for o in twinned if o in set(table["object"])]
    if twinned:
        try:
            table = pd.concat([table, color_twins(table, twinned, twins["hue"])], ignore_index=True)
        except HeatdataError as exc:
            raise ConfigError(f"color_twins: {exc}") from None
    if sh3f["files"]:  # each object (a twin too) is extracted to its own folder by rule extract_model
        table["path"] = [f"{config['results']}/models/{o}/{f}" for o, f in zip(table["object"], table["file"])]
    return table.set_index("object", drop=False)


def run_inputs(config: dict[str, Any], catalog: pd.DataFrame) -> list[tuple[str, str]]:
    """Every file and folder the run reads, each with the config key that names it.

    Parameters
    ----------
    config : dict
        The validated config.
    catalog : pandas.DataFrame
        The run's catalogue rows (:func:`run_catalog`): their model files are inputs, unless the run extracts them
        from ``sh3f.files`` into its results.

    Returns
    -------
    list of (str, str)
        ``(key, path)`` pairs.
    """
    if config["sh3f"]["files"]:
        inputs = [("sh3f.files", f) for f in config["sh3f"]["files"]]
    elif config["models_dir"]:
        inputs = [("models_dir", config["models_dir"])]
    else:
        inputs = [("catalog", config["catalog"])]
        inputs += [(f"the catalogue's model of {obj}", path) for obj, path in catalog["path"].items()]
    inputs += [
        (f"stitch.pairs[{k}].{key}", pair[key])
        for k, pair in enumerate(config["stitch"]["pairs"])
        for key in ("first", "second")
    ]
    for key, value in (
        ("captures.dir", config["captures"]["dir"]),
        ("people.reallusion", config["people"]["reallusion"]),
        ("ablation", config["ablation"]),
    ):
        if value:
            inputs.append((key, value))
    return inputs


def check_results(config: dict[str, Any], catalog: pd.DataFrame) -> None:
    """The config's ``results`` is a folder of the run's own: no output the run plans (all lie under it) can
    overwrite one of its inputs.

    Parameters
    ----------
    config : dict
        The validated config.
    catalog : pandas.DataFrame
        The run's catalogue rows (:func:`run_catalog`).

    Raises
    ------
    ConfigError
        ``results`` is empty, the filesystem's root, the working folder or one above it, a file, a folder holding
        one of :func:`run_inputs`, or a folder inside an input folder.
    """
    given = config["results"]
    if not given.strip():
        raise ConfigError("results: give the folder for the run's outputs (it is empty)")
    folder = Path(given).resolve()
    here = Path.cwd().resolve()
    if folder == here or folder in here.parents:
        raise ConfigError(
            f"results: {given} is {'the working folder' if folder == here else 'a folder above the working one'}: "
            "give the outputs a folder of their own (results/...)"
        )
    if folder.exists() and not folder.is_dir():
        raise ConfigError(f"results: {given} is a file, not a folder")
    for key, path in run_inputs(config, catalog):
        read = Path(path).resolve()
        if read == folder or folder in read.parents:
            raise ConfigError(
                f"results: {given} holds {key} ({path}), which the run reads: its outputs could overwrite it; "
                "give the outputs another folder"
            )
        if read.is_dir() and read in folder.parents:
            raise ConfigError(f"results: {given} lies inside {key} ({path}), which the run reads: give another folder")


def checked_spec(d: dict[str, Any], where: str) -> DescriptorSpec:
    """A config's descriptor checked against its kind: its options, and that this machine can compute it.

    Parameters
    ----------
    d : dict
        The descriptor's keys (``kind``, ``samples``, ``source``, ``sampling``, ``options``).
    where : str
        Its config key, for the error (``descriptors[2]``).

    Returns
    -------
    DescriptorSpec
    """
    try:
        spec = DescriptorSpec.from_dict(d)
    except (HeatdataError, TypeError) as exc:
        raise ConfigError(f"{where}: {exc}") from None
    if DESCRIPTORS[spec.kind] is not None:
        raise ConfigError(f"{where}: {spec.kind} is not available here: {DESCRIPTORS[spec.kind]}")
    return spec


def descriptor_specs(config: dict[str, Any]) -> list[DescriptorSpec]:
    """The configured descriptors, each checked (:func:`checked_spec`), distinct, and naming the primary one.

    Parameters
    ----------
    config : dict
        The validated config.

    Returns
    -------
    list of DescriptorSpec
    """
    specs = [checked_spec(d, f"descriptors[{k}]") for k, d in enumerate(config["descriptors"])]
    names = [s.name for s in specs]
    if len(set(names)) < len(names):
        raise ConfigError(f"descriptors: the same descriptor twice in {names}")
    if config["primary_descriptor"] not in names:
        raise ConfigError(
            f"primary_descriptor {config['primary_descriptor']!r} is not one of descriptors {names}"
            f"{did_you_mean(config['primary_descriptor'], names)}"
        )
    return specs


def stitched_objects(config: dict[str, Any], catalog: pd.DataFrame) -> pd.DataFrame:
    """The config's JASNOM pairs (``stitch.pairs``) as catalogue rows whose model rule ``stitch`` writes.

    Parameters
    ----------
    config : dict
        The validated config.
    catalog : pandas.DataFrame
        The run's other objects (:func:`run_catalog`): a pair may not reuse one of their names.

    Returns
    -------
    pandas.DataFrame
        One row per pair, with ``catalog``'s columns, indexed by ``object``.
    """
    rows: list[dict[str, str]] = []
    for k, pair in enumerate(config["stitch"]["pairs"]):
        missing = [pair[key] for key in ("first", "second") if not Path(pair[key]).is_file()]
        if missing:
            raise ConfigError(f"stitch.pairs[{k}]: {', '.join(missing)} do(es) not exist")
        try:
            rigid_motion(pair.get("motion", np.eye(4)))
        except HeatdataError:
            raise ConfigError(
                f"stitch.pairs[{k}].motion is not a rigid motion (a rotation, no reflection, last row 0 0 0 1)"
            ) from None
        if pair["object"] in catalog.index or pair["object"] in [r["object"] for r in rows]:
            raise ConfigError(f"stitch.pairs[{k}]: object {pair['object']!r} is already one of the run's objects")
        rows.append(
            {
                "object": pair["object"],
                "label": pair.get("label", "") or pair["object"],
                "file": f"{pair['object']}.ply",
                "path": f"{config['results']}/stitched/{pair['object']}.ply",
            }
        )
    return pd.DataFrame(rows, columns=catalog.columns).fillna("").set_index("object", drop=False)


def run_captures(config: dict[str, Any], objects: list[str]) -> dict[str, list[dict[str, Any]]]:
    """The captured frames of ``captures.dir`` (:func:`~heatdata.experiments.captures.find_captures`), by object.

    Parameters
    ----------
    config : dict
        The validated config.
    objects : list of str
        The run's objects: every capture's folder must name one.

    Returns
    -------
    dict
        Object -> its captures; empty when ``captures.dir`` is not set.
    """
    captures: dict[str, list[dict[str, Any]]] = {}
    if not config["captures"]["dir"]:
        return captures
    try:
        for capture in find_captures(config["captures"]["dir"]):
            captures.setdefault(capture["object"], []).append(capture)
    except HeatdataError as exc:
        raise ConfigError(f"captures.dir: {exc}") from None
    unknown = sorted(set(captures) - set(objects))
    if unknown:
        raise ConfigError(
            f"captures.dir: folder(s) {unknown} are not among the run's objects (a capture's folder "
            "names the object it shows)"
        )
    depth_range = config["captures"]["depth_range"]
    if depth_range and (len(depth_range) != 2 or depth_range[0] >= depth_range[1]):
        raise ConfigError(f"captures.depth_range must be [near, far] with near < far, got {depth_range}")
    return captures


def check_stages(config: dict[str, Any], objects: list[str], specs: list[DescriptorSpec]) -> None:
    """What each enabled stage needs of the run: compact libraries, the comparison, multi-view, people.

    Parameters
    ----------
    config : dict
        The validated config.
    objects : list of str
        The run's objects.
    specs : list of DescriptorSpec
        The run's descriptors (:func:`descriptor_specs`).

    Raises
    ------
    ConfigError
        The first check that fails, naming its key.
    """
    views = config["views"]
    if len(objects) * views["train"] < 4:
        raise ConfigError(
            f"views.train: the Isomap of the library views (figures/isomap.png) needs four or more; "
            f"{len(objects)} object(s) x {views['train']} view(s) give {len(objects) * views['train']}"
        )
    if config["compact"]["enabled"]:
        compact = checked_spec(config["compact"]["descriptor"], "compact.descriptor")
        if not compact.impl.multi_source:
            raise ConfigError(
                f"compact.descriptor: {article(compact.kind)} {compact.kind} has no heat source to take "
                "candidates of (ch. 6)"
            )
        if min(config["library_sizes"]) < 2:
            raise ConfigError(
                "compact: a compact library needs two or more views around the circle; "
                f"library_sizes has {min(config['library_sizes'])}"
            )
        if len(objects) < 2 and min(config["compact"]["alphas"]) < 1:
            raise ConfigError(
                "compact: alpha < 1 rewards distance to other objects (eq. 6.10); give two or more objects"
            )
    if config["comparison"]["enabled"]:
        if config.get("objects_limit"):  # a run cut short draws the Isomaps of the objects it kept
            kept = [o for o in config["comparison"]["isomap_objects"] if o in objects]
            config["comparison"]["isomap_objects"] = kept or list(objects[:4])
        missing = sorted(set(config["comparison"]["isomap_objects"]) - set(objects))
        if missing:
            raise ConfigError(f"comparison.isomap_objects: {missing} are not among the run's objects")
    if config["ablation"]:
        try:
            read_ablation(config["ablation"])
        except HeatdataError as exc:
            raise ConfigError(f"ablation: {exc}") from None
    multiview = multiview_descriptor(config)
    if config["multiview"]["enabled"]:
        if multiview not in [s.name for s in specs]:
            raise ConfigError(f"multiview.descriptor {multiview!r} is not one of descriptors")
        if any(s.impl.time_scaled for s in specs if s.name == multiview):
            raise ConfigError(
                "multiview.descriptor: a time-scaled kind (ft-pvhk) describes test views once per "
                "object; choose a descriptor with one row per view"
            )
        if len(objects) < 2:
            raise ConfigError("multiview: recognition among objects needs two or more objects")
        if views["test"] < 4:
            raise ConfigError("multiview: needs four or more test views per object (half learn the similarity)")
        large = [n for n in config["multiview"]["library_views"] if n > views["train"]]
        if large:
            raise ConfigError(f"multiview.library_views {large} exceed views.train = {views['train']}")
    if config["people"]["enabled"]:
        for k, d in enumerate(config["people"]["descriptors"]):
            spec = checked_spec(d, f"people.descriptors[{k}]")
            if spec.impl.fitted or spec.impl.time_scaled:
                raise ConfigError(
                    f"people.descriptors[{k}]: {article(spec.kind)} {spec.kind} needs "
                    f"{'fitting' if spec.impl.fitted else 'time scales'}; people are described one view "
                    "at a time"
                )
        if config["people"]["reallusion"] and not Path(config["people"]["reallusion"]).is_file():
            raise ConfigError(
                f"people.reallusion: {config['people']['reallusion']} does not exist (apt-get install "
                "sweethome3d-furniture ships /usr/share/sweethome3d/furniture/Reallusion.sh3f)"
            )
    too_large = [s for s in config["library_sizes"] if s > views["train"]]
    if too_large:
        raise ConfigError(f"library_sizes {too_large} exceed views.train = {views['train']} rendered views")


def run_scenes(
    config: dict[str, Any], objects: list[str], specs: list[DescriptorSpec], sizes: dict[str, list[float]] | None = None
) -> dict[str, Any]:
    """The scenes of the run (config ``scenes``): each scene's objects, the libraries that recognize them.

    Parameters
    ----------
    config : dict
        The validated config.
    objects : list of str
        The run's objects.
    specs : list of DescriptorSpec
        The run's descriptors.
    sizes : dict, optional
        The objects' real sizes, ``{object: [width, height, depth]}`` m (:func:`heatdata.io.catalog.catalog_sizes`):
        an object too large for the table (furniture) is left out of the scenes. An object without a size is
        measured when its scene is rendered, and left out there.

    Returns
    -------
    dict
        ``scenes`` (scene name -> its objects; empty when the stage is off or no object fits the table),
        ``descriptors`` (the spec names whose libraries recognize them), ``size`` (their library views per object),
        ``primary`` (the descriptor drawn in the overlays) and ``left_out`` (the objects too large for the table).

    Raises
    ------
    ConfigError
        A descriptor not among the run's, a library size the run does not build, a range given high to low.
    """
    from heatdata.experiments.scenes import choose_objects, fits_table

    settings = config["scenes"]
    off: dict[str, Any] = {"scenes": {}, "descriptors": [], "size": None, "primary": None, "left_out": []}
    if not settings["enabled"]:
        return off
    for key in ("objects", "distance", "elevation", "wall_gap"):
        low, high = settings[key]
        if low > high:
            raise ConfigError(f"scenes.{key}: [{low}, {high}] runs high to low")
    names = [s.name for s in specs]
    unknown = [d for d in settings["descriptors"] if d not in names]
    if unknown:
        raise ConfigError(
            f"scenes.descriptors: {unknown} are not among the run's descriptors ({', '.join(names)})"
            f"{did_you_mean(unknown[0], names)}"
        )
    size = settings["library_size"] or max(config["library_sizes"])
    if size not in config["library_sizes"]:
        raise ConfigError(f"scenes.library_size {size} is not one of library_sizes {config['library_sizes']}")
    descriptors = settings["descriptors"] or names
    primary = config["primary_descriptor"] if config["primary_descriptor"] in descriptors else descriptors[0]
    sizes = sizes or {}
    left_out = [o for o in objects if o in sizes and not fits_table(sizes[o][0], sizes[o][2], settings["table"])]
    fitting = [o for o in objects if o not in left_out]
    if not fitting:
        return {**off, "left_out": left_out}
    scenes = {f"scene-{k:03d}": choose_objects(fitting, settings, k) for k in range(settings["count"])}
    return {"scenes": scenes, "descriptors": descriptors, "size": size, "primary": primary, "left_out": left_out}


def multiview_descriptor(config: dict[str, Any]) -> str:
    """The descriptor multi-view recognition uses: ``multiview.descriptor``, else the primary one."""
    return config["multiview"]["descriptor"] or config["primary_descriptor"]
