"""turn_about_up: a rotation about a model's +y, +z towards +x."""

import numpy as np
import pytest

from heatdata.core.geometry import turn_about_up


def test_a_quarter_turn_takes_z_to_x_and_keeps_y():
    turn = turn_about_up(90.0)
    assert np.allclose(turn @ [0.0, 0.0, 1.0], [1.0, 0.0, 0.0])
    assert np.allclose(turn @ [0.0, 1.0, 0.0], [0.0, 1.0, 0.0])


@pytest.mark.parametrize("degrees", [0.0, 37.0, -120.0, 400.0])
def test_it_is_a_rotation_and_turns_add(degrees):
    turn = turn_about_up(degrees)
    assert np.allclose(turn @ turn.T, np.eye(3)) and np.isclose(np.linalg.det(turn), 1.0)
    assert np.allclose(turn_about_up(degrees) @ turn_about_up(20.0), turn_about_up(degrees + 20.0))
