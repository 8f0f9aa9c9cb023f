"""Candidate heat sources by mesh simplification (thesis 6.2)."""

import numpy as np
import pytest
from scipy.spatial import cKDTree

import heatdata as hd


def coverage(view: hd.View, sources: np.ndarray) -> float:
    """Largest distance from a view vertex to its nearest candidate source."""
    return float(cKDTree(view.vertices[sources]).query(view.vertices)[0].max())


def test_candidates_are_distinct_interior_and_spread_over_the_view(mug):
    view = hd.render_view(mug, 30.0, 30.0, 1.15, seed=0)
    sources = hd.candidate_sources(view, 250)
    assert len(sources) == 250 and len(np.unique(sources)) == 250
    assert not set(sources) & set(view.boundary)
    area = 0.5 * np.linalg.norm(np.cross(*(view.vertices[view.faces[:, k]] - view.vertices[view.faces[:, 0]]
                                          for k in (1, 2))), axis=1).sum()
    spacing = np.sqrt(area / 250)  # the side of one candidate's share of the surface
    assert coverage(view, sources) < 3 * spacing
    assert np.array_equal(sources, hd.candidate_sources(view, 250))  # deterministic


def test_candidates_cover_a_disc_evenly(disc):
    sources = hd.candidate_sources(disc, 40)
    radius = np.linalg.norm(disc.vertices[:, :2], axis=1).max()
    # 40 points on a disc of radius R: each covers ~pi R^2 / 40, a circle of radius R / sqrt(40)
    assert coverage(disc, sources) < 3 * radius / np.sqrt(40)


def test_all_interior_vertices_and_too_many_asked(square):
    interior = hd.candidate_sources(square, None)
    assert len(interior) == square.n_vertices - len(square.boundary)
    with pytest.raises(hd.ViewError, match=f"only {len(interior)} vertices off its outer boundary"):
        hd.candidate_sources(square, len(interior) + 1)
    with pytest.raises(hd.ViewError, match="at least one"):
        hd.candidate_sources(square, 0)
    assert len(hd.candidate_sources(square, len(interior))) == len(interior)
