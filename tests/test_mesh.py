"""Mesh topology shared by views and models: boundary loops and consistent winding."""

import numpy as np

from heatdata.mesh import boundary_loops, consistent_winding

SQUARE = np.array([[0, 1, 2], [0, 2, 3]])  # two counter-clockwise triangles
TETRAHEDRON = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])


def test_the_boundary_of_a_square_runs_with_its_faces():
    (loop,) = boundary_loops(SQUARE)
    start = int(np.flatnonzero(loop == 0)[0])
    assert np.roll(loop, -start).tolist() == [0, 1, 2, 3]


def test_a_closed_surface_has_no_boundary():
    assert boundary_loops(TETRAHEDRON) == []


def test_two_squares_touching_at_a_vertex_give_two_loops_with_planar_positions():
    bowtie = np.vstack([SQUARE, [[2, 4, 5], [2, 5, 6]]])  # a second square at vertex 2
    planar = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [2, 1], [2, 2], [1, 2]], dtype=float)
    loops = boundary_loops(bowtie, planar)
    assert sorted(len(loop) for loop in loops) == [4, 4]


def test_winding_is_made_consistent_by_the_majority():
    flipped = TETRAHEDRON.copy()
    flipped[1] = flipped[1, ::-1]
    faces, count = consistent_winding(flipped)
    assert count == 1 and np.array_equal(faces, TETRAHEDRON)
    faces, count = consistent_winding(TETRAHEDRON)
    assert count == 0 and np.array_equal(faces, TETRAHEDRON)
