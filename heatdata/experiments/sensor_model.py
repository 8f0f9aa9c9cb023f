"""The depth sensor measured on real frames, and the renderer's sensor profiles fitted to it
(:mod:`heatdata.views.sensor`).

Every measure reads a frame through its own segmentation (:func:`heatdata.segmentation.segment.segment_frame`): the
support plane, and the objects standing on it.

- **noise and quantization against depth**: the table is cut into square windows of :data:`WINDOW` pixels wholly
  on the plane; a plane is fitted to each window's points by least squares, and the residuals' standard deviation
  is the noise at the window's depth; the median gap between its distinct depths is the quantization step there;
- **the ring** round each object (:data:`RING` pixels outside its readings) is where the sensor's edge effects
  are. Each of its pixels is **a hole** (no reading), **on the object** (within :func:`gap` of the nearest object
  reading's depth), **on the table** (within it of the plane), or **between**: a flying pixel, mixed of both sides.
  Those between that stand less than :data:`HALO_HEIGHT` above the plane are **the halo** round an object's base,
  the readings that bridge neighbours in a segmentation;
- **holes on dark surfaces**: inside each object's region (its readings and the holes they enclose), the share
  without a reading in bins of the colour's luminance (Rec. 709).

:func:`fit_profile` turns them into a :class:`heatdata.views.sensor.SensorProfile`: the noise coefficient ``tau``
of ``sigma = tau z^2`` (the depth image's own unit step's variance taken out), and the share of flying pixels
scaled by what the renderer's own profile gives on rendered frames measured the same way.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy import ndimage

from heatdata.segmentation.segment import Segmentation, segment_frame
from heatdata.views.depth import back_project

#: pixels on a side of the windows a plane is fitted to (noise and quantization)
WINDOW = 12
#: the share of a window's pixels that must be plane readings
WINDOW_FULL = 0.95
#: pixels on a side of an object's ring
RING = 3
#: a ring reading between object and table that stands less than this above the plane is the halo (metres)
HALO_HEIGHT = 0.02
#: the luminance bins of the dark-surface measure
LUMINANCE_BINS = (0.0, 0.05, 0.1, 0.2, 0.4, 1.0)
#: the depth bins of the noise table (metres)
DEPTH_BIN = 0.1


def gap(depth: np.ndarray | float, tau: float = 1.5e-3) -> np.ndarray:
    """How far a reading may lie from a surface and still be on it: three standard deviations of the Kinect-class
    noise ``tau z^2`` at its depth, at least 5 mm (metres)."""
    return np.maximum(3.0 * tau * np.square(depth), 0.005)


@dataclass
class FrameMeasures:
    """What one frame shows of its sensor.

    Attributes
    ----------
    windows : pandas.DataFrame
        ``depth, sigma, step`` per plane window (metres).
    ring : dict
        Pixel counts of the objects' rings: ``ring``, ``hole``, ``object``, ``table``, ``between``, ``halo``.
    dark : pandas.DataFrame
        ``luminance`` bin (its lower edge), ``pixels`` and ``holes`` inside the objects' regions.
    """

    windows: pd.DataFrame
    ring: dict
    dark: pd.DataFrame


def measure_frame(
    depth: np.ndarray, intrinsics: dict, rgb: np.ndarray | None = None, segmentation: Segmentation | None = None
) -> FrameMeasures:
    """The module's measures of one frame.

    Parameters
    ----------
    depth : (h, w) float
        Metres; 0, NaN or infinite where there is no reading.
    intrinsics : dict
    rgb : (h, w, 3) uint8 or float in [0, 1], optional
        The colour, for the dark-surface measure (none without it).
    segmentation : Segmentation, optional
        The frame's, when the caller has it.

    Returns
    -------
    FrameMeasures
    """
    depth = np.where(np.isfinite(depth) & (depth > 0), depth, np.nan)
    found = segmentation or segment_frame(depth, intrinsics, rgb)
    points = back_project(depth, intrinsics)
    empty = FrameMeasures(pd.DataFrame(columns=["depth", "sigma", "step"]), {}, pd.DataFrame())
    if found.plane is None:
        return empty
    normal, offset = np.asarray(found.plane[:3], float), float(found.plane[3])
    height = points @ normal + offset
    objects = np.zeros(depth.shape, bool)
    for segment in found.segments:
        objects |= segment.mask
    read = np.isfinite(depth)
    table = read & (np.abs(height) < gap(depth)) & ~ndimage.binary_dilation(objects, iterations=RING)
    return FrameMeasures(
        _plane_windows(points, table),
        _ring(depth, points, height, objects, read, intrinsics, normal, offset),
        _dark(objects, read, rgb),
    )


def _plane_windows(points: np.ndarray, table: np.ndarray) -> pd.DataFrame:
    rows = []
    h, w = table.shape
    for v in range(0, h - WINDOW + 1, WINDOW):
        for u in range(0, w - WINDOW + 1, WINDOW):
            inside = table[v : v + WINDOW, u : u + WINDOW]
            if inside.mean() < WINDOW_FULL:
                continue
            p = points[v : v + WINDOW, u : u + WINDOW][inside]
            design = np.c_[p[:, 0], p[:, 1], np.ones(len(p))]
            fitted, *_ = np.linalg.lstsq(design, p[:, 2], rcond=None)
            levels = np.unique(np.round(p[:, 2], 6))
            step = float(np.median(np.diff(levels))) if len(levels) > 2 else np.nan
            rows.append((float(np.median(p[:, 2])), float(np.std(p[:, 2] - design @ fitted)), step))
    return pd.DataFrame(rows, columns=["depth", "sigma", "step"])


def _ring(depth, points, height, objects, read, intrinsics, normal, offset) -> dict:
    ring = ndimage.binary_dilation(objects, iterations=RING) & ~objects
    _, (rows, cols) = ndimage.distance_transform_edt(~objects, return_indices=True)
    nearest_object = depth[rows, cols]  # the depth of each pixel's nearest object reading
    k = intrinsics
    v, u = np.mgrid[0 : depth.shape[0], 0 : depth.shape[1]]
    ray = np.stack([(u - k["cx"]) / k["fx"], (v - k["cy"]) / k["fy"], np.ones(depth.shape)], axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        table_depth = -offset / (ray @ normal)  # where each pixel's ray meets the plane
    reading = ring & read
    tolerance = gap(depth)
    on_object = reading & (np.abs(depth - nearest_object) < tolerance)
    on_table = reading & ~on_object & (np.abs(depth - table_depth) < tolerance)
    between = reading & ~on_object & ~on_table
    return {
        "ring": int(ring.sum()),
        "hole": int((ring & ~read).sum()),
        "object": int(on_object.sum()),
        "table": int(on_table.sum()),
        "between": int(between.sum()),
        "halo": int((between & (height < HALO_HEIGHT)).sum()),
    }


def _dark(objects: np.ndarray, read: np.ndarray, rgb: np.ndarray | None) -> pd.DataFrame:
    if rgb is None:
        return pd.DataFrame(columns=["luminance", "pixels", "holes"])
    colour = np.asarray(rgb, np.float64)
    colour = colour / 255.0 if np.asarray(rgb).dtype.kind in "ui" else colour
    luminance = colour @ np.array([0.2126, 0.7152, 0.0722])
    region = ndimage.binary_fill_holes(ndimage.binary_closing(objects, iterations=2))
    edges = np.asarray(LUMINANCE_BINS)
    which = np.clip(np.digitize(luminance, edges) - 1, 0, len(edges) - 2)
    rows = [
        (float(edges[b]), int((region & (which == b)).sum()), int((region & (which == b) & ~read).sum()))
        for b in range(len(edges) - 1)
    ]
    return pd.DataFrame(rows, columns=["luminance", "pixels", "holes"])


def pooled(measures: list[FrameMeasures], sensor: str) -> dict[str, pd.DataFrame | dict]:
    """Several frames' measures pooled: the noise table by depth, the ring's shares and the dark surfaces' holes.

    Parameters
    ----------
    measures : list of FrameMeasures
    sensor : str
        Its name, a column of each table.

    Returns
    -------
    dict
        ``noise``: ``sensor, depth`` (the bin's centre), ``windows``, ``sigma`` and ``step`` (medians, metres);
        ``ring``: the shares of the ring's pixels (``hole, object, table, between, halo``) and ``pixels``;
        ``dark``: ``sensor, luminance, pixels, holes, share``.
    """
    windows = pd.concat([m.windows for m in measures], ignore_index=True)
    bins = np.floor(windows["depth"] / DEPTH_BIN) * DEPTH_BIN + DEPTH_BIN / 2
    noise = (
        windows.assign(bin=bins.round(3))
        .groupby("bin")
        .agg(windows=("sigma", "size"), sigma=("sigma", "median"), step=("step", "median"))
        .reset_index()
        .rename(columns={"bin": "depth"})
        .assign(sensor=sensor)
    )
    totals = pd.DataFrame([m.ring for m in measures if m.ring]).sum()
    ring = {key: float(totals[key] / totals["ring"]) for key in ("hole", "object", "table", "between", "halo")}
    dark_rows = [m.dark for m in measures if not m.dark.empty]
    dark = pd.DataFrame(columns=["luminance", "pixels", "holes"])
    if dark_rows:
        dark = pd.concat(dark_rows).groupby("luminance", as_index=False)[["pixels", "holes"]].sum()
    dark = dark.assign(sensor=sensor, share=dark["holes"] / dark["pixels"].where(dark["pixels"] > 0))
    return {"noise": noise, "ring": {"sensor": sensor, "pixels": int(totals["ring"]), **ring}, "dark": dark}


def fit_tau(noise: pd.DataFrame, unit: float = 0.0, min_windows: int = 20) -> float:
    """The noise coefficient ``tau`` of ``sigma = tau z^2`` (thesis 2.6.1) that fits a noise table best.

    Parameters
    ----------
    noise : pandas.DataFrame
        :func:`pooled`'s ``noise``.
    unit : float
        The depth image's step (1 mm for a uint16 PNG in millimetres): its variance ``unit^2 / 12`` is taken out of
        each bin's.
    min_windows : int
        Bins of fewer windows are left out.

    Returns
    -------
    float
        1/m; least squares over the bins, each weighed by its windows.
    """
    used = noise[noise["windows"] >= min_windows]
    variance = np.maximum(np.square(used["sigma"]) - unit**2 / 12.0, 0.0)
    z2 = np.square(used["depth"])
    weights = used["windows"]
    return float(np.sum(weights * np.sqrt(variance) * z2) / np.sum(weights * z2 * z2))
