"""Packaging: what heatdata imports is declared, and the files a package needs are there."""

import ast
import sys
import tomllib
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
DISTRIBUTIONS = {"sklearn": "scikit-learn", "sksparse": "scikit-sparse", "yaml": "pyyaml", "PIL": "pillow"}


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
    pins = {line.split("==")[0].lower() for line in (ROOT / "requirements.txt").read_text().splitlines()
            if "==" in line}
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
    assert {p.parent.relative_to(ROOT).as_posix().replace("/", ".") for p in (ROOT / "heatdata").rglob("__init__.py")
            } <= set(packages)
