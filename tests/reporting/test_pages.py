"""The report's pages: the landing summary and the measured ablation table."""

import numpy as np
import pandas as pd
import pytest
from conftest import ROOT

import heatdata as hd
from heatdata.io.tables import ABLATION_COLUMNS, read_ablation
from heatdata.reporting.pages import ablation_page, best_library, front_page, precision_by_size, recognize_command


def documented_ablation_rows() -> list[list[str]]:
    """The rows of the ablation table on the complex objects' page, cell by cell."""
    lines = (ROOT / "docs/chapters/complex.md").read_text().split("## The ablation: why", 1)[1].splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("| "))
    table = []
    for line in lines[start:]:
        if not line.startswith("|"):
            break
        table.append([cell.strip() for cell in line.strip().strip("|").split(" | ")])
    return table[2:]  # past the header and its rule


def test_the_docs_and_the_report_show_the_same_ablation():
    committed = read_ablation(ROOT / "config" / "experiments" / "chairs_ablation.csv")
    assert committed.values.tolist() == documented_ablation_rows()
    assert len(committed) >= 10


def test_the_ablation_page_keeps_code_and_bold_and_escapes_the_rest():
    table = pd.DataFrame(
        [["a <b> factor", "**+3** points", "x", "`snakemake --configfile a.yaml`"]], columns=list(ABLATION_COLUMNS)
    )
    page = ablation_page(table, "docs/results/x.csv")
    assert "a &lt;b&gt; factor" in page and "<b>+3</b> points" in page
    assert "<code>snakemake --configfile a.yaml</code>" in page and "docs/results/x.csv" in page
    assert "not real sensor data" in page


def test_a_bad_ablation_table_is_an_error_naming_the_file(tmp_path):
    with pytest.raises(hd.HeatdataError, match=r"no\.csv: not a readable ablation table"):
        read_ablation(tmp_path / "no.csv")
    (tmp_path / "short.csv").write_text("factor,effect\na,b\n")
    with pytest.raises(hd.HeatdataError, match=r"short\.csv: .* missing \['measured', 'command'\]"):
        read_ablation(tmp_path / "short.csv")
    (tmp_path / "empty.csv").write_text("factor,measured,effect,command\n")
    with pytest.raises(hd.HeatdataError, match="no rows"):
        read_ablation(tmp_path / "empty.csv")


def test_the_landing_summary_shows_object_precision_primary_first_and_the_scenes():
    precision = pd.DataFrame(
        [
            {"descriptor": name, "library_size": size, "level": level, "group": group, "precision": value}
            for name, value in (("pvhk", 0.5), ("hgd<b>", 0.875))
            for size in (5, 40)
            for level in ("object", "class")
            for group in ("all", "cup")
        ]
    )
    table = precision_by_size(precision, ["pvhk", "hgd<b>"])
    page = front_page(table, "hgd<b>", {"scene-000": b"png bytes"})
    assert page.startswith("<div class='heatdata-front'>") and page.rstrip().endswith("</div>")
    assert "<b>hgd&lt;b&gt;</b>" in page and "<b>" not in page.replace("<b>hgd&lt;b&gt;</b>", "")  # escaped, bold
    assert page.index("hgd&lt;b&gt;") < page.index("pvhk") and "<td>class</td>" not in page  # object rows only
    assert page.count("<tr>") == 2 and "87.5" in page and "5 views" in page and "40 views" in page
    assert "title='scene-000' src='data:image/png;base64,cG5nIGJ5dGVz'" in page and "not real sensor data" in page
    assert "<img" not in front_page(table, "pvhk")  # no scenes, no overlays


CONFIG = {
    "results": "results",
    "library_sizes": [40, 8],
    "primary_descriptor": "hgd/color=hue-saturation",
    "descriptors": [{"kind": "hgd", "color": "hue-saturation"}, {"kind": "esf"}],
}


def test_the_best_library_is_the_scenes_best_else_the_best_precision_ties_to_the_primary():
    table = pd.DataFrame(
        {"precision": ["object", "object"], "descriptor": ["hgd/color=hue-saturation", "esf"],
         "8 views": ["90.0", "95.0"], "40 views": ["99.0", "99.0"]}
    )  # fmt: skip
    assert best_library(table, CONFIG) == "hgd/color=hue-saturation"  # a tie at 40 views: the primary
    assert best_library(table, {**CONFIG, "library_sizes": [8]}) == "esf"
    scenes = pd.DataFrame(
        {"descriptor": ["hgd/color=hue-saturation", "esf"], "recall": [1.0, 1.0], "named_sure": [0.5, 0.75]}
    )
    assert best_library(table, CONFIG, scenes) == "esf"


def test_the_recognize_command_names_the_frame_files_and_gives_colour_to_a_colour_library():
    frame = "results/scenes/frames/scene-000.png"
    assert recognize_command("hgd/color=hue-saturation", CONFIG, frame) == (
        "heatdata recognize results/scenes/frames/scene-000.png --intrinsics results/scenes/frames/scene-000.json "
        "--rgb results/scenes/frames/scene-000.rgb.png --library results/libraries/hgd_color=hue-saturation-40.parquet"
    )
    assert recognize_command("esf", CONFIG) == (
        "heatdata recognize depth.png --intrinsics camera.json --library results/libraries/esf-40.parquet"
    )


def test_scenes_where_nothing_is_named_leave_the_choice_to_precision():
    table = pd.DataFrame(
        {"precision": ["object", "object"], "descriptor": ["hgd/color=hue-saturation", "esf"],
         "8 views": ["90.0", "95.0"], "40 views": ["90.0", "99.0"]}
    )  # fmt: skip
    nothing = pd.DataFrame(
        {"descriptor": ["hgd/color=hue-saturation", "esf"], "recall": [0.0, 0.0], "named_sure": [np.nan, np.nan]}
    )
    assert best_library(table, CONFIG, nothing) == "esf"
