"""Every published table and figure is made by a docs_* target (issue 32): the manifest names each file's target and
config, every target dry-runs with its config, and the steps the targets run do what they say."""

import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pandas as pd
import pytest
import yaml
from conftest import ROOT

from heatdata.errors import HeatdataError
from heatdata.experiments import docs_targets, publish

SNAKEMAKE = Path(sys.executable).parent / "snakemake"
TARGETS = docs_targets.targets([], "results")
MANIFEST = publish.read_manifest(ROOT / publish.MANIFEST)
SWEET_HOME = Path("/usr/share/sweethome3d/furniture")


def published_files() -> set[str]:
    return {
        p.relative_to(ROOT).as_posix()
        for folder, pattern in (("docs/results", "*.csv"), ("docs/images", "*.png"))
        for p in (ROOT / folder).glob(pattern)
        if p.name != "MANIFEST.csv"
    }


def test_every_published_file_is_in_the_manifest_with_the_target_that_writes_it():
    assert set(MANIFEST["file"]) == published_files()
    assert not MANIFEST["file"].duplicated().any()
    for row in MANIFEST.itertuples():
        assert row.target in TARGETS, f"{row.file}: the workflow has no target {row.target}"
        target = TARGETS[row.target]
        assert row.file in target.outputs, f"{row.file}: {row.target} does not write it"
        assert row.config == (" ".join(target.configs) or "none"), row.file
        assert row.commit, row.file
    assert {f for t in TARGETS.values() for f in t.outputs} == set(MANIFEST["file"])


def test_every_config_a_target_names_exists():
    for name, target in TARGETS.items():
        for config in target.configs:
            assert (ROOT / config).is_file(), f"{name}: {config}"


def foreign_inputs(target: docs_targets.Target) -> list[str]:
    """Inputs from another run than the target's own (a comparison of two runs reads both)."""
    if target.results in (None, "results"):
        return []
    return [path for path in target.inputs if not path.startswith(target.results + "/")]


def dry_run(names: str | list[str], workdir: Path, configs: list[str] | None = None) -> subprocess.CompletedProcess:
    """``snakemake --dry-run`` of targets in ``workdir`` with the config files of the first (or ``configs``)."""
    names = [names] if isinstance(names, str) else names
    configs = [str(ROOT / c) for c in (TARGETS[names[0]].configs if configs is None else configs)]
    return subprocess.run(
        [str(SNAKEMAKE), "-s", str(ROOT / "Snakefile"), "--directory", str(workdir), "--cores", "2", "--dry-run"]
        + names
        + (["--configfile", *configs] if configs else []),
        capture_output=True,
        text=True,
        timeout=600,
        env=dict(os.environ, PYTHONPATH=str(ROOT)),
    )


@pytest.fixture(scope="module")
def mirror(tmp_path_factory) -> Path:
    """A working folder that sees the repository's configs, data and docs, with the other runs' inputs in place."""
    workdir = tmp_path_factory.mktemp("docs_targets")
    for name in ("config", "data", "docs", "scripts", "examples"):
        (workdir / name).symlink_to(ROOT / name)
    for target in TARGETS.values():
        for path in foreign_inputs(target):
            (workdir / path).parent.mkdir(parents=True, exist_ok=True)
            (workdir / path).touch()
    return workdir


@pytest.mark.slow
@pytest.mark.workflow
def test_every_docs_target_dry_runs_with_its_configs(mirror):
    needs_sweet_home = {n for n, t in TARGETS.items() if any("chairs" in c or "people" in c for c in t.configs)}
    names = [n for n in TARGETS if SWEET_HOME.is_dir() or n not in needs_sweet_home]
    same_configs: dict[tuple, list[str]] = {}  # one dry run for the targets of the same config files
    for name in names:
        same_configs.setdefault(tuple(TARGETS[name].configs), []).append(name)
    with ThreadPoolExecutor(2) as pool:
        groups = list(same_configs.values())
        done = pool.map(lambda group: dry_run(group, mirror), groups)
        runs = {name: run for group, run in zip(groups, done, strict=True) for name in group}
    for name, run in runs.items():
        assert run.returncode == 0, f"{name}: {run.stdout[-1500:]}{run.stderr[-1500:]}"
        assert f"rule {name}:" in run.stdout, name
        written = run.stdout.split(f"rule {name}:", 1)[1].split("output:", 1)[1].splitlines()[0]
        assert {f.strip() for f in written.split(",")} == set(TARGETS[name].outputs), name
    if not SWEET_HOME.is_dir():
        pytest.skip(f"sweethome3d-furniture is not installed: {len(needs_sweet_home)} targets were not dry-run")


@pytest.mark.workflow
def test_a_target_run_with_another_config_names_the_configs_it_needs(mirror):
    run = dry_run("docs_chairs", mirror, ["config/config.yaml"])
    assert run.returncode != 0
    assert (
        "docs_chairs publishes the run in results/chairs; give its config files: --configfile "
        in run.stdout + run.stderr
    )


def test_the_steps_cut_label_and_concatenate_tables(tmp_path):
    precision = tmp_path / "precision.csv"
    pd.DataFrame(
        {
            "level": ["object", "object", "class"],
            "group": ["all", "cup", "all"],
            "descriptor": ["compact alpha=1", "compact alpha=1", "compact alpha=1"],
            "library_size": [5, 5, 5],
            "precision": [0.5, 0.25, 0.75],
        }
    ).to_csv(precision, index=False)
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    pd.DataFrame({"x": [1]}).to_csv(a, index=False)
    pd.DataFrame({"x": [2]}).to_csv(b, index=False)
    script = tmp_path / "make.py"
    script.write_text("import sys; open(sys.argv[1], 'w').write('made')\n")
    out = tmp_path / "docs"
    outputs = [str(out / n) for n in ("precision.csv", "compact.csv", "labelled.csv", "concat.csv", "copy.csv", "made")]
    steps = [
        {"precision": [str(precision), outputs[0]]},
        {"compact": [str(precision), "pvst/polar/interior/64/T0.75", outputs[1]]},
        {"labelled": ["run", {"first": str(a), "second": str(b)}, outputs[2]]},
        {"concat": [[str(a), str(b)], outputs[3]]},
        {"copy": [str(a), outputs[4]]},
        {"script": [str(script), outputs[5]]},
    ]
    manifest = tmp_path / "MANIFEST.csv"
    publish.publish(steps, outputs, "docs_test", ["config/a.yaml"], str(tmp_path / "log"), str(manifest))
    assert pd.read_csv(outputs[0]).to_dict("records") == [
        {"descriptor": "compact alpha=1", "library_size": 5, "precision": 0.5}
    ]
    assert pd.read_csv(outputs[1]).to_dict("records") == [
        {
            "descriptor": "pvst/polar/interior/64/T0.75",
            "library": "compact alpha=1",
            "library_size": 5,
            "precision": 0.5,
        }
    ]
    assert pd.read_csv(outputs[2]).to_dict("records") == [{"run": "first", "x": 1}, {"run": "second", "x": 2}]
    assert pd.read_csv(outputs[3])["x"].tolist() == [1, 2]
    assert Path(outputs[5]).read_text() == "made"
    recorded = publish.read_manifest(manifest)
    assert recorded["file"].tolist() == sorted(outputs)
    assert set(recorded["target"]) == {"docs_test"} and set(recorded["config"]) == {"config/a.yaml"}
    assert recorded["wall_seconds"].str.fullmatch(r"\d+").all() and recorded["machine"].str.contains("cores").all()


def test_the_manifest_keeps_other_rows_and_replaces_a_files_row(tmp_path):
    manifest = tmp_path / "MANIFEST.csv"
    publish.record(manifest, ["docs/a.csv", "docs/b.csv"], "docs_one", [], 3.0)
    publish.record(manifest, ["docs/b.csv"], "docs_two", ["config/x.yaml"], 5.0)
    table = publish.read_manifest(manifest)
    assert table[["file", "target", "config", "wall_seconds"]].values.tolist() == [
        ["docs/a.csv", "docs_one", "none", "3"],
        ["docs/b.csv", "docs_two", "config/x.yaml", "5"],
    ]


def test_a_step_that_fails_or_writes_nothing_is_an_error(tmp_path):
    failing = tmp_path / "fail.py"
    failing.write_text("raise SystemExit(3)\n")
    log = str(tmp_path / "log")
    with pytest.raises(HeatdataError, match="fail.py failed \\(exit 3\\)"):
        publish.publish([{"script": [str(failing)]}], [], "docs_x", [], log, str(tmp_path / "M.csv"))
    with pytest.raises(HeatdataError, match="did not write"):
        publish.publish([], [str(tmp_path / "never.csv")], "docs_x", [], log, str(tmp_path / "M.csv"))
    with pytest.raises(HeatdataError, match="unknown step"):
        publish.publish([{"paint": []}], [], "docs_x", [], log, str(tmp_path / "M.csv"))
    assert not (tmp_path / "M.csv").exists()


def test_the_reproduce_page_lists_every_target():
    page = (ROOT / "docs/guide/reproduce.md").read_text()
    assert all(f"| `{name}` |" in page for name in TARGETS), [n for n in TARGETS if f"| `{n}` |" not in page]


def test_the_commit_is_marked_changed_by_edits_but_not_by_the_published_files(tmp_path):
    def git(*args):
        subprocess.run(["git", *args], cwd=tmp_path, check=True, capture_output=True)

    git("init", "-q")
    (tmp_path / "docs/results").mkdir(parents=True)
    (tmp_path / "docs/results/a.csv").write_text("x\n")
    (tmp_path / "code.py").write_text("pass\n")
    git("add", "-A")
    git("-c", "user.name=t", "-c", "user.email=t@t", "commit", "-q", "-m", "one")
    clean = publish.commit(tmp_path, exclude=publish.PUBLISHED)
    assert clean and "+" not in clean
    (tmp_path / "docs/results/a.csv").write_text("y\n")
    assert publish.commit(tmp_path, exclude=publish.PUBLISHED) == clean
    assert publish.commit(tmp_path) == clean + "+changes"
    (tmp_path / "code.py").write_text("print()\n")
    assert publish.commit(tmp_path, exclude=publish.PUBLISHED) == clean + "+changes"
    assert publish.commit(tmp_path / "nowhere") == "unknown"


def test_the_targets_table_is_checked_by_its_schema(tmp_path):
    table = docs_targets.read_targets()
    assert set(table) == set(TARGETS) and all(name.startswith("docs_") for name in table)
    broken = dict(table, docs_main={**table["docs_main"], "outputs": ["docs/results/household steps.txt"]})
    path = tmp_path / "docs_targets.yaml"
    path.write_text(yaml.safe_dump(broken))
    with pytest.raises(HeatdataError, match="docs_main/outputs/0: 'docs/results/household steps.txt' does not match"):
        docs_targets.targets([], "results", path)
    path.write_text(yaml.safe_dump(dict(table, docs_main={**table["docs_main"], "steps": [{"move": ["a", "b"]}]})))
    with pytest.raises(HeatdataError, match="docs_main/steps/0"):
        docs_targets.targets([], "results", path)
    poses = TARGETS["docs_poses"]  # the placeholder is the default descriptor's library, as recognize reads it
    assert f"results/libraries/{docs_targets.DEFAULT_LIBRARY}" in poses.inputs and "{default" not in str(TARGETS)


def test_an_analysis_script_s_precision_is_printed_by_library_size_and_written_whole(tmp_path, capsys):
    table = pd.DataFrame(
        {
            "descriptor": ["b", "b", "a", "a"],
            "library_size": [12, 4, 12, 4],
            "precision": [0.5, 0.25, 1.0, 0.875],
            "test_views": [8, 8, 8, 8],
        }
    )
    out = tmp_path / "precision.csv"
    publish.print_precision(table, ["descriptor"], out, sort=False)
    printed = capsys.readouterr().out.splitlines()
    assert printed[0].split() == ["library_size", "12", "4"]  # the table's order
    assert printed[-2].split() == ["b", "50.0%", "25.0%"] and printed[-1].split() == ["a", "100.0%", "87.5%"]
    assert pd.read_csv(out).equals(table)
    publish.print_precision(table, ["descriptor"])
    printed = capsys.readouterr().out.splitlines()
    assert printed[0].split() == ["library_size", "4", "12"] and printed[-2].split() == ["a", "87.5%", "100.0%"]
