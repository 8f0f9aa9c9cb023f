"""The documentation site builds with warnings as errors, runs every gallery example, and covers the API."""

import re
import shutil
import subprocess
import sys
import time

import pytest
from conftest import ROOT

import heatdata as hd

pytest.importorskip("sphinx_gallery", reason="the documentation tools: scripts/setup.sh --docs")

EXAMPLES = sorted((ROOT / "examples").glob("plot_*.py"))


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """The site built from a copy of the sources (the build writes its gallery and API stubs into them)."""
    work = tmp_path_factory.mktemp("docs")
    for folder in ("docs", "examples"):
        shutil.copytree(ROOT / folder, work / folder, ignore=shutil.ignore_patterns("_build", "gallery", "generated"))
    shutil.copy(ROOT / "CHANGELOG.md", work / "CHANGELOG.md")
    start = time.perf_counter()
    build = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", "docs", "html"],
        cwd=work,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert build.returncode == 0, build.stderr[-5000:]
    return work, time.perf_counter() - start


@pytest.mark.slow
def test_the_site_builds_with_warnings_as_errors_within_three_minutes(site):
    work, seconds = site
    assert seconds < 180, f"the docs build took {seconds:.0f} s"
    html = work / "html"
    for page in ("index", "install", "api", "changelog", "guide/workflow", "chapters/complex", "gallery/index"):
        assert (html / f"{page}.html").is_file(), page
    assert "not real sensor data" in (html / "index.html").read_text()
    # the maths renders offline: pages load the MathJax the site carries, never a CDN's
    pages = [p.read_text() for p in html.rglob("*.html")]
    assert any("_static/mathjax/tex-chtml.js" in page for page in pages)
    assert not any("cdn.jsdelivr.net" in page or "mathjax@3" in page for page in pages)
    assert (html / "_static/mathjax/tex-chtml.js").stat().st_size > 100_000


@pytest.mark.slow
def test_every_gallery_example_ran_in_under_thirty_seconds_and_drew_a_picture(site):
    work, _ = site
    assert len(EXAMPLES) >= 5
    for example in EXAMPLES:
        page = (work / "docs/gallery" / f"{example.stem}.rst").read_text()
        assert list((work / "html/_images").glob(f"sphx_glr_{example.stem}_*.png")), f"{example.name} drew nothing"
        # its thumbnail is a figure of its own, drawn to be read at that size, not the whole figure shrunk
        assert "# sphinx_gallery_thumbnail_number = 2" in example.read_text(), f"{example.name}: no thumbnail figure"
        assert list((work / "html/_images").glob(f"sphx_glr_{example.stem}_002.png")), f"{example.name}: one figure"
        took = re.search(r"Total running time of the script:\*\* \((\d+) minutes ([\d.]+) seconds\)", page)
        assert took, f"{example.name}: no running time recorded"
        seconds = 60 * int(took.group(1)) + float(took.group(2))
        assert seconds < 30, f"{example.name} took {seconds:.1f} s"


@pytest.mark.slow
def test_the_api_reference_has_a_page_for_every_public_name(site):
    work, _ = site
    documented = {p.stem.removeprefix("heatdata.") for p in (work / "html/generated").glob("heatdata.*.html")}
    constants = {"DESCRIPTORS", "__version__", "descriptors.COLOR_MAPS"}  # described in the page's prose
    beneath = {f"{module.removeprefix('heatdata.')}.{name}" for name, module in hd._MOVED_TO.items()}
    missing = (set(hd.__all__) | beneath) - constants - documented
    assert not missing, f"not in docs/api.rst: {sorted(missing)}"


def test_every_page_is_in_a_table_of_contents():
    """Sphinx warns of an orphan page, but only when it builds: this says which, in a second."""
    pages = {p.relative_to(ROOT / "docs").with_suffix("").as_posix() for p in (ROOT / "docs").rglob("*.md")}
    pages -= {p for p in pages if p.startswith(("_build", "gallery", "generated", "results"))}
    listed = {"index"}
    for page in pages | {"api"}:
        path = ROOT / "docs" / (page + (".rst" if page == "api" else ".md"))
        for block in re.findall(r"```\{toctree\}\n(.*?)```", path.read_text(), re.S):
            folder = page.rsplit("/", 1)[0] + "/" if "/" in page else ""
            listed |= {folder + line.strip() for line in block.splitlines() if line.strip() and ":" not in line}
    assert pages <= listed, sorted(pages - listed)
