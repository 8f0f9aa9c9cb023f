"""Mesh topology shared by views and models: boundary loops and consistent winding."""

import numpy as np

from heatdata.core.mesh import (
    boundary_loops,
    consistent_winding,
    merged_vertices,
    surface_distances,
    surface_samples,
)

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


def test_winding_is_made_consistent_beside_a_face_alone_in_its_patch():
    # the first two faces cross edge 1-2 the same way; the third shares no edge (a speck left by a decimation)
    faces, count = consistent_winding(np.array([[0, 1, 2], [1, 2, 3], [4, 5, 6]]))
    assert count == 1 and faces[2].tolist() == [4, 5, 6]
    edges = [{(int(f[i]), int(f[(i + 1) % 3])) for i in range(3)} for f in faces[:2]]
    assert ((1, 2) in edges[0]) != ((1, 2) in edges[1])  # now crossed in opposite directions


def test_surface_samples_are_uniform_by_area_on_the_mesh():
    # a unit square (two triangles) and a 3x1 rectangle beside it: a quarter of the samples on the square
    vertices = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [4, 0, 0], [4, 1, 0]], float)
    faces = np.array([[0, 1, 2], [0, 2, 3], [1, 4, 5], [1, 5, 2]])
    points = surface_samples(vertices, faces, 40000, seed=3)
    assert np.allclose(points[:, 2], 0) and (points[:, :2] >= 0).all() and (points[:, 0] <= 4).all()
    assert (points[:, 1] <= 1).all()
    assert abs((points[:, 0] < 1).mean() - 0.25) < 0.01
    np.testing.assert_array_equal(points, surface_samples(vertices, faces, 40000, seed=3))


def test_surface_distances_of_two_concentric_spheres_are_the_radii_gap():
    import trimesh

    inner = trimesh.creation.icosphere(subdivisions=4, radius=1.0)
    outer = (inner.vertices * 1.1, inner.faces)
    out, back = surface_distances((inner.vertices, inner.faces), outer, samples=5000)
    # the polyhedra's faces lie inside their spheres by at most r (1 - cos(edge/2r)): about 2e-4 r here
    assert np.allclose(out, 0.1, atol=2e-3) and np.allclose(back, 0.1, atol=2e-3)
    same, _ = surface_distances((inner.vertices, inner.faces), (inner.vertices, inner.faces), samples=1000)
    assert same.max() < 1e-5


def test_vertices_within_the_tolerance_merge_into_the_first_and_chains_merge_whole():
    vertices = np.array([[0.0, 0, 0], [1, 0, 0], [0, 0, 1e-4], [1, 0, 0.9e-3], [1, 0, 1.8e-3], [5, 0, 0]])
    index, first = merged_vertices(vertices, 1e-3)
    # 0 and 2 are one vertex; 1, 3 and 4 a chain (4 is 1.8e-3 from 1, but 0.9e-3 from 3); 5 stays alone
    np.testing.assert_array_equal(first, [0, 1, 5])
    np.testing.assert_array_equal(index, [0, 1, 0, 1, 1, 2])
    index, first = merged_vertices(vertices, 1e-5)
    np.testing.assert_array_equal(index, np.arange(6))
    np.testing.assert_array_equal(first, np.arange(6))
