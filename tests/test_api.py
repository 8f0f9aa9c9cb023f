"""What ``import heatdata as hd`` offers, and the level beneath it: every name resolves, is documented (numpy
style) and typed; the top level holds the user's path, the rest is imported from its module."""

import dataclasses
import importlib
import inspect
import subprocess
import sys
import warnings

import pytest

import heatdata as hd


def test_import_heatdata_loads_no_renderer_no_mesh_reader_and_no_plotting():
    heavy = "{'open3d', 'trimesh', 'matplotlib', 'numba', 'cvxpy'}"
    # nor does loading a library: the pose's ICP imports open3d when it runs (0.9 s of a 400,000-view load)
    for imports in ("heatdata", "heatdata.recognition.library"):
        code = f"import sys, {imports}; print(sorted({{m.split('.')[0] for m in sys.modules}} & {heavy}))"
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
        assert out.strip() == "[]", imports


def test_every_public_name_resolves_and_none_shadows_a_module():
    for name in hd.__all__:
        value = getattr(hd, name)
        assert not inspect.ismodule(value), f"hd.{name} is a module"
    assert inspect.isfunction(hd.stitch) and inspect.isfunction(hd.distance)
    assert inspect.isfunction(hd.descriptors.pvst)  # the function; its module is heatdata.descriptors.stochastic_time
    assert sorted(hd.__all__, key=str.lower) == sorted(set(hd.__all__), key=str.lower)
    with pytest.raises(AttributeError, match="no attribute 'nearest_neighbours'"):
        hd.nearest_neighbours  # noqa: B018 (renamed: nearest_neighbors)


def test_the_top_level_is_the_users_path_and_the_rest_is_one_level_down():
    eager = {name for name, value in vars(hd).items() if not name.startswith("_") and not inspect.ismodule(value)}
    eager -= {"Any"} | set(hd._MODULE_OF)  # the package's own typing import; lazy names once used
    assert set(hd.__all__) == eager | set(hd._MODULE_OF) | {"__version__"}  # __all__ lists the imports and _LAZY
    assert len(hd.__all__) <= 60 and not set(hd.__all__) & set(hd._MOVED_TO)
    assert {"load_model", "render_view", "describe", "load_library", "stitch", "HeatdataError"} <= set(hd.__all__)
    for name, module in hd._MOVED_TO.items():
        beneath = getattr(importlib.import_module(module), name)
        with pytest.warns(DeprecationWarning, match=rf"heatdata\.{name} has moved: import it from {module}"):
            assert getattr(hd, name) is beneath
        assert name not in dir(hd)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for name in hd.__all__:
            getattr(hd, name)


def test_every_error_is_in_errors_and_derives_from_heatdataerror():
    from heatdata import errors

    raised = {name for name in hd.__all__ if name.endswith("Error")}
    assert raised == {n for n, v in vars(errors).items() if inspect.isclass(v) and issubclass(v, Exception)}
    for name in raised:
        assert getattr(hd, name).__module__ == "heatdata.errors" and issubclass(getattr(hd, name), hd.HeatdataError)


def _problems(obj, name):
    doc = inspect.getdoc(obj) or ""
    sig = inspect.signature(obj)
    params = [
        p
        for p in sig.parameters.values()
        if p.name not in ("self", "cls") and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)
    ]
    found = []
    if params and "Parameters\n---" not in doc:
        found.append(f"{name}: no Parameters section")
    if sig.return_annotation is inspect.Signature.empty:
        found.append(f"{name}: no return hint")
    elif sig.return_annotation not in (None, "None") and "Returns\n---" not in doc and "Yields\n---" not in doc:
        found.append(f"{name}: no Returns section")
    found += [f"{name}({p.name}): no hint" for p in params if p.annotation is inspect.Parameter.empty]
    return found


def test_every_public_function_and_method_has_parameters_returns_and_hints():
    problems = []
    beneath = {name: getattr(importlib.import_module(module), name) for name, module in hd._MOVED_TO.items()}
    for name in [*hd.__all__, *beneath]:
        value = beneath[name] if name in beneath else getattr(hd, name)
        if inspect.isfunction(value):
            problems += _problems(value, name)
        elif inspect.isclass(value) and not issubclass(value, BaseException):
            for attr, member in vars(value).items():
                if attr == "__init__" and inspect.isfunction(member):
                    given = [p for p in inspect.signature(member).parameters.values() if p.name != "self"]
                    if given and not dataclasses.is_dataclass(value):
                        if "Parameters\n---" not in (inspect.getdoc(value) or ""):
                            problems.append(f"{name}: no Parameters section in the class docstring")
                elif not attr.startswith("_") and isinstance(member, (classmethod, staticmethod)):
                    problems += _problems(member.__func__, f"{name}.{attr}")
                elif not attr.startswith("_") and inspect.isfunction(member):
                    problems += _problems(member, f"{name}.{attr}")
    assert problems == []
