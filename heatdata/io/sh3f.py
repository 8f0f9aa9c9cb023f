"""Sweet Home 3D furniture libraries (``.sh3f``): their catalogue entries, and models imported from them."""

from __future__ import annotations

import codecs
import csv
import logging
import re
import zipfile
from pathlib import Path, PurePosixPath

import pandas as pd

from heatdata.errors import ModelError
from heatdata.io.catalog import CATALOG_COLUMNS, SH3F_LICENCES

log = logging.getLogger(__name__)


def parse_properties(text: str) -> dict[str, str]:
    """Parse a Java ``.properties`` text (``key=value`` lines, ``\\uXXXX`` escapes)."""
    result: dict[str, str] = {}
    logical, pending = [], ""
    for raw in text.splitlines():
        line = pending + raw.lstrip() if pending else raw.strip()
        if line.endswith("\\") and not line.endswith("\\\\"):
            pending = line[:-1]
            continue
        pending = ""
        logical.append(line)
    for line in logical:
        if not line or line[0] in "#!":
            continue
        match = re.match(r"((?:[^=:\\\s]|\\.)+)\s*[=:]?\s*(.*)", line)
        if match:
            key, value = (codecs.decode(s, "unicode_escape") for s in match.groups())
            result[key] = value
    return result


def sh3f_entries(sh3f_path: str | Path) -> pd.DataFrame:
    """The furniture entries of a Sweet Home 3D library (``.sh3f``), one row each.

    Columns: ``index, name, category, model, width, depth, height, rotation, creator``;
    sizes converted from centimetres to metres.
    """
    sh3f_path = Path(sh3f_path)
    try:
        with zipfile.ZipFile(sh3f_path) as archive:
            text = archive.read("PluginFurnitureCatalog.properties").decode("latin-1")
    except (OSError, zipfile.BadZipFile, KeyError) as exc:
        raise ModelError(f"{sh3f_path}: not a readable Sweet Home 3D furniture library ({exc})") from exc
    props = parse_properties(text)
    indices = sorted({int(k.split("#")[1]) for k in props if k.startswith("name#")})
    rows = []
    for i in indices:
        model = props.get(f"model#{i}", "").lstrip("/")
        if ".." in PurePosixPath(model).parts or "\\" in model:  # untrusted: it must stay inside the library
            log.warning(
                "%s: furniture #%d (%s) left out: its model path %r leads outside the library",
                sh3f_path,
                i,
                props[f"name#{i}"],
                model,
            )
            continue
        try:
            sizes = {key: float(props[f"{key}#{i}"]) / 100.0 for key in ("width", "depth", "height")}
        except (KeyError, ValueError) as exc:
            raise ModelError(
                f"{sh3f_path}: furniture #{i} ({props[f'name#{i}']}) has a missing or non-numeric "
                f"size ({exc}); width, depth and height are centimetres"
            ) from None
        rows.append(
            {
                "index": i,
                "name": props[f"name#{i}"],
                "category": props.get(f"category#{i}", ""),
                "model": model,
                **sizes,
                "rotation": props.get(f"modelRotation#{i}", ""),
                "creator": props.get(f"creator#{i}", ""),
            }
        )
    return pd.DataFrame(rows)


def sh3f_catalog(
    sh3f_path: str | Path,
    *,
    name_pattern: str | None = None,
    label: str | None = None,
    exclude_pattern: str | None = None,
    allow_empty: bool = False,
) -> pd.DataFrame:
    """Catalogue rows of a Sweet Home 3D library's furniture, without extracting anything.

    ``file`` is the model's path inside the archive (and inside a folder it is extracted
    to with :func:`extract_sh3f_model`). Object ids are ``<library>-<index>-<model>``.
    ``name_pattern`` keeps and ``exclude_pattern`` drops furniture by name (case-insensitive
    regular expressions). No match is an error unless ``allow_empty``.
    """
    sh3f_path = Path(sh3f_path)
    entries = sh3f_entries(sh3f_path)
    for what, pattern in (("names", name_pattern), ("exclude", exclude_pattern)):
        try:
            re.compile(pattern or "")
        except re.error as exc:
            raise ModelError(f"{what} {pattern!r} is not a regular expression: {exc}") from None
    if name_pattern:
        entries = entries[entries["name"].str.contains(name_pattern, case=False, regex=True)]
    if exclude_pattern:
        entries = entries[~entries["name"].str.contains(exclude_pattern, case=False, regex=True)]
    if entries.empty and not allow_empty:
        raise ModelError(
            f"{sh3f_path}: no furniture matches {name_pattern!r}"
            + (f" without {exclude_pattern!r}" if exclude_pattern else "")
        )
    library = sh3f_path.stem
    rows = [
        {
            "object": f"{library}-{entry.index:03d}-{Path(entry.model).stem}",
            "label": label or entry.name.lower(),
            "file": entry.model,
            "width": entry.width,
            "height": entry.height,
            "depth": entry.depth,
            "rotation": entry.rotation,
            "name": entry.name,
            "source": f"Sweet Home 3D {library}, {entry.creator}",
            "licence": SH3F_LICENCES.get(library.lower(), "CC-BY-3.0"),
            "scale": 1.0,
        }
        for entry in entries.itertuples()
    ]
    return pd.DataFrame(rows, columns=CATALOG_COLUMNS)


def sh3f_catalogs(
    sh3f_paths: list[str | Path],
    *,
    name_pattern: str | None = None,
    label: str | None = None,
    exclude_pattern: str | None = None,
) -> pd.DataFrame:
    """:func:`sh3f_catalog` of several libraries, with each row's library in an ``archive`` column.

    A library without matching furniture contributes nothing; none at all is an error.
    """
    tables = [
        sh3f_catalog(
            path, name_pattern=name_pattern, label=label, exclude_pattern=exclude_pattern, allow_empty=True
        ).assign(archive=str(path))
        for path in sh3f_paths
    ]
    table = pd.concat(tables, ignore_index=True) if tables else pd.DataFrame()
    if table.empty:
        raise ModelError(
            f"{', '.join(map(str, sh3f_paths)) or 'no library given'}: no furniture matches "
            f"{name_pattern!r}" + (f" without {exclude_pattern!r}" if exclude_pattern else "")
        )
    log.info("%d models from %d Sweet Home 3D libraries", len(table), len(sh3f_paths))
    return table


def extract_sh3f_model(sh3f_path: str | Path, model: str, out_dir: str | Path) -> Path:
    """Extract one model's folder (OBJ, MTL, textures, licence) from a ``.sh3f``; return the OBJ path."""
    folder = str(Path(model).parent) + "/"
    root = Path(out_dir).resolve()
    try:
        with zipfile.ZipFile(sh3f_path) as archive:
            members = [n for n in archive.namelist() if n.startswith(folder) and not n.endswith("/")]
            if model not in members:
                raise ModelError(f"{sh3f_path}: no model {model!r} in the library")
            for member in members:  # untrusted names: nothing is written outside out_dir
                if not (root / member).resolve().is_relative_to(root):
                    raise ModelError(f"{sh3f_path}: member {member!r} would be written outside {out_dir}")
                archive.extract(member, out_dir)
    except (OSError, zipfile.BadZipFile) as exc:
        raise ModelError(f"{sh3f_path}: cannot extract {model!r} ({exc})") from exc
    return Path(out_dir) / model


def import_sh3f(
    sh3f_path: str | Path,
    out_dir: str | Path,
    *,
    name_pattern: str | None = None,
    label: str | None = None,
    exclude_pattern: str | None = None,
) -> pd.DataFrame:
    """Extract models of a Sweet Home 3D furniture library into a catalogue folder.

    Parameters
    ----------
    sh3f_path : path
        A ``.sh3f`` file, e.g. ``/usr/share/sweethome3d/furniture/Scopia.sh3f`` from the
        Debian package ``sweethome3d-furniture``.
    out_dir : path
        Folder to write the models and ``catalog.csv`` into (appends to an existing one).
    name_pattern : str, optional
        Case-insensitive regular expression on the furniture name (e.g. ``"chair|stool"``).
    label : str, optional
        Class for every imported object; by default the lower-cased furniture name.
    exclude_pattern : str, optional
        Case-insensitive regular expression of furniture names to leave out (e.g. ``"bench"``).

    Returns
    -------
    pandas.DataFrame
        The catalogue rows written for this library.
    """
    out_dir = Path(out_dir)
    table = sh3f_catalog(sh3f_path, name_pattern=name_pattern, label=label, exclude_pattern=exclude_pattern)
    if out_dir.exists() and not out_dir.is_dir():
        raise ModelError(f"{out_dir}: the output folder is a file")
    out_dir.mkdir(parents=True, exist_ok=True)
    for model in table["file"]:
        extract_sh3f_model(sh3f_path, model, out_dir)
    catalog_path = out_dir / "catalog.csv"
    if catalog_path.exists():
        old = pd.read_csv(catalog_path, dtype=str, keep_default_na=False)
        table = pd.concat([old[~old["object"].isin(table["object"])], table.astype(str)])
    table.to_csv(catalog_path, index=False, quoting=csv.QUOTE_MINIMAL)
    log.info("imported %d models from %s into %s", len(table), sh3f_path, out_dir)
    return table
