"""Flat lattice views for the heat kinds' tests: a grid over a mask, and the squares of thesis Fig. 5.4."""

import numpy as np

import heatdata as hd


def lattice_view(mask: np.ndarray, spacing: float = 0.002, name: str = "lattice") -> hd.View:
    """A flat grid mesh over the True cells of a (rows, cols) mask (a cell needs all 4 corners)."""
    ny, nx = mask.shape
    index = -np.ones(mask.shape, int)
    index[mask] = np.arange(mask.sum())
    ys, xs = np.nonzero(mask)
    vertices = np.column_stack([(xs - nx / 2) * spacing, (ys - ny / 2) * spacing, np.ones(len(xs))])
    a, b, c, d = index[:-1, :-1], index[:-1, 1:], index[1:, :-1], index[1:, 1:]
    keep = (a >= 0) & (b >= 0) & (c >= 0) & (d >= 0)
    faces = np.concatenate([np.column_stack([a[keep], b[keep], c[keep]]), np.column_stack([b[keep], d[keep], c[keep]])])
    return hd.View.from_arrays(vertices, faces, view_id=name)


def squares(bottleneck: bool) -> np.ndarray:
    """Fig. 5.4: a 21x21 square, alone or joined to a 9x9 square by a one-cell-wide bottleneck."""
    mask = np.zeros((21, 42), bool)
    mask[:, :21] = True
    if bottleneck:
        mask[9:11, 21:33] = True
        mask[6:15, 33:42] = True
    return mask
