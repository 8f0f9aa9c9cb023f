"""What a scan's camera measured along its rays (heatdata.jasnom.rays): depths in front of a wall, analytically."""

import numpy as np

from heatdata.jasnom.rays import RayDepths


def wall(distance=1.0, count=21):
    xy = np.stack(np.meshgrid(np.linspace(-0.1, 0.1, count), np.linspace(-0.1, 0.1, count)), -1).reshape(-1, 2)
    return np.column_stack([xy, np.full(len(xy), distance)])


def test_a_point_on_a_ray_is_as_far_in_front_as_it_is_nearer_the_camera():
    seen = wall()
    rays = RayDepths.of(seen)
    ranges = np.linalg.norm(seen, axis=1)
    np.testing.assert_allclose(rays.in_front(0.5 * seen), 0.5 * ranges)  # half as far along the same rays
    np.testing.assert_allclose(rays.in_front(2.0 * seen), -ranges)  # behind the wall: negative
    np.testing.assert_allclose(rays.in_front(seen), 0.0, atol=1e-15)


def test_a_point_off_every_ray_has_no_depth():
    rays = RayDepths.of(wall())
    assert np.isnan(rays.in_front(wall() + [5.0, 0.0, 0.0])).all()
    assert 0.009 < rays.spacing < 0.0101  # the wall's 1 cm grid, 1 m away: about 0.01 rad between rays
    # within two ray spacings of a ray, a point takes that ray's surface
    assert np.isfinite(rays.in_front(np.array([[0.005, 0.0, 0.5]]))).all()
