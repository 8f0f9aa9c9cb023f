"""Model catalogues: a CSV listing objects with their class, file and real size.

Both the embedded default data (``data/models/catalog.csv``) and any Sweet Home 3D
furniture library imported with :func:`import_sh3f` are described by the same table,
so the rest of heatdata reads models one way:

============  =====================================================================
column        meaning
============  =====================================================================
object        stable object identifier (unique in the catalogue)
label         object class used for recognition (e.g. ``mug``)
file          model file, relative to the catalogue's folder
width         real size along the model's x axis, metres (empty: file units are m)
height        real size along y (up), metres
depth         real size along z, metres
rotation      optional 9 numbers (row-major 3x3) applied before scaling
scale         optional factor from file units to metres when no size is given
units         optional file units when no size is given: m, cm or mm (times ``scale``)
up_axis       optional up axis of the file: y (default) or z (YCB, BOP, most CAD files)
hue           optional degrees by which the model's colours are turned (a colour twin, 3.4)
name          human-readable name
source        where the model came from (library and creator)
licence       licence of the model
============  =====================================================================
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, overload

import numpy as np
import pandas as pd

from heatdata.errors import ModelError
from heatdata.io.files import is_partial, require_file
from heatdata.io.models import SUPPORTED_SUFFIXES, UP_AXES, Model, hue_rotated, load_model

CATALOG_COLUMNS = [
    "object",
    "label",
    "file",
    "width",
    "height",
    "depth",
    "rotation",
    "name",
    "source",
    "licence",
    "scale",
    "hue",
    "units",
    "up_axis",
]

#: file units a catalogue, ``models_units`` or ``--units`` may name, as metres
UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001}


SH3F_LICENCES = {"blendswap-cc-0": "CC0-1.0"}


def embedded_catalog() -> Path:
    """The catalogue of the embedded CC0 models: ``data/models/`` of the repository, or of an installed wheel.

    A wheel ships the repository's ``data/`` folder as ``heatdata/embedded/`` (pyproject.toml).

    Returns
    -------
    Path
        ``.../models/catalog.csv``.
    """
    package = Path(__file__).resolve().parents[1]
    for folder in (package / "embedded", package.parent / "data"):
        if (folder / "models" / "catalog.csv").is_file():
            return folder / "models" / "catalog.csv"
    raise ModelError(f"no embedded models next to {package} (expected embedded/models/ or ../data/models/)")


def read_catalog(path: str | Path) -> pd.DataFrame:
    """Read and check a catalogue CSV.

    Parameters
    ----------
    path : str or Path
        A catalogue CSV (columns as in this module's docstring).

    Returns
    -------
    pandas.DataFrame
        Every column of :data:`CATALOG_COLUMNS` (empty where the file lacks it) and ``path``, each
        model's file resolved against the catalogue's folder.

    Raises
    ------
    ModelError
        The file is missing, lacks a column, has duplicate object ids, or names a model
        file that does not exist.
    """
    path = require_file(path, "catalogue", ModelError)
    try:
        table = pd.read_csv(
            path, dtype={"object": str, "label": str, "file": str, "rotation": str}, keep_default_na=False
        )
    except (ValueError, UnicodeDecodeError) as exc:  # pandas' parser errors are ValueErrors
        raise ModelError(f"{path}: not a readable catalogue CSV ({exc})") from None
    missing = [c for c in ("object", "label", "file") if c not in table.columns]
    if missing:
        raise ModelError(f"{path}: catalogue lacks column(s) {', '.join(missing)}")
    duplicated = table["object"][table["object"].duplicated()].tolist()
    if duplicated:
        raise ModelError(f"{path}: duplicate object id(s) {duplicated}")
    for column in CATALOG_COLUMNS:
        if column not in table.columns:
            table[column] = ""
    table["path"] = [str(path.parent / f) for f in table["file"]]
    return table


def catalog_from_folder(
    models_dir: str | Path, scale: float = 1.0, units: str = "m", up_axis: str = "y"
) -> pd.DataFrame:
    """A catalogue of a folder of meshes: one file per object, the class is the subfolder name.

    ``models_dir/mugs/red.obj`` becomes object ``mugs-red`` of class ``mugs``; files
    directly in ``models_dir`` get the class ``unlabelled``. File units times ``scale``
    are metres.

    Parameters
    ----------
    models_dir : str or Path
        A folder of mesh files, optionally one subfolder per class.
    scale : float
        File units times ``scale`` are metres.
    units : {"m", "cm", "mm"}
        The files' units (:data:`UNITS`; times ``scale``).
    up_axis : {"y", "z"}
        The files' up axis (:func:`heatdata.io.models.load_model`).

    Returns
    -------
    pandas.DataFrame
        The catalogue's columns (:data:`CATALOG_COLUMNS`) and ``path``, one row per file.

    Raises
    ------
    ModelError
        The folder does not exist or holds no supported mesh file.
    """
    root = Path(models_dir)
    if not root.is_dir():
        raise ModelError(f"{root}: no such models folder")
    files = sorted(
        p
        for p in root.rglob("*")
        if p.suffix.lower() in SUPPORTED_SUFFIXES
        and not any(is_partial(part) for part in p.relative_to(root).parts)
        and p.is_file()
    )
    if not files:
        raise ModelError(f"{root}: no mesh files ({', '.join(SUPPORTED_SUFFIXES)}) in the models folder")
    rows = []
    for path in files:
        relative = path.relative_to(root)
        label = relative.parts[0] if len(relative.parts) > 1 else "unlabelled"
        rows.append(
            {
                "object": f"{label}-{path.stem}" if label != "unlabelled" else path.stem,
                "label": label,
                "file": str(relative),
                "width": "",
                "height": "",
                "depth": "",
                "rotation": "",
                "name": path.stem,
                "source": str(path),
                "licence": "",
                "scale": scale,
                "units": units,
                "up_axis": up_axis,
            }
        )
    table = pd.DataFrame(rows)
    duplicated = table["object"][table["object"].duplicated()].tolist()
    if duplicated:
        raise ModelError(f"{root}: object names repeat ({duplicated}); give the files distinct names")
    table["path"] = [str(root / f) for f in table["file"]]
    return table


@overload
def _number(value: Any, default: float) -> float: ...


@overload
def _number(value: Any, default: None = None) -> float | None: ...


def _number(value: Any, default: float | None = None) -> float | None:
    """A catalogue cell as a float; empty or NaN cells give ``default``; other text is a :class:`ValueError`."""
    if value is None or str(value).strip() in ("", "nan", "NaN"):
        return default
    return float(value)


def _size(row: pd.Series | dict) -> tuple[float, float, float] | None:
    """A row's real size: its three cells all given, or none of them (the file's units times ``scale``)."""
    cells = {key: row.get(key) for key in ("width", "height", "depth")}
    try:
        numbers = {key: _number(value) for key, value in cells.items()}
    except ValueError:
        raise ModelError(f"{row['object']}: width, height and depth must be numbers (metres), got {cells}") from None
    width, height, depth = numbers.values()
    if width is None and height is None and depth is None:
        return None
    if width is None or height is None or depth is None:
        raise ModelError(
            f"{row['object']}: give width, height and depth together (metres), or none of them; got {cells}"
        )
    return width, height, depth


def catalog_sizes(catalog: pd.DataFrame) -> dict[str, list[float]]:
    """Each object's real size, where its catalogue row gives one.

    Parameters
    ----------
    catalog : pandas.DataFrame
        Catalogue rows with an ``object`` column (as :func:`read_catalog` returns).

    Returns
    -------
    dict
        ``{object: [width, height, depth]}`` in metres; objects without a size (their file's units) left out.

    Raises
    ------
    ModelError
        A row gives some of the three sizes but not all, or a size that is not a number.
    """
    sizes = {}
    for row in catalog.to_dict("records"):
        size = _size(row)
        if size is not None:
            sizes[str(row["object"])] = list(size)
    return sizes


def load_catalog_model(row: pd.Series | dict) -> Model:
    """Load the model of one catalogue row, scaled to its real size.

    Parameters
    ----------
    row : pandas.Series or dict
        A catalogue row (:func:`read_catalog`): ``path``, ``object``, ``label`` and the optional
        ``width``/``height``/``depth``, ``rotation``, ``scale`` and ``hue``.

    Returns
    -------
    Model
        The model in metres, turned by ``hue`` degrees when the row is a colour twin.
    """
    size = _size(row)
    rotation = None
    if str(row.get("rotation", "")).strip():
        try:
            rotation = np.array([float(x) for x in str(row["rotation"]).split()]).reshape(3, 3)
        except ValueError:
            raise ModelError(
                f"{row['object']}: rotation {row['rotation']!r} is not 9 numbers (a row-major 3x3)"
            ) from None
    try:
        scale, hue = _number(row.get("scale"), 1.0), _number(row.get("hue"), 0.0)
    except ValueError:
        raise ModelError(
            f"{row['object']}: scale and hue must be numbers, got {row.get('scale')!r}, {row.get('hue')!r}"
        ) from None
    units, up_axis = _cell(row, "units", "m", UNITS), _cell(row, "up_axis", "y", UP_AXES)
    model = load_model(
        row["path"],
        size=size,
        scale=scale * UNITS[units],
        rotation=rotation,
        up_axis=up_axis,
        name=row["object"],
        label=row["label"],
    )
    return hue_rotated(model, hue, name=row["object"]) if hue % 360 else model


def _cell(row: pd.Series | dict, column: str, default: str, allowed) -> str:
    """A catalogue row's text cell, ``default`` where empty, refused unless one of ``allowed``."""
    value = str(row.get(column, "") or "").strip()
    if value in ("", "nan"):
        return default
    if value not in allowed:
        raise ModelError(f"{row['object']}: {column} must be one of {', '.join(allowed)}, got {value!r}")
    return value


def with_model_defaults(catalog: pd.DataFrame, units: str, up_axis: str) -> pd.DataFrame:
    """A catalogue whose rows without ``units`` or ``up_axis`` take the run's (``models_units``,
    ``models_up_axis``); rows that name their own keep them.

    Parameters
    ----------
    catalog : pandas.DataFrame
        Catalogue rows (:func:`read_catalog`).
    units : {"m", "cm", "mm"}
    up_axis : {"y", "z"}

    Returns
    -------
    pandas.DataFrame
        A copy with both columns filled.
    """
    table = catalog.copy()
    for column, value in (("units", units), ("up_axis", up_axis)):
        cells = table[column].fillna("").astype(str).str.strip() if column in table else pd.Series("", table.index)
        table[column] = cells.where(~cells.isin(["", "nan"]), value)
    return table


def color_twins(catalog: pd.DataFrame, objects: list[str], degrees: float) -> pd.DataFrame:
    """Catalogue rows of colour twins (thesis 3.4): each of ``objects`` with its colours turned by ``degrees``.

    A twin is object ``<object>-hue<degrees>``, of the same class, file and size; only its
    colour tells it from the original (:func:`heatdata.io.models.hue_rotated`, applied by
    :func:`load_catalog_model`).

    Raises
    ------
    ModelError
        An object is not in the catalogue, the turn is a whole number of turns, or a twin's id is taken.
    """
    missing = sorted(set(objects) - set(catalog["object"]))
    if missing:
        raise ModelError(f"colour twins of {missing}: not in the catalogue")
    if not np.isfinite(degrees) or degrees % 360 == 0:
        raise ModelError(f"a colour twin needs a hue turn that is not a whole number of turns, got {degrees}")
    twins = catalog[catalog["object"].isin(objects)].copy()
    twins["name"] = [f"{n or o}, hue turned {degrees:g} degrees" for n, o in zip(twins["name"], twins["object"])]
    twins["object"] = [f"{o}-hue{degrees:g}" for o in twins["object"]]
    twins["hue"] = degrees
    taken = sorted(set(twins["object"]) & set(catalog["object"]))
    if taken:
        raise ModelError(f"colour twins {taken}: object ids already in the catalogue")
    return twins
