"""heatdata: heat-diffusion descriptors of partial 3D views (Brandao 2015).

>>> import heatdata as hd
>>> model = hd.load_model(hd.embedded_catalog().parent / "beer-mug/beerGlass.obj", size=(0.154, 0.165, 0.102))
>>> view = hd.render_view(model, azimuth=30.0, elevation=45.0, distance=1.0, noise=True, seed=0)
>>> d = hd.pvhk(view, samples=64, source="closest")

The package's stages, each a subpackage that imports only those before it:

- :mod:`heatdata.core`: mesh topology, the Laplace-Beltrami spectrum and heat, the MHD (thesis ch. 2, 3.2);
- :mod:`heatdata.io`: models, catalogues, Sweet Home 3D libraries, Parquet tables, MakeHuman bodies;
- :mod:`heatdata.views`: the :class:`View`, the virtual Kinect, depth frames;
- :mod:`heatdata.frames`: frames as sensors and PCL write them (PCD, range maps and grids), and
  :mod:`heatdata.segmentation`: a frame cut into the objects on its support plane;
- :mod:`heatdata.descriptors`: every descriptor kind (PVHK and its family, PVST, the baselines) and heat sources;
- :mod:`heatdata.recognition`, :mod:`heatdata.jasnom`, :mod:`heatdata.rump`: the thesis's uses of them;
- :mod:`heatdata.experiments`: the workflow's steps; :mod:`heatdata.reporting`: figures and pages;
  :mod:`heatdata.cli`: the ``heatdata`` command.

``import heatdata as hd`` offers the user's path, from a model to a recognized frame: models and catalogues,
views and depth frames, descriptor specs and ``describe``, libraries and their answers, JASNOM's stitches, the
body-condition score and the errors. The rest (spectra and heat, distances, heat sources, compact-library costs,
the multi-view filters, metrics) is reached through its module, as ``from heatdata.core.distances import mhd``.
Those names were once at the top level too: they still resolve there, with a DeprecationWarning that names their
module, until version 0.3.

The descriptors, the errors and the :class:`View` are imported with the package; the other names are imported
the first time one is used (``hd.render_view`` imports open3d, ``hd.load_model`` trimesh), so a job that only
compares descriptor tables loads neither (nor matplotlib).
"""

import importlib
import warnings
from typing import Any

from heatdata.descriptors import (
    DESCRIPTORS,
    Descriptor,
    DescriptorSpec,
    c_pvhk,
    describe,
    distance,
    fit_spec,
    ft_pvhk,
    pvhk,
    pvst,
)
from heatdata.errors import (
    ConfigError,
    HeatdataError,
    LibraryError,
    ModelError,
    OutputError,
    RenderError,
    RumpError,
    SpecError,
    SpectrumError,
    StitchError,
    ViewError,
)
from heatdata.version import __version__
from heatdata.views.view import View, kinect_intrinsics

#: the user's path beyond the names imported above, imported on first use, by module
_LAZY = {
    "heatdata.io.catalog": ["catalog_from_folder", "embedded_catalog", "load_catalog_model", "read_catalog"],
    "heatdata.io.models": ["Model", "load_model"],
    "heatdata.io.sh3f": ["import_sh3f"],
    "heatdata.frames.clouds": ["read_organized_cloud"],
    "heatdata.views.depth": ["read_depth", "read_depth_frame", "view_from_depth", "write_depth"],
    "heatdata.views.render": ["Placement", "render_scene", "render_view"],
    "heatdata.segmentation.segment": ["SegmentSettings", "segment_frame"],
    "heatdata.views.sensor": ["SensorProfile"],
    "heatdata.recognition.library": ["Library", "load_library"],
    "heatdata.recognition.answers": ["Detection", "Match", "Recognition", "SceneRecognition", "SequenceStep"],
    "heatdata.recognition.confidence": ["Confidence"],
    "heatdata.recognition.pose": ["Pose"],
    "heatdata.jasnom.cuts": ["split_model"],
    "heatdata.jasnom.seam": ["Stitched", "stitch", "stitch_scans"],
    "heatdata.jasnom.table": ["TableScan", "table_scan"],
    "heatdata.rump": ["hbrd"],
}
#: names that have moved off the top level: each resolves from its module, with a DeprecationWarning
_MOVED = {
    "heatdata.core.distances": [
        "Nearest",
        "NearestPair",
        "chi_square_matrix",
        "mhd",
        "mhd_matrix",
        "nearest_pair_mhd",
        "weighted_mhd",
    ],
    "heatdata.core.spectrum": [
        "HeatModel",
        "HeatOperator",
        "Spectrum",
        "eigen_spectrum",
        "first_crossings",
        "heat_model",
        "krylov_heat",
        "lambda2",
        "laplacian",
    ],
    "heatdata.descriptors": [
        "COLOR_MAPS",
        "global_derivative",
        "heat_kernel",
        "object_time_scale",
        "part_weights",
        "sample_boundary",
        "source_vertex",
        "view_time_scale",
    ],
    "heatdata.descriptors.sources": ["candidate_descriptors", "candidate_sources"],
    "heatdata.io.models": ["hue_rotated", "transformed"],
    "heatdata.views.render": ["camera_pose"],
    "heatdata.recognition.pose": ["Surface", "pose_errors", "sample_surface"],
    "heatdata.recognition.compact": ["combined_costs", "consecutive_costs", "other_object_distances", "select_sources"],
    "heatdata.recognition.evaluate": ["library_subset"],
    "heatdata.recognition.metrics": ["confusion_matrix", "precision_by"],
    "heatdata.recognition.multiview.appearance": ["AppearanceModel", "appearance_model", "learn_similarity"],
    "heatdata.recognition.multiview.filters": ["ExhaustiveFilter", "ParticleFilter"],
    "heatdata.recognition.nearest": ["classify_candidates", "nearest_neighbors"],
    "heatdata.jasnom.align": ["Alignment", "align"],
    "heatdata.jasnom.cuts": ["closed_part"],
    "heatdata.rump": ["rump_heat"],
}
_MODULE_OF = {name: module for module, names in _LAZY.items() for name in names}
_MOVED_TO = {name: module for module, names in _MOVED.items() for name in names}
# a literal list, as type checkers read a typed package's exports; tests/test_api.py checks it against the imports
# above and _LAZY
__all__ = [
    "DESCRIPTORS",
    "Confidence",
    "ConfigError",
    "Descriptor",
    "DescriptorSpec",
    "Detection",
    "HeatdataError",
    "Library",
    "LibraryError",
    "Match",
    "Model",
    "ModelError",
    "OutputError",
    "Placement",
    "Pose",
    "Recognition",
    "RenderError",
    "RumpError",
    "SceneRecognition",
    "SegmentSettings",
    "SensorProfile",
    "SequenceStep",
    "SpecError",
    "SpectrumError",
    "StitchError",
    "Stitched",
    "TableScan",
    "View",
    "ViewError",
    "__version__",
    "c_pvhk",
    "catalog_from_folder",
    "describe",
    "distance",
    "embedded_catalog",
    "fit_spec",
    "ft_pvhk",
    "hbrd",
    "import_sh3f",
    "kinect_intrinsics",
    "load_catalog_model",
    "load_library",
    "load_model",
    "pvhk",
    "pvst",
    "read_catalog",
    "read_depth",
    "read_depth_frame",
    "read_organized_cloud",
    "render_scene",
    "render_view",
    "segment_frame",
    "split_model",
    "stitch",
    "stitch_scans",
    "table_scan",
    "view_from_depth",
    "write_depth",
]


def __getattr__(name: str) -> Any:
    if name in _MOVED_TO:
        warnings.warn(
            f"heatdata.{name} has moved: import it from {_MOVED_TO[name]} (the top level keeps the user's path; "
            "the old name goes in 0.3)",
            DeprecationWarning,
            stacklevel=2,
        )
        return getattr(importlib.import_module(_MOVED_TO[name]), name)
    if name not in _MODULE_OF:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(_MODULE_OF[name]), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
