"""One source per library view around the circle: the LP of thesis 6.3 against a dynamic program."""

import itertools
import logging
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

import heatdata as hd
import heatdata.recognition.compact as library
from heatdata.core.distances import mhd
from heatdata.descriptors.sources import candidate_descriptors, candidate_sources
from heatdata.experiments.compact import compact_libraries
from heatdata.recognition._minplus_kernel import minplus
from heatdata.recognition.compact import select_sources
from heatdata.recognition.evaluate import evaluate_compact
from heatdata.recognition.metrics import precision_table


def random_costs(rng, layers, low, high):
    sizes = rng.integers(low, high, size=layers)
    return [rng.random((sizes[i], sizes[(i + 1) % layers])) for i in range(layers)]


def check(costs):
    choice, cost = select_sources(costs)
    _, best = library.cyclic_dp(costs)
    assert cost == pytest.approx(best, rel=1e-9)
    assert cost == pytest.approx(sum(c[choice[i], choice[(i + 1) % len(costs)]] for i, c in enumerate(costs)))


def test_lp_optimum_equals_the_dynamic_program_on_random_graphs():
    rng = np.random.default_rng(0)
    for _ in range(25):
        check(random_costs(rng, int(rng.integers(2, 7)), 1, 7))


def test_negative_costs_choose_as_the_shifted_costs_do():
    """Eq. 6.11's rewards make costs negative; a constant on every edge moves every cycle alike (issue 31)."""
    rng = np.random.default_rng(4)
    for _ in range(5):
        costs = random_costs(rng, 5, 2, 6)
        choice, cost = select_sources(costs)
        shifted_choice, shifted_cost = select_sources([c - 3.0 for c in costs])
        check([c - 3.0 for c in costs])
        assert shifted_cost == pytest.approx(cost - 3.0 * len(costs)) and shifted_cost < 0
        assert np.array_equal(shifted_choice, choice)


def test_column_generation_finds_edges_left_out_at_the_start(monkeypatch):
    monkeypatch.setattr(library, "FULL_POOL", 0)
    monkeypatch.setattr(library, "START_EDGES", 1)  # the first LP sees each node's cheapest kept edge only
    rng = np.random.default_rng(2)
    for _ in range(8):
        check(random_costs(rng, int(rng.integers(3, 9)), 5, 20))


def test_the_edges_kept_are_those_of_the_cheapest_cycles():
    rng = np.random.default_rng(4)
    for trial in range(12):
        costs = random_costs(rng, int(rng.integers(2, 5)), 1, 5)
        if trial % 2:  # near-flat costs with ties, as on real descriptors
            costs = [np.round(c * 2) / 2 for c in costs]
        graph = library._Graph(costs)
        cycles = {
            choice: library._cycle_cost(costs, np.array(choice))
            for choice in itertools.product(*(range(c.shape[0]) for c in costs))
        }
        best = min(cycles.values())
        assert graph.upper == pytest.approx(best, abs=1e-12)
        for i, kept in enumerate(graph.kept):
            on_best = np.zeros_like(kept)
            for choice, cost in cycles.items():
                if cost <= best + 1e-9:
                    on_best[choice[i], choice[(i + 1) % len(costs)]] = True
            assert np.array_equal(kept, on_best), (trial, i)
        # a lower bound of every cycle through each start, exact for the starts it searched from
        through = [min(cost for choice, cost in cycles.items() if choice[0] == s) for s in range(costs[0].shape[0])]
        assert np.all(graph.start_bound <= np.array(through) + 1e-12)


def test_minplus_product_against_broadcasting():
    rng = np.random.default_rng(5)
    a, b = rng.random((7, 5)), rng.random((5, 9))
    a[2] = np.inf
    a[3, 1] = np.inf
    expected = np.min(a[:, :, None] + b[None, :, :], axis=1)
    assert np.array_equal(minplus(a, b), expected)


def test_a_fractional_relaxation_is_branched_to_the_exact_cycle(caplog):
    # Winding twice (0 -> 0 -> 1 -> 1 -> 0) costs 0, i.e. 0 per turn; every single turn costs 5.
    costs = [np.array([[0.0, 5.0], [5.0, 0.0]]), np.array([[5.0, 0.0], [0.0, 5.0]])]
    with caplog.at_level(logging.INFO, logger="heatdata.recognition.compact"):
        choice, cost = select_sources(costs)
    assert "fractional" in caplog.text
    assert cost == 5.0 and library.cyclic_dp(costs)[1] == 5.0


@pytest.mark.parametrize(
    "costs, message",
    [
        ([np.ones((2, 2))], "at least two views"),
        ([np.ones((2, 3)), np.ones((2, 2))], "view 0: edge costs of shape"),
        ([np.ones((2, 0)), np.ones((0, 2))], "non-empty"),
        ([np.ones((2, 2)), np.full((2, 2), np.nan)], "view 1: edge costs must be finite"),
    ],
)
def test_bad_graphs_are_named(costs, message):
    with pytest.raises(hd.HeatdataError, match=message):
        select_sources(costs, name="chair-7")


def test_a_missing_solver_is_named(monkeypatch):
    monkeypatch.setattr(library, "SOLVER", "GUROBI_NOT_HERE")
    with pytest.raises(hd.HeatdataError, match="chair-7: the LP solver GUROBI_NOT_HERE is not installed"):
        select_sources([np.ones((2, 2)), np.ones((2, 2))], name="chair-7")


def curve(offset, wiggle, m=16):
    x = np.linspace(0, 2 * np.pi, m, endpoint=False)
    return offset + 0.1 * np.sin(wiggle * x)


def candidate_table(rng):
    """Two objects, 8 library and 2 test views each. Per library view, candidate 0 is the object's
    steady curve, 1 a random one and 2 a curve far from everything of the other object that changes from
    view to view."""
    rows = []
    for k, obj in enumerate("ab"):
        base, far = curve(k, 2 + k), curve(4 + 3 * k, 5)
        for split, count in (("train", 8), ("test", 2)):
            for i in range(count):
                view = dict(
                    object=obj, label="thing", split=split, view_id=f"{obj}/{split}/{i}", azimuth=360.0 * i / count
                )
                values = [base + 0.01 * rng.standard_normal(16), curve(rng.uniform(0, 2), 7), far + 0.5 * (i % 3)]
                rows += [dict(view, source_rule="candidates", source=s, values=v) for s, v in enumerate(values)]
                rows.append(dict(view, source_rule="center", source=99, values=curve(rng.uniform(0, 2), 3)))
    return pd.DataFrame(rows)


def test_consecutive_costs_and_other_object_distances_against_brute_force():
    rng = np.random.default_rng(5)
    views = [rng.random((n, 16)) for n in (3, 4, 5)]
    costs = library.consecutive_costs(views)
    assert [c.shape for c in costs] == [(3, 4), (4, 5), (5, 3)]
    np.testing.assert_allclose(costs[2], np.abs(views[2][:, None, :] - views[0][None, :, :]).sum(axis=2))
    other = [rng.random((2, 16))]
    rho = library.other_object_distances({"a": views, "b": other}, block=2)
    l1 = np.abs(views[1][:, None, :] - other[0][None, :, :]).sum(axis=2)
    np.testing.assert_allclose(rho["a"][1], l1.min(axis=1))
    l1 = np.abs(other[0][:, None, :] - np.vstack(views)[None, :, :]).sum(axis=2)
    np.testing.assert_allclose(rho["b"][0], l1.min(axis=1))
    with pytest.raises(hd.HeatdataError, match="two or more objects"):
        library.other_object_distances({"a": views})
    with pytest.raises(hd.HeatdataError, match="unknown distance 'l2' for c of eq. 6.6"):
        library.consecutive_costs(views, "l2")
    with pytest.raises(hd.HeatdataError, match="unknown norm 'mhd' for rho"):
        library.other_object_distances({"a": views, "b": other}, norm="mhd")


def test_the_thesis_distances_for_c_and_rho():
    """c in the MHD of eq. 3.1 (eq. 6.6's d) and rho in the Euclidean norm (eq. 6.4), each pair by hand."""
    rng = np.random.default_rng(8)
    views = [rng.random((n, 12)) for n in (3, 2)]
    costs = library.consecutive_costs(views, "mhd")
    assert [c.shape for c in costs] == [(3, 2), (2, 3)]
    for i, j in np.ndindex(3, 2):
        assert costs[0][i, j] == pytest.approx(mhd(views[0][i], views[1][j]), rel=1e-5)
        assert costs[1][j, i] == pytest.approx(mhd(views[1][j], views[0][i]), rel=1e-5)
    other = [rng.random((4, 12))]
    rho = library.other_object_distances({"a": views, "b": other}, norm="l2")
    l2 = np.sqrt(((views[0][:, None, :] - other[0][None, :, :]) ** 2).sum(axis=2))
    np.testing.assert_allclose(rho["a"][0], l2.min(axis=1))


def test_combined_costs_mix_the_two_terms():
    c = [np.array([[1.0, 2.0]]), np.array([[3.0], [4.0]])]
    rho = [np.array([0.5]), np.array([1.0, 2.0])]
    assert np.array_equal(library.combined_costs(c, rho, 1.0)[1], c[1])
    # w_ab = -rho_a - rho_b (eq. 6.10, Alg. 6.3)
    assert np.array_equal(library.combined_costs(c, rho, 0.0)[0], [[-1.5, -2.5]])
    assert np.allclose(library.combined_costs(c, rho, 0.25)[1], 0.25 * c[1] - 0.75 * np.array([[1.5], [2.5]]))
    with pytest.raises(hd.HeatdataError, match="alpha"):
        library.combined_costs(c, rho, 1.5)


def test_compact_libraries_follow_alpha_and_classify_the_test_views():
    table = candidate_table(np.random.default_rng(6))
    libraries = compact_libraries(table, [8, 4], [0.0, 1.0])
    assert set(libraries["descriptor"]) == {"initial center", "compact alpha=0", "compact alpha=1"}
    sizes = libraries.groupby(["descriptor", "library_size", "object"]).size()
    assert set(sizes.xs(8, level="library_size")) == {8} and set(sizes.xs(4, level="library_size")) == {4}
    steady = libraries[libraries["descriptor"] == "compact alpha=1"]
    assert (steady["source"] == 0).all()  # Alg. 6.2: the candidate that changes least around the circle
    distant = libraries[libraries["descriptor"] == "compact alpha=0"]
    assert (distant["source"] == 2).all()  # eq. 6.3: the candidate farthest from the other object
    assert (libraries.loc[libraries["descriptor"] == "initial center", "source"] == 99).all()
    by_dp = compact_libraries(table, [8, 4], [0.0, 1.0], solver="dp")
    assert np.allclose(by_dp["cost"], libraries["cost"], equal_nan=True)
    with pytest.raises(hd.HeatdataError, match="unknown solver"):
        compact_libraries(table, [8], [1.0], solver="simplex")
    with pytest.raises(hd.HeatdataError, match="unknown distance 'cosine' or norm 'l1'"):
        compact_libraries(table, [8], [1.0], distance="cosine")
    thesis = compact_libraries(table, [8], [0.0, 1.0], distance="mhd", norm="l2")
    for alpha, source in (("1", 0), ("0", 2)):  # the same choices as in L1 on these well-separated candidates
        assert (thesis.loc[thesis["descriptor"] == f"compact alpha={alpha}", "source"] == source).all()
    predictions = evaluate_compact(table, libraries)
    assert len(predictions) == 3 * 2 * 4  # libraries x sizes x test views
    assert predictions.loc[predictions["descriptor"] == "compact alpha=1", "correct"].all()
    precision = precision_table(predictions)
    assert set(precision["descriptor"]) == set(libraries["descriptor"])


def test_compact_libraries_leave_out_failed_views_and_need_two_views(caplog):
    table = candidate_table(np.random.default_rng(7))
    broken = table["view_id"] == "a/train/3"
    table.loc[broken, "values"] = pd.Series([np.full(16, np.nan)] * int(broken.sum()), index=table.index[broken])
    with caplog.at_level(logging.WARNING, logger="heatdata.recognition.compact"):
        libraries = compact_libraries(table, [8], [1.0])
    assert "a/train/3" in caplog.text
    assert len(libraries[(libraries["object"] == "a") & (libraries["descriptor"] == "compact alpha=1")]) == 7
    with pytest.raises(hd.HeatdataError, match=r"b \(1 views\): a compact library needs two or more views"):
        compact_libraries(table[table["object"] == "b"], [1], [1.0])
    with pytest.raises(hd.HeatdataError, match="candidate rows and initial-rule rows"):
        compact_libraries(table[table["source_rule"] == "candidates"], [8], [1.0])


def test_an_lp_that_ends_infeasible_is_an_error_naming_the_object():
    graph = library._Graph([np.ones((2, 2)), np.ones((2, 2))])
    dead_end = [{(0, 0)}, set()]  # flow can leave view 0 but never come back
    with pytest.raises(hd.HeatdataError, match="chair-7: the source-selection LP ended infeasible"):
        library._solve(graph, dead_end, None, [], "chair-7")
    with pytest.raises(hd.HeatdataError, match="chair-7: the LP solver HIGHS failed"):
        library._solve(graph, [set(), set()], None, [], "chair-7")  # no edge at all


@pytest.mark.slow
def test_solver_output_goes_to_the_log_not_to_stdout():
    """HiGHS prints a banner from C once per process: a fresh process shows whether it reaches stdout."""
    code = (
        "import logging, numpy as np; from heatdata.recognition.compact import select_sources; "
        "logging.basicConfig(level=logging.DEBUG); "
        "rng = np.random.default_rng(0); select_sources([rng.random((6, 6)) for _ in range(5)])"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout == "" and "solver output: Running HiGHS" in done.stderr


def test_ch6_costs_take_the_descriptor_lists_candidate_descriptors_returns(disc, square):
    spec = hd.DescriptorSpec("pvhk", 32, "center", "polar")
    per_view = [candidate_descriptors(v, candidate_sources(v, 5), spec) for v in (disc, square, disc)]
    arrays = [np.stack([d.values for d in zs]) for zs in per_view]
    for got, want in zip(library.consecutive_costs(per_view), library.consecutive_costs(arrays)):
        np.testing.assert_array_equal(got, want)
    rho = library.other_object_distances({"a": per_view, "b": per_view[:1]})
    assert [len(r) for r in rho["a"]] == [len(zs) for zs in per_view]
    with pytest.raises(hd.HeatdataError, match="different lengths"):
        library.consecutive_costs([arrays[0], arrays[1][:, :16]])
    with pytest.raises(hd.HeatdataError, match="different lengths"):
        library.other_object_distances({"a": arrays, "b": [arrays[0][:, :16]]})
    with pytest.raises(hd.HeatdataError, match="library view 1: nothing to stack"):
        library.consecutive_costs([arrays[0], []])
