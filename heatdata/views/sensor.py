"""What a structured-light depth sensor does to the true depth: the Kinect's sensor profile (thesis 2.1, 2.6.1).

A :class:`SensorProfile` turns a ray-cast z-depth image into what a Kinect would report. Each effect is an option,
off when its number is 0:

- **depth noise** (2.6.1): ``z = z0 + z0^2 eps``, ``eps ~ N(0, tau^2)``, ``tau = 1.42e-3`` 1/m;
- **the projector's shadow**: the Kinect sees the pattern its projector casts from ``baseline`` metres to the
  camera's right (+x); a surface the camera sees but the projector does not gets no depth, the band beside
  each object's left edge (cast by :func:`heatdata.views.render.render_scene` and :func:`heatdata.render_view`,
  which know the scene);
- **disparity quantization**: depth comes from a disparity ``d = fx b / z`` measured in steps of
  ``disparity_step`` pixels (1/8 at fx = 580 px and b = 7.5 cm: about 2.9 mm at 1 m, 11.5 mm at 2 m);
- **flying pixels**: block matching mixes the two sides of a depth edge, so a share of the pixels along each
  edge reads a depth between the near and the far surface;
- **dark surfaces**: the infrared pattern is not seen on very dark (or absorbing) surfaces; pixels whose colour's
  luminance is below ``dark`` get no depth (the rendered colour stands in for the infrared albedo);
- **the stored unit**: a depth image of whole millimetres (uint16 PNG) rounds every reading to ``depth_unit``.

``SENSORS`` names the profiles: ``ideal`` (none of them), ``noise`` (the depth noise only: what every view had
before this profile, and still the workflow's default), ``kinect`` (all of them) and ``realsense`` (an active
stereo camera of the RealSense D400 kind). ``kinect`` and ``realsense`` are fitted to real frames
(:mod:`heatdata.experiments.sensor_model`, ``docs/guide/sensors.md``): the Kinect's to mOSD's 56 table-tops, the
RealSense's to the YCB table-tops of ``realdata/``. Rendered frames remain renderings, not sensor data.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields

import numpy as np

from heatdata.errors import RenderError

KINECT_TAU = 1.42e-3  # 1/m, depth noise of 2.6.1
KINECT_BASELINE = 0.075  # m, projector to infrared camera
KINECT_DISPARITY_STEP = 1.0 / 8.0  # pixels of disparity per step at fx = 580 px
EDGE_JUMP = 0.02  # relative depth step between neighbouring pixels that makes a depth edge (as the triangulation)


@dataclass(frozen=True)
class SensorProfile:
    """The effects a depth sensor adds to a rendered depth image (see the module docstring).

    Attributes
    ----------
    tau : float
        Depth noise, 1/m (2.6.1); 0: none.
    baseline : float
        Projector to camera along +x, metres: the disparity's baseline, and where shadows are cast from.
    shadows : bool
        No depth where the projector's light does not reach.
    disparity_step : float
        Disparity quantization step, pixels; 0: none.
    flying_pixels : float
        Share of the pixels on each side of a depth edge that read a depth between both sides; 0: none.
    dark : float
        No depth where the colour's luminance (Rec. 709, in [0, 1]) is below this; 0: none.
    depth_unit : float
        The stored depth's step, metres (0.001: a uint16 image in millimetres); 0: none.
    """

    tau: float = KINECT_TAU
    baseline: float = KINECT_BASELINE
    shadows: bool = True
    disparity_step: float = KINECT_DISPARITY_STEP
    flying_pixels: float = 0.5
    dark: float = 0.04
    depth_unit: float = 0.0

    def __post_init__(self) -> None:
        bad = [
            f"{name}={getattr(self, name)!r}"
            for name in ("tau", "baseline", "disparity_step", "flying_pixels", "dark", "depth_unit")
            if isinstance(getattr(self, name), bool)
            or not isinstance(getattr(self, name), (int, float))
            or not np.isfinite(getattr(self, name))
            or getattr(self, name) < 0
        ]
        if not bad and self.flying_pixels > 1:
            bad.append(f"flying_pixels={self.flying_pixels} (a share in [0, 1])")
        if not bad and self.dark >= 1:
            bad.append(f"dark={self.dark} (a luminance below 1)")
        if not bad and self.baseline == 0 and (self.shadows or self.disparity_step):
            bad.append("baseline=0 with shadows or disparity_step (both need the projector's offset)")
        if bad:
            raise RenderError(f"bad sensor profile: {', '.join(bad)}")

    @classmethod
    def named(cls, profile: str | dict | SensorProfile | None) -> SensorProfile:
        """A profile by name (:data:`SENSORS`), from a mapping of its fields, or itself.

        Parameters
        ----------
        profile : str, dict, SensorProfile or None
            ``"ideal"``, ``"noise"``, ``"kinect"`` or ``"realsense"``; a mapping with ``profile`` (a name to start
            from) and any field to change; None: ``"noise"``.

        Returns
        -------
        SensorProfile
        """
        if isinstance(profile, SensorProfile):
            return profile
        if profile is None:
            return SENSORS["noise"]
        if isinstance(profile, str):
            if profile not in SENSORS:
                raise RenderError(f"unknown sensor profile {profile!r} (use {', '.join(SENSORS)})")
            return SENSORS[profile]
        if isinstance(profile, dict):
            changes = dict(profile)
            base = cls.named(changes.pop("profile", "kinect"))
            unknown = sorted(set(changes) - {f.name for f in fields(cls)})
            if unknown:
                raise RenderError(
                    f"a sensor profile has no {', '.join(unknown)} (its fields: {', '.join(asdict(base))})"
                )
            return cls(**{**asdict(base), **changes})
        raise RenderError(f"a sensor profile is a name or a mapping, got {profile!r}")

    def to_dict(self) -> dict:
        """The fields as plain types (a table's metadata, a scene's ground truth).

        Returns
        -------
        dict
            Each field's value by name.
        """
        return asdict(self)

    def measure(self, depth: np.ndarray, colors: np.ndarray | None, fx: float, rng: np.random.Generator) -> np.ndarray:
        """What the sensor reports for a true z-depth image: noise, flying pixels, quantization and dark surfaces.

        The projector's shadow needs the scene and is applied by the renderer before this.

        Parameters
        ----------
        depth : (h, w) float
            True z-depth, metres; NaN where there is no surface.
        colors : (h, w, 3) float in [0, 1], optional
            The surface's colour at each pixel (for ``dark``).
        fx : float
            The focal length in pixels (the disparity's scale).
        rng : numpy.random.Generator
            The source of the noise and of the flying pixels.

        Returns
        -------
        (h, w) float64
            The measured depth, NaN where the sensor gives no reading.
        """
        z = np.array(depth, dtype=np.float64)
        valid = np.isfinite(z)
        if self.dark and colors is not None:
            luminance = np.asarray(colors, np.float64) @ np.array([0.2126, 0.7152, 0.0722])
            z[valid & (luminance < self.dark)] = np.nan
            valid = np.isfinite(z)
        if self.tau:
            z[valid] += z[valid] ** 2 * rng.normal(0.0, self.tau, int(valid.sum()))
        if self.flying_pixels:
            z = _flying_pixels(z, self.flying_pixels, rng)
        if self.disparity_step:
            z = quantize_depth(z, fx, self.baseline, self.disparity_step)
        if self.depth_unit:
            z = np.round(z / self.depth_unit) * self.depth_unit
        return z


def quantize_depth(depth: np.ndarray, fx: float, baseline: float, step: float) -> np.ndarray:
    """Depth measured through a disparity ``fx baseline / z`` rounded to ``step`` pixels.

    Parameters
    ----------
    depth : (h, w) float
        Metres, NaN where there is no reading.
    fx, baseline, step : float
        Focal length (pixels), baseline (metres), disparity step (pixels).

    Returns
    -------
    (h, w) float64
        The depth of the nearest disparity step (NaN stays NaN; a disparity that rounds to 0 is no reading).
    """
    scale = fx * baseline
    with np.errstate(divide="ignore", invalid="ignore"):
        disparity = np.round(scale / np.asarray(depth, np.float64) / step) * step
        z = scale / disparity
    z[~np.isfinite(z) | (disparity <= 0)] = np.nan
    return z


def depth_edges(depth: np.ndarray, jump: float = EDGE_JUMP) -> tuple[np.ndarray, np.ndarray]:
    """The pixels on either side of a depth edge, and the depth across it.

    Parameters
    ----------
    depth : (h, w) float
        Metres, NaN where there is no reading.
    jump : float
        Neighbours whose depths differ by more than ``jump`` times their mean make an edge.

    Returns
    -------
    edge : (h, w) bool
        Pixels with a 4-neighbour across an edge.
    other : (h, w) float64
        For each edge pixel, the depth of its neighbour across the edge with the largest step (NaN elsewhere).
    """
    z = np.asarray(depth, np.float64)
    other = np.full(z.shape, np.nan)
    best = np.zeros(z.shape)
    for axis in (0, 1):
        for shift in (1, -1):
            neighbour = np.full(z.shape, np.nan)
            source = [slice(None), slice(None)]
            target = [slice(None), slice(None)]
            source[axis] = slice(None, -1) if shift == 1 else slice(1, None)
            target[axis] = slice(1, None) if shift == 1 else slice(None, -1)
            neighbour[tuple(target)] = z[tuple(source)]
            with np.errstate(invalid="ignore"):
                step = np.abs(neighbour - z)
                larger = np.isfinite(step) & (step > jump * 0.5 * (neighbour + z)) & (step > best)
            best[larger] = step[larger]
            other[larger] = neighbour[larger]
    return np.isfinite(other), other


def _flying_pixels(depth: np.ndarray, share: float, rng: np.random.Generator) -> np.ndarray:
    """A ``share`` of the pixels along depth edges moved to a random depth between the two sides."""
    edge, other = depth_edges(depth)
    pick = edge & (rng.random(depth.shape) < share)
    mixed = depth.copy()
    weight = rng.uniform(0.1, 0.9, int(pick.sum()))
    mixed[pick] = depth[pick] + weight * (other[pick] - depth[pick])
    return mixed


#: the named profiles: no effect, the depth noise of 2.6.1 alone (the default), the Kinect's and a RealSense's.
#: ``kinect`` and ``realsense`` are fitted to real frames measured as rendered ones are
#: (:mod:`heatdata.experiments.sensor_model`, ``docs/results/sensor_model.csv``): the noise coefficient so that a
#: rendered table's noise matches a real one's (the disparity steps add their own, so a Kinect's is below the
#: thesis's 1.42e-3, which its real tables measure), the flying pixels so that the share of readings between object
#: and table round each object matches (8.9% on mOSD, 5.4% on the YCB frames)
SENSORS: dict[str, SensorProfile] = {
    "ideal": SensorProfile(tau=0.0, shadows=False, disparity_step=0.0, flying_pixels=0.0, dark=0.0),
    "noise": SensorProfile(shadows=False, disparity_step=0.0, flying_pixels=0.0, dark=0.0),
    "kinect": SensorProfile(tau=1.1e-3, flying_pixels=0.35),
    "realsense": SensorProfile(
        tau=0.64e-3, baseline=0.055, disparity_step=1.0 / 32.0, flying_pixels=0.25, dark=0.0, depth_unit=0.001
    ),
}
