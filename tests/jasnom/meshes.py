"""Meshes with known answers for JASNOM's tests: an ellipsoid cut in two and moved, halves with their vertices
duplicated as an STL file or a cutting tool leaves them."""

import numpy as np
import trimesh
from scipy.spatial.transform import Rotation

from heatdata.io.models import Model, transformed
from heatdata.jasnom.cuts import split_model

MOTION = Rotation.from_rotvec([0.5, -1.0, 0.3]), np.array([0.3, 0.1, -0.2])


def as_trimesh(model: Model) -> trimesh.Trimesh:
    return trimesh.Trimesh(model.vertices, model.faces, process=False)


def truth(rotation: Rotation, translation: np.ndarray) -> np.ndarray:
    """The 4x4 inverse of the motion that moved the second half: what JASNOM must find."""
    inverse = np.eye(4)
    inverse[:3, :3] = rotation.inv().as_matrix()
    inverse[:3, 3] = -rotation.inv().apply(translation)
    return inverse


def moved_half(model: Model, normal, amplitude: float = 0.0, offset: float = 0.0) -> tuple[Model, Model]:
    a, b = split_model(model, normal, amplitude=amplitude, offset=offset)
    return a, transformed(b, MOTION[0].as_matrix(), MOTION[1])


def unwelded(model: Model, where: np.ndarray, noise: float = 0.0) -> Model:
    """``model`` with each face given its own copy of the vertices in ``where`` (a mask), moved by up to
    ``noise``: the duplicated vertices an STL file or a cutting tool leaves."""
    faces = model.faces.copy()
    vertices = [model.vertices]
    count = len(model.vertices)
    rng = np.random.default_rng(1)
    for f, c in zip(*np.nonzero(where[model.faces]), strict=True):
        vertices.append(model.vertices[faces[f, c]][None] + rng.uniform(-noise, noise, (1, 3)))
        faces[f, c] = count
        count += 1
    return Model.untextured(model.name, np.vstack(vertices), faces, model.corner_colors)
