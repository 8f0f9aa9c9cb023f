"""The descriptor comparison of thesis 3.6 (Fig. 3.13-3.15): heat kinds beside the baselines.

Precision against library size for every kind comes from the ordinary evaluation; this
module adds what 3.6.2 looks at beyond it: how each kind's descriptors of boxes change
when holes are cut in the boxes' faces (the ESF's weakness on planar objects, Fig. 3.15),
measured against how much they change between neighbouring view angles.
"""

from __future__ import annotations

import logging

import numpy as np
import pandas as pd
import trimesh

from heatdata.descriptors import DescriptorSpec, describe, distance
from heatdata.errors import HeatdataError
from heatdata.io.models import Model
from heatdata.views.render import render_view

log = logging.getLogger(__name__)

GREY = 0.7


def holed_box(size: tuple[float, float, float], hole: float = 0.0, *, edge: float = 0.004, name: str = "box") -> Model:
    """A grey box of ``size`` metres (x, y, z), meshed at ``edge`` metres, with a round hole in each face.

    ``hole`` is the hole's radius as a fraction of the face's shorter side (0: no hole);
    the triangles whose centroids lie within it of the face's centre are removed.
    """
    if not 0.0 <= hole < 0.5:
        raise HeatdataError(f"{name}: the hole radius must be in [0, 0.5) of the face's shorter side, got {hole}")
    box = trimesh.creation.box(extents=size)
    vertices, faces = trimesh.remesh.subdivide_to_size(box.vertices, box.faces, max_edge=edge)
    if hole > 0:
        half = np.asarray(size) / 2.0
        centroids = vertices[faces].mean(axis=1)
        keep = np.ones(len(faces), dtype=bool)
        for axis in range(3):
            others = [a for a in range(3) if a != axis]
            radius = hole * 2.0 * half[others].min()
            on_face = np.isclose(np.abs(centroids[:, axis]), half[axis])
            keep &= ~(on_face & (np.linalg.norm(centroids[:, others], axis=1) < radius))
        faces = faces[keep]
    return Model.untextured(name, vertices, faces, GREY, label="box", source="heatdata.experiments.holes.holed_box")


def hole_sensitivity(
    specs: list[DescriptorSpec],
    sizes: list,
    *,
    hole: float = 0.3,
    azimuths: int = 16,
    elevation: float = 30.0,
    camera_distance: float = 1.0,
) -> pd.DataFrame:
    """How each kind copes with holes cut in boxes' faces (Fig. 3.14-3.15).

    Each box of ``sizes`` is rendered solid and holed at ``azimuths`` evenly spaced view
    angles, without sensor noise (only the holes and the angle differ). Per kind and
    holed view: ``d_hole``, its distance to the solid box's view at the same angle;
    ``d_step``, the distance between that solid view and the next solid one (360 /
    ``azimuths`` degrees on), the change a descriptor must tolerate anyway; and whether
    its nearest solid view over all boxes (the library) is of its own box.

    Returns
    -------
    pandas.DataFrame
        ``descriptor, kind, box, azimuth, d_hole, d_step, ratio, nearest_box, correct``.
    """
    angles = np.arange(azimuths) * 360.0 / azimuths
    solid, holed, labels = [], [], []
    for k, size in enumerate(sizes):
        label = "x".join(f"{100 * s:.0f}" for s in size) + " cm"
        models = holed_box(size, name=f"box{k}"), holed_box(size, hole, name=f"box{k}-holes")
        for azimuth in angles:
            a, b = (
                describe(render_view(m, azimuth, elevation, camera_distance, noise=False), specs, times=[0.01])
                for m in models
            )
            solid.append(a)
            holed.append(b)
            labels.append(label)
        log.info("holes: box %s described (%d angles, solid and holed)", label, azimuths)
    names = np.array(labels)
    rows = []
    for j, spec in enumerate(specs):
        library = np.stack([d[j].values for d in solid])
        queries = np.stack([d[j].values for d in holed])
        nearest = spec.impl.nearest(queries, library).index
        for i in range(len(holed)):
            following = i + 1 if (i + 1) % azimuths else i + 1 - azimuths  # the next angle of the same box
            d_hole, d_step = distance(solid[i][j], holed[i][j]), distance(solid[i][j], solid[following][j])
            rows.append(
                {
                    "descriptor": spec.name,
                    "kind": spec.kind,
                    "box": names[i],
                    "azimuth": angles[i % azimuths],
                    "d_hole": d_hole,
                    "d_step": d_step,
                    "ratio": d_hole / d_step if d_step > 0 else np.inf,
                    "nearest_box": names[nearest[i]],
                    "correct": names[nearest[i]] == names[i],
                }
            )
    return pd.DataFrame(rows)


def hole_summary(table: pd.DataFrame) -> pd.DataFrame:
    """Per descriptor: the share of holed views recognized as their own box, and the median ``d_hole / d_step``."""
    return (
        table.groupby("descriptor", sort=False)
        .agg(
            kind=("kind", "first"),
            holed_views=("correct", "size"),
            precision=("correct", "mean"),
            median_ratio=("ratio", "median"),
        )
        .reset_index()
    )
