"""The search index beside the exact search: its spaces, its files, and answers identical to the exact search's."""

import logging

import numpy as np
import pandas as pd
import pytest
from conftest import ROOT
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

import heatdata as hd
from heatdata.core.distances import chi_square_matrix
from heatdata.descriptors import kind_of
from heatdata.descriptors.rows import descriptor_rows
from heatdata.errors import HeatdataError, LibraryError
from heatdata.experiments.views import render_views, view_plan
from heatdata.recognition import index as ix
from heatdata.recognition.confidence import nearest_two
from heatdata.recognition.evaluate import classify
from heatdata.recognition.library import (
    Library,
    build_library,
    load_library,
    write_library,
    write_library_index,
)

SPEC = hd.DescriptorSpec("hgd")
BINS = 48


@settings(max_examples=60, deadline=None)
@given(
    arrays(np.float64, (2, 12), elements=st.floats(0, 1)).filter(lambda h: np.all(h.sum(axis=1) > 0)),
)
def test_the_hellinger_map_bounds_chi_square_within_a_factor_two(histograms):
    a, b = histograms / histograms.sum(axis=1, keepdims=True)
    mapped = ix.mapped(np.stack([a, b]), "hellinger").astype(np.float64)
    hellinger = float(np.sum((mapped[0] - mapped[1]) ** 2))
    chi = float(chi_square_matrix(a[None], b[None])[0, 0])
    assert hellinger / 2 - 1e-6 <= chi <= hellinger + 1e-6


def test_the_spaces_map_as_documented():
    values = np.array([[0.25, 0.0, 0.75, np.nan]])
    assert np.allclose(ix.mapped(values, "hellinger"), [[0.5, 0.0, np.sqrt(0.75), 0.0]])
    assert np.allclose(ix.mapped(values, "l1"), [[0.25, 0.0, 0.75, 0.0]])
    assert ix.mapped(values, "l2").dtype == np.float32
    with pytest.raises(HeatdataError, match="unknown index space"):
        ix.mapped(values, "cosine")
    assert kind_of("hgd").index_space == "hellinger" and kind_of("pvhk").index_space == "l1"
    assert kind_of("ft-pvhk").index_space is None and kind_of("pointnet").index_space == "l2"


def histograms(objects: int, views: int, noise: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Views of objects as histograms that change smoothly with the view angle: each object two random histograms,
    mixed by the angle, with multiplicative noise (seeded by ``noise``)."""
    ends = np.random.default_rng(0).dirichlet(np.full(BINS, 0.3), size=(objects, 2))
    rng = np.random.default_rng(noise)
    mix = 0.5 + 0.5 * np.cos(np.linspace(0, 2 * np.pi, views, endpoint=False))
    values = mix[None, :, None] * ends[:, :1] + (1 - mix[None, :, None]) * ends[:, 1:]
    values = values * rng.lognormal(0, 0.2, values.shape)
    values /= values.sum(axis=2, keepdims=True)
    return values.reshape(objects * views, BINS), np.repeat(np.arange(objects), views)


def library_of(values: np.ndarray, owners: np.ndarray) -> Library:
    names = np.array([f"object-{o:03d}" for o in owners])
    views = pd.Series(owners).groupby(owners).cumcount().to_numpy()
    rows = pd.DataFrame(
        {
            "object": names,
            "label": "thing",
            "view_id": [f"{n}/train/{v:03d}" for n, v in zip(names, views, strict=True)],
            "split": "train",
            "azimuth": 360.0 * views / views.max(),
            "elevation": 30.0,
            "distance": 1.0,
            "values": list(values),
            "weights": None,
            "time_object": "",
        }
    )
    metadata = {
        "spec": {"kind": "hgd", "options": SPEC.options, "fitted": None, "name": SPEC.name},
        "time_rule": "plausible",
        "library_size": int(views.max()) + 1,
        "heatdata_version": hd.__version__,
        "confidence": None,
    }
    return Library(rows, metadata, "synthetic")


@pytest.mark.parametrize("objects", [14, 58])  # the embedded run's and the chairs' libraries, of 40 views
def test_answers_through_the_index_are_the_exact_searchs(objects):
    library = library_of(*histograms(objects, 40))
    library.use_index(ix.build_index(library._values, "hellinger"))
    queries, _ = histograms(objects, 40, noise=1)  # other noise: near, not equal to, the library views
    for values in queries[::3]:
        query = pd.DataFrame({"values": [values]})
        near, exact = library.distances(query), library.distances(query, exact=True)
        assert np.array_equal(library._nearest_views(near)[:5], library._nearest_views(exact)[:5])
        found = library._nearest_views(near)[:5]
        assert np.array_equal(near[found], exact[found])
        assert nearest_two(near[None], library._codes)[1:] == nearest_two(exact[None], library._codes)[1:]


def test_object_positions_and_the_shortlist_keep_the_librarys_order():
    codes, names, positions = ix.object_positions(np.array(["b", "a", "b", "c", "a"]))
    assert names == ["a", "b", "c"] and codes.tolist() == [1, 0, 1, 2, 0]
    assert [p.tolist() for p in positions] == [[1, 4], [0, 2], [3]]
    # candidates name b, then a; -1 is no candidate: every view of b and a, in the library's order
    assert ix.shortlist(np.array([2, 4, -1, 0]), codes, positions).tolist() == [0, 1, 2, 4]
    assert ix.shortlist(np.array([-1, -1]), codes, positions).size == 0
    assert ix.candidate_count(1) == ix.CANDIDATE_ROWS and ix.candidate_count(40) == 40 * ix.SHORTLIST_OBJECTS


@pytest.mark.parametrize("objects", [14, 58])
def test_the_nearest_views_through_the_index_are_the_exhaustive_searchs(objects):
    values, owners = histograms(objects, 40)
    queries, _ = histograms(objects, 40, noise=1)
    codes, _, positions = ix.object_positions(owners)
    search = ix.build_index(values, "hellinger")
    hgd = kind_of("hgd")
    index, distance = ix.nearest_through_index(hgd, search, queries, values, codes, positions, 40, chunk=100)
    exact = hgd.nearest(queries, values)
    assert np.array_equal(index, exact.index) and np.allclose(distance, exact.distance, rtol=1e-12)


def test_a_query_the_index_finds_nothing_for_is_compared_with_every_view():
    values, owners = histograms(6, 10)
    codes, _, positions = ix.object_positions(owners)
    search = ix.build_index(values, "hellinger")
    search.candidates = lambda queries, count: np.full((len(queries), count), -1)  # empty probed lists
    index, distance = ix.nearest_through_index(kind_of("hgd"), search, values[[7, 33]], values, codes, positions, 10)
    assert index.tolist() == [7, 33] and np.allclose(distance, 0)


def test_classify_through_the_index_predicts_what_the_exhaustive_search_does(caplog):
    values, owners = histograms(58, 40)
    queries, query_owners = histograms(58, 40, noise=1)
    rows = pd.concat(
        [
            pd.DataFrame({"object": [f"object-{o:03d}" for o in own], "split": split, "values": list(v)})
            for own, split, v in ((owners, "train", values), (query_owners[::5], "test", queries[::5]))
        ],
        ignore_index=True,
    ).assign(label="thing", azimuth=0.0, descriptor="hgd", kind="hgd")
    rows["view_id"] = [f"{o}/{s}/{k}" for k, (o, s) in enumerate(zip(rows["object"], rows["split"], strict=True))]
    with caplog.at_level(logging.INFO, logger="heatdata.recognition.index"):
        near = classify(rows, "hgd", exact=False)
    assert "flat index of 2320 views" in caplog.text
    exact = classify(rows, "hgd", exact=True)
    assert near["predicted_view_id"].tolist() == exact["predicted_view_id"].tolist()
    assert np.allclose(near["distance"], exact["distance"], rtol=1e-12)
    caplog.clear()
    with caplog.at_level(logging.INFO, logger="heatdata.recognition.index"):
        classify(rows, "hgd")  # 2,320 library views: below INDEX_ROWS, the exhaustive search
    assert "index" not in caplog.text


def test_an_ivf_index_finds_what_the_flat_one_finds(monkeypatch):
    values, owners = histograms(60, 40)
    flat = ix.build_index(values, "hellinger", what="test")
    monkeypatch.setattr(ix, "FLAT_ROWS", 100)
    monkeypatch.setattr(ix, "PROBES", 4)
    ivf = ix.build_index(values, "hellinger", what="test")
    assert "IVF-Flat" in ivf.description and flat.description == "flat" and len(ivf) == len(values)
    queries, _ = histograms(60, 40, noise=2)
    found, truth = ivf.candidates(queries[::7], 1)[:, 0], flat.candidates(queries[::7], 1)[:, 0]
    assert found.shape == (len(queries[::7]),)
    assert np.mean(owners[found] == owners[truth]) >= 0.95
    assert ivf.candidates(values[17], 5)[0, 0] == 17  # a library view is its own nearest


def test_an_index_file_reads_back_and_refuses_another_librarys(tmp_path, monkeypatch):
    values, _ = histograms(20, 10)
    path = tmp_path / "a.faiss"
    ix.build_index(values, "hellinger").write(path)
    back = ix.read_index(path, values, "hellinger")
    assert np.array_equal(back.candidates(values[3], 4), ix.build_index(values, "hellinger").candidates(values[3], 4))
    other = values.copy()
    other[-1] = other[0]
    with pytest.raises(HeatdataError, match="index of other views"):
        ix.read_index(path, other, "hellinger")
    with pytest.raises(HeatdataError, match="not of this library's 199"):
        ix.read_index(path, values[:-1], "hellinger")
    with pytest.raises(HeatdataError, match="not of this library's"):
        ix.read_index(path, values, "l1")
    path.write_bytes(b"not an index at all")
    with pytest.raises(HeatdataError, match="not an index that heatdata writes"):
        ix.read_index(path, values, "hellinger")
    path.write_bytes(bytes(10**7))
    with pytest.raises(HeatdataError, match="more than an index"):
        ix.read_index(path, values, "hellinger")
    monkeypatch.setattr(ix, "FLAT_ROWS", 50)  # an IVF index's file too
    ix.build_index(values, "hellinger").write(path)
    assert "IVF-Flat" in ix.read_index(path, values, "hellinger").description


@pytest.fixture(scope="module")
def library_file(tmp_path_factory):
    """A library file of rendered views of three embedded objects (the HGD: an index space)."""
    catalog = hd.read_catalog(ROOT / "data/models/catalog.csv")
    parts = []
    for row in catalog[catalog["object"].isin(["coffee-cup", "beer-mug", "milk-carton"])].to_dict("records"):
        plan = view_plan([row["object"]], 8, 2, elevation=30.0, distance=1.0, seed=0)
        parts.append(descriptor_rows(render_views(hd.load_catalog_model(row), plan), plan, [SPEC]))
    path = tmp_path_factory.mktemp("library") / "hgd-8.parquet"
    write_library(*build_library(pd.concat(parts, ignore_index=True), SPEC, 8), path)
    return path


def test_a_library_without_its_index_builds_one_and_says_so(library_file, caplog, mug):
    ix.index_path(library_file).unlink(missing_ok=True)
    with caplog.at_level(logging.INFO, logger="heatdata"):
        library = load_library(library_file)
    assert library.index is not None and "no index beside it" in caplog.text
    assert load_library(library_file, index=False).index is None
    view = hd.render_view(mug, azimuth=50.0, elevation=30.0, seed=5)
    near, exact = library.recognize(view, pose=False), library.recognize(view, pose=False, exact=True)
    assert near.matches == exact.matches and near.confidence == exact.confidence


def test_heatdata_index_writes_the_index_a_library_then_reads(library_file, caplog):
    written = write_library_index(library_file)
    assert written == library_file.with_suffix(".faiss") and written.stat().st_size > 0
    caplog.clear()
    with caplog.at_level(logging.INFO, logger="heatdata"):
        library = load_library(library_file)
    assert "no index beside it" not in caplog.text and len(library.index) == len(library.views)
    values = library._values.copy()
    values[0] += 0.01  # an index of another library beside this one: refused, built anew
    ix.build_index(values, "hellinger").write(written)
    with caplog.at_level(logging.WARNING, logger="heatdata"):
        assert load_library(library_file).index is not None
    assert "index of other views" in caplog.text
    written.unlink()


def test_an_index_that_does_not_fit_is_refused(library_file):
    library = load_library(library_file, index=False)
    with pytest.raises(LibraryError, match="does not fit"):
        library.use_index(ix.build_index(library._values[:-1], "hellinger"))
    with pytest.raises(LibraryError, match="does not fit"):
        library.use_index(ix.build_index(library._values, "l1"))


def test_a_kind_without_an_index_space_answers_by_the_exact_search(library_file, monkeypatch):
    monkeypatch.setattr(type(kind_of("hgd")), "index_space", None)  # as the FT-PVHK and a combined kind
    assert load_library(library_file).index is None
    with pytest.raises(LibraryError, match="a hgd library answers by the exact search and has no index"):
        write_library_index(library_file)


def test_a_library_written_with_its_index_reads_it_back(library_file, tmp_path, caplog):
    library = load_library(library_file, index=False)
    rows = pd.concat([library.views, library.independent], ignore_index=True)
    path = tmp_path / "again.parquet"
    write_library(rows, library.metadata, path, index=True)
    with caplog.at_level(logging.INFO, logger="heatdata"):
        again = load_library(path)
    assert path.with_suffix(".faiss").exists() and "no index beside it" not in caplog.text
    assert np.array_equal(again._values, library._values) and len(again.index) == len(library.views)
