"""heatdata: heat-diffusion descriptors of partial 3D views (Brandao 2015).

>>> import heatdata as hd
>>> model = hd.load_model(hd.embedded_catalog().parent / "beer-mug/beerGlass.obj", size=(0.154, 0.165, 0.102))
>>> view = hd.render_view(model, azimuth=30.0, elevation=45.0, distance=1.0, noise=True, seed=0)
>>> d = hd.pvhk(view, samples=64, source="closest")

The README's "Using the library" runs a whole example (recognition, the baselines, a compact library).

The descriptors, distances, spectra and views are imported with the package; the other stages are imported
the first time one of their names is used (``hd.render_view`` imports open3d, ``hd.load_model`` trimesh), so
a job that only compares descriptor tables does not load the renderer (~260 MB of open3d).
"""

import importlib

from .descriptors import (COLOR_MAPS, DESCRIPTORS, Descriptor, DescriptorSpec, c_pvhk, describe, distance, fit_spec,
                          ft_pvhk, global_derivative, heat_kernel, object_time_scale, part_weights, pvhk, pvst,
                          sample_boundary, source_vertex, view_time_scale)
from .distance import chi_square_matrix, mhd, mhd_matrix, nearest_pair_mhd, weighted_mhd
from .errors import HeatdataError, ModelError, RenderError, SpectrumError, ViewError
from .spectrum import (HeatModel, HeatOperator, Spectrum, eigen_spectrum, first_crossings, heat_model, krylov_heat,
                       lambda2, laplacian)
from .version import __version__
from .view import View, kinect_intrinsics

# ``hd.distance`` is the descriptor-level distance function; the module of distance matrices stays
# importable as ``heatdata.distance`` (``from heatdata.distance import mhd_matrix``). It is bound above, after
# the module was loaded, so importing the module later does not rebind it.

#: names imported on first use, by module
_LAZY = {
    "catalog": ["catalog_from_folder", "embedded_catalog", "import_sh3f", "load_catalog_model", "read_catalog"],
    "depth": ["read_depth", "read_organized_cloud", "view_from_depth", "write_depth"],
    "library": ["combined_costs", "consecutive_costs", "library_subset", "other_object_distances", "select_sources"],
    "models": ["Model", "hue_rotated", "load_model"],
    "multiview": ["AppearanceModel", "ExhaustiveFilter", "ParticleFilter", "appearance_model", "learn_similarity"],
    "recognition": ["precision_by", "classify_candidates", "confusion_matrix", "nearest_neighbours"],
    "render": ["camera_pose", "render_view"],
    "rump": ["RumpError", "hbrd", "rump_heat"],
    "sources": ["candidate_descriptors", "candidate_sources"],
    "stitch": ["StitchError"],
}
_MODULE_OF = {name: module for module, names in _LAZY.items() for name in names}


def __getattr__(name: str):
    if name == "stitch":  # the module: hd.stitch.stitch(first, second), hd.stitch.split_model(...)
        return importlib.import_module(".stitch", __name__)
    if name not in _MODULE_OF:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{_MODULE_OF[name]}", __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))

__all__ = [
    "AppearanceModel", "appearance_model", "learn_similarity", "ParticleFilter", "ExhaustiveFilter", "precision_by",
    "c_pvhk", "camera_pose", "candidate_descriptors", "candidate_sources", "catalog_from_folder",
    "chi_square_matrix", "DESCRIPTORS", "distance", "embedded_catalog", "fit_spec", "library_subset",
    "classify_candidates", "COLOR_MAPS", "combined_costs", "confusion_matrix", "consecutive_costs", "describe",
    "Descriptor", "DescriptorSpec", "eigen_spectrum", "first_crossings", "ft_pvhk", "global_derivative",
    "heat_kernel", "heat_model", "HeatdataError", "HeatModel", "HeatOperator", "import_sh3f", "kinect_intrinsics",
    "krylov_heat", "lambda2", "laplacian", "load_catalog_model", "load_model", "mhd", "mhd_matrix", "Model",
    "ModelError", "nearest_neighbours", "stitch", "StitchError", "nearest_pair_mhd", "object_time_scale",
    "other_object_distances", "part_weights", "pvhk", "pvst", "read_catalog", "render_view", "RenderError",
    "sample_boundary", "select_sources", "source_vertex", "Spectrum", "SpectrumError", "View", "view_time_scale",
    "ViewError", "weighted_mhd", "view_from_depth", "read_depth", "read_organized_cloud", "write_depth", "hbrd",
    "rump_heat", "RumpError", "hue_rotated",
    "__version__",
]
