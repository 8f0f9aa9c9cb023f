"""Descriptors of partial views, one registered kind each (thesis ch. 2-3, 5 and the baselines of 3.6.1).

Modules: ``base`` (the :class:`Descriptor`, :class:`DescriptorSpec` and :class:`Kind`
types and the registry), ``boundary`` (source rules and boundary sampling), ``work``
(what one view's descriptors share), ``compute`` (:func:`describe`), ``heat`` (PVHK,
C-PVHK, FT-PVHK), ``stochastic_time`` (PVST), ``sources`` (candidate sources, thesis 6.2) and
one module per baseline (``sihks``, ``fpfh``, ``vfh``,
``esf``, over ``histograms``). Every module of this package is imported here, so a new
kind registers itself by being a module in it.
"""

import importlib
import pkgutil

from heatdata.descriptors.base import (
    KINDS,
    Descriptor,
    DescriptorSpec,
    Kind,
    Option,
    available,
    distance,
    file_name,
    fit_spec,
    kind_of,
    register,
    stack_values,
)
from heatdata.descriptors.boundary import (
    COLOR_MAPS,
    SAMPLINGS,
    SOURCE_RULES,
    color_rates,
    sample_boundary,
    source_vertex,
)
from heatdata.descriptors.compute import describe
from heatdata.descriptors.heat import (
    CANDIDATES_RULE,
    COLOR_KIND,
    DEFAULT_KIND,
    c_pvhk,
    ft_pvhk,
    global_derivative,
    object_time_scale,
    part_weights,
    pvhk,
    view_time_scale,
)
from heatdata.descriptors.stochastic_time import PVST_THRESHOLD, THRESHOLD_KIND, pvst
from heatdata.descriptors.work import ViewWork, heat_kernel, heat_operator

for _module in pkgutil.iter_modules(__path__):  # every kind registers itself; the compiled kernels load on use
    if _module.name.startswith("_"):
        continue
    importlib.import_module(f"{__name__}.{_module.name}")

#: every kind heatdata knows: None if this machine can compute it, else the reason
DESCRIPTORS = available()

#: the default descriptor, the main job's primary one (config/config.yaml): the HGD with hue-saturation colour. What
#: ``heatdata describe`` computes when no kind or boundary option is given, and whose library ``heatdata recognize``
#: reads when none is named
DEFAULT_DESCRIPTOR = DescriptorSpec("hgd", color="hue-saturation")

__all__ = [
    "CANDIDATES_RULE",
    "COLOR_KIND",
    "COLOR_MAPS",
    "DEFAULT_KIND",
    "DESCRIPTORS",
    "KINDS",
    "PVST_THRESHOLD",
    "SAMPLINGS",
    "SOURCE_RULES",
    "THRESHOLD_KIND",
    "Descriptor",
    "DescriptorSpec",
    "Kind",
    "Option",
    "ViewWork",
    "available",
    "c_pvhk",
    "color_rates",
    "describe",
    "distance",
    "file_name",
    "fit_spec",
    "ft_pvhk",
    "global_derivative",
    "heat_kernel",
    "heat_operator",
    "kind_of",
    "object_time_scale",
    "part_weights",
    "pvhk",
    "pvst",
    "register",
    "sample_boundary",
    "source_vertex",
    "stack_values",
    "view_time_scale",
]
