"""The report's pages: the measured ablation table."""

import pandas as pd
import pytest
from conftest import ROOT

import heatdata as hd
from heatdata.io.tables import ABLATION_COLUMNS, read_ablation
from heatdata.reporting.pages import ablation_page


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
