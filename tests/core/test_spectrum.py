"""The Laplace-Beltrami operator, spectra and heat diffusion against known answers."""

import numpy as np
import pytest
import scipy.linalg as sl
import scipy.sparse as sp
import scipy.sparse.linalg as sla
from conftest import grid_mesh, square_view

import heatdata as hd
from heatdata.core.spectrum import HeatOperator, eigen_spectrum, heat_model, krylov_heat, lambda2, laplacian
from heatdata.descriptors import (
    heat_operator,
)


def test_laplacian_rows_sum_to_zero_and_symmetric(square):
    L = laplacian(square.vertices, square.edges)
    assert np.allclose(np.asarray(L.sum(axis=1)).ravel(), 0.0, atol=1e-6 * L.diagonal().max())
    assert abs(L - L.T).max() == 0.0


def test_laplacian_weights_are_inverse_squared_lengths():
    vertices = np.array([[0.0, 0, 1], [0.5, 0, 1], [0, 2.0, 1]])
    L = laplacian(vertices, np.array([[0, 1], [0, 2]]))
    assert L[0, 1] == pytest.approx(-1 / 0.25)
    assert L[0, 2] == pytest.approx(-1 / 4.0)
    assert L[0, 0] == pytest.approx(4.25)


def test_zero_length_edge_is_an_error():
    vertices = np.array([[0.0, 0, 1], [0.0, 0, 1], [1, 0, 1]])
    with pytest.raises(hd.SpectrumError, match="zero-length"):
        laplacian(vertices, np.array([[0, 1], [1, 2]]))


def test_one_zero_eigenvalue_per_component():
    v1, f1 = grid_mesh(5, 5)
    v2, f2 = grid_mesh(4, 6)
    vertices = np.vstack([v1, v2 + [1.0, 0, 0]])
    faces = np.vstack([f1, f2 + len(v1)])
    view = hd.View.from_arrays(vertices, faces)
    values = sl.eigvalsh(laplacian(view.vertices, view.edges).toarray())
    scale = values.max()
    assert np.sum(values < 1e-10 * scale) == 2 == view.n_components


def test_lambda2_matches_dense(square):
    L = laplacian(square.vertices, square.edges)
    exact = sl.eigvalsh(L.toarray())[1]
    assert lambda2(HeatOperator(L)) == pytest.approx(exact, rel=1e-9)


def test_generalized_lambda2_matches_dense(square):
    L = laplacian(square.vertices, square.edges)
    rates = np.random.default_rng(1).uniform(0.5, 2.0, square.n_vertices)
    exact = sl.eigh(L.toarray(), np.diag(rates), eigvals_only=True)[1]
    assert lambda2(HeatOperator(L, rates)) == pytest.approx(exact, rel=1e-9)


@pytest.mark.parametrize("with_color", [False, True])
def test_krylov_heat_matches_expm_multiply(square, with_color):
    L = laplacian(square.vertices, square.edges)
    n = square.n_vertices
    rates = np.random.default_rng(2).uniform(0.5, 2.0, n) if with_color else np.ones(n)
    op = HeatOperator(L, rates)
    t2 = 1.0 / lambda2(op)
    times = np.array([0.05, 0.3, 1.0]) * t2
    source = 37
    got = krylov_heat(op, source, times, tol=1e-10)
    pulse = np.zeros(n)
    pulse[source] = 1.0
    A = -(sp.diags(1.0 / rates) @ L)  # dT/dt = -C^{-1} L T
    for k, t in enumerate(times):
        reference = sla.expm_multiply(t * A, pulse) / (rates[source] / rates.sum())
        assert np.max(np.abs(got[k] - reference)) < 1e-8


def test_a_shifted_operator_reuses_the_analysis_and_solves_its_own_matrix(square):
    L = laplacian(square.vertices, square.edges)
    rates = np.random.default_rng(3).uniform(0.5, 2.0, square.n_vertices)
    op = HeatOperator(L, rates)
    shifted = op.shifted(10.0)
    y = np.random.default_rng(4).standard_normal(square.n_vertices)
    dense = L.toarray() + 10.0 * np.diag(rates)
    assert np.allclose(shifted.factor.solve_A(y), np.linalg.solve(dense, y), rtol=1e-10, atol=1e-12)
    assert np.array_equal(shifted.factor.P(), op.factor.P())


def test_heat_is_conserved(square):
    rates = np.random.default_rng(3).uniform(0.5, 2.0, square.n_vertices)
    op = HeatOperator(laplacian(square.vertices, square.edges), rates)
    t2 = 1.0 / lambda2(op)
    temps = krylov_heat(op, 5, [0.1 * t2, t2, 10 * t2])
    # normalized so that the equilibrium is 1: the c-weighted mean temperature is 1 at all times
    assert np.allclose(temps @ rates / rates.sum(), 1.0, atol=1e-9)
    assert np.allclose(temps[-1], 1.0, atol=1e-3)  # near equilibrium after 10 time scales


def test_eigen_spectrum_is_c_orthonormal_and_matches_dense(square):
    L = laplacian(square.vertices, square.edges)
    rates = np.random.default_rng(4).uniform(0.5, 2.0, square.n_vertices)
    spectrum = eigen_spectrum(HeatOperator(L, rates), 12)
    exact = sl.eigh(L.toarray(), np.diag(rates), eigvals_only=True)[:12]
    assert np.allclose(spectrum.values, exact, rtol=1e-8, atol=1e-8 * exact[1])
    gram = spectrum.vectors.T @ (rates[:, None] * spectrum.vectors)
    assert np.allclose(gram, np.eye(12), atol=1e-8)


def test_spectrum_heat_with_all_modes_is_exact():
    view = square_view(n=8)
    L = laplacian(view.vertices, view.edges)
    op = HeatOperator(L)
    spectrum = eigen_spectrum(op, view.n_vertices - 2)
    t = 0.5 / spectrum.lambda2
    exact = sla.expm_multiply(-t * L, np.eye(view.n_vertices)[:, [3, 9]]).T * view.n_vertices
    got = spectrum.heat([3, 9], t)
    assert np.max(np.abs(got - exact)) < 2 * spectrum.truncation(t) * view.n_vertices + 1e-9


def test_bad_rates_and_times_are_errors(square):
    L = laplacian(square.vertices, square.edges)
    with pytest.raises(hd.SpectrumError, match="positive"):
        HeatOperator(L, np.zeros(square.n_vertices))
    with pytest.raises(hd.SpectrumError, match="times"):
        krylov_heat(HeatOperator(L), 0, [-1.0])


def test_non_convergence_is_reported_not_hidden(square):
    op = HeatOperator(laplacian(square.vertices, square.edges))
    with pytest.raises(hd.SpectrumError, match="did not converge"):
        krylov_heat(op, 0, [1e-6], max_steps=4)
    with pytest.raises(hd.SpectrumError, match="did not converge"):
        lambda2(op, max_steps=4, rtol=1e-16)


def test_tiny_mesh_krylov_space_becomes_invariant_and_is_exact():
    view = square_view(n=6)
    L = laplacian(view.vertices, view.edges)
    op = HeatOperator(L)
    t = 1.0 / lambda2(op)
    got = krylov_heat(op, 0, [t], tol=0.0, max_steps=200)[0]  # tol 0: only an invariant space stops it
    pulse = np.zeros(view.n_vertices)
    pulse[0] = 1.0
    assert np.allclose(got, sla.expm_multiply(-t * L, pulse) * view.n_vertices, atol=1e-9)


def test_a_shifted_factorization_gives_the_same_heat():
    op = heat_operator(square_view(15))
    times = np.array([1e-6, 1e-5, 1e-4])
    base = heat_model(op, 112, times, max_steps=200)(times)
    early = heat_model(op.shifted(1e6), 112, times)(times)
    assert np.allclose(base, early, atol=1e-6)
