"""One source per library view around the circle: the LP of thesis 6.3 against a dynamic program."""

import logging

import numpy as np
import pytest

import heatdata as hd
import heatdata.library as library


def random_costs(rng, layers, low, high):
    sizes = rng.integers(low, high, size=layers)
    return [rng.random((sizes[i], sizes[(i + 1) % layers])) for i in range(layers)]


def check(costs):
    choice, cost = hd.select_sources(costs)
    _, best = library.cyclic_dp(costs)
    assert cost == pytest.approx(best, rel=1e-9)
    assert cost == pytest.approx(sum(c[choice[i], choice[(i + 1) % len(costs)]] for i, c in enumerate(costs)))


def test_lp_optimum_equals_the_dynamic_program_on_random_graphs():
    rng = np.random.default_rng(0)
    for _ in range(25):
        check(random_costs(rng, int(rng.integers(2, 7)), 1, 7))


def test_column_generation_finds_edges_left_out_at_the_start(monkeypatch):
    monkeypatch.setattr(library, "FULL_POOL", 0)
    monkeypatch.setattr(library, "START_EDGES", 1)  # the first LP sees each node's cheapest kept edge only
    rng = np.random.default_rng(2)
    for _ in range(8):
        check(random_costs(rng, int(rng.integers(3, 9)), 5, 20))


def test_a_fractional_relaxation_is_branched_to_the_exact_cycle(caplog):
    # Winding twice (0 -> 0 -> 1 -> 1 -> 0) costs 0, i.e. 0 per turn; every single turn costs 5.
    costs = [np.array([[0.0, 5.0], [5.0, 0.0]]), np.array([[5.0, 0.0], [0.0, 5.0]])]
    with caplog.at_level(logging.INFO, logger="heatdata.library"):
        choice, cost = hd.select_sources(costs)
    assert "fractional" in caplog.text
    assert cost == 5.0 and library.cyclic_dp(costs)[1] == 5.0


@pytest.mark.parametrize("costs, message", [
    ([np.ones((2, 2))], "at least two views"),
    ([np.ones((2, 3)), np.ones((2, 2))], "view 0: edge costs of shape"),
    ([np.ones((2, 0)), np.ones((0, 2))], "non-empty"),
    ([np.ones((2, 2)), np.full((2, 2), np.nan)], "view 1: edge costs must be finite"),
])
def test_bad_graphs_are_named(costs, message):
    with pytest.raises(hd.HeatdataError, match=message):
        hd.select_sources(costs, name="chair-7")


def test_a_missing_solver_is_named(monkeypatch):
    monkeypatch.setattr(library, "SOLVER", "GUROBI_NOT_HERE")
    with pytest.raises(hd.HeatdataError, match="chair-7: the LP solver GUROBI_NOT_HERE is not installed"):
        hd.select_sources([np.ones((2, 2)), np.ones((2, 2))], name="chair-7")
