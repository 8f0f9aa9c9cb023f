"""A cup and a mug whose curves are identical except where the mug's handle shows (azimuths 90-180 deg), the
ambiguity of thesis Fig. 4.2-4.3: a small synthetic library with known answers for the multi-view tests."""

import functools

import numpy as np
import pandas as pd

from heatdata.recognition.multiview.appearance import learn_similarity

ANGLES = np.arange(0.0, 360.0, 30.0)
SAMPLES = 16


def curve(obj: str, azimuth: float, noise: float = 0.0, rng=None) -> np.ndarray:
    x = np.arange(SAMPLES) / SAMPLES
    values = 1.0 + 0.1 * np.cos(2 * np.pi * x) + 0.02 * np.cos(np.radians(azimuth))
    if obj == "mug" and 90 <= azimuth % 360 <= 180:
        values = values + 0.3 * np.exp(-(((x - 0.5) / 0.08) ** 2))  # the handle
    if noise:
        values = values + rng.normal(0, noise, SAMPLES)
    return values


def table(objects=("cup", "mug"), copies: int = 2, noise: float = 0.002, seed: int = 0) -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    return pd.DataFrame(
        [
            {"object": o, "azimuth": a, "kind": "pvhk", "values": curve(o, a, noise, rng)}
            for o in objects
            for a in ANGLES
            for _ in range(copies)
        ]
    )


def observe(obj, azimuth, seed):
    rng = np.random.default_rng(seed)
    return [curve(obj, azimuth, 0.002, rng) for _ in range(2)]


def views_every_3_degrees(objects=("cup", "mug"), seed=4) -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    return pd.DataFrame(
        [
            {"object": o, "azimuth": a, "kind": "pvhk", "values": curve(o, a, 0.002, rng)}
            for o in objects
            for a in np.arange(1.5, 360.0, 3.0)
        ]
    )


@functools.cache
def cup_mug() -> pd.DataFrame:
    """The library: each object at every 30 degrees, two noisy copies per angle (shared: do not change it)."""
    return table(seed=0)


@functools.cache
def cup_mug_similarity() -> np.ndarray:
    """The similarity of eq. 4.6 between :func:`cup_mug`'s views, learned from an independent draw."""
    return learn_similarity(cup_mug(), table(seed=1))
