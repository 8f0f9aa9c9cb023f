"""The Snakemake workflow: a tiny DAG end to end, config checks, failures, lint, reruns."""

import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import trimesh
import yaml

from heatdata.descriptors import DescriptorSpec, file_name
from heatdata.io.tables import DESCRIPTOR_SCHEMA, PREDICTION_SCHEMA, TRIAL_SCHEMA, VIEW_SCHEMA, read_table

pytestmark = pytest.mark.workflow  # every test here runs snakemake

ROOT = Path(__file__).resolve().parents[2]
SNAKEFILE = ROOT / "Snakefile"
SNAKEMAKE = Path(sys.executable).parent / "snakemake"


def tiny_config(**overrides):
    config = {
        "catalog": str(ROOT / "data/models/catalog.csv"),
        "objects": ["plastic-cup", "beer-mug"],
        "views": {"train": 8, "test": 6},
        "library_sizes": [8, 4],
        "descriptors": [
            {"kind": "pvhk", "samples": 32, "source": "center", "sampling": "polar"},
            {"kind": "pvhk", "samples": 32, "source": "closest", "sampling": "arclength"},
            {"kind": "ft-pvhk", "samples": 32, "source": "center", "sampling": "polar"},
            {"kind": "pvst", "samples": 32, "source": "center", "sampling": "polar"},
            {"kind": "esf", "triplets": 2000},
            {"kind": "si-hks", "words": 8, "modes": 30},
            {"kind": "esf"},
            {"kind": "hgd"},
            {"kind": "hgd", "color": "hue-saturation"},
            {
                "kind": "combined",
                "parts": [{"kind": "hgd"}, {"kind": "pvhk", "samples": 32, "source": "center", "sampling": "polar"}],
            },
        ],
        "primary_descriptor": "pvhk/polar/center/32",
    }
    config.update(overrides)
    return config


def run_snakemake(directory: Path, *args: str) -> subprocess.CompletedProcess:
    """The repository's workflow run in ``directory`` on 2 cores, its output captured as text."""
    return subprocess.run(
        [str(SNAKEMAKE), "-s", str(SNAKEFILE), "--directory", str(directory), "--cores", "2", *args],
        capture_output=True,
        text=True,
        timeout=900,
    )


def snakemake(workdir: Path, config: dict, *args: str) -> subprocess.CompletedProcess:
    """:func:`run_snakemake` in ``workdir`` with ``config`` as its config file."""
    (workdir / "config").mkdir(parents=True, exist_ok=True)
    (workdir / "config" / "config.yaml").write_text(yaml.safe_dump(config))
    return run_snakemake(workdir, *args)


def run_script(script: str, *args, **options) -> subprocess.CompletedProcess:
    """``scripts/<script>`` run by the suite's Python, its output captured as text (within 300 s unless told)."""
    return subprocess.run(
        [sys.executable, ROOT / "scripts" / script, *args],
        capture_output=True,
        text=True,
        **{"timeout": 300, **options},
    )


COMPACT = {"enabled": True, "library_candidates": 12, "test_candidates": 8, "alphas": [0.25, 1.0]}
COMPARISON = {
    "enabled": True,
    "isomap_objects": ["plastic-cup", "beer-mug"],
    "boxes": [[0.1, 0.15, 0.08]],
    "azimuths": 3,
}
MULTIVIEW = {
    "enabled": True,
    "library_views": [8, 4],
    "particles": [5, 20],
    "repetitions": 2,
    "starts": 1,
    "step": 45,
    "max_degrees": 360,
}
SCENES = {
    "enabled": True,
    "count": 2,
    "objects": [1, 2],
    "descriptors": ["pvhk/polar/center/32", "hgd/color=hue-saturation"],
    "offaxis": 2,
}
EXPERIMENTS = {
    "compact": COMPACT,
    "comparison": COMPARISON,
    "multiview": MULTIVIEW,
    "scenes": SCENES,
    "ablation": str(ROOT / "config" / "experiments" / "chairs_ablation.csv"),
}


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory):
    workdir = tmp_path_factory.mktemp("workflow")
    result = snakemake(workdir, tiny_config(**EXPERIMENTS))
    assert result.returncode == 0, result.stderr[-3000:]
    return workdir


@pytest.mark.slow
def test_dag_writes_tables_with_their_schemas(tiny_run):
    results = tiny_run / "results"
    views, meta = read_table(results / "views" / "beer-mug.parquet")
    assert list(views.columns) == VIEW_SCHEMA.names and len(views) == 14
    assert meta["views"]["train"] == 8 and meta["heatdata_version"]
    descriptors, _ = read_table(results / "descriptors.parquet")
    assert list(descriptors.columns) == DESCRIPTOR_SCHEMA.names
    # per object: 14 views x 9 single descriptors, and an FT-PVHK per library view (its own object's
    # time scale) and per test view x object (every object's)
    assert len(descriptors) == 2 * (14 * 9 + 8 + 6 * 2)
    lengths = descriptors.groupby("kind")["values"].agg(lambda v: sorted(set(map(len, v))))
    assert lengths.to_dict() == {
        "esf": [640],
        "ft-pvhk": [32],
        "pvhk": [32],
        "pvst": [32],
        "si-hks": [8],
        "hgd": [128, 153],
        "combined": [1 + 3 * 2 + 128 + 32],
    }
    histograms = descriptors[descriptors["kind"].isin(["esf", "si-hks", "hgd"])]
    assert histograms[["sampling", "source_rule", "color_map"]].isna().all().all()
    assert np.allclose(histograms["values"].map(sum), 1.0)
    assert (results / "fitted" / "si-hks_words=8_modes=30.npz").is_file()
    for log in (
        "logs/classify/pvhk_polar_center_32.log",
        "benchmarks/classify/esf_triplets=2000.tsv",
        "logs/classify/pvst_polar_center_32_T0.75.log",
    ):
        assert (results / log).is_file(), log  # named by descriptor, not by index
    pvhk = descriptors[descriptors["kind"] == "pvhk"]
    assert np.allclose(pvhk["time"] * pvhk["lambda2"], 1.0) and np.allclose(pvhk["time"], pvhk["t_global"])
    scales = pd.concat([pd.read_csv(p) for p in (results / "time_scales").glob("*.csv")]).set_index("object")
    ft = descriptors[descriptors["kind"] == "ft-pvhk"]
    library = ft[ft["split"] == "train"]
    assert (library["time_object"] == library["object"]).all()
    assert np.allclose(library["time"], scales.loc[library["object"], "time_scale"])
    # Alg. 5.1: the time scale is the smallest 1/lambda_2 of the object's library views
    assert np.allclose(library.groupby("object")["t_global"].min(), scales["time_scale"].sort_index())
    assert ft.groupby("view_id")["time_object"].nunique().max() == 2 and ft["weights"].map(len).eq(32).all()
    assert descriptors.loc[descriptors["kind"] != "ft-pvhk", "weights"].isna().all()
    predictions, _ = read_table(results / "evaluation" / "predictions.parquet")
    assert list(predictions.columns) == PREDICTION_SCHEMA.names
    assert sorted(predictions["library_size"].unique()) == [4, 8]
    assert len(predictions) == 10 * 2 * 12  # descriptors x library sizes x test views
    precision = pd.read_csv(results / "evaluation" / "precision.csv")
    overall = precision[(precision["group"] == "all") & (precision["level"] == "object")]
    assert len(overall) == 20 and overall["precision"].between(0, 1).all()
    assert overall["precision"].max() > 0.8
    for figure in (
        "precision.png",
        "isomap.png",
        "views.png",
        "global_derivative.png",
        "view_angles.png",
        "curves.png",
        "misclassified.png",
        "confusion/pvhk_polar_center_32/objects_4_views.png",
        "confusion/pvhk_polar_center_32/classes_8_views.png",
        "confusion/pvst_polar_center_32_T0.75/objects_8_views.png",
        "confusion/ft-pvhk_polar_center_32/objects_4_views.png",
        "confusion/esf_triplets=2000/classes_8_views.png",
        "isomap_descriptors.png",
        "holes.png",
    ):
        assert (results / "figures" / figure).stat().st_size > 10_000
    summary = (results / "summary.md").read_text()
    assert "not real sensor data" in summary and "('" not in summary and "{'" not in summary  # no Python reprs
    assert "| object      | pvhk/polar/center/32 " in summary and "accuracy" not in summary.lower()
    inline = (results / "figures" / "summary.html").read_text()
    assert "<table" in inline and "pvhk/polar/center/32" in inline and "Run parameters" in inline
    assert "<table" in (results / "figures" / "precision.html").read_text()
    assert (results / "benchmarks" / "describe" / "beer-mug.tsv").is_file()
    assert (results / "logs" / "render" / "plastic-cup.log").read_text().count("views rendered") >= 1
    holes = pd.read_csv(results / "comparison" / "holes.csv")
    assert len(holes) == 10 * 3 and set(holes["box"]) == {"10x15x8 cm"} and (holes["d_hole"] > 0).all()


def test_compact_libraries_and_their_precision(tiny_run):
    results = tiny_run / "results"
    candidates, meta = read_table(results / "compact" / "candidates" / "beer-mug.parquet")
    assert meta["compact"]["library_candidates"] == 12
    counts = candidates.groupby(["split", "source_rule"]).size()
    assert counts["train", "candidates"] == 8 * 12 and counts["test", "candidates"] == 6 * 8
    assert counts["train", "center"] == 8 and candidates["values"].map(len).eq(64).all()
    libraries, _ = read_table(results / "compact" / "libraries.parquet")
    per = libraries.groupby(["descriptor", "library_size", "object"]).size()
    assert set(per.index.get_level_values(0)) == {"initial center", "compact alpha=0.25", "compact alpha=1"}
    assert per.xs(4, level="library_size").eq(4).all() and per.xs(8, level="library_size").eq(8).all()
    predictions, _ = read_table(results / "compact" / "predictions.parquet")
    assert list(predictions.columns) == PREDICTION_SCHEMA.names and len(predictions) == 3 * 2 * 12
    precision = pd.read_csv(results / "compact" / "precision.csv")
    assert precision["precision"].between(0, 1).all()
    assert (results / "figures" / "compact_precision.png").stat().st_size > 10_000


def test_multiview_trials_and_their_figure(tiny_run):
    results = tiny_run / "results"
    trials, meta = read_table(results / "multiview" / "trials.parquet")
    assert list(trials.columns) == TRIAL_SCHEMA.names and meta["multiview"]["repetitions"] == 2
    # 2 library sizes x 2 objects x 1 start x (2 particle counts x (2 bootstraps fixed + active) x 2 repetitions
    # + one exhaustive run)
    assert len(trials) == 2 * 2 * (2 * 3 * 2 + 1) and set(trials["policy"]) == {"fixed", "active"}
    assert (trials.loc[trials["bootstrap"] == "exhaustive", "particles"] == 2 * 360).all()
    assert (trials["degrees"] <= 360 + 90).all() and trials["descriptor"].eq("pvhk/polar/center/32").all()
    similarity, _ = read_table(results / "multiview" / "similarity.parquet")
    assert len(similarity) == 16**2 + 8**2
    summary = pd.read_csv(results / "multiview" / "summary.csv")
    assert summary["accuracy"].between(0, 1).all() and (results / "figures" / "multiview.png").stat().st_size > 10_000
    assert "<table" in (results / "figures" / "multiview.html").read_text()


@pytest.mark.slow
def test_the_protocol_and_time_scale_scripts_read_a_run_s_table(tiny_run, tmp_path):
    """scripts/protocols.py and scripts/ft_time_scales.py (issue 17) on the tiny run's descriptor table."""
    table = tiny_run / "results/descriptors.parquet"
    out = tmp_path / "protocols.csv"
    result = run_script(
        "protocols.py",
        table,
        "--descriptor",
        "pvhk/polar/center/32",
        "ft-pvhk/polar/center/32",
        "--sizes",
        "6",
        "3",
        "--out",
        out,
    )
    assert result.returncode == 0, result.stderr[-2000:]
    protocols = pd.read_csv(out).set_index(["descriptor", "protocol", "library_size"])
    assert len(protocols) == 8 and protocols["test_views"].eq(12).all()
    # the thesis's protocol with every test view in the library: each finds itself
    assert protocols.loc[("pvhk/polar/center/32", "thesis", 6), "precision"] == 1.0
    assert protocols.loc[("ft-pvhk/polar/center/32", "thesis", 6), "precision"] == 1.0
    out = tmp_path / "time_scales.csv"
    result = run_script("ft_time_scales.py", table, "ft-pvhk/polar/center/32", "--sizes", "8", "4", "--out", out)
    assert result.returncode == 0, result.stderr[-2000:]
    scales = pd.read_csv(out)
    assert len(scales) == 16 and set(scales["rule"]) == {"nearest", "normalized", "plausible", "known"}
    assert scales["test_views"].eq(12).all() and scales["precision"].between(0, 1).all()
    # the workflow's own predictions are the "nearest" rule, weighted
    precision = pd.read_csv(tiny_run / "results/evaluation/precision.csv")
    workflow = precision[
        (precision["level"] == "object")
        & (precision["group"] == "all")
        & (precision["descriptor"] == "ft-pvhk/polar/center/32")
    ].set_index("library_size")
    nearest = scales[(scales["rule"] == "nearest") & (scales["weights"] == "weighted")].set_index("library_size")
    assert np.allclose(nearest.loc[[8, 4], "precision"], workflow.loc[[8, 4], "precision"], atol=1e-4)


@pytest.mark.slow
def test_the_value_scale_script_reads_a_run_s_table(tiny_run, tmp_path):
    """scripts/value_scales.py (issue 17): x1 is the workflow's MHD; a log scale for the PVST's times."""
    table, out = tiny_run / "results/descriptors.parquet", tmp_path / "scales.csv"
    result = run_script(
        "value_scales.py",
        table,
        "--descriptor",
        "pvhk/polar/center/32",
        "pvst/polar/center/32/T0.75",
        "--transform",
        "x1",
        "x0.1",
        "log10x0.3",
        "--sizes",
        "8",
        "4",
        "--leave-one-out",
        "--out",
        out,
    )
    assert result.returncode == 0, result.stderr[-2000:]
    scales = pd.read_csv(out)
    assert len(scales) == 18 and scales["precision"].between(0, 1).all()
    assert (scales["library_size"] == 0).sum() == 6  # leave-one-out among the library views, per transform
    precision = pd.read_csv(tiny_run / "results/evaluation/precision.csv")
    workflow = precision[
        (precision["level"] == "object")
        & (precision["group"] == "all")
        & (precision["descriptor"] == "pvhk/polar/center/32")
    ].set_index("library_size")
    thesis = scales[(scales["descriptor"] == "pvhk/polar/center/32") & (scales["transform"] == "x1")]
    assert np.allclose(
        thesis.set_index("library_size").loc[[8, 4], "precision"], workflow.loc[[8, 4], "precision"], atol=1e-4
    )
    result = run_script("value_scales.py", table, "--descriptor", "pvhk/polar/center/32", "--transform", "sqrt")
    assert result.returncode != 0 and "unknown transform 'sqrt'" in result.stderr


@pytest.mark.slow
def test_the_complex_ablation_script_reads_a_run_s_views(tiny_run, tmp_path):
    """scripts/complex_ablation.py (issue 28): its PVHK and ESF rows are the workflow's precision on the same views."""
    out = tmp_path / "steps.csv"
    result = run_script(
        "complex_ablation.py",
        tiny_run / "results",
        "--test-every",
        "1",
        "--sizes",
        "8",
        "4",
        "--samples",
        "32",
        "--triplets",
        "2000",
        "--jobs",
        "1",
        "--out",
        out,
        timeout=600,
    )
    assert result.returncode == 0, result.stderr[-2000:]
    steps = pd.read_csv(out)
    assert set(steps["step"]) == {"view", "boundary", "signature", "distance"} and steps["views"].eq(28).all()
    measured = steps.dropna(subset=["precision"])
    assert len(measured) == 2 * 16 and measured["precision"].between(0, 100).all()
    precision = pd.read_csv(tiny_run / "results/evaluation/precision.csv")
    workflow = precision[(precision["level"] == "object") & (precision["group"] == "all")]
    for variant, descriptor in (
        ("PVHK at t_s = 1/lambda_2 (the workflow's)", "pvhk/polar/center/32"),
        ("largest component, as rendered (ESF)", "esf/triplets=2000"),
    ):
        mine = measured[measured["variant"] == variant].set_index("library_size")["precision"]
        theirs = 100 * workflow[workflow["descriptor"] == descriptor].set_index("library_size")["precision"]
        assert np.allclose(mine.loc[[8, 4]], theirs.loc[[8, 4]], atol=0.051), (variant, mine, theirs)
    figure = tmp_path / "steps.png"
    drawn = run_script("complex_ablation.py", "--plot", out, out, "--figure", figure)
    assert drawn.returncode == 0 and figure.stat().st_size > 10_000, drawn.stderr[-2000:]
    empty = run_script("complex_ablation.py", tmp_path, "--out", out)
    assert empty.returncode != 0 and "no views in" in empty.stderr


@pytest.mark.slow
def test_the_combination_script_scores_kinds_alone_as_the_workflow_does(tiny_run, tmp_path):
    """scripts/combine_kinds.py (issue 28): each kind alone is the workflow's precision; weights from the library."""
    table, out = tiny_run / "results/descriptors.parquet", tmp_path / "combined.csv"
    names = ["pvhk/polar/center/32", "esf/triplets=2000"]
    result = run_script("combine_kinds.py", table, "--descriptor", *names, "--sizes", "8", "4", "--out", out)
    assert result.returncode == 0, result.stderr[-2000:]
    combined = pd.read_csv(out)
    assert set(combined["method"]) == {*names, "sum", "learned", "rank"} and combined["test_views"].eq(12).all()
    learned = combined[combined["method"] == "learned"]
    assert learned["weights"].map(lambda w: sum(map(float, w.split()))).sub(1).abs().lt(1e-9).all()
    assert learned["leave_one_out"].between(0, 1).all()
    precision = pd.read_csv(tiny_run / "results/evaluation/precision.csv")
    workflow = precision[(precision["level"] == "object") & (precision["group"] == "all")]
    for name in names:
        mine = combined[combined["method"] == name].set_index("library_size")["precision"]
        theirs = workflow[workflow["descriptor"] == name].set_index("library_size")["precision"]
        assert np.allclose(mine.loc[[8, 4]], theirs.loc[[8, 4]])
    refused = run_script("combine_kinds.py", table, "--descriptor", names[0], "ft-pvhk/polar/center/32", "--out", out)
    assert refused.returncode != 0 and "time-scaled" in refused.stderr


def test_kinds_combined_are_fitted_on_the_library_views_and_classified_like_any_kind(tiny_run):
    name = "combined/hgd+pvhk/polar/center/32"
    fitted = np.load(tiny_run / "results/fitted" / f"{file_name(name)}.npz")
    assert fitted["weights"].sum() == pytest.approx(1.0) and np.all(fitted["scales"] > 0)
    precision = pd.read_csv(tiny_run / "results/evaluation/precision.csv")
    assert set(precision.loc[precision["descriptor"] == name, "library_size"]) == {8, 4}


def test_colour_share_splits_the_hgd_colour_option_into_its_parts(tiny_run, tmp_path):
    """scripts/color_share.py (issue 28): the HGD and ESF alone are the workflow's precision."""
    out = tmp_path / "share.csv"
    result = run_script("color_share.py", tiny_run / "results/descriptors.parquet", "--sizes", "8", "4", "--out", out)
    assert result.returncode == 0, result.stderr[-2000:]
    share = pd.read_csv(out).set_index(["variant", "library_size"])["precision"]
    assert set(share.index.get_level_values(0)) == {"colour alone", "ESF", "HGD", "ESF + colour", "HGD + colour"}
    precision = pd.read_csv(tiny_run / "results/evaluation/precision.csv")
    workflow = precision[(precision["level"] == "object") & (precision["group"] == "all")]
    for variant, name in (("ESF", "esf"), ("HGD", "hgd"), ("HGD + colour", "hgd/color=hue-saturation")):
        theirs = workflow[workflow["descriptor"] == name].set_index("library_size")["precision"]
        assert np.allclose([share[variant, 8], share[variant, 4]], 100 * theirs.loc[[8, 4]], atol=0.05)


@pytest.mark.slow
def test_rerun_with_nothing_changed_runs_no_job(tiny_run):
    result = snakemake(tiny_run, tiny_config(**EXPERIMENTS), "--dry-run")
    assert result.returncode == 0
    assert "Nothing to be done" in result.stdout + result.stderr


@pytest.mark.slow
def test_report_is_self_contained_html(tiny_run):
    result = snakemake(tiny_run, tiny_config(**EXPERIMENTS), "--report", "results/report.html")
    assert result.returncode == 0, result.stderr[-2000:]
    html = (tiny_run / "results" / "report.html").read_text(errors="replace")
    assert len(html) > 100_000 and "rendered" in html
    # confusion matrices grouped by descriptor, labelled by matrix and library size, with their own captions
    assert '"matrix": "classes", "library views": "8"' in html and "Confusion matrix of classes for" in html
    assert "Misclassified test views of the primary descriptor" in html and "{{ snakemake" not in html
    assert "The measured ablation named by config key" in html  # the Ablation category, from config key ablation
    # it opens on a summary: every descriptor's object precision, then links to each section and chapter's page
    assert "Object precision (%) by library views per object" in html and "heatdata-front" in html
    assert "app.showCategory('Precision')" in html
    assert "../docs/chapters/recognition.md" in html
    page = (tiny_run / "results" / "figures" / "ablation.html").read_text()
    assert "<td style='text-align:left'>protocol: the thesis&#x27;s library views" in page


@pytest.mark.parametrize(
    "overrides, message",
    [
        ({"colour": 1}, "colour"),
        ({"objects": ["unicorn"]}, "unicorn"),
        ({"time_scale_rule": "label"}, "time_scale_rule: 'label' is not one of ['plausible', 'every']"),
        ({"views": {"train": 8, "test": 6, "elevation": 95}}, "95"),
        ({"views": {"train": 8, "test": 6, "distance": float("nan")}}, "views.distance: nan is not a finite number"),
        ({"objects": ["plastic-cup"], "views": {"train": 2, "test": 6}}, "1 object(s) x 2 view(s) give 2"),
        ({"compact": {"enabled": True, "alphas": [1.5]}}, "1.5"),
        ({"multiview": {"enabled": True, "policies": ["greedy"]}}, "greedy"),
        (
            {"stitch": {"pairs": [{"object": "x", "first": "/no/top.ply", "second": "/no/bottom.ply"}]}},
            "stitch.pairs[0]: /no/top.ply, /no/bottom.ply do(es) not exist",
        ),
        ({"stitch": {"pairs": [{"object": "x", "first": "a.ply"}]}}, "'second' is a required property"),
        ({"captures": {"dir": "/no/captures"}}, "captures.dir: /no/captures: no such folder of captures"),
        # snakemake data/models/catalog.csv with results: data/models rewrote the input catalogue, exit status 0
        ({"results": str(ROOT / "data/models")}, "config error: results: "),
        (
            {"stitch": {"pairs": [{"object": "x", "first": "a.ply", "second": "b.ply", "motion": [[1, 0, 0]]}]}},
            "motion",
        ),
    ],
)
@pytest.mark.slow
def test_bad_config_is_rejected_before_any_job(tmp_path, overrides, message):
    """The schema's errors and a few of heatdata.experiments.config's, through snakemake (the rest of the checks:
    tests/experiments/test_config.py, without snakemake)."""
    result = snakemake(tmp_path, tiny_config(**overrides), "--dry-run")
    assert result.returncode != 0
    assert message in result.stdout + result.stderr
    assert not (tmp_path / "results").exists()


@pytest.mark.slow
def test_config_from_the_command_line_is_read_by_the_schema_and_errors_are_one_line(tmp_path):
    """Snakemake hands nested --config values over as strings: '4' failed 'is not of type integer'. A misspelled
    key printed the whole schema (over 500 lines)."""
    result = snakemake(tmp_path, tiny_config(), "--dry-run", "--config", 'views={"train": 8, "test": 3}')
    assert result.returncode == 0, (result.stdout + result.stderr)[-2000:]
    result = snakemake(tmp_path, tiny_config(), "--dry-run", "--config", "colour=1")
    text = result.stdout + result.stderr
    assert result.returncode != 0 and "config error: the config: Additional properties are not allowed" in text
    assert len(text.splitlines()) < 30
    result = snakemake(tmp_path, tiny_config(), "--dry-run", "--config", 'views={"train": "many"}')
    assert "config error: views.train: 'many' is not of type 'integer'" in result.stdout + result.stderr
    # a descriptor's options are the kind's, not the schema's: '16' was refused as not a whole number
    result = snakemake(
        tmp_path,
        tiny_config(),
        "--dry-run",
        "--config",
        'descriptors=[{"kind": "pvhk", "samples": 16, "source": "center", "sampling": "polar"}]',
        "primary_descriptor=pvhk/polar/center/16",
    )
    assert result.returncode == 0, (result.stdout + result.stderr)[-2000:]


def make_models_dir(root: Path, classes: dict) -> Path:
    for cls, names in classes.items():
        (root / cls).mkdir(parents=True, exist_ok=True)
        for i, name in enumerate(names):
            box = trimesh.creation.box(extents=(0.1 + 0.03 * i, 0.12, 0.08))
            box.export(root / cls / f"{name}.ply")
    return root


@pytest.mark.slow
def test_models_dir_checks(tmp_path):
    empty = tmp_path / "empty"
    empty.mkdir()
    result = snakemake(tmp_path / "run1", tiny_config(objects=[], models_dir=str(empty)), "--dry-run")
    assert result.returncode != 0 and "no mesh files" in result.stdout + result.stderr


@pytest.mark.slow
def test_one_object_per_class_recognizes_objects_and_says_so(tmp_path):
    models = make_models_dir(tmp_path / "models", {"boxes": ["a"], "crates": ["c"], "bins": ["e"]})
    config = tiny_config(objects=[], models_dir=str(models), views={"train": 4, "test": 3}, library_sizes=[4])
    config["descriptors"] = config["descriptors"][:1]
    result = snakemake(tmp_path / "run", config)
    assert result.returncode == 0, result.stderr[-3000:]
    results = tmp_path / "run" / "results"
    summary = (results / "summary.md").read_text()
    assert "Each of the 3 classes holds one object" in summary and "class precision equals object precision" in summary
    precision = pd.read_csv(results / "evaluation" / "precision.csv").query("group == 'all'")
    assert precision.groupby("level")["precision"].first().nunique() == 1  # class precision = object precision


@pytest.mark.slow
def test_a_corrupt_model_fails_its_jobs_and_keep_going_finishes_the_rest(tmp_path):
    models = make_models_dir(tmp_path / "models", {"boxes": ["a", "b"], "crates": ["c", "d"]})
    (models / "crates" / "d.ply").write_bytes(b"ply\ngarbage")
    # PVHKs only: with an FT-PVHK every describe job waits for every object's time scale (Alg. 5.2)
    config = tiny_config(objects=[], models_dir=str(models))
    config["descriptors"] = config["descriptors"][:2]
    objects = ("boxes-a", "boxes-b", "crates-c", "crates-d")
    result = snakemake(tmp_path / "run", config, "--keep-going", *(f"results/descriptors/{o}.parquet" for o in objects))
    assert result.returncode != 0
    log = (tmp_path / "run" / "results" / "logs" / "render" / "crates-d.log").read_text()
    assert "crates/d.ply" in log and "cannot read the model file" in log
    for obj in ("boxes-a", "boxes-b", "crates-c"):
        assert (tmp_path / "run" / "results" / "descriptors" / f"{obj}.parquet").is_file()


@pytest.mark.slow
def test_the_root_snakefile_plans_the_whole_run_with_the_default_profile(tmp_path):
    """`snakemake` from the repository root runs the workflow, as the layout promises (not "Nothing to be done")."""
    result = snakemake(tmp_path, tiny_config(), "--dry-run")
    text = result.stdout + result.stderr
    assert result.returncode == 0, text[-2000:]
    assert "Using workflow specific profile profiles/default" in text and "Nothing to be done" not in text
    assert "render" in text and "report_figures" in text


@pytest.mark.slow
def test_lint_has_only_the_conda_warning(tmp_path):
    result = snakemake(tmp_path, tiny_config(), "--lint")
    text = result.stdout + result.stderr
    items = [line.strip() for line in text.splitlines() if line.startswith("    * ")]
    assert items, text[-2000:]
    # the one lint left: there is no conda here, the rules run in the pinned .venv of scripts/setup.sh
    assert all(item.startswith("* Specify a conda environment or container") for item in items), items


@pytest.mark.slow
@pytest.mark.parametrize("profile", ["default", "slurm"])
def test_every_profile_key_is_an_option_of_this_snakemake(profile):
    """A profile key snakemake does not know fails every run that uses the profile: each must be an option."""
    settings = yaml.safe_load((ROOT / "profiles" / profile / "config.yaml").read_text())
    options = subprocess.run([str(SNAKEMAKE), "--help"], capture_output=True, text=True, check=True).stdout
    unknown = [key for key in settings if not re.search(rf"--{re.escape(key)}\b", options)]
    assert not unknown, f"profiles/{profile}: snakemake has no option {unknown}"
    if profile == "slurm":
        assert settings["executor"] == "slurm" and settings["slurm-status-command"] == "squeue"
        # account and partition are the user's (--default-resources slurm_account=... slurm_partition=...)
        assert "slurm-no-account" not in settings and "slurm_partition" not in settings["default-resources"]


SH3F = Path("/usr/share/sweethome3d/furniture/BlendSwap-CC-0.sh3f")


@pytest.mark.slow
def test_a_catalogue_row_the_schema_refuses_is_one_line_naming_it(tmp_path):
    """workflow/schemas/catalog.schema.yaml checks every row of the run's catalogue before any job."""
    shutil.copytree(ROOT / "data" / "models", tmp_path / "models")
    catalog = (tmp_path / "models" / "catalog.csv").read_text().splitlines()
    catalog[1] = catalog[1].replace(
        "plastic-cup,cup,plastic-cup/plasticCup.obj,0.079", "plastic-cup,cup,plastic-cup/plasticCup.obj,-0.079"
    )
    (tmp_path / "models" / "catalog.csv").write_text("\n".join(catalog) + "\n")
    result = snakemake(tmp_path, tiny_config(catalog=str(tmp_path / "models" / "catalog.csv")), "--dry-run")
    assert result.returncode != 0
    assert "config error: catalogue row plastic-cup: width: -0.079 is not valid" in result.stdout + result.stderr


@pytest.mark.slow
def test_missing_sweet_home_library_is_a_config_error(tmp_path):
    config = tiny_config(objects=[], sh3f={"files": [str(tmp_path / "none.sh3f")]})
    result = snakemake(tmp_path, config, "--dry-run")
    assert result.returncode != 0 and "apt-get install sweethome3d-furniture" in result.stdout + result.stderr


@pytest.mark.slow
@pytest.mark.skipif(not SH3F.exists(), reason="Debian's sweethome3d-furniture is not installed")
def test_objects_from_a_sweet_home_library(tmp_path):
    config = tiny_config(
        objects=[],
        sh3f={"files": [str(SH3F)], "names": "^(Plastic cup|Coffee cup)$"},
        views={"train": 4, "test": 2},
        library_sizes=[4],
    )
    config["descriptors"] = config["descriptors"][:1]  # the import is under test, not the kinds
    result = snakemake(tmp_path, config, "results/catalog.csv", "results/evaluation/predictions.parquet")
    assert result.returncode == 0, result.stderr[-3000:]
    catalog = pd.read_csv(tmp_path / "results" / "catalog.csv")
    assert sorted(catalog["label"]) == ["coffee cup", "plastic cup"]
    assert set(catalog["licence"]) == {"CC0-1.0"}
    assert (tmp_path / "results" / "models" / catalog["object"][0]).is_dir()


def schema_keys(node: dict, prefix: str = "") -> list[str]:
    keys = []
    for key, value in node.get("properties", {}).items():
        keys.append(prefix + key)
        keys += schema_keys(value, prefix + key + ".")
    return keys


def test_config_readme_describes_every_key_and_file():
    schema = yaml.safe_load((ROOT / "workflow" / "schemas" / "config.schema.yaml").read_text())
    readme = (ROOT / "config" / "README.md").read_text()
    keys = schema_keys(schema)
    assert len(keys) > 30
    assert [k for k in keys if f"| `{k}` |" not in readme] == []
    assert [p.name for p in (ROOT / "config").rglob("*.yaml") if f"`{p.name}`" not in readme] == []
    assert sorted(p.name for p in (ROOT / "config").glob("*.yaml")) == ["config.yaml", "small.yaml"]  # the layer
    # that cuts any run small beside the default; the experiments in experiments/


@pytest.mark.slow
def test_the_twins_config_plans_22_objects(tmp_path):
    result = run_snakemake(
        ROOT, "--configfile", "config/experiments/twins.yaml", "--config", f"results={tmp_path}/twins", "--dry-run"
    )
    assert result.returncode == 0, (result.stdout + result.stderr)[-2000:]
    assert re.search(r"render +22\b", result.stdout) and re.search(r"classify +12\b", result.stdout)
    assert f"{tmp_path}/twins/views/bread-hue120.parquet" in result.stdout


@pytest.mark.slow
def test_smoke_config_plans_a_small_run(tmp_path):
    result = run_snakemake(
        ROOT, "--configfile", "config/experiments/smoke.yaml", "--config", f"results={tmp_path}/smoke", "--dry-run"
    )
    assert result.returncode == 0, (result.stdout + result.stderr)[-2000:]
    assert f"{tmp_path}/smoke/summary.md" in result.stdout
    assert re.search(r"describe +3\b", result.stdout) and re.search(r"classify +2\b", result.stdout)


@pytest.mark.slow
def test_captured_depth_images_are_recognized_against_the_library(tmp_path):
    """Rule capture_views (thesis 2.1): a folder of depth PNGs, one subfolder per object, as test views."""
    import json

    from PIL import Image

    import heatdata as hd

    catalog = hd.read_catalog(ROOT / "data/models/catalog.csv").set_index("object", drop=False)
    captures = tmp_path / "captures"
    for obj in ("plastic-cup", "beer-mug"):
        (captures / obj).mkdir(parents=True)
        model = hd.load_catalog_model(catalog.loc[obj])
        for k, azimuth in enumerate((50.0, 140.0, 230.0)):
            view = hd.render_view(model, azimuth, 30.0, 1.0, seed=100 + k)
            hd.write_depth(view, captures / obj / f"shot{k}.png", captures / "camera.json")  # one camera for all
            rgb = np.zeros((480, 640, 3), np.uint8)
            pixels = np.round(view.pixels).astype(int)
            rgb[pixels[:, 1], pixels[:, 0]] = np.round(view.colors * 255)
            Image.fromarray(rgb).save(captures / obj / f"shot{k}.rgb.png")
    config = tiny_config(
        views={"train": 8, "test": 2}, library_sizes=[8, 4], captures={"dir": str(captures), "depth_range": [0.5, 1.5]}
    )
    config["descriptors"] = config["descriptors"][:3]
    result = snakemake(tmp_path / "run", config, "results/figures/captures.html")
    assert result.returncode == 0, result.stderr[-3000:]
    results = tmp_path / "run" / "results"
    views, _ = read_table(results / "captures" / "views" / "plastic-cup.parquet")
    assert len(views) == 3 and set(views["split"]) == {"test"} and views["colors"].map(len).min() > 0
    assert json.loads(views["intrinsics"].iloc[0])["fx"] == 580.0
    precision = pd.read_csv(results / "captures" / "precision.csv")
    assert set(precision["descriptor"]) == {
        "pvhk/polar/center/32",
        "pvhk/arclength/closest/32",
        "ft-pvhk/polar/center/32",
    }
    overall = precision[(precision["group"] == "all") & (precision["level"] == "object")]
    assert len(overall) == 6 and overall["precision"].between(0, 1).all()
    page = (results / "figures" / "captures.html").read_text()
    assert "6 captures of 2 objects" in page and "plastic-cup/capture/shot0" in page
    backwards = snakemake(
        tmp_path / "run3", {**config, "captures": {"dir": str(captures), "depth_range": [1.5, 0.5]}}, "--dry-run"
    )
    assert backwards.returncode != 0 and "near < far" in backwards.stdout + backwards.stderr
    (captures / "unicorn").mkdir()
    (captures / "unicorn" / "x.npy").write_bytes(b"")
    stray = snakemake(tmp_path / "run2", config, "--dry-run")
    assert stray.returncode != 0
    assert "folder(s) ['unicorn'] are not among the run's objects" in stray.stdout + stray.stderr


@pytest.mark.slow
def test_the_rump_proxy_orders_bodies_and_says_they_are_not_goats(tmp_path):
    """Rule rump (thesis ch. 8): HBRD of a small MakeHuman population, its Isomap and classifier, in the report."""
    config = tiny_config(rump={"enabled": True, "bodies": 8, "image_scale": 0.5, "n_neighbors": 3})
    result = snakemake(tmp_path, config, "results/figures/rump.html")
    assert result.returncode == 0, result.stderr[-3000:]
    table = pd.read_csv(tmp_path / "results" / "rump" / "descriptors.csv")
    assert len(table) == 8 and list(table["weight"]) == sorted(table["weight"]) and table["z0"].notna().all()
    assert {"muscle", "isomap1", "z31"} <= set(table.columns)
    page = (tmp_path / "results" / "figures" / "rump.html").read_text()
    assert "a proxy, not goats" in page and "leave-one-out accuracy" in page
    assert (tmp_path / "results" / "figures" / "rump.png").stat().st_size > 20_000
    small = snakemake(tmp_path / "small", tiny_config(rump={"enabled": True, "bodies": 4}), "--dry-run")
    assert small.returncode != 0 and "4 is less than the minimum of 8" in small.stdout + small.stderr


@pytest.mark.slow
def test_people_s_poses_and_colour_twins_reach_the_report(tmp_path):
    """Rule people (thesis 3.5): one body's poses in the Isomap and two people of one shape told apart by colour."""
    shape = {"kind": "pvhk", "samples": 64, "source": "center", "sampling": "polar"}
    colour = {**shape, "kind": "c-pvhk", "color_map": "c2"}  # the rule's default descriptors
    people = {"enabled": True, "frames": 8, "image_scale": 0.25, "n_neighbors": 3, "descriptors": [shape, colour]}
    result = snakemake(tmp_path, tiny_config(people=people), "results/figures/people.html")
    assert result.returncode == 0, result.stderr[-3000:]
    results = tmp_path / "results"
    frames = pd.read_csv(results / "people" / "frames.csv")
    assert len(frames) == 16 and set(frames["person"]) == {"person A", "person B"}
    assert frames["isomap1"].notna().sum() == 8  # the first person's sequence
    twins = pd.read_csv(results / "people" / "twins.csv")
    assert len(twins) == 2 * 8 and set(twins["pair"]) == {"MakeHuman"}
    assert twins[twins["descriptor"] == DescriptorSpec(**colour).name]["correct"].all()
    page = (results / "figures" / "people.html").read_text()
    assert "Twins (Fig. 3.12)" in page and "not real sensor data" in page
    assert (results / "figures" / "people_twins.png").stat().st_size > 20_000
    assert (results / "figures" / "people_poses.png").stat().st_size > 20_000
    bad = tiny_config(people={"enabled": True, "descriptors": [{"kind": "pvhk"}, {"kind": "ft-pvhk"}]})
    refused = snakemake(tmp_path / "bad", bad, "--dry-run")
    assert refused.returncode != 0 and "people.descriptors[1]: an ft-pvhk needs time scales" in (
        refused.stdout + refused.stderr
    )
    missing = snakemake(
        tmp_path / "missing", tiny_config(people={"enabled": True, "reallusion": "no.sh3f"}), "--dry-run"
    )
    assert missing.returncode != 0 and "people.reallusion: no.sh3f does not exist" in missing.stdout + missing.stderr


@pytest.mark.slow
def test_colour_twins_join_the_run_and_only_colour_tells_them_apart(tmp_path):
    """Key color_twins (thesis 3.4): a twin, the same mesh in turned colours, is rendered and described like any
    object."""
    shape = {"kind": "pvhk", "samples": 32, "source": "center", "sampling": "polar"}
    colour = {**shape, "kind": "c-pvhk", "color_map": "sat-hue", "clock": "shape"}
    config = tiny_config(
        objects=["yogurt-bottle", "beer-mug"],
        color_twins={"objects": ["yogurt-bottle"]},
        descriptors=[shape, colour],
        library_sizes=[8],
    )
    result = snakemake(tmp_path, config, "results/catalog.csv", "results/evaluation/predictions.parquet")
    assert result.returncode == 0, result.stderr[-3000:]
    results = tmp_path / "results"
    twin_row = pd.read_csv(results / "catalog.csv").set_index("object").loc["yogurt-bottle-hue120"]
    assert twin_row["hue"] == 120 and twin_row["label"] == "bottle"
    original, twin = (
        read_table(results / "views" / f"{o}.parquet")[0] for o in ("yogurt-bottle", "yogurt-bottle-hue120")
    )
    assert np.array_equal(original["azimuth"], twin["azimuth"])  # the same views (their noise is their own)
    mean_colour = [np.concatenate(t["colors"].tolist()).reshape(-1, 3).mean(axis=0) for t in (original, twin)]
    assert np.abs(mean_colour[0] - mean_colour[1]).max() > 0.05
    # 120 degrees turn red to green: the twin's (R, G, B) is the original's (B, R, G)
    assert np.allclose(mean_colour[1], np.roll(mean_colour[0], 1), atol=0.01)
    predictions, _ = read_table(results / "evaluation" / "predictions.parquet")
    pair = predictions[predictions["object"].str.startswith("yogurt")]
    precision = pair.groupby("descriptor")["correct"].mean()
    assert precision[DescriptorSpec(**colour).name] > precision[DescriptorSpec(**shape).name]
    out, picture = tmp_path / "twins.csv", tmp_path / "twins.png"
    run_script("color_twins.py", str(results), "--out", str(out), "--figure", str(picture), check=True, cwd=ROOT)
    table = pd.read_csv(out).set_index("descriptor")
    assert table.loc[list(precision.index), "pairs"].round(4).tolist() == precision.round(4).tolist()
    assert picture.stat().st_size > 10_000


@pytest.mark.slow
def test_a_stitched_pair_joins_the_run_as_an_object(tmp_path):
    """Rule stitch (thesis ch. 7): two halves of a model, one moved, are stitched and rendered like any object."""
    from scipy.spatial.transform import Rotation

    from heatdata.io.catalog import load_catalog_model, read_catalog
    from heatdata.io.models import save_model, transformed
    from heatdata.jasnom.cuts import closed_part, split_model

    catalog = read_catalog(ROOT / "data/models/catalog.csv").set_index("object", drop=False)
    mug = closed_part(load_catalog_model(catalog.loc["beer-mug"]))
    top, bottom = split_model(mug, [0.2, 1.0, 0.1])
    save_model(top, tmp_path / "top.ply")
    rotation, translation = Rotation.from_rotvec([0.4, 1.2, -0.3]), np.array([0.2, 0.0, 0.1])
    save_model(transformed(bottom, rotation.as_matrix(), translation), tmp_path / "bottom.ply")
    pair = {
        "object": "stitched-mug",
        "label": "mug",
        "first": str(tmp_path / "top.ply"),
        "second": str(tmp_path / "bottom.ply"),
    }
    back = np.eye(4)  # registered cameras: the motion is given
    back[:3, :3], back[:3, 3] = rotation.inv().as_matrix(), -rotation.inv().apply(translation)
    registered = {**pair, "object": "registered-mug", "motion": back.tolist()}
    config = tiny_config(
        objects=["plastic-cup"],
        views={"train": 4, "test": 3},
        library_sizes=[4],
        stitch={"pairs": [pair, registered], "samples": 32},
    )
    config["descriptors"] = config["descriptors"][:1]
    made = ["results/catalog.csv", "results/views/stitched-mug.parquet", "results/figures/stitch/stitched-mug.png"]
    result = snakemake(tmp_path / "run", config, *made, "results/stitched/registered-mug.json")
    assert result.returncode == 0, result.stderr[-3000:]
    results = tmp_path / "run" / "results"
    mesh = trimesh.load(results / "stitched" / "stitched-mug.ply", process=False)
    assert mesh.is_watertight and mesh.is_winding_consistent
    summary = yaml.safe_load((results / "stitched" / "stitched-mug.json").read_text())
    assert summary["loop_pairs"] >= 1 and summary["open_loops"] == 0
    assert (results / "figures" / "stitch" / "stitched-mug.png").stat().st_size > 10_000
    views, _ = read_table(results / "views" / "stitched-mug.parquet")
    assert len(views) == 7 and set(views["label"]) == {"mug"}
    assert {"stitched-mug", "registered-mug"} <= set(pd.read_csv(results / "catalog.csv")["object"])
    given = yaml.safe_load((results / "stitched" / "registered-mug.json").read_text())
    np.testing.assert_allclose(given["rotation"], back[:3, :3], atol=1e-9)
    assert trimesh.load(results / "stitched" / "registered-mug.ply", process=False).is_watertight
    duplicate = snakemake(
        tmp_path / "run2", {**config, "stitch": {"pairs": [{**pair, "object": "plastic-cup"}]}}, "--dry-run"
    )
    assert duplicate.returncode != 0 and "already one of the run's objects" in duplicate.stdout + duplicate.stderr


# -- scenes --------------------------------------------------------------------------------------------------


@pytest.mark.slow
def test_scenes_are_rendered_recognized_scored_and_drawn(tiny_run, capsys):
    import json

    from PIL import Image

    from heatdata.cli import main
    from heatdata.io.tables import DETECTION_SCHEMA

    results = tiny_run / "results"
    frames = results / "scenes" / "frames"
    for scene in ("scene-000", "scene-001"):
        for part in (".png", ".rgb.png", ".json", ".labels.png", ".truth.json"):
            assert (frames / f"{scene}{part}").is_file(), (scene, part)
        truth = json.loads((frames / f"{scene}.truth.json").read_text())
        assert 1 <= len(truth["objects"]) <= 2 and {o["object"] for o in truth["objects"]} <= {
            "plastic-cup",
            "beer-mug",
        }
        assert np.asarray(Image.open(results / "scenes" / "overlays" / f"{scene}.png")).shape == (480, 640, 3)
    detections, meta = read_table(results / "scenes" / "detections" / "hgd_color=hue-saturation.parquet")
    assert list(detections.columns) == DETECTION_SCHEMA.names and meta["library"].endswith("-8.parquet")
    assert set(detections["scene"]) == {"scene-000", "scene-001"} and (detections["seconds"] > 0).all()
    summary = pd.read_csv(results / "scenes" / "summary.csv")
    assert summary["descriptor"].tolist() == SCENES["descriptors"]
    assert {"recall", "false_segments", "naming", "naming_occluded", "median_seconds"} <= set(summary.columns)
    assert {"posed", "pose_add_s", "pose_translation", "pose_rotation", "pose_seconds"} <= set(summary.columns)
    posed = detections[detections["add_s"].notna()]  # posed as their true object: scored against the truth
    assert len(posed) and posed["add_s_ok"].all() and (posed["translation_error"] < 0.02).all()
    assert (detections["seconds_without_pose"] > 0).all()
    offaxis = pd.read_csv(results / "scenes" / "offaxis.csv")
    assert len(offaxis) == len(tiny_config()["descriptors"]) and (offaxis["views"] == 2 * 2).all()
    assert offaxis[["same_reseeded", "same_off_axis"]].stack().between(0, 1).all()
    moved, _ = read_table(results / "scenes" / "offaxis" / "views" / "beer-mug.parquet")
    kinds = moved["view_id"].str.split("/").str[1]
    assert sorted(kinds) == ["offaxis", "offaxis", "reseeded", "reseeded"]
    off = moved[kinds == "offaxis"]
    assert all(any("off the image centre" in r for r in repairs) for repairs in off["repairs"])
    page = (results / "figures" / "scenes.html").read_text()
    assert page.count("<img") == 3 and "Objects anywhere in the frame" in page  # two overlays, the known/unknown curve
    assert "Known or unknown" in page and "pose_add_s" in page
    library = results / "libraries" / "hgd_color=hue-saturation-8.parquet"
    assert main(["recognize", str(frames / "scene-000.png"), "--intrinsics", str(frames / "scene-000.json"),
                 "--rgb", str(frames / "scene-000.rgb.png"), "--library", str(library), "--json"]) == 0  # fmt: skip
    answer = json.loads(capsys.readouterr().out)
    assert answer["plane"] is not None and len(answer["objects"]) >= 1
    assert all(o["pose"] is None or len(o["pose"]["matrix"]) == 4 for o in answer["objects"])


@pytest.mark.slow
def test_the_summary_leads_with_the_scenes_and_its_recognize_command_runs(tiny_run, capsys, monkeypatch):
    import shlex

    import heatdata as hd
    from heatdata.cli import main
    from heatdata.recognition.library import uses_colour

    summary = (tiny_run / "results" / "summary.md").read_text()
    assert summary.index("## Scenes") < summary.index("## Recognize with") < summary.index("## Run")
    command = shlex.split(summary.split("## Recognize with", 1)[1].split("`")[1])
    library = hd.load_library(tiny_run / command[command.index("--library") + 1])
    assert command[:2] == ["heatdata", "recognize"] and ("--rgb" in command) == uses_colour(library.spec)
    assert "--rgb" not in command or command[command.index("--rgb") + 1].endswith(".rgb.png")
    monkeypatch.chdir(tiny_run)  # the summary's paths are the run's, from where snakemake ran
    assert main([*command[1:], "--json"]) == 0
    assert capsys.readouterr().out.lstrip().startswith("{")


# -- libraries and `heatdata recognize` (issue 33) -----------------------------------------------------------


def tiny_test_views(run: Path) -> list:
    from heatdata.views.frames import frame_to_views

    frames = [read_table(path)[0] for path in sorted((run / "results/views").glob("*.parquet"))]
    return [v for frame in frames for v in frame_to_views(frame[frame["split"] == "test"])]


@pytest.mark.slow
def test_a_library_recognizes_every_test_view_as_classify_does(tiny_run):
    import heatdata as hd

    libraries = sorted((tiny_run / "results/libraries").glob("*.parquet"))
    assert len(libraries) == len(tiny_config(**EXPERIMENTS)["descriptors"]) * 2
    summary = (tiny_run / "results/summary.md").read_text()
    assert all(str(path.relative_to(tiny_run)) in summary for path in libraries)
    predictions, _ = read_table(tiny_run / "results/evaluation/predictions.parquet")
    views = tiny_test_views(tiny_run)
    checked = 0
    for path in libraries:
        if not path.name.endswith("-8.parquet") and not path.name.startswith("pvhk_polar_center"):
            continue  # every descriptor at the larger size, the PVHK at both
        library = hd.load_library(path)
        expected = predictions[
            (predictions["descriptor"] == library.descriptor) & (predictions["library_size"] == library.library_size)
        ].set_index("view_id")
        for view in views:
            answer = library.recognize(view, k=2)
            assert answer.best.object == expected.loc[view.view_id, "predicted_object"], (path.name, view.view_id)
            assert answer.best.view_id == expected.loc[view.view_id, "predicted_view_id"], (path.name, view.view_id)
            # the library's distances are float32 (mhd_matrix), the evaluation's exact search float64: a distance
            # between values near 1 keeps five digits (2e-6 to 1.1e-5 apart in this run)
            assert answer.best.distance == pytest.approx(expected.loc[view.view_id, "distance"], rel=1e-4)
            assert [m.distance for m in answer.matches] == sorted(m.distance for m in answer.matches)
            checked += 1
    assert checked >= 11 * len(views)


@pytest.mark.slow
def test_heatdata_recognize_names_the_object_of_a_depth_png_and_follows_a_circle(tiny_run, tmp_path, capsys):
    import json

    import heatdata as hd
    from heatdata.cli import main

    library = tiny_run / "results/libraries/pvhk_polar_center_32-8.parquet"
    models = {
        r["object"]: hd.load_catalog_model(r)
        for r in hd.read_catalog(ROOT / "data/models/catalog.csv").to_dict("records")
    }
    view = hd.render_view(models["beer-mug"], azimuth=100.0, elevation=30.0, seed=5)
    hd.write_depth(view, tmp_path / "frame.png")
    command = ["recognize", str(tmp_path / "frame.png"), "--intrinsics", str(tmp_path / "frame.json")]
    assert main([*command, "--library", str(library), "--json"]) == 0
    answer = json.loads(capsys.readouterr().out)
    (found,) = answer["objects"]  # a frame of one isolated object: no support plane, one object
    assert answer["plane"] is None and found["object"] == "beer-mug" and found["matches"][0]["object"] == "beer-mug"
    assert {"distance", "azimuth", "label", "view_id"} <= set(found["matches"][0])
    assert found["pixels"] == pytest.approx(view.n_vertices, rel=0.02)
    assert library.with_suffix(".faiss").exists()  # the library rule writes its index beside it
    library.with_suffix(".faiss").unlink()
    assert main(["index", str(library)]) == 0 and library.with_suffix(".faiss").exists()
    capsys.readouterr()
    assert main([*command, "--library", str(library), "--json", "--exact"]) == 0  # every library view compared
    assert json.loads(capsys.readouterr().out)["objects"][0]["matches"] == found["matches"]
    assert main([*command, "--library", str(library)]) == 0
    table = capsys.readouterr().out
    assert "1 object;" in table and " beer-mug " in table and "no support plane" in table

    circle = tmp_path / "circle"
    circle.mkdir()
    for k, azimuth in enumerate(range(20, 380, 60)):  # six frames around the mug, 60 degrees apart
        frame = hd.render_view(models["beer-mug"], azimuth=float(azimuth), elevation=30.0, seed=10 + k)
        hd.write_depth(frame, circle / f"frame{k}.png")
    for exact in ([], ["--exact"]):
        assert main(["recognize", str(circle), "--moves", "60", "--library", str(library), *exact]) == 0
        out = capsys.readouterr().out
        assert "converged on beer-mug" in out, out
        assert out.count("frame ") == 6


@pytest.mark.slow
def test_recognize_refuses_bad_frames_and_libraries_in_one_line(tiny_run, tmp_path, caplog, capsys):
    import numpy as np

    import heatdata as hd
    from heatdata.cli import main
    from heatdata.io.tables import write_table

    library = tiny_run / "results/libraries/pvhk_polar_center_32-8.parquet"
    view = tiny_test_views(tiny_run)[0]
    hd.write_depth(view, tmp_path / "frame.png")
    intrinsics = ["--intrinsics", str(tmp_path / "frame.json")]
    empty = np.zeros((view.intrinsics["height"], view.intrinsics["width"]), np.uint8)
    from PIL import Image

    Image.fromarray(empty).save(tmp_path / "empty.mask.png")
    frame_rows, metadata = read_table(library)
    write_table(
        frame_rows,
        tmp_path / "other.parquet",
        DESCRIPTOR_SCHEMA,
        {"library": {**metadata["library"], "probe": [0.0] * len(metadata["library"]["probe"])}},
    )
    write_table(frame_rows, tmp_path / "table.parquet", DESCRIPTOR_SCHEMA, {})
    cases = [
        (["--library", str(library), "--mask", str(tmp_path / "empty.mask.png"), *intrinsics], "no valid pixel"),
        (["--library", str(library), "--depth-range", "3", "4", *intrinsics], "no valid pixel"),
        (["--library", str(tmp_path / "other.parquet"), *intrinsics], "describes views differently"),
        (["--library", str(tmp_path / "table.parquet"), *intrinsics], "not a library file"),
        (["--library", str(tmp_path / "missing.parquet"), *intrinsics], "missing.parquet"),
        (["--library", str(library)], "needs --intrinsics"),
    ]
    for extra, message in cases:
        caplog.clear()
        assert main(["recognize", str(tmp_path / "frame.png"), *extra]) == 1, extra
        errors = [r.getMessage() for r in caplog.records if r.levelname == "ERROR"]
        assert len(errors) == 1 and "\n" not in errors[0] and message in errors[0], (extra, errors)
    caplog.clear()
    assert (
        main(
            [
                "recognize",
                str(tmp_path / "frame.png"),
                str(tmp_path / "frame.png"),
                *intrinsics,
                "--library",
                str(library),
            ]
        )
        == 1
    )
    assert "give --moves" in caplog.records[-1].getMessage()
    capsys.readouterr()
