"""Catalogues, the Sweet Home 3D importer and the embedded default data."""

import zipfile
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from conftest import make_sh3f

import heatdata as hd
from heatdata.io.catalog import catalog_from_folder, catalog_sizes, color_twins
from heatdata.io.models import hue_rotated
from heatdata.io.sh3f import extract_sh3f_model, parse_properties, sh3f_catalog, sh3f_entries

SH3F_DIR = Path("/usr/share/sweethome3d/furniture")


def test_parse_properties_handles_escapes_and_continuations():
    text = "a=1\nb = two words\n! note\nc=caf\\u00e9\nd=first \\\n   second\n"
    assert parse_properties(text) == {"a": "1", "b": "two words", "c": "café", "d": "first second"}
    # a file in Latin-1 with raw non-ASCII bytes (Sweet Home 3D's "Parking slot 90°"), decoded as Latin-1
    assert parse_properties("name#1=Parking slot 90\xb0 \\u00e9\n".encode("latin-1").decode("latin-1")) == {
        "name#1": "Parking slot 90° é"
    }


def test_sh3f_entries_in_metres(tmp_path):
    entries = sh3f_entries(make_sh3f(tmp_path))
    assert entries["name"].tolist() == ["Coffee mug", "Café chair"]
    assert entries.loc[0, ["width", "height", "depth"]].tolist() == [0.12, 0.10, 0.08]


def test_import_and_load(tmp_path):
    out = tmp_path / "models"
    table = hd.import_sh3f(make_sh3f(tmp_path), out, name_pattern="mug|chair")
    assert len(table) == 2
    catalog = hd.read_catalog(out / "catalog.csv")
    mug = hd.load_catalog_model(catalog.iloc[0])
    assert mug.label == "coffee mug" and np.allclose(mug.extents, [0.12, 0.10, 0.0])
    chair = hd.load_catalog_model(catalog.iloc[1])
    assert catalog.iloc[1]["licence"] == "CC-BY-3.0"
    assert np.allclose(chair.extents, [0.4, 0.0, 0.4])  # the rotation laid the quad in the xz-plane
    again = hd.import_sh3f(make_sh3f(tmp_path), out, name_pattern="mug")  # appends without duplicates
    assert len(hd.read_catalog(out / "catalog.csv")) == 2 and len(again) == 2


def test_an_objects_class_is_its_label_its_name_or_its_category(tmp_path):
    path = make_sh3f(tmp_path)
    entries = sh3f_entries(path)
    assert sh3f_catalog(path)["label"].tolist() == ["coffee mug", "café chair"]
    by_category = sh3f_catalog(path, classes="category")["label"].tolist()
    assert by_category == [c.lower() for c in entries["category"]]
    assert sh3f_catalog(path, classes="category", label="thing")["label"].tolist() == ["thing", "thing"]
    with pytest.raises(hd.ModelError, match="classes 'room': use name or category"):
        sh3f_catalog(path, classes="room")


def test_entries_leading_outside_the_library_are_left_out(tmp_path, caplog):
    """A .sh3f is untrusted: an entry whose model path climbs out is not imported, and nothing is written outside."""
    path = make_sh3f(tmp_path)
    with zipfile.ZipFile(path, "a") as archive:
        props = archive.read("PluginFurnitureCatalog.properties").decode("latin-1")
        archive.writestr("../../escape/quad.obj", (tmp_path / "src" / "quad.obj").read_text())
    escaped = props + "\nname#3=Escaping mug\nmodel#3=../../escape/quad.obj\nwidth#3=1\ndepth#3=1\nheight#3=1\n"
    rebuilt = tmp_path / "Escape.sh3f"
    with zipfile.ZipFile(path) as source, zipfile.ZipFile(rebuilt, "w") as archive:
        for item in source.infolist():
            if item.filename != "PluginFurnitureCatalog.properties":
                archive.writestr(item, source.read(item))
        archive.writestr("PluginFurnitureCatalog.properties", escaped)
    out = tmp_path / "deep" / "out"
    table = hd.import_sh3f(rebuilt, out, name_pattern="mug")
    assert table["name"].tolist() == ["Coffee mug"] and "leads outside the library" in caplog.text
    assert not any(".." in f for f in hd.read_catalog(out / "catalog.csv")["file"])
    assert not (tmp_path / "escape").exists() and not (out / "escape").exists()
    with pytest.raises(hd.ModelError, match="outside"):
        extract_sh3f_model(rebuilt, "../../escape/quad.obj", tmp_path / "x")


def test_import_errors(tmp_path):
    with pytest.raises(hd.ModelError, match="no furniture matches"):
        hd.import_sh3f(make_sh3f(tmp_path), tmp_path / "m", name_pattern="piano")
    bad = tmp_path / "bad.sh3f"
    bad.write_bytes(b"junk")
    with pytest.raises(hd.ModelError, match="not a readable Sweet Home 3D"):
        hd.import_sh3f(bad, tmp_path / "m")


def test_catalog_errors(tmp_path):
    path = tmp_path / "catalog.csv"
    pd.DataFrame({"object": ["a", "a"], "label": ["x", "y"], "file": ["a.obj", "b.obj"]}).to_csv(path, index=False)
    with pytest.raises(hd.ModelError, match="duplicate object"):
        hd.read_catalog(path)
    pd.DataFrame({"object": ["a"], "file": ["a.obj"]}).to_csv(path, index=False)
    with pytest.raises(hd.ModelError, match="lacks column"):
        hd.read_catalog(path)
    with pytest.raises(hd.ModelError, match="no such catalogue"):
        hd.read_catalog(tmp_path / "none.csv")


def test_embedded_data_is_complete(catalog):
    assert len(catalog) >= 12
    assert (catalog["licence"] == "CC0-1.0").all()
    assert {"cup", "mug", "box", "bottle"} <= set(catalog["label"])
    assert (catalog["label"] == "box").sum() >= 2 and (catalog["label"] == "cup").sum() >= 2
    for _, row in catalog.iterrows():
        model = hd.load_catalog_model(row)
        assert np.allclose(model.extents, row[["width", "height", "depth"]].astype(float), rtol=1e-6)
    root = Path(catalog["path"].iloc[0]).parents[1]
    assert (root / "LICENSE-BlendSwap-CC-0.txt").is_file()
    assert sum(f.stat().st_size for f in root.rglob("*") if f.is_file()) < 8e6


@pytest.mark.skipif(
    not (SH3F_DIR / "BlendSwap-CC-0.sh3f").exists(), reason="Debian's sweethome3d-furniture is not installed"
)
def test_real_sweet_home_library(tmp_path):
    table = hd.import_sh3f(SH3F_DIR / "BlendSwap-CC-0.sh3f", tmp_path, name_pattern="^Plastic cup$")
    model = hd.load_catalog_model(hd.read_catalog(tmp_path / "catalog.csv").iloc[0])
    assert table.iloc[0]["licence"] == "CC0-1.0"
    assert np.allclose(model.extents, [0.079, 0.10, 0.079])


def test_catalog_from_folder(tmp_path):
    import trimesh

    for cls, name in (("mugs", "red"), ("mugs", "blue"), ("boxes", "tea")):
        (tmp_path / cls).mkdir(exist_ok=True)
        trimesh.creation.box(extents=(100.0, 80.0, 60.0)).export(tmp_path / cls / f"{name}.stl")
    table = catalog_from_folder(tmp_path, scale=0.001)
    assert sorted(table["object"]) == ["boxes-tea", "mugs-blue", "mugs-red"]
    assert table.set_index("object").loc["mugs-red", "label"] == "mugs"
    model = hd.load_catalog_model(table.iloc[0])
    assert np.allclose(sorted(model.extents), [0.06, 0.08, 0.1])


def test_catalog_sizes_leave_out_objects_in_their_files_units(catalog, tmp_path):
    sizes = catalog_sizes(catalog)
    assert set(sizes) == set(catalog["object"])
    assert np.allclose(sizes["beer-mug"], catalog.set_index("object").loc["beer-mug", ["width", "height", "depth"]])
    unsized = pd.DataFrame({"object": ["a", "b"], "width": ["", 0.1], "height": ["", 0.2], "depth": [None, 0.3]})
    assert catalog_sizes(unsized) == {"b": [0.1, 0.2, 0.3]}
    with pytest.raises(hd.ModelError, match="together"):
        catalog_sizes(pd.DataFrame({"object": ["c"], "width": [0.1], "height": [""], "depth": [""]}))


def test_empty_models_folder(tmp_path):
    with pytest.raises(hd.ModelError, match="no mesh files"):
        catalog_from_folder(tmp_path)
    with pytest.raises(hd.ModelError, match="no such models folder"):
        catalog_from_folder(tmp_path / "absent")


def test_several_libraries_with_names_kept_and_left_out(tmp_path):
    from heatdata.io.sh3f import sh3f_catalog, sh3f_catalogs

    (tmp_path / "one").mkdir()
    (tmp_path / "two").mkdir()
    first, second = make_sh3f(tmp_path / "one"), make_sh3f(tmp_path / "two")
    table = sh3f_catalogs([first, second], name_pattern="mug|chair", exclude_pattern="caf")
    assert table["name"].tolist() == ["Coffee mug", "Coffee mug"]
    assert table["archive"].tolist() == [str(first), str(second)]
    assert sh3f_catalog(first, name_pattern="piano", allow_empty=True).empty
    one = sh3f_catalog(first)
    kept = sh3f_catalog(first, exclude_pattern=f"^{one['object'].iloc[0]}$")  # by object id, not by name
    assert kept["object"].tolist() == one["object"].tolist()[1:]
    with pytest.raises(hd.ModelError, match="no furniture matches 'mug' without 'mug'"):
        sh3f_catalogs([first, second], name_pattern="mug", exclude_pattern="mug")


def test_color_twins_are_the_same_model_turned_in_hue(catalog):
    twins = color_twins(catalog, ["yogurt-bottle", "bread"], 120)
    assert twins["object"].tolist() == ["yogurt-bottle-hue120", "bread-hue120"]
    assert twins["label"].tolist() == ["bottle", "food"] and (twins["hue"] == 120).all()
    original = hd.load_catalog_model(catalog.set_index("object", drop=False).loc["bread"])
    twin = hd.load_catalog_model(twins.iloc[1])
    assert twin.name == "bread-hue120" and np.array_equal(twin.vertices, original.vertices)
    turned = hue_rotated(original, 120)
    assert all(np.array_equal(a, b) for a, b in zip(twin.textures, turned.textures))
    assert not np.allclose(twin.textures[0], original.textures[0])


def test_colour_twin_errors(catalog):
    with pytest.raises(hd.ModelError, match="not in the catalogue"):
        color_twins(catalog, ["no-such-object"], 120)
    with pytest.raises(hd.ModelError, match="whole number of turns"):
        color_twins(catalog, ["bread"], 360)
    with_twin = pd.concat([catalog, color_twins(catalog, ["bread"], 90)])
    with pytest.raises(hd.ModelError, match="already in the catalogue"):
        color_twins(with_twin, ["bread"], 90)


def test_a_folder_of_z_up_millimetre_models_stands_on_y_in_metres(tmp_path, caplog):
    import trimesh

    (tmp_path / "bottles").mkdir()
    # a bottle as YCB and BOP ship it: 60 x 60 mm across, 200 mm tall along z
    trimesh.creation.box(extents=(60.0, 60.0, 200.0)).export(tmp_path / "bottles" / "tall.stl")
    table = catalog_from_folder(tmp_path, units="mm", up_axis="z")
    model = hd.load_catalog_model(table.iloc[0])
    assert np.allclose(model.extents, [0.06, 0.2, 0.06])
    assert "lies on its side" not in caplog.text
    lying = hd.load_catalog_model(catalog_from_folder(tmp_path, units="mm").iloc[0])
    assert np.allclose(lying.extents, [0.06, 0.06, 0.2])
    assert "lies on its side" in caplog.text and "up_axis z" in caplog.text


def test_a_catalogues_rows_keep_their_own_up_axis_and_units_and_take_the_runs_elsewhere(tmp_path):
    from heatdata.io.catalog import with_model_defaults

    table = pd.DataFrame({"object": ["a", "b", "c"], "up_axis": ["", "y", None], "units": ["mm", "", "nan"]})
    filled = with_model_defaults(table, units="cm", up_axis="z")
    assert filled["up_axis"].tolist() == ["z", "y", "z"]
    assert filled["units"].tolist() == ["mm", "cm", "cm"]
    assert with_model_defaults(pd.DataFrame({"object": ["a"]}), "m", "y")[["units", "up_axis"]].values.tolist() == [
        ["m", "y"]
    ]


@pytest.mark.parametrize(("column", "value"), [("up_axis", "x"), ("units", "inch")])
def test_an_unknown_up_axis_or_unit_is_refused_naming_the_object(tmp_path, column, value):
    import trimesh

    trimesh.creation.box(extents=(1.0, 1.0, 1.0)).export(tmp_path / "cube.stl")
    row = catalog_from_folder(tmp_path).iloc[0].to_dict() | {column: value}
    with pytest.raises(hd.ModelError, match=f"cube: {column} must be one of .*'{value}'"):
        hd.load_catalog_model(row)
