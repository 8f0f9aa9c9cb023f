"""heatdata: heat-diffusion descriptors of partial 3D views (Brandao 2015).

>>> import heatdata as hd
>>> model = hd.load_model(hd.embedded_catalog().parent / "beer-mug/beerGlass.obj", size=(0.154, 0.165, 0.102))
>>> view = hd.render_view(model, azimuth=30.0, elevation=45.0, distance=1.0, noise=True, seed=0)
>>> d = hd.pvhk(view, samples=64, source="closest")

The package's stages, each a subpackage that imports only those before it:

- :mod:`heatdata.core`: mesh topology, the Laplace-Beltrami spectrum and heat, the MHD (thesis ch. 2, 3.2);
- :mod:`heatdata.io`: models, catalogues, Sweet Home 3D libraries, Parquet tables, MakeHuman bodies;
- :mod:`heatdata.views`: the :class:`View`, the virtual Kinect, depth frames and organized clouds;
- :mod:`heatdata.descriptors`: every descriptor kind (PVHK and its family, PVST, the baselines) and heat sources;
- :mod:`heatdata.recognition`, :mod:`heatdata.jasnom`, :mod:`heatdata.rump`: the thesis's uses of them;
- :mod:`heatdata.experiments`: the workflow's steps; :mod:`heatdata.reporting`: figures and pages;
  :mod:`heatdata.cli`: the ``heatdata`` command.

The names below are what ``import heatdata as hd`` offers. The descriptors, distances, spectra and views
are imported with the package; the other names are imported the first time one is used
(``hd.render_view`` imports open3d, ``hd.load_model`` trimesh), so a job that only compares descriptor
tables loads neither (nor matplotlib).
"""

import importlib
from typing import Any

from heatdata.core.distances import (
    Nearest,
    NearestPair,
    chi_square_matrix,
    mhd,
    mhd_matrix,
    nearest_pair_mhd,
    weighted_mhd,
)
from heatdata.core.spectrum import (
    HeatModel,
    HeatOperator,
    Spectrum,
    eigen_spectrum,
    first_crossings,
    heat_model,
    krylov_heat,
    lambda2,
    laplacian,
)
from heatdata.descriptors import (
    COLOR_MAPS,
    DESCRIPTORS,
    Descriptor,
    DescriptorSpec,
    c_pvhk,
    describe,
    distance,
    fit_spec,
    ft_pvhk,
    global_derivative,
    heat_kernel,
    object_time_scale,
    part_weights,
    pvhk,
    pvst,
    sample_boundary,
    source_vertex,
    view_time_scale,
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

#: names imported on first use, by module
_LAZY = {
    "heatdata.descriptors.sources": ["candidate_descriptors", "candidate_sources"],
    "heatdata.recognition.library": ["Library", "load_library"],
    "heatdata.recognition.answers": ["Detection", "Match", "Recognition", "SceneRecognition", "SequenceStep"],
    "heatdata.recognition.confidence": ["Confidence"],
    "heatdata.recognition.pose": ["Pose", "Surface", "pose_errors", "sample_surface"],
    "heatdata.io.catalog": ["catalog_from_folder", "embedded_catalog", "load_catalog_model", "read_catalog"],
    "heatdata.io.models": ["Model", "hue_rotated", "load_model", "transformed"],
    "heatdata.io.sh3f": ["import_sh3f"],
    "heatdata.jasnom.align": ["Alignment", "align"],
    "heatdata.jasnom.cuts": ["closed_part", "split_model"],
    "heatdata.jasnom.seam": ["Stitched", "stitch", "stitch_scans"],
    "heatdata.jasnom.table": ["TableScan", "table_scan"],
    "heatdata.recognition.compact": ["combined_costs", "consecutive_costs", "other_object_distances", "select_sources"],
    "heatdata.recognition.evaluate": ["library_subset"],
    "heatdata.recognition.metrics": ["confusion_matrix", "precision_by"],
    "heatdata.recognition.multiview.appearance": ["AppearanceModel", "appearance_model", "learn_similarity"],
    "heatdata.recognition.multiview.filters": ["ExhaustiveFilter", "ParticleFilter"],
    "heatdata.recognition.nearest": ["classify_candidates", "nearest_neighbors"],
    "heatdata.rump": ["hbrd", "rump_heat"],
    "heatdata.views.clouds": ["read_organized_cloud"],
    "heatdata.views.depth": ["read_depth", "view_from_depth", "write_depth"],
    "heatdata.views.render": ["Placement", "camera_pose", "render_scene", "render_view"],
    "heatdata.views.segment": ["SegmentSettings", "segment_frame"],
    "heatdata.views.sensor": ["SensorProfile"],
}
_MODULE_OF = {name: module for module, names in _LAZY.items() for name in names}


def __getattr__(name: str) -> Any:
    if name not in _MODULE_OF:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(_MODULE_OF[name]), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


__all__ = [
    "COLOR_MAPS",
    "DESCRIPTORS",
    "Alignment",
    "AppearanceModel",
    "Confidence",
    "ConfigError",
    "Descriptor",
    "DescriptorSpec",
    "Detection",
    "ExhaustiveFilter",
    "HeatModel",
    "HeatOperator",
    "HeatdataError",
    "Library",
    "LibraryError",
    "Match",
    "Model",
    "ModelError",
    "Nearest",
    "NearestPair",
    "OutputError",
    "ParticleFilter",
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
    "Spectrum",
    "SpectrumError",
    "StitchError",
    "Stitched",
    "Surface",
    "TableScan",
    "View",
    "ViewError",
    "__version__",
    "align",
    "appearance_model",
    "c_pvhk",
    "camera_pose",
    "candidate_descriptors",
    "candidate_sources",
    "catalog_from_folder",
    "chi_square_matrix",
    "classify_candidates",
    "closed_part",
    "combined_costs",
    "confusion_matrix",
    "consecutive_costs",
    "describe",
    "distance",
    "eigen_spectrum",
    "embedded_catalog",
    "first_crossings",
    "fit_spec",
    "ft_pvhk",
    "global_derivative",
    "hbrd",
    "heat_kernel",
    "heat_model",
    "hue_rotated",
    "import_sh3f",
    "kinect_intrinsics",
    "krylov_heat",
    "lambda2",
    "laplacian",
    "learn_similarity",
    "library_subset",
    "load_catalog_model",
    "load_library",
    "load_model",
    "mhd",
    "mhd_matrix",
    "nearest_neighbors",
    "nearest_pair_mhd",
    "object_time_scale",
    "other_object_distances",
    "part_weights",
    "pose_errors",
    "precision_by",
    "pvhk",
    "pvst",
    "read_catalog",
    "read_depth",
    "read_organized_cloud",
    "render_scene",
    "render_view",
    "rump_heat",
    "sample_boundary",
    "sample_surface",
    "segment_frame",
    "select_sources",
    "source_vertex",
    "split_model",
    "stitch",
    "stitch_scans",
    "table_scan",
    "transformed",
    "view_from_depth",
    "view_time_scale",
    "weighted_mhd",
    "write_depth",
]
