"""Cut models for JASNOM's experiments: the closed part of a mesh."""

import numpy as np
import pytest
import trimesh
from meshes import as_trimesh

from heatdata.errors import StitchError
from heatdata.io.models import Model
from heatdata.jasnom.cuts import closed_part, split_model


def test_the_closed_part_merges_seams_keeps_the_largest_piece_and_faces_outwards(ellipsoid):
    seamed = ellipsoid.faces.copy()
    copies = len(ellipsoid.vertices) + np.arange(3)  # the first face's corners duplicated, as at a texture seam
    seamed[0] = copies
    vertices = np.vstack([ellipsoid.vertices, ellipsoid.vertices[ellipsoid.faces[0]]])
    speck = trimesh.creation.icosphere(subdivisions=0, radius=0.01)  # a small separate piece
    faces = np.vstack([seamed, speck.faces + len(vertices)])[:, ::-1]  # and everything wound inwards
    vertices = np.vstack([vertices, speck.vertices + 1.0])
    messy = Model.untextured("messy", vertices, faces, (0.0, 0.0, 0.0))
    part = closed_part(messy)
    mesh = as_trimesh(part)
    assert len(part.faces) == len(ellipsoid.faces) and mesh.is_watertight and mesh.volume > 0
    with pytest.raises(StitchError, match="not closed"):
        closed_part(split_model(ellipsoid, [0.0, 1.0, 0.0])[0])
