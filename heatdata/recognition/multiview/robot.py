"""A robot circling an object (thesis 4.5): its views, and Algorithm 4.1 run along its moves."""

from __future__ import annotations

import numpy as np
import pandas as pd

from heatdata.errors import HeatdataError
from heatdata.recognition.multiview.appearance import AppearanceModel, angle_gap
from heatdata.recognition.multiview.filters import (
    HypothesisFilter,
    ParticleFilter,
)


# --- the robot of 4.5 and Algorithm 4.1 run along its moves ------------------------------------------------
def robot_views(
    model,
    start_azimuth: float,
    moves,
    spec,
    *,
    per_stop: int = 2,
    elevation: float = 30.0,
    distance: float = 1.0,
    noise: bool = True,
    seed: int = 0,
) -> list[tuple[list, float]]:
    """A simulated robot circling ``model`` (4.5.4): rendered noisy views along its path, with the odometry.

    Parameters
    ----------
    model : Model
    start_azimuth : float
        Where the robot starts, degrees.
    moves : sequence of float
        The azimuth steps between stops (e.g. ``[15] * 23``); the first stop is the start.
    spec : DescriptorSpec
        How each view is described.
    per_stop : int
        Views taken at each stop, each with its own noise (two in the thesis).

    Returns
    -------
    list of (descriptors, displacement)
        Per stop: the ``per_stop`` descriptors and the azimuth moved since the last stop
        (0 at the start), ready for :meth:`ParticleFilter.step`.
    """
    from heatdata.descriptors import describe
    from heatdata.views.render import render_view

    path, azimuth = [], float(start_azimuth)
    for k, move in enumerate([0.0, *moves]):
        azimuth += move
        views = [
            render_view(model, azimuth % 360.0, elevation, distance, noise=noise, seed=seed + 1000 * k + j)
            for j in range(per_stop)
        ]
        path.append(([describe(v, [spec])[0] for v in views], float(move)))
    return path


class TableRobot:
    """The robot of the experiments: at each stop it observes the ``per_stop`` test views nearest its azimuth.

    The log-likelihoods of each stop's observations under the appearance model are
    cached, so many runs over the same test views cost one comparison per stop.
    """

    def __init__(self, model: AppearanceModel, tests: pd.DataFrame, per_stop: int = 2):
        if tests["object"].nunique() != 1:
            raise HeatdataError(f"a robot observes one object, got {sorted(tests['object'].unique())}")
        if per_stop < 1 or per_stop > len(tests):
            raise HeatdataError(f"per_stop must be in 1..{len(tests)} (the test views), got {per_stop}")
        self.model, self.per_stop = model, per_stop
        self.azimuths = tests["azimuth"].to_numpy(dtype=np.float64)
        self.values = list(tests["values"])
        self._cache: dict[tuple, np.ndarray] = {}

    def views(self, azimuth: float) -> tuple:
        """Indices of the test views seen from ``azimuth``: the nearest ones."""
        order = np.argsort(angle_gap(self.azimuths, azimuth % 360.0), kind="stable")
        return tuple(sorted(order[: self.per_stop].tolist()))

    def log_likelihood(self, azimuth: float) -> np.ndarray:
        """log p(Z | s) of the observations at ``azimuth`` for every library label."""
        key = self.views(azimuth)
        if key not in self._cache:
            self._cache[key] = self.model.log_likelihood([self.values[i] for i in key])
        return self._cache[key]


def recognize(
    f: HypothesisFilter,
    robot: TableRobot,
    start: float,
    *,
    policy: str = "fixed",
    step: float = 15.0,
    candidates=(-90.0, -45.0, -15.0, 15.0, 45.0, 90.0),
    max_degrees: float = 720.0,
) -> dict:
    """Run Algorithm 4.1 (or the exhaustive filter) with ``robot`` from ``start`` until it converges or travels
    ``max_degrees``.

    ``policy`` is ``"fixed"`` (``step`` degrees each time, as in 4.5.4) or ``"active"``
    (:meth:`ParticleFilter.best_move` among ``candidates``). Returns the estimate,
    whether it converged, the degrees travelled, the stops and the restarts.
    """
    if policy not in ("fixed", "active"):
        raise HeatdataError(f"policy is 'fixed' or 'active', got {policy!r}")
    if policy == "active" and not isinstance(f, ParticleFilter):
        raise HeatdataError(f"the active policy needs a ParticleFilter, got {type(f).__name__}")
    azimuth, travelled = float(start), 0.0
    f.update(robot.log_likelihood(azimuth), 0.0)
    while not f.converged:
        move = f.best_move(candidates) if isinstance(f, ParticleFilter) and policy == "active" else step
        if travelled + abs(move) > max_degrees:
            break
        azimuth += move
        travelled += abs(move)
        f.update(robot.log_likelihood(azimuth), move)
    return {
        "estimate": f.estimate,
        "converged": f.converged,
        "degrees": travelled,
        "stops": f.steps,
        "restarts": f.restarts,
    }
