"""Descriptors of partial views, one registered kind each (thesis ch. 2-3, 5 and the baselines of 3.6.1).

Modules: ``base`` (the :class:`Descriptor`, :class:`DescriptorSpec` and :class:`Kind`
types and the registry), ``boundary`` (source rules and boundary sampling), ``work``
(what one view's descriptors share), ``compute`` (:func:`describe`), ``heat`` (PVHK,
C-PVHK, FT-PVHK), ``pvst`` and one module per baseline (``sihks``, ``fpfh``, ``vfh``,
``esf``, over ``histograms``). Every module of this package is imported here, so a new
kind registers itself by being a module in it.
"""

import importlib
import pkgutil

from .base import (KINDS, Descriptor, DescriptorSpec, Kind, Option, available, distance, file_name, fit_spec, kind_of,
                   register, stack_values)
from .boundary import COLOR_MAPS, SAMPLINGS, SOURCE_RULES, color_rates, sample_boundary, source_vertex
from .compute import describe
from .heat import (CANDIDATES_RULE, COLOR_KIND, DEFAULT_KIND, c_pvhk, ft_pvhk, global_derivative, object_time_scale,
                   part_weights, pvhk, view_time_scale)
from .pvst import PVST_THRESHOLD, pvst
from .work import ViewWork, heat_kernel, heat_operator

for _module in pkgutil.iter_modules(__path__):
    importlib.import_module(f"{__name__}.{_module.name}")

#: every kind heatdata knows: None if this machine can compute it, else the reason
DESCRIPTORS = available()

__all__ = [
    "available", "c_pvhk", "CANDIDATES_RULE", "COLOR_KIND", "COLOR_MAPS", "color_rates", "DEFAULT_KIND", "describe",
    "Descriptor", "DESCRIPTORS", "DescriptorSpec", "distance", "file_name", "fit_spec", "ft_pvhk", "global_derivative",
    "heat_kernel", "heat_operator", "Kind", "kind_of", "KINDS", "object_time_scale", "Option", "part_weights",
    "pvhk", "pvst", "PVST_THRESHOLD", "register", "sample_boundary", "SAMPLINGS", "source_vertex", "SOURCE_RULES",
    "stack_values", "view_time_scale", "ViewWork",
]
