"""Rigid geometry shared by the stages: the smallest rotation between two directions, and a turn about the up axis."""

from __future__ import annotations

import numpy as np


def rotation_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The smallest rotation taking the direction of ``a`` to that of ``b`` (Rodrigues' formula).

    Parameters
    ----------
    a, b : (3,) float
        Non-zero vectors.

    Returns
    -------
    (3, 3) float64
        ``R`` with ``R @ a / |a| = b / |b|``, a rotation about ``a x b``; the identity for parallel vectors. For
        opposite vectors (no smallest rotation) a half turn about an axis normal to ``a``.
    """
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    a = a / np.linalg.norm(a)
    b = b / np.linalg.norm(b)
    axis = np.cross(a, b)
    sine, cosine = float(np.linalg.norm(axis)), float(a @ b)
    if sine < 1e-15:
        if cosine > 0:
            return np.eye(3)
        axis = np.cross(a, np.eye(3)[int(np.argmin(np.abs(a)))])
        sine = float(np.linalg.norm(axis))
        axis, sine, cosine = axis / sine, 0.0, -1.0
    else:
        axis = axis / sine
    cross = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + sine * cross + (1.0 - cosine) * cross @ cross


def turn_about_up(degrees: float) -> np.ndarray:
    """The rotation by ``degrees`` about +y, a model's up axis (+z towards +x for a positive turn).

    Parameters
    ----------
    degrees : float

    Returns
    -------
    (3, 3) float64
    """
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
