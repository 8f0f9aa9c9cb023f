"""Every documented run is known to CI: the docs' snakemake commands and the docs targets, each config file once at
least, and no command that snakemake would misread."""

from pathlib import Path

from conftest import ROOT

from heatdata.experiments.documented_runs import (
    DOCUMENTS,
    Run,
    command_configs,
    documented_runs,
    run_small,
    targets_after_configs,
)


def test_a_command_gives_its_config_files_in_order_and_an_optional_one_both_ways():
    text = (
        "run `snakemake --cores 2 --configfile config/experiments/a.yaml config/experiments/b.yaml "
        "[config/experiments/c.yaml]` and\n.venv/bin/snakemake --configfile config/experiments/NAME.yaml  # a name"
    )
    assert command_configs(text) == [
        ("config/experiments/a.yaml", "config/experiments/b.yaml"),
        ("config/experiments/a.yaml", "config/experiments/b.yaml", "config/experiments/c.yaml"),
    ]


def test_a_target_after_the_config_files_is_caught():
    assert targets_after_configs("snakemake --cores 2 --configfile config/experiments/x.yaml docs_x") == [
        "--configfile config/experiments/x.yaml docs_x"
    ]
    assert targets_after_configs("snakemake docs_x --configfile config/experiments/x.yaml  # the target first") == []
    assert targets_after_configs("`--configfile config/a.yaml config/b.yaml`, the same") == []


def test_every_config_file_is_in_a_documented_run_and_every_documented_file_exists():
    runs = documented_runs()
    named = {config for run in runs for config in run.configs}
    assert {p.relative_to(ROOT).as_posix() for p in (ROOT / "config/experiments").glob("*.yaml")} <= named
    assert all((ROOT / config).is_file() for config in named), sorted(c for c in named if not (ROOT / c).is_file())
    assert runs[0] == Run("config", ("config/config.yaml",), "README.md")
    assert len({run.name for run in runs}) == len(runs)


def test_no_page_puts_a_target_after_its_config_files():
    pages = [ROOT / "README.md", ROOT / "config/README.md", *sorted((ROOT / "docs").rglob("*.md"))]
    assert DOCUMENTS == ("README.md", "config/README.md", "docs")
    for page in pages:
        assert not targets_after_configs(page.read_text()), page


def test_a_run_that_does_not_dry_run_fails_before_running(tmp_path: Path):
    outcome = run_small(Run("missing", ("config/experiments/missing.yaml",), "nowhere"), tmp_path / "out")
    assert not outcome.ok and outcome.error.startswith("dry run:") and outcome.run_seconds is None
    assert not (tmp_path / "out").exists()
