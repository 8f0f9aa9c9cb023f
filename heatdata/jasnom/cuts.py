"""Models cut in two and closed parts: the test objects of JASNOM (thesis 7.5)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from numpy.typing import ArrayLike

from heatdata.core.mesh import (
    boundary_loops,
    component_labels,
    consistent_winding,
    mesh_edges,
)
from heatdata.errors import StitchError
from heatdata.io.models import Model, reversed_faces
from heatdata.jasnom.boundary import _manifold_edges


def _submodel(model: Model, keep: np.ndarray, name: str) -> Model:
    used = np.unique(model.faces[keep])
    index = np.full(len(model.vertices), -1, np.int64)
    index[used] = np.arange(len(used))
    return Model(
        name=name,
        vertices=model.vertices[used],
        faces=index[model.faces[keep]],
        corner_colors=model.corner_colors[keep],
        corner_uv=model.corner_uv[keep],
        face_texture=model.face_texture[keep],
        textures=list(model.textures),
        label=model.label,
        source=model.source,
        repairs=list(model.repairs),
    )


def split_model(
    model: Model, normal: ArrayLike, *, offset: float = 0.0, amplitude: float = 0.0, waves: int = 3
) -> tuple[Model, Model]:
    """Cut a model in two along its edges: the ground truth of the JASNOM experiments.

    Each face goes to the side of the surface ``n . (c - centre) = size * (offset +
    amplitude * sin(waves * phi))`` its centroid c lies on (a plane for ``amplitude`` 0, a
    wavy cut otherwise; phi is the angle about ``n``, size the bounding-box diagonal). The
    halves share their boundary vertices' positions exactly.

    Parameters
    ----------
    model : Model
        A closed mesh.
    normal : (3,) float
        The cut's normal n (any length).
    offset : float
        The cut's distance from the centre, a fraction of the bounding-box diagonal.
    amplitude : float
        The wave's height, the same fraction (0: a plane).
    waves : int
        Periods of the wave around n.

    Returns
    -------
    first, second : Model
        The faces on the positive side of the cut, and the rest.
    """
    n = np.asarray(normal, dtype=np.float64)
    n = n / np.linalg.norm(n)
    centroids = model.vertices[model.faces].mean(axis=1) - model.center
    u = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    v = np.cross(n, u)
    phi = np.arctan2(centroids @ v, centroids @ u)
    size = float(np.linalg.norm(model.extents))
    side = centroids @ n > size * (offset + amplitude * np.sin(waves * phi))
    if side.all() or not side.any():
        raise StitchError(f"{model.name}: the cut leaves every face on one side")
    return _submodel(model, side, f"{model.name}-a"), _submodel(model, ~side, f"{model.name}-b")


def closed_part(model: Model, tolerance: float = 1e-6) -> Model:
    """The largest closed 2-manifold piece of a model, or a :class:`StitchError` saying why there is none.

    Vertices closer than ``tolerance`` times the bounding-box diagonal are merged (files
    split vertices at texture seams), faces that collapse are dropped, and the connected
    piece with the most faces is kept if every edge of it has exactly two faces.

    Parameters
    ----------
    model : Model
        Any mesh.
    tolerance : float
        Vertices closer than this fraction of the bounding-box diagonal are one.

    Returns
    -------
    Model
        The piece, named ``model.name``.
    """
    size = float(np.linalg.norm(model.extents))
    keys = np.round(model.vertices / (tolerance * size)).astype(np.int64)
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    faces = first[inverse.ravel()][model.faces]
    good = (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])
    _, unique = np.unique(np.sort(faces, axis=1), axis=0, return_index=True)
    keep = np.zeros(len(faces), dtype=bool)
    keep[unique] = True
    keep &= good
    n = len(model.vertices)
    component = component_labels(mesh_edges(faces[keep], n), n)
    counts = np.bincount(component[faces[keep][:, 0]], minlength=component.max() + 1)
    keep &= component[faces[:, 0]] == int(np.argmax(counts))
    part = _submodel(replace(model, faces=faces), keep, model.name)
    _manifold_edges(part.faces, model.name)
    faces, flipped = consistent_winding(part.faces)
    if flipped or boundary_loops(faces):
        raise StitchError(f"{model.name}: its largest piece ({len(faces)} faces) is not closed and consistently wound")
    corners = part.vertices[part.faces]
    if np.einsum("ij,ij->i", corners[:, 0], np.cross(corners[:, 1], corners[:, 2])).sum() < 0:  # wound inwards
        part = reversed_faces(part)
    return part
