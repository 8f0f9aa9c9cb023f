"""Sweet Home 3D furniture libraries (``.sh3f``): their catalogue entries, and models imported from them."""

from __future__ import annotations

import csv
import logging
import posixpath
import re
import zipfile
import zlib
from pathlib import Path, PurePosixPath

import numpy as np
import pandas as pd

from heatdata.errors import ModelError
from heatdata.io.catalog import CATALOG_COLUMNS, SH3F_LICENCES
from heatdata.io.files import atomic, check_folder, check_output, require_file
from heatdata.log import progress

log = logging.getLogger(__name__)


#: what an imported object's class can be without a label: its furniture name or its catalogue category
CLASSES = ("name", "category")


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
            # the text is Latin-1 (or pure ASCII), so its characters map back to the bytes the escapes decode from
            key, value = (s.encode("latin-1", "backslashreplace").decode("unicode_escape") for s in match.groups())
            result[key] = value
    return result


def sh3f_entries(sh3f_path: str | Path) -> pd.DataFrame:
    """The furniture entries of a Sweet Home 3D library (``.sh3f``), one row each.

    Columns: ``index, name, category, model, width, depth, height, rotation, creator``;
    sizes converted from centimetres to metres.
    """
    sh3f_path = Path(sh3f_path)
    require_file(sh3f_path, "Sweet Home 3D furniture library", ModelError)
    try:
        with zipfile.ZipFile(sh3f_path) as archive:
            data = _read_member(archive, "PluginFurnitureCatalog.properties", sh3f_path, MAX_PROPERTIES_BYTES)
    except (*UNREADABLE, KeyError) as exc:
        raise ModelError(f"{sh3f_path}: not a readable Sweet Home 3D furniture library ({exc})") from None
    props = parse_properties(data.decode("latin-1"))
    indices, odd = set(), []
    for key in props:
        if key.startswith("name#"):
            number = key.partition("#")[2]
            if number.isdigit():
                indices.add(int(number))
            else:
                odd.append(key)
    if odd:
        log.warning("%s: keys left out, not of a numbered furniture: %s", sh3f_path, ", ".join(odd[:5]))
    rows = []
    for i in sorted(indices):
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
        if not all(np.isfinite(s) and s > 0 for s in sizes.values()):
            raise ModelError(
                f"{sh3f_path}: furniture #{i} ({props[f'name#{i}']}) has a size that is not a positive length: "
                + ", ".join(f"{key}#{i}={props[f'{key}#{i}']}" for key in sizes)
                + " (centimetres)"
            )
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
    classes: str = "name",
) -> pd.DataFrame:
    """Catalogue rows of a Sweet Home 3D library's furniture, without extracting anything.

    ``file`` is the model's path inside the archive (and inside a folder it is extracted
    to with :func:`extract_sh3f_model`). Object ids are ``<library>-<index>-<model>``.
    ``name_pattern`` keeps furniture by name and ``exclude_pattern`` drops it by name or by
    object id (case-insensitive regular expressions). No match is an error unless ``allow_empty``. An object's class is
    ``label`` when given, else (``classes``) its lower-cased furniture name or its catalogue
    category ("living room", "kitchen", ...).
    """
    if classes not in CLASSES:
        raise ModelError(f"classes {classes!r}: use {' or '.join(CLASSES)}")
    sh3f_path = Path(sh3f_path)
    entries = sh3f_entries(sh3f_path)
    for what, pattern in (("names", name_pattern), ("exclude", exclude_pattern)):
        try:
            re.compile(pattern or "")
        except re.error as exc:
            raise ModelError(f"{what} {pattern!r} is not a regular expression: {exc}") from None
    library = sh3f_path.stem
    if not entries.empty:
        ids = [f"{library}-{index:03d}-{Path(model).stem}" for index, model in zip(entries["index"], entries["model"])]
        entries = entries.assign(object=ids)
        if name_pattern:
            entries = entries[entries["name"].str.contains(name_pattern, case=False, regex=True)]
        if exclude_pattern:
            dropped = [entries[c].str.contains(exclude_pattern, case=False, regex=True) for c in ("name", "object")]
            entries = entries[~(dropped[0] | dropped[1])]
    if entries.empty and not allow_empty:
        raise ModelError(f"{sh3f_path}: {_nothing_matches(name_pattern, exclude_pattern)}")
    rows = [
        {
            "object": entry.object,
            "label": label or (entry.category if classes == "category" else entry.name).lower(),
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


def _nothing_matches(name_pattern: str | None, exclude_pattern: str | None) -> str:
    if not name_pattern and not exclude_pattern:
        return "no furniture in the library"
    return " ".join(
        ([f"no furniture matches {name_pattern!r}"] if name_pattern else ["no furniture is left"])
        + ([f"without {exclude_pattern!r}"] if exclude_pattern else [])
    )


def sh3f_catalogs(
    sh3f_paths: list[str | Path],
    *,
    name_pattern: str | None = None,
    label: str | None = None,
    exclude_pattern: str | None = None,
    classes: str = "name",
) -> pd.DataFrame:
    """:func:`sh3f_catalog` of several libraries, with each row's library in an ``archive`` column.

    A library without matching furniture contributes nothing; none at all is an error.
    """
    tables = [
        sh3f_catalog(
            path,
            name_pattern=name_pattern,
            label=label,
            exclude_pattern=exclude_pattern,
            allow_empty=True,
            classes=classes,
        ).assign(archive=str(path))
        for path in sh3f_paths
    ]
    table = pd.concat(tables, ignore_index=True) if tables else pd.DataFrame()
    if table.empty:
        libraries = ", ".join(map(str, sh3f_paths)) or "no library given"
        raise ModelError(f"{libraries}: {_nothing_matches(name_pattern, exclude_pattern)}")
    log.info("%d models from %d Sweet Home 3D libraries", len(table), len(sh3f_paths))
    return table


# what zipfile raises on a damaged archive: a bad header or CRC, a corrupt stream, an encrypted or unknown method
UNREADABLE = (OSError, EOFError, zipfile.BadZipFile, zlib.error, NotImplementedError, RuntimeError, ValueError)
MAX_PROPERTIES_BYTES = 16 * 2**20  # the largest catalogue in Debian's libraries is 0.15 MB
MAX_MEMBER_BYTES = 64 * 2**20  # the largest model file there is 8.8 MB
MAX_RATIO = 100  # compression ratio; their models and textures compress at most 11:1
RATIO_FROM_BYTES = 2**20  # smaller members may compress better (a few zeros): no ratio cap below
TEXTURE_KEYS = ("map_kd", "map_ka", "map_ks", "map_ns", "map_d", "map_bump", "bump", "disp", "decal", "refl")


def _checked_member(
    archive: zipfile.ZipFile, name: str, sh3f_path: Path, cap: int = MAX_MEMBER_BYTES
) -> zipfile.ZipInfo:
    """The archive's entry ``name``, refused when it would inflate beyond ``cap`` or ``MAX_RATIO`` (a zip bomb)."""
    info = archive.getinfo(name)
    if info.file_size > cap:
        raise ModelError(
            f"{sh3f_path}: member {name!r} inflates to {info.file_size / 2**20:.0f} MB, above the cap of "
            f"{cap / 2**20:.0f} MB: refused"
        )
    if info.file_size > RATIO_FROM_BYTES and info.file_size > MAX_RATIO * max(info.compress_size, 1):
        raise ModelError(
            f"{sh3f_path}: member {name!r} is compressed {info.file_size / max(info.compress_size, 1):.0f}:1, "
            f"above the cap of {MAX_RATIO}:1 (a zip bomb?): refused"
        )
    return info


def _read_member(archive: zipfile.ZipFile, name: str, sh3f_path: Path, cap: int = MAX_MEMBER_BYTES) -> bytes:
    """A member's bytes, read no further than its checked size (a header that lies about it is refused)."""
    info = _checked_member(archive, name, sh3f_path, cap)
    try:
        with archive.open(info) as member:
            data = member.read(info.file_size + 1)
    except UNREADABLE as exc:
        raise ModelError(f"{sh3f_path}: member {name!r} cannot be read ({type(exc).__name__}: {exc})") from None
    if len(data) > info.file_size:
        raise ModelError(f"{sh3f_path}: member {name!r} holds more than its header says: refused")
    return data


def _named_files(text: str, keys: tuple[str, ...]) -> list[str]:
    """The file names that ``keys`` lines of an OBJ or MTL text give: the whole rest of the line, and its last word
    (a texture's options come first: ``map_Kd -s 1 1 1 wood.png``)."""
    names = []
    for line in text.splitlines():
        key, _, rest = line.strip().partition(" ")
        if key.lower() in keys and rest.strip():
            names += [rest.strip(), rest.split()[-1]]
            if key.lower() == "mtllib":
                names += rest.split()
    return names


def model_members(archive: zipfile.ZipFile, model: str, sh3f_path: str | Path) -> list[str]:
    """The members a model needs: its OBJ, the MTLs it names, the textures those name, and its folder's licence.

    Parameters
    ----------
    archive : zipfile.ZipFile
        The open ``.sh3f``.
    model : str
        The OBJ's path in the archive.
    sh3f_path : str or Path
        The archive's path, for messages.

    Returns
    -------
    list of str
        Member names, the OBJ first; names the files give that the archive lacks are left out (loading the model
        then notes them in its ``repairs``).

    Raises
    ------
    ModelError
        A member is above the size or compression caps.
    """
    sh3f_path = Path(sh3f_path)
    present = {n for n in archive.namelist() if not n.endswith("/")}
    folder = posixpath.dirname(model)

    def resolve(names: list[str], base: str) -> list[str]:
        found = (posixpath.normpath(posixpath.join(base, n.replace("\\", "/"))) for n in names)
        return [n for n in dict.fromkeys(found) if n in present]

    obj = _read_member(archive, model, sh3f_path).decode("latin-1")
    mtls = resolve(_named_files(obj, ("mtllib",)), folder)
    textures: list[str] = []
    for mtl in mtls:
        text = _read_member(archive, mtl, sh3f_path).decode("latin-1")
        textures += resolve(_named_files(text, TEXTURE_KEYS), posixpath.dirname(mtl))
    licences = sorted(
        n for n in present if posixpath.dirname(n) == folder and re.search("licen[cs]e", posixpath.basename(n), re.I)
    )
    return list(dict.fromkeys([model, *mtls, *textures, *licences]))


def extract_sh3f_model(sh3f_path: str | Path, model: str, out_dir: str | Path) -> Path:
    """Extract what one model needs (:func:`model_members`) from a ``.sh3f``; return the OBJ path.

    Parameters
    ----------
    sh3f_path : str or Path
        The library.
    model : str
        The OBJ's path in it (a catalogue row's ``file``).
    out_dir : str or Path
        The folder the model's folder is written into.

    Returns
    -------
    Path
        The extracted OBJ.

    Raises
    ------
    ModelError
        No such model, a member that would be written outside ``out_dir`` or over the library itself, or one
        above the size or compression caps (nothing of that member is written).
    """
    sh3f_path = Path(sh3f_path)
    root = Path(out_dir).resolve()
    try:
        with zipfile.ZipFile(sh3f_path) as archive:
            if model not in archive.namelist():
                raise ModelError(f"{sh3f_path}: no model {model!r} in the library")
            for member in model_members(archive, model, sh3f_path):  # untrusted names: nothing outside out_dir
                target = (root / member).resolve()
                if not target.is_relative_to(root):
                    raise ModelError(f"{sh3f_path}: member {member!r} would be written outside {out_dir}")
                if target == sh3f_path.resolve():
                    raise ModelError(f"{sh3f_path}: member {member!r} would be written over the library itself")
                data = _read_member(archive, member, sh3f_path)
                with atomic(target) as temporary:
                    temporary.write_bytes(data)
    except UNREADABLE as exc:
        raise ModelError(f"{sh3f_path}: cannot extract {model!r} ({exc})") from None
    return Path(out_dir) / model


def _existing_catalog(path: Path) -> pd.DataFrame | None:
    """The catalogue a former import left in the folder (rows are appended to it), checked before extracting."""
    if not path.exists():
        return None
    try:
        old = pd.read_csv(path, dtype=str, keep_default_na=False)
    except (OSError, ValueError, UnicodeDecodeError) as exc:
        raise ModelError(
            f"{path}: the folder's catalogue cannot be read ({exc}); move it away or import elsewhere"
        ) from None
    if "object" not in old.columns:
        raise ModelError(f"{path}: the folder holds a catalog.csv without an object column; move it away")
    return old


def import_sh3f(
    sh3f_path: str | Path,
    out_dir: str | Path,
    *,
    name_pattern: str | None = None,
    label: str | None = None,
    exclude_pattern: str | None = None,
    classes: str = "name",
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
        Case-insensitive regular expression of furniture names or object ids to leave out
        (e.g. ``"bench"``, ``"^Scopia-336-"``).
    classes : {"name", "category"}
        Without ``label``, each object's class: its furniture name or its catalogue category.

    Returns
    -------
    pandas.DataFrame
        The catalogue rows written for this library.
    """
    out_dir = check_folder(out_dir, inputs=[sh3f_path])
    catalog_path = check_output(out_dir / "catalog.csv", inputs=[sh3f_path], what="the catalogue")
    table = sh3f_catalog(
        sh3f_path, name_pattern=name_pattern, label=label, exclude_pattern=exclude_pattern, classes=classes
    )
    old = _existing_catalog(catalog_path)
    for model in progress(table["file"], desc="extracting", unit="model"):
        extract_sh3f_model(sh3f_path, model, out_dir)
    if old is not None:
        table = pd.concat([old[~old["object"].isin(table["object"])], table.astype(str)])
    with atomic(catalog_path) as temporary:
        table.to_csv(temporary, index=False, quoting=csv.QUOTE_MINIMAL)
    log.info("imported %d models from %s into %s", len(table), sh3f_path, out_dir)
    return table
