"""People (heatdata.experiments.people, thesis 3.5): pose sequences, pose grouping measures and colour twins."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from heatdata.descriptors import DescriptorSpec, describe
from heatdata.errors import HeatdataError
from heatdata.experiments.people import (
    CLOTHES,
    GROUPS,
    POSE_RANGES,
    pose_measures,
    pose_sequence,
    reallusion_experiment,
    reallusion_people,
    reallusion_pose,
    sequence_views,
    twin_experiment,
    twin_predictions,
)
from heatdata.views.view import kinect_intrinsics

REALLUSION = Path("/usr/share/sweethome3d/furniture/Reallusion.sh3f")
SMALL = {"intrinsics": kinect_intrinsics(0.25), "noise": False}
SPECS = [DescriptorSpec("pvhk", 32, "center", "polar"), DescriptorSpec("c-pvhk", 32, "center", "polar", "c2")]


def test_a_pose_sequence_alternates_its_groups_within_their_ranges_and_is_seeded():
    sequence = pose_sequence(10, seed=3, turn=20.0)
    assert list(sequence["group"]) == [GROUPS[k % 2] for k in range(10)]
    for row in sequence.to_dict("records"):
        for key, (low, high) in POSE_RANGES[row["group"]].items():
            assert low <= row[key] <= high
        assert -20.0 <= row["azimuth"] <= 20.0
    pd.testing.assert_frame_equal(sequence, pose_sequence(10, seed=3, turn=20.0))
    assert not sequence.equals(pose_sequence(10, seed=4, turn=20.0))
    with pytest.raises(HeatdataError, match="at least 2 frames"):
        pose_sequence(1)


def test_reallusion_poses_come_from_the_catalogue_names():
    assert [reallusion_pose(n) for n in ("Holding female", "Sitting boy", "Lying down male", "Girl")] == [
        "holding",
        "sitting",
        "lying",
        "standing",
    ]


def test_pose_measures_of_two_clusters_and_leaving_each_person_out():
    points = np.concatenate([np.zeros((5, 1)), np.full((5, 1), 10.0)]) + np.arange(10)[:, None] * 0.01
    distances = np.abs(points - points.T)
    groups = np.repeat(["close", "away"], 5)
    m = pose_measures(distances, groups, n_neighbors=3)
    assert m["nearest_accuracy"] == 1.0 and m["silhouette"] > 0.99 and m["embedding"].shape == (10, 2)
    assert m["within"]["close"] == pytest.approx(0.02) and m["between"] == pytest.approx(10.05)
    # each person shows both poses; the nearest view of another person then has the other pose
    persons = np.array([0, 1, 2, 3, 4, 4, 0, 1, 2, 3])
    near = np.where(persons[:, None] == persons[None], 0.0, np.where(groups[:, None] == groups[None], 5.0, 1.0))
    np.fill_diagonal(near, 0.0)
    assert pose_measures(near, groups, owners=persons, n_neighbors=3)["nearest_accuracy"] == 0.0
    with pytest.raises(HeatdataError, match="two groups"):
        pose_measures(distances, np.repeat("close", 10), n_neighbors=3)
    with pytest.raises(HeatdataError, match=r"\(N, N\)"):
        pose_measures(distances[:5], groups, n_neighbors=3)


def test_twin_predictions_take_the_nearest_library_view_s_person():
    values = np.array([[0.0, 0.0], [1.0, 1.0], [0.1, 0.0], [0.9, 1.0]])
    people = ["A", "B", "A", "B"]
    table = twin_predictions(
        {"d": values},
        people,
        [True, True, False, False],
        searches={"d": lambda q, lib: (np.abs(q[:, None] - lib[None]).sum(axis=2).argmin(axis=1), None)},
    )
    assert list(table["predicted"]) == ["A", "B"] and table["correct"].all()
    with pytest.raises(HeatdataError, match="no library view of"):
        twin_predictions({"d": values}, people, [True, False, False, False])
    with pytest.raises(HeatdataError, match="both library and test"):
        twin_predictions({"d": values}, people, [True] * 4)


def test_twins_in_one_pose_have_one_pvhk_and_different_c_pvhks():
    sequence = pose_sequence(2, seed=0)
    views = {
        person: sequence_views(sequence, clothes=colours, name=person, **SMALL) for person, colours in CLOTHES.items()
    }
    a, b = ([describe(v, SPECS) for v in views[p]] for p in CLOTHES)
    for x, y in zip(a, b, strict=True):
        np.testing.assert_allclose(x[0].values, y[0].values, rtol=1e-6)  # colour-blind: the same descriptor
        assert np.abs(x[1].values - y[1].values).max() > 0.05 * np.ptp(x[1].values)
    assert views["person A"][0].view_id == "person A-0"


def test_the_twin_experiment_tells_the_twins_apart_by_colour():
    predictions, values, frames, views = twin_experiment(SPECS, frames=6, **SMALL)
    assert len(views) == len(frames) == 12 and values[SPECS[0].name].shape == (12, 32)
    assert frames.groupby("person")["library"].sum().tolist() == [3, 3]
    precision = predictions.groupby("descriptor")["correct"].mean()
    assert precision[SPECS[1].name] == 1.0 and set(predictions["pair"]) == {"MakeHuman"}
    assert len(predictions) == 2 * 6


@pytest.mark.slow
@pytest.mark.skipif(not REALLUSION.exists(), reason="Debian's sweethome3d-furniture is not installed")
def test_reallusion_s_people_are_imported_posed_and_one_is_set_against_its_hue_rotated_twin(tmp_path):
    people = reallusion_people(str(REALLUSION), str(tmp_path))
    assert len(people) == 25 and set(people["pose"]) == {"standing", "holding", "sitting", "lying"}
    assert (people["licence"] == "CC-BY-3.0").all()
    values, views, predictions, examples = reallusion_experiment(
        SPECS, people, azimuths=[0.0], twin="male01", twin_views=6, **SMALL
    )
    assert len(views) == 25 and values[SPECS[0].name].shape == (25, 32)
    assert len(predictions) == 2 * 2 * 3 and set(predictions["pair"]) == {"Reallusion male01"}
    colour = predictions[predictions["descriptor"] == SPECS[1].name]
    assert colour["correct"].all()
    assert [title for _, title in examples["Reallusion male01"]] == ["male01 original", "male01 hue +120 deg"]
    with pytest.raises(HeatdataError, match="no Reallusion person"):
        reallusion_experiment(SPECS, people, azimuths=[0.0], twin="goat")
