"""A robot circling an object (heatdata.recognition.multiview.robot): fixed steps and the active policy, the rendered
views along its path, and the trials of the workflow's multi-view step."""

import numpy as np
import pandas as pd
import pytest
from cupmug import cup_mug, cup_mug_similarity, views_every_3_degrees

import heatdata as hd
from heatdata.experiments.multiview import ambiguous_starts, multiview_trials
from heatdata.recognition.multiview.appearance import appearance_model
from heatdata.recognition.multiview.filters import ParticleFilter
from heatdata.recognition.multiview.robot import TableRobot, recognize, robot_views


def test_recognize_fixed_steps_and_the_active_policy():
    library, similarity = cup_mug(), cup_mug_similarity()
    tests = views_every_3_degrees()
    model = appearance_model(library)
    robot = TableRobot(model, tests[tests["object"] == "mug"], per_stop=2)
    assert robot.views(270.0) == robot.views(270.0 + 720.0) and len(robot.views(0.0)) == 2
    fixed = recognize(ParticleFilter(model, similarity, particles=60, seed=1), robot, 270.0, step=30.0)
    assert fixed["converged"] and fixed["estimate"] == "mug" and 180.0 <= fixed["degrees"] <= 270.0
    active = recognize(
        ParticleFilter(model, similarity, particles=60, seed=1),
        robot,
        270.0,
        policy="active",
        candidates=(-90.0, -30.0, 30.0, 90.0),
    )
    assert active["converged"] and active["estimate"] == "mug" and active["degrees"] < fixed["degrees"]
    with pytest.raises(hd.HeatdataError, match="policy"):
        recognize(ParticleFilter(model, similarity, seed=1), robot, 0.0, policy="greedy")
    with pytest.raises(hd.HeatdataError, match="one object"):
        TableRobot(model, tests)


def test_ambiguous_starts_are_the_mugs_hidden_handle_views():
    library = cup_mug()
    starts = ambiguous_starts(library, views_every_3_degrees(), count=3)
    mug = starts[starts["object"] == "mug"]
    assert len(starts) == 6 and not mug["azimuth"].between(90, 180).any()
    assert (mug["nearest_other"] == "cup").all()


def test_trials_cover_every_setting():
    library, similarity = cup_mug(), cup_mug_similarity()
    starts = pd.DataFrame({"object": ["mug"], "azimuth": [270.0]})

    def run() -> pd.DataFrame:
        return multiview_trials(
            library,
            similarity,
            views_every_3_degrees(),
            starts,
            particles=(10, 30),
            policies=("fixed", "active"),
            repetitions=2,
            step=30.0,
        )

    trials = run()
    # 2 particle counts x (2 bootstraps fixed + similarity active) x 2 repetitions, and one exhaustive run
    assert len(trials) == 2 * 3 * 2 + 1
    exact = trials[trials["bootstrap"] == "exhaustive"].iloc[0]
    assert exact["particles"] == 2 * 360 and exact["policy"] == "fixed" and exact["identified"]
    assert {"correct", "degrees", "comparisons", "exhaustive"} <= set(trials.columns)
    particles = trials[trials["bootstrap"] != "exhaustive"]
    assert (particles["comparisons"] == particles["particles"] * particles["stops"]).all()
    assert exact["comparisons"] == exact["exhaustive"]
    assert (trials["exhaustive"] == 24 * trials["stops"]).all()
    pd.testing.assert_frame_equal(trials.drop(columns="seconds"), run().drop(columns="seconds"))  # seeded


def test_the_robot_renders_noisy_views_along_its_path(mug):
    spec = hd.DescriptorSpec("pvhk", 16, "center", "polar")
    path = robot_views(mug, 30.0, [15.0, -45.0], spec, per_stop=2)
    assert [move for _, move in path] == [0.0, 15.0, -45.0]
    first, _ = path[0]
    assert len(first) == 2 and all(len(d.values) == 16 for d in first)
    assert not np.array_equal(first[0].values, first[1].values)  # two noise draws per stop


def test_a_run_stops_before_travelling_past_max_degrees():
    library, similarity = cup_mug(), cup_mug_similarity()
    twins_tests = views_every_3_degrees()
    robot = TableRobot(appearance_model(library), twins_tests[twins_tests["object"] == "cup"])
    f = ParticleFilter(library, similarity, particles=30, seed=0)
    result = recognize(f, robot, 0.0, step=45.0, max_degrees=100.0)
    assert result["degrees"] <= 100.0
