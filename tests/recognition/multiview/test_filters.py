"""The particle filter of Algorithm 4.1 and the exact filter beside it (heatdata.recognition.multiview.filters)."""

import numpy as np
import pandas as pd
import pytest
from cupmug import ANGLES, SAMPLES, cup_mug, cup_mug_similarity, observe, table, views_every_3_degrees

import heatdata as hd
from heatdata.recognition.multiview.appearance import angle_gap, appearance_model, learn_similarity
from heatdata.recognition.multiview.filters import (
    ExhaustiveFilter,
    ParticleFilter,
    _label_cells,
    stochastic_universal_sampling,
)
from heatdata.recognition.multiview.robot import TableRobot, recognize


def test_a_library_of_one_object_converges_at_once():
    one = table(objects=("cup",))
    f = ParticleFilter(one, learn_similarity(one, table(objects=("cup",), seed=1)), particles=20, seed=0)
    assert f.converged and f.estimate == "cup" and f.posterior() == {"cup": 1.0}
    f.step(observe("cup", 60.0, 0), 0.0)
    assert f.converged and f.estimate == "cup"


def test_the_true_object_keeps_particles_while_ambiguous_then_wins():
    library, similarity = cup_mug(), cup_mug_similarity()
    f = ParticleFilter(library, similarity, particles=60, seed=3)
    azimuth = 270.0
    f.step(observe("mug", azimuth, 10), 0.0)
    for k in range(3):  # 270 -> 360: the handle stays hidden
        azimuth += 30.0
        f.step(observe("mug", azimuth, 11 + k), 30.0)
        assert not f.converged and f.posterior()["mug"] > 0.2
    for k in range(5):  # 30 -> 180: the handle comes into view
        azimuth += 30.0
        f.step(observe("mug", azimuth, 20 + k), 30.0)
        if f.converged:
            break
    assert f.converged and f.estimate == "mug" and azimuth >= 90.0


def test_the_baseline_bootstrap_replaces_particles_near_survivors_and_is_seeded():
    library, similarity = cup_mug(), cup_mug_similarity()

    def bootstrapped(seed):
        f = ParticleFilter(library, similarity, particles=40, bootstrap="angular", seed=seed)
        f.object = np.repeat([f.objects.index("mug"), f.objects.index("cup")], 20)
        f.azimuth = np.tile(np.arange(20) * 18.0, 2)
        f.log_w = np.where(f.object == f.objects.index("mug"), 0.0, -50.0)  # the cups far below the best hypothesis
        f.log_w -= np.log(np.exp(f.log_w).sum())
        survivors = f.azimuth[:20].copy()
        f._bootstrap()
        return f, survivors

    f, survivors = bootstrapped(5)
    assert (f.object == f.objects.index("mug")).all()  # every cup was replaced by a newcomer of a survivor's object
    np.testing.assert_array_equal(f.azimuth[:20], survivors)  # the survivors stay where they were
    gap = np.abs((f.azimuth[20:, None] - survivors[None, :] + 180.0) % 360.0 - 180.0).min(axis=1)
    assert gap.max() <= 30.0 and gap.max() > 0  # within `neighbourhood` degrees of a survivor, not on it
    assert np.exp(f.log_w).sum() == pytest.approx(1.0)
    again, _ = bootstrapped(5)
    np.testing.assert_array_equal(f.azimuth, again.azimuth)  # seeded
    assert not np.array_equal(f.azimuth, bootstrapped(6)[0].azimuth)


def test_an_unexplained_observation_restarts_instead_of_dividing_by_zero():
    library, similarity = cup_mug(), cup_mug_similarity()
    f = ParticleFilter(library, similarity, particles=30, seed=0)
    f.object[:] = f.objects.index("cup")  # every particle on the cup: none explains the handle
    f.step(observe("mug", 120.0, 1), 0.0)
    assert f.restarts >= 1 and np.isfinite(f.log_w).all() and f.weights.sum() == pytest.approx(1.0)
    far = [np.full(SAMPLES, 1e6)]  # nothing in the library is near: every likelihood underflows
    f.step(far, 0.0)
    assert np.isfinite(f.log_w).all() and f.weights.sum() == pytest.approx(1.0)


def test_odometry_wraps_around_360():
    library, similarity = cup_mug(), cup_mug_similarity()
    a = ParticleFilter(library, similarity, particles=10, seed=1)
    b = ParticleFilter(library, similarity, particles=10, seed=1)
    obs = observe("cup", 0.0, 0)
    a.step(obs, 370.0)
    b.step(obs, -350.0)
    np.testing.assert_allclose(a.azimuth, b.azimuth)
    assert ((a.azimuth >= 0) & (a.azimuth < 360)).all()
    with pytest.raises(hd.HeatdataError, match="finite angle"):
        a.step(obs, float("nan"))


def test_bad_observations_and_tables_are_clear_errors():
    library, similarity = cup_mug(), cup_mug_similarity()
    f = ParticleFilter(library, similarity, particles=10, seed=0)
    with pytest.raises(hd.HeatdataError, match="observations have 8 values, the library's pvhk descriptors 16"):
        f.step([np.ones(8)], 0.0)
    esf = hd.Descriptor(
        kind="esf",
        values=np.ones(SAMPLES),
        positions=np.zeros(SAMPLES),
        source=-1,
        time=np.nan,
        lambda2=np.nan,
        sampling=None,
    )
    with pytest.raises(hd.HeatdataError, match="observations are esf descriptors, the library's pvhk"):
        f.step([esf], 0.0)
    with pytest.raises(hd.HeatdataError, match="does not match the library"):
        ParticleFilter(library[library["azimuth"] < 300], similarity)
    with pytest.raises(hd.HeatdataError, match="lack library object"):
        learn_similarity(library, table(objects=("cup",), seed=1))
    with pytest.raises(hd.HeatdataError, match="whole number"):
        ParticleFilter(library, similarity, particles=0)
    with pytest.raises(hd.HeatdataError, match="lacks column"):
        ParticleFilter(library.drop(columns="values"), similarity)


def test_best_move_looks_where_the_handle_shows():
    library, similarity = cup_mug(), cup_mug_similarity()
    f = ParticleFilter(library, similarity, particles=80, seed=2)
    f.step(observe("mug", 270.0, 0), 0.0)  # handle hidden: cup or mug
    assert not f.converged
    # -90 deg reaches 180 (handle in view); +90 deg reaches 0 (still hidden)
    assert f.best_move([90.0, -90.0]) == -90.0


def test_stochastic_universal_sampling_is_proportional():
    rng = np.random.default_rng(0)
    counts = np.bincount(stochastic_universal_sampling(np.array([1.0, 0.0, 3.0]), 8, rng), minlength=3)
    assert counts.tolist() == [2, 0, 6]


def test_best_move_keeps_circling_when_no_step_can_tell_twins_apart():
    twins = pd.concat([table(objects=("cup",)), table(objects=("cup",)).assign(object="twin")])
    f = ParticleFilter(
        twins,
        learn_similarity(
            twins, table(objects=("cup",), seed=1).pipe(lambda t: pd.concat([t, t.assign(object="twin")]))
        ),
        particles=40,
        seed=0,
    )
    half = f.n // 2  # the same angles on both twins: no step can move mass between them
    f.object[:half], f.object[half:] = 0, 1
    f.azimuth[half:] = f.azimuth[:half]
    assert not f.converged
    assert f.best_move([-90.0, -15.0, 15.0, 90.0]) == 15.0
    f.visited, f.position = [0.0, 15.0, 345.0], 345.0  # stops at 0, +15, then back to -15 (odometry)
    assert f.best_move([-15.0, 15.0]) == -15.0  # +15 returns to the first stop's views: onwards to new ones
    assert f.best_move([15.0]) == 15.0  # nothing new in reach: keep circling anyway


def test_best_move_does_not_return_to_views_already_seen():
    library, similarity = cup_mug(), cup_mug_similarity()
    f = ParticleFilter(library, similarity, particles=80, seed=2)
    f.step(observe("mug", 270.0, 0), 0.0)
    f.step(observe("mug", 180.0, 1), -90.0)  # the handle seen: now at -90 by odometry
    assert f.visited == [0.0, 270.0]
    assert f.best_move([90.0, -90.0]) == -90.0  # +90 goes back to the first stop


def test_newcomers_start_at_the_survivors_mean_or_least_weight():
    library, similarity = cup_mug(), cup_mug_similarity()
    for rule, summary in (("mean", np.mean), ("least", np.min)):
        f = ParticleFilter(library, similarity, particles=60, seed=3, newcomer=rule)
        f.step(observe("mug", 270.0, 10), 0.0)
        best = f.labels()[0]
        survivors = int((f.labels() == best).sum())
        f.update(np.where(np.arange(len(f.model.labels)) == best, 0.0, -50.0), 0.0)  # only one label explains it
        assert survivors < f.n  # the survivors come first, then the newcomers
        np.testing.assert_allclose(f.weights[survivors:], summary(f.weights[:survivors]))
    with pytest.raises(hd.HeatdataError, match="newcomer is 'mean' or 'least'"):
        ParticleFilter(library, similarity, newcomer="max")


def test_newcomers_start_anywhere_in_their_labels_cell_or_at_its_view():
    library, similarity = cup_mug(), cup_mug_similarity()
    lopsided = pd.DataFrame({"object": "a", "azimuth": [0.0, 90.0, 120.0]})
    np.testing.assert_allclose(_label_cells(lopsided), [[120, 45], [45, 15], [15, 120]])
    for rule in ("cell", "view"):
        f = ParticleFilter(library, similarity, particles=60, seed=3, repopulate=rule)
        f.step(observe("mug", 270.0, 10), 0.0)
        best = f.labels()[0]
        survivors = int((f.labels() == best).sum())
        f.update(np.where(np.arange(len(f.model.labels)) == best, 0.0, -50.0), 0.0)
        newcomers = f.azimuth[survivors:]
        offset = angle_gap(newcomers, f.model.labels["azimuth"].to_numpy()[f.labels()[survivors:]])
        assert (offset <= 15.0 + 1e-9).all()  # the library is 30 deg apart: a cell is +-15 deg
        assert (offset > 0.5).any() if rule == "cell" else (offset == 0).all()
    with pytest.raises(hd.HeatdataError, match="repopulate is 'cell' or 'view'"):
        ParticleFilter(library, similarity, repopulate="near")


def test_the_exhaustive_filter_is_the_exact_bayes_posterior():
    library = cup_mug()
    model = appearance_model(library)
    f = ExhaustiveFilter(model, resolution=30.0)  # start azimuths on the library's own angles
    assert len(f.object) == 2 * 12 and f.posterior() == {"cup": 0.5, "mug": 0.5}
    log_p = [model.log_likelihood(observe("mug", a, k)) for k, a in enumerate((270.0, 300.0, 120.0))]
    for p, move in zip(log_p, (0.0, 30.0, 180.0), strict=True):
        f.update(p, move)
    # by hand: hypothesis (object, start) sums log p at start, start + 30, start + 210
    labels = model.labels
    index = {(o, a): k for k, (o, a) in enumerate(zip(labels["object"], labels["azimuth"], strict=True))}
    score = {
        o: [sum(p[index[(o, (a + off) % 360)]] for p, off in zip(log_p, (0, 30, 210), strict=True)) for a in ANGLES]
        for o in ("cup", "mug")
    }
    mug = np.exp(np.logaddexp.reduce(score["mug"]) - np.logaddexp.reduce(score["cup"] + score["mug"]))
    assert f.posterior()["mug"] == pytest.approx(mug) and f.estimate == "mug" and f.converged
    g = ExhaustiveFilter(model)
    g.update(log_p[0], 370.0)
    h = ExhaustiveFilter(model)
    h.update(log_p[0], 10.0)
    assert g.posterior() == pytest.approx(h.posterior())  # odometry wraps
    with pytest.raises(hd.HeatdataError, match="resolution"):
        ExhaustiveFilter(model, resolution=0.0)
    with pytest.raises(hd.HeatdataError, match="confidence"):
        ExhaustiveFilter(model, confidence=1.0)
    robot = TableRobot(model, views_every_3_degrees().query("object == 'mug'"))
    with pytest.raises(hd.HeatdataError, match="active policy needs a ParticleFilter"):
        recognize(f, robot, 0.0, policy="active")


def test_the_unknown_hypothesis_is_bayes_on_the_confidences():
    library, similarity = cup_mug(), cup_mug_similarity()
    for belief in (ExhaustiveFilter(library), ParticleFilter(library, similarity, particles=20, seed=0)):
        assert belief.unknown == 0.0 and belief.log_unknown is None  # the thesis's filter: none
        belief.expect_unknown(0.5)
        belief.step(observe("mug", 120.0, 0), 0.0)
        for confidence in (0.2, 0.2):  # two views each four times likelier of an object the library lacks
            belief.weigh_unknown(confidence)
        assert belief.unknown == pytest.approx(0.5 * 0.8**2 / (0.5 * 0.8**2 + 0.5 * 0.2**2))
        assert sum(belief.posterior().values()) + belief.unknown == pytest.approx(1.0)
        assert belief.estimate is None  # 0.94 unknown: more than any object
        belief.weigh_unknown(1.0)  # a view surely of the library's: the unknown object is ruled out
        assert belief.unknown < 1e-9 and belief.estimate == "mug"
        with pytest.raises(hd.HeatdataError, match=r"in \(0, 1\)"):
            belief.expect_unknown(1.0)
        with pytest.raises(hd.HeatdataError, match=r"in \[0, 1\]"):
            belief.weigh_unknown(1.5)
    with pytest.raises(hd.HeatdataError, match="no unknown hypothesis"):
        ExhaustiveFilter(library).weigh_unknown(0.5)
