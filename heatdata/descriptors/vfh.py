"""Viewpoint Feature Histogram (Rusu et al. 2010; thesis 3.6.1), computed by PCL's own tools.

Debian's ``pcl-tools`` (PCL 1.13) runs as two processes per view: ``pcl_normal_estimation``
(normals from the neighbours within ``normal_radius``, oriented towards the camera at
the origin) and ``pcl_vfh_estimation`` (the 308-bin VFH: 4 x 45 bins of angles between
the normals and the central direction, 128 viewpoint bins). Without normals PCL's VFH is
silently all zeros, so the normal step always runs and an all-zero result is an error.
The view travels as a binary PCD file in a temporary folder. Compared by the chi-square
distance, after normalizing the histogram to sum 1.
"""

from __future__ import annotations

import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np

from heatdata.descriptors.base import DescriptorSpec, Option, number, register
from heatdata.descriptors.histograms import HistogramKind
from heatdata.errors import ViewError

TOOLS = ("pcl_normal_estimation", "pcl_vfh_estimation")
TIMEOUT = 120  # seconds per tool call


def write_pcd(path: Path, points: np.ndarray) -> None:
    """A binary PCD v0.7 file of (n, 3) points (float32), viewpoint at the origin."""
    x = np.ascontiguousarray(points, dtype="<f4")
    header = (
        f"# .PCD v0.7 - heatdata\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
        f"WIDTH {len(x)}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {len(x)}\nDATA binary\n"
    )
    Path(path).write_bytes(header.encode() + x.tobytes())


def read_vfh(path: Path) -> np.ndarray:
    """The 308 values of the one-point ASCII PCD that ``pcl_vfh_estimation`` writes."""
    text = Path(path).read_text()
    head, sep, data = text.partition("DATA ascii\n")
    if not sep or "FIELDS vfh" not in head:
        raise ViewError(f"{path}: not the ASCII VFH file pcl_vfh_estimation writes")
    return np.array(data.split(), dtype=np.float64)


def _run(command: list[str], name: str) -> None:
    try:
        done = subprocess.run(command, capture_output=True, text=True, timeout=TIMEOUT, check=False)
    except (OSError, subprocess.TimeoutExpired) as exc:
        raise ViewError(f"{name}: {command[0]} failed: {exc}") from exc
    if done.returncode != 0:
        tail = (done.stderr or done.stdout).strip().splitlines()[-3:]
        raise ViewError(f"{name}: {command[0]} exited with {done.returncode}: {' / '.join(tail)}")


class VFH(HistogramKind):
    name = "vfh"
    summary = "Viewpoint Feature Histogram, by PCL's pcl_normal_estimation + pcl_vfh_estimation (thesis 3.6.1)"
    bins = 308
    options = (Option("normal_radius", 0.01, "radius of PCL's normal estimation, metres", number(0.0, 1.0)),)

    def unavailable(self) -> str | None:
        missing = [tool for tool in TOOLS if shutil.which(tool) is None]
        if missing:
            return (
                f"{', '.join(missing)} not found: install Debian's pcl-tools (apt-get install pcl-tools, "
                "or bash scripts/setup.sh --baselines)"
            )
        return None

    def compute(self, work, spec: DescriptorSpec, **context):
        view = work.view
        reason = self.unavailable()
        if reason is not None:
            raise ViewError(f"{view.name}: no vfh here: {reason}")
        self.check_points(view)
        with tempfile.TemporaryDirectory(prefix="heatdata-vfh-") as temporary:
            folder = Path(temporary)
            write_pcd(folder / "view.pcd", view.vertices)
            _run(
                [TOOLS[0], str(folder / "view.pcd"), str(folder / "normals.pcd"), "-radius", f"{spec.normal_radius:g}"],
                view.name,
            )
            _run([TOOLS[1], str(folder / "normals.pcd"), str(folder / "vfh.pcd")], view.name)
            values = read_vfh(folder / "vfh.pcd")
        if values.shape != (self.bins,) or not np.all(np.isfinite(values)) or not values.any():
            raise ViewError(
                f"{view.name}: PCL gave an empty or malformed VFH ({values.shape[0]} values, sum "
                f"{np.nansum(values):g}); are there normals within normal_radius = "
                f"{spec.normal_radius:g} m?"
            )
        return [self.histogram(spec, values, view)]


register(VFH())
