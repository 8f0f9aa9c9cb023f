"""Candidate heat sources by mesh simplification (thesis 6.2)."""

import sys

import numpy as np
import pytest
from scipy.spatial import cKDTree

import heatdata as hd
from heatdata.core.spectrum import HeatOperator
from heatdata.descriptors.sources import candidate_descriptors, candidate_sources


def coverage(view: hd.View, sources: np.ndarray) -> float:
    """Largest distance from a view vertex to its nearest candidate source."""
    return float(cKDTree(view.vertices[sources]).query(view.vertices)[0].max())


def test_candidates_are_distinct_interior_and_spread_over_the_view(mug):
    view = hd.render_view(mug, 30.0, 30.0, 1.15, seed=0)
    sources = candidate_sources(view, 250)
    assert len(sources) == 250 and len(np.unique(sources)) == 250
    assert not set(sources) & set(view.boundary)
    area = (
        0.5
        * np.linalg.norm(
            np.cross(*(view.vertices[view.faces[:, k]] - view.vertices[view.faces[:, 0]] for k in (1, 2))), axis=1
        ).sum()
    )
    spacing = np.sqrt(area / 250)  # the side of one candidate's share of the surface
    assert coverage(view, sources) < 3 * spacing
    assert np.array_equal(sources, candidate_sources(view, 250))  # deterministic


def test_candidates_cover_a_disc_evenly(disc):
    sources = candidate_sources(disc, 40)
    radius = np.linalg.norm(disc.vertices[:, :2], axis=1).max()
    # 40 points on a disc of radius R: each covers ~pi R^2 / 40, a circle of radius R / sqrt(40)
    assert coverage(disc, sources) < 3 * radius / np.sqrt(40)


def test_all_interior_vertices_and_too_many_asked(square):
    interior = candidate_sources(square, None)
    assert len(interior) == square.n_vertices - len(square.boundary)
    with pytest.raises(hd.ViewError, match=f"only {len(interior)} vertices off its outer boundary"):
        candidate_sources(square, len(interior) + 1)
    with pytest.raises(hd.ViewError, match="at least one"):
        candidate_sources(square, 0)
    assert len(candidate_sources(square, len(interior))) == len(interior)


@pytest.mark.parametrize("kind, clock", [("pvhk", None), ("c-pvhk", "color"), ("c-pvhk", "shape"), ("ft-pvhk", None)])
def test_candidate_descriptors_from_one_spectrum_match_one_solve_per_source(mug, kind, clock):
    view = hd.render_view(mug, 30.0, 30.0, 1.15, seed=0)
    sources = candidate_sources(view, 20)
    spec = hd.DescriptorSpec(kind=kind, sampling="polar", color_map="c3" if kind == "c-pvhk" else None, clock=clock)
    times = [0.02, 0.05] if kind == "ft-pvhk" else None
    many = candidate_descriptors(view, sources, spec, times=times)
    assert len(many) == len(sources) * (2 if times else 1)
    for k in (0, 7, 19):  # against the Krylov solve of describe(), source by source
        single = hd.describe(
            view,
            [
                hd.DescriptorSpec(
                    kind=kind, sampling="polar", source=int(sources[k]), color_map=spec.get("color_map"), clock=clock
                )
            ],
            times=times,
            part_weights=False,
        )
        for j, one in enumerate(single):
            d = many[k * len(single) + j]
            assert d.source == sources[k] and d.time == pytest.approx(one.time, rel=1e-9)
            np.testing.assert_allclose(d.values, one.values, atol=2e-6 * np.abs(one.values).max())


def test_candidate_descriptors_on_a_view_of_two_parts(square):
    from heatdata.core.geometry import rotation_between

    turn = rotation_between([0.0, 0.0, 1.0], [0.1, 0.0, 1.0])  # the square again, the camera turned away from it
    first = square.vertices + [0.0003, 0.0007, 0.0]  # no vertex on the x axis, where the boundary's origin is
    two = hd.View(
        vertices=np.vstack([first, first @ turn.T]),
        colors=np.vstack([square.colors] * 2),
        faces=np.vstack([square.faces, square.faces + square.n_vertices]),
        view_id="two squares",
    )
    sources = np.array([square.n_vertices + 220, 220])  # the centre of each square, second part first
    a, b = candidate_descriptors(two, sources, hd.DescriptorSpec(kind="pvhk"))
    assert (a.source, b.source) == (square.n_vertices + 220, 220)
    np.testing.assert_allclose(a.values, b.values, atol=1e-9)  # the same square seen the same way, the same heat


def test_candidate_pvsts_share_the_view_work_and_match_one_at_a_time(square, monkeypatch):
    spec = hd.DescriptorSpec(kind="pvst", sampling="polar")
    pvst_module = sys.modules["heatdata.descriptors.stochastic_time"]
    shifts, models = [], []
    shifted, heat_model = HeatOperator.shifted, pvst_module.heat_model
    monkeypatch.setattr(HeatOperator, "shifted", lambda op, sigma: shifts.append(sigma) or shifted(op, sigma))
    monkeypatch.setattr(pvst_module, "heat_model", lambda op, *a, **k: models.append(op) or heat_model(op, *a, **k))
    many = candidate_descriptors(square, [220, 200, 242, 221, 219], spec)
    assert [d.source for d in many] == [220, 200, 242, 221, 219]
    early = [op for op in models if op.sigma != models[0].sigma]  # models on a shifted factorization
    assert len(early) >= 5 and 1 <= len(shifts) < len(early)  # neighbouring sources share their factorizations
    assert len(set(shifts)) == len(shifts) and np.array_equal(np.log2(shifts), np.round(np.log2(shifts)))
    one = hd.pvst(square, source=200, sampling="polar")
    np.testing.assert_allclose(many[1].values, one.values, rtol=1e-9)
    with pytest.raises(hd.ViewError, match="outer boundary"):
        candidate_descriptors(square, [220, 0], spec)  # vertex 0 is a corner


def test_candidate_descriptors_refuse_what_they_cannot_do(square):
    with pytest.raises(hd.SpecError, match="needs times="):
        candidate_descriptors(square, [220], hd.DescriptorSpec(kind="ft-pvhk"))
    with pytest.raises(hd.ViewError, match="vertex indices"):
        candidate_descriptors(square, [square.n_vertices], hd.DescriptorSpec())
