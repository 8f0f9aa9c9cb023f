"""Descriptor types and the registry of kinds: one :class:`Kind` object per descriptor kind.

Everything outside this package asks a kind what to do instead of comparing kind
names: how it is computed on a view (:meth:`Kind.compute`, sharing the view's work),
its distance (:meth:`Kind.distance_matrix`), whether it is learned on library views
(:attr:`Kind.fitted`), whether it is described at the objects' time scales
(:attr:`Kind.time_scaled`, Alg. 5.1-5.2), whether it can be computed from many sources
of one view (:attr:`Kind.multi_source`, ch. 6), and whether this machine can compute it
(:meth:`Kind.unavailable`).

A new kind is one module in this package that defines a :class:`Kind` subclass and
calls :func:`register` on an instance; the package imports every module in it.
"""

from __future__ import annotations

import logging
import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from heatdata.core.distances import Nearest
from heatdata.errors import HeatdataError, SpecError, ViewError, did_you_mean

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class Descriptor:
    """One descriptor of one view.

    Attributes
    ----------
    kind : str
        A registered kind (:data:`DESCRIPTORS`).
    values : (M,) float64
        Boundary kinds: normalized temperatures (equilibrium = 1) along the boundary, or
        for a ``pvst`` the first times they reach the threshold (NaN where they do not).
        Histogram kinds: the normalized histogram (sums to 1).
    positions : (M,) float64
        Where each value was taken: fraction of the boundary length (arclength, and
        per-vertex descriptors), polar angle / 2 pi (polar), or bin / M (histograms).
    source : int
        Source vertex, indexed in the view passed in; -1 for kinds without a source.
    time : float
        Stopping time: t_s = 1/lambda_2 (PVHK), the fixed time (FT-PVHK), the end of the
        search window (PVST); NaN for kinds without one.
    lambda2 : float
        First non-zero eigenvalue of the (coloured) view; NaN when it was not needed.
    sampling : str or None
        Boundary sampling; None for histogram kinds.
    color_map : str or None
    repairs : tuple of str
        Repairs made to the view for this descriptor (e.g. a component kept).
    weights : (M,) float64 or None
        Part weights rho of eq. 5.13 at the same samples (FT-PVHK), else None.
    """

    kind: str
    values: np.ndarray
    positions: np.ndarray
    source: int
    time: float
    lambda2: float
    sampling: str | None
    color_map: str | None = None
    repairs: tuple = field(default_factory=tuple)
    weights: np.ndarray | None = None


@dataclass(frozen=True)
class Option:
    """One option of a kind: its default, a check that returns the value to keep, and help text.

    ``check(value)`` raises :class:`ValueError` or :class:`TypeError` with what is wrong;
    the spec turns that into a :class:`heatdata.SpecError` naming the kind and option.
    A default of None is kept as None without a check.
    """

    name: str
    default: Any
    help: str
    check: Callable[[Any], Any] = lambda value: value
    #: None given for this option means its default (False: None is a value, e.g. samples=None)
    none_is_default: bool = True
    #: the value that describes as a spec saved before the option existed did (None: its default does); a library
    #: file whose spec lacks the option reads with it (:func:`heatdata.recognition.library_check.spec_of`)
    before: Any = None


def integer(low: int, high: int | None = None, *, allow_none: bool = False) -> Callable[[Any], Any]:
    """A check for whole numbers in ``[low, high]`` (bools and floats such as 2.5 are refused)."""

    def check(value):
        if value is None and allow_none:
            return None
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
            raise TypeError(f"must be a whole number, got {value!r}")
        if value < low or (high is not None and value > high):
            raise ValueError(f"must be in {low}..{'' if high is None else high}, got {value}")
        return int(value)

    return check


def number(low: float, high: float, *, open_low: bool = True) -> Callable[[Any], Any]:
    """A check for real numbers in ``(low, high]`` (``[low, high]`` with ``open_low=False``)."""

    def check(value):
        if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
            raise TypeError(f"must be a number, got {value!r}")
        value = float(value)
        if not np.isfinite(value) or value > high or value < low or (open_low and value == low):
            raise ValueError(f"must be in {'(' if open_low else '['}{low:g}, {high:g}], got {value}")
        return value

    return check


def one_of(choices, aliases: dict[str, str] | None = None) -> Callable[[Any], Any]:
    """A check for one of ``choices``; an old spelling in ``aliases`` is renamed with a DeprecationWarning."""

    def check(value):
        if aliases and isinstance(value, str) and value in aliases:
            warnings.warn(f"{value!r} is deprecated: spell it {aliases[value]!r}", DeprecationWarning, stacklevel=2)
            value = aliases[value]
        if value not in choices:
            raise ValueError(f"must be one of {', '.join(map(str, choices))}, got {value!r}")
        return value

    return check


class Kind:
    """What a descriptor kind is and how the rest of heatdata uses it.

    Subclasses set the class attributes and implement :meth:`compute`; the defaults
    suit a kind with no source, no fitting and no time scales.
    """

    #: the kind's name, e.g. ``"pvhk"``
    name: str = ""
    #: one line for ``heatdata kinds`` and the docs, with the thesis section
    summary: str = ""
    #: the options, in the order positional spec arguments take them
    options: tuple[Option, ...] = ()
    #: learned on library views before use (:func:`fit_spec`), e.g. SI-HKS's codebook
    fitted: bool = False
    #: a network trained on the library views (the pointnet): left out where a test cannot afford its training, and
    #: of the open-set runs that leave each object out (it has seen them all)
    learned: bool = False
    #: described at given fixed times (the objects' time scales, Alg. 5.1); a test view once per object
    time_scaled: bool = False
    #: can be computed from many sources of one view (:func:`heatdata.descriptors.sources.candidate_descriptors`, ch. 6)
    multi_source: bool = False
    #: the descriptor carries part weights used by its distance (eq. 5.14)
    weighted: bool = False
    #: what :meth:`distance_matrix` computes, for figure titles
    distance_name: str = ""
    #: how a library's search index compares the values before :meth:`distance_matrix` re-ranks its candidates
    #: (:mod:`heatdata.recognition.index`): ``"hellinger"`` (chi-square histograms), ``"l2"``, ``"l1"``, or None
    #: where only the exact search answers (a time-scaled kind, whose query differs per object)
    index_space: str | None = None
    #: what ``Descriptor.values`` holds, with its unit, for figure axes
    value_label: str = "value"

    def unavailable(self) -> str | None:
        """Why this machine cannot compute the kind (a missing tool), or None."""
        return None

    def validate(self, options: dict) -> dict:
        """Checks across options, after each option's own check; returns the options to keep."""
        return options

    def label(self, options: Mapping) -> str:
        """The stable name of a spec: the kind, then each option that differs from its default."""
        defaults = {o.name: o.default for o in self.options}
        parts = [self.name] + [f"{k}={v}" for k, v in options.items() if v != defaults[k]]
        return "/".join(parts)

    def compute(self, work, spec: DescriptorSpec, **context) -> list[Descriptor]:
        """The descriptors of ``spec`` on the view of ``work`` (a :class:`heatdata.descriptors.work.ViewWork`).

        ``context`` holds what :func:`heatdata.describe` was given (``times``,
        ``part_weights``, ``t_final``, ``method``); a kind takes what it needs.
        """
        raise NotImplementedError

    def size(self, spec: DescriptorSpec, view) -> int:
        """How many values a descriptor of ``spec`` has on ``view`` (a failed view's NaN row has as many)."""
        raise NotImplementedError

    def distance_matrix(
        self, queries: np.ndarray, library: np.ndarray, *, query_weights=None, library_weights=None
    ) -> np.ndarray:
        """(Q, N) distances between (Q, M) query and (N, M) library values."""
        raise NotImplementedError

    def nearest(
        self,
        queries: np.ndarray,
        library: np.ndarray,
        *,
        query_weights=None,
        library_weights=None,
        within=None,
        chunk: int = 4096,
    ) -> Nearest:
        """(Q,) index and distance of each query's nearest library row (the first of equals), under
        :meth:`distance_matrix`, ``chunk`` queries at a time so that memory stays bounded.

        ``within`` (Q,): only rows nearer than this count; a query with none gets index -1
        and distance ``within`` (as :func:`heatdata.core.distances.nearest_mhd`).
        """
        index, distance = np.empty(len(queries), np.int64), np.empty(len(queries))
        for q0 in range(0, len(queries), chunk):
            rows = slice(q0, q0 + chunk)
            d = self.distance_matrix(
                queries[rows],
                library,
                query_weights=None if query_weights is None else query_weights[rows],
                library_weights=library_weights,
            )
            index[rows] = np.argmin(d, axis=1)
            distance[rows] = d[np.arange(len(d)), index[rows]]
        if within is not None:
            far = distance >= within
            index[far], distance[far] = -1, np.asarray(within, np.float64)[far]
        return Nearest(index, distance)

    def fit(self, spec: DescriptorSpec, views: list) -> dict[str, np.ndarray]:
        """What the kind learns from library ``views``, as named arrays (only if :attr:`fitted`)."""
        raise SpecError(f"{article(self.name)} {self.name} is not fitted")

    def fitted_shapes(self, spec: DescriptorSpec) -> dict[str, tuple[int, ...]]:
        """The names and shapes of what :meth:`fit` learns for ``spec`` (only if :attr:`fitted`): a fit of other
        names or shapes (a damaged library file) is refused when a spec is made with it."""
        raise SpecError(f"{article(self.name)} {self.name} is not fitted")

    def foreign_fit(self, spec: DescriptorSpec, objects: list[str]) -> str | None:
        """Why what ``spec`` learned does not belong to a library of ``objects`` (weights trained on other objects),
        or None; a kind that learns nothing object-specific keeps the default."""
        return None

    def candidates(
        self, view, sources: np.ndarray, spec: DescriptorSpec, *, times=None, modes: int = 32
    ) -> list[Descriptor]:
        """One descriptor per source vertex (only if :attr:`multi_source`)."""
        raise SpecError(
            f"{article(self.name)} {self.name} has no heat source: candidate descriptors (ch. 6) "
            "need one of "
            f"{', '.join(k for k, v in KINDS.items() if v.multi_source)}"
        )


KINDS: dict[str, Kind] = {}


def article(name: str) -> str:
    """'a' or 'an' before a kind's name as it is spoken letter by letter ("an esf", "a pvhk")."""
    return "an" if name[:1].lower() in "aefhilmnorsx" else "a"


def register(kind: Kind) -> Kind:
    """Add a kind to the registry (once per name)."""
    if not kind.name or kind.name in KINDS:
        raise HeatdataError(f"descriptor kind {kind.name!r} is unnamed or registered twice")
    KINDS[kind.name] = kind
    return kind


def kind_of(name: str) -> Kind:
    """The registered kind called ``name``; a clear error for an unknown one."""
    try:
        return KINDS[name]
    except (KeyError, TypeError):
        raise SpecError(
            f"unknown descriptor kind {name!r}{did_you_mean(name, KINDS)} (use one of {', '.join(KINDS)})"
        ) from None


def available() -> dict[str, str | None]:
    """Every registered kind: None if this machine can compute it, else the reason."""
    return {name: kind.unavailable() for name, kind in KINDS.items()}


class DescriptorSpec:
    """What to compute for a view: a kind and its options (validated against the kind).

    ``DescriptorSpec("pvhk", 64, "center", "polar")`` takes options positionally in the
    kind's order, or by name: ``DescriptorSpec("esf", seed=3)``. An option given as None
    takes its default (``samples=None`` means one value per boundary vertex); None for an
    option the kind does not have is ignored. A fitted kind's spec carries what
    :func:`fit_spec` learned in :attr:`fitted` (not part of its name or equality).

    Parameters
    ----------
    kind : str
        A registered kind (:data:`heatdata.DESCRIPTORS`).
    *args
        Its options in the kind's order (``heatdata kinds`` lists them).
    fitted : mapping of str to array, optional
        What the kind learned from library views.
    **given
        Options by name.

    Attributes
    ----------
    kind : str
    options : dict
        Every option of the kind, with defaults filled in.
    fitted : dict of str to ndarray, or None
    """

    __slots__ = ("fitted", "kind", "options")

    def __init__(self, kind: str = "pvhk", *args: Any, fitted: Mapping | None = None, **given: Any) -> None:
        impl = kind_of(kind)
        names = [o.name for o in impl.options]
        if len(args) > len(names):
            raise SpecError(
                f"{article(kind)} {kind} takes at most {len(names)} options ({', '.join(names)}), got {len(args)}"
            )
        for name, value in zip(names, args, strict=False):
            if name in given:
                raise SpecError(f"{kind}: option {name} given twice")
            given[name] = value
        unknown = sorted(k for k, v in given.items() if k not in names and v is not None)
        if unknown:
            raise SpecError(
                f"{article(kind)} {kind} takes no {', '.join(unknown)} (its options: {', '.join(names) or 'none'})"
            )
        options = {}
        for option in impl.options:
            value = given.get(option.name, option.default)
            if value is None and option.none_is_default:
                value = option.default
            try:
                options[option.name] = None if value is None and option.default is None else option.check(value)
            except (TypeError, ValueError) as exc:
                raise SpecError(f"{kind}: option {option.name} {exc}") from None
        object.__setattr__(self, "kind", kind)
        object.__setattr__(self, "options", impl.validate(options))
        object.__setattr__(self, "fitted", None if fitted is None else _checked_fit(kind, impl, self, fitted))

    def __getattr__(self, name: str):
        options = object.__getattribute__(self, "options")
        if name in options:
            return options[name]
        kind = object.__getattribute__(self, "kind")
        raise AttributeError(f"{article(kind)} {kind} spec has no option {name!r}")

    def __setattr__(self, name, value):
        raise AttributeError("DescriptorSpec is immutable; use spec.replace(...)")

    def __reduce__(self):  # pickled for process pools: rebuilt (and re-validated) from kind and options
        return _rebuild, (self.kind, self.options, self.fitted)

    def get(self, name: str, default: Any = None) -> Any:
        """The option ``name``, or ``default`` if the kind has no such option.

        Parameters
        ----------
        name : str
            An option's name.
        default : object
            What to return when the kind has no such option.

        Returns
        -------
        object
            The option's value.
        """
        return self.options.get(name, default)

    @property
    def impl(self) -> Kind:
        """The registered :class:`Kind` of this spec."""
        return KINDS[self.kind]

    @property
    def name(self) -> str:
        """Stable identifier, e.g. ``pvhk/polar/center/64``, ``pvst/polar/center/64/T0.75``, ``esf``."""
        return self.impl.label(self.options)

    def replace(self, **changes) -> DescriptorSpec:
        """A copy with some options changed (what was fitted is kept).

        Returns
        -------
        DescriptorSpec
            The copy, validated like a new spec.
        """
        return DescriptorSpec(self.kind, fitted=self.fitted, **{**self.options, **changes})

    def with_fitted(self, fitted: Mapping) -> DescriptorSpec:
        """A copy that carries what the kind learned from library views (:func:`fit_spec`).

        Parameters
        ----------
        fitted : mapping of str to array
            What :meth:`Kind.fit` learned (e.g. SI-HKS's codebook).

        Returns
        -------
        DescriptorSpec
            The same kind and options with ``fitted`` (part of its identity and of its JSON).
        """
        return DescriptorSpec(self.kind, fitted=fitted, **self.options)

    def to_dict(self) -> dict[str, Any]:
        """The spec as plain data, the form a config's ``descriptors`` entry takes, for a file or a process.

        Returns
        -------
        dict
            ``{"kind": ..., option: value, ...}`` with every option (a combined kind's parts as such dicts), and
            ``"fitted": {name: nested lists}`` when the kind learned something. :meth:`from_dict` of it is an equal
            spec with the same fit.
        """
        data = {"kind": self.kind, **_plain(self.options)}
        if self.fitted is not None:
            data["fitted"] = {name: np.asarray(value).tolist() for name, value in self.fitted.items()}
        return data

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> DescriptorSpec:
        """The spec of :meth:`to_dict`'s data or of a config's ``descriptors`` entry (options left out take their
        defaults; ``fitted`` is optional).

        Parameters
        ----------
        data : mapping
            ``kind`` (default ``pvhk``), the options by name, and optionally ``fitted``.

        Returns
        -------
        DescriptorSpec

        Raises
        ------
        SpecError
            Not a mapping, or an unknown kind, option or value.
        """
        if not isinstance(data, Mapping):
            raise SpecError(f"a descriptor is a mapping of kind and options, got {data!r}")
        return cls(**{str(key): value for key, value in data.items()})

    def _key(self):
        return self.kind, tuple(
            (k, v if isinstance(v, (str, int, float, tuple, type(None))) else id(v)) for k, v in self.options.items()
        )

    def __eq__(self, other) -> bool:
        return isinstance(other, DescriptorSpec) and self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())

    def __repr__(self) -> str:
        options = ", ".join(f"{k}={v!r}" for k, v in self.options.items())
        return f"DescriptorSpec({self.kind!r}{', ' if options else ''}{options}{', fitted' if self.fitted else ''})"


def file_name(descriptor: str) -> str:
    """A descriptor name as a file name: ``pvhk/polar/center/64`` -> ``pvhk_polar_center_64``."""
    return descriptor.replace("/", "_")


def _checked_fit(kind: str, impl: Kind, spec: DescriptorSpec, fitted: Mapping) -> dict[str, np.ndarray]:
    """``fitted`` as finite float arrays of the names and shapes :meth:`Kind.fitted_shapes` gives for ``spec``."""
    if not impl.fitted:
        raise SpecError(f"{article(kind)} {kind} is not fitted, but a fit was given")
    shapes = impl.fitted_shapes(spec)
    if set(fitted) != set(shapes):
        raise SpecError(f"{kind}: a fit of {sorted(fitted)}, not {sorted(shapes)}")
    checked = {}
    for name, shape in shapes.items():
        try:
            value = np.asarray(fitted[name], dtype=np.float64)
        except (TypeError, ValueError):
            raise SpecError(f"{kind}: the fitted {name} is not an array of numbers") from None
        if value.shape != shape or not np.all(np.isfinite(value)):
            raise SpecError(f"{kind}: the fitted {name} is {value.shape}, not finite {shape}")
        checked[name] = value
    return checked


def _plain(value: Any) -> Any:
    """An option's value as plain data: a spec (a combined kind's part) as its :meth:`DescriptorSpec.to_dict`."""
    if isinstance(value, DescriptorSpec):
        return value.to_dict()
    if isinstance(value, dict):
        return {name: _plain(v) for name, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    return value


def _rebuild(kind: str, options: dict, fitted) -> DescriptorSpec:
    return DescriptorSpec(kind, fitted=fitted, **options)


def fit_spec(spec: DescriptorSpec, library_views: list) -> DescriptorSpec:
    """Fit a learned kind on library views (e.g. SI-HKS's codebook); other kinds come back as they are.

    Parameters
    ----------
    spec : DescriptorSpec
        What to compute.
    library_views : list of View
        The views it may learn from (for SI-HKS, its codebook).

    Returns
    -------
    DescriptorSpec
        ``spec`` with its fitted state (:meth:`DescriptorSpec.with_fitted`), or ``spec`` itself.
    """
    if not spec.impl.fitted:
        return spec
    views = list(library_views)
    if not views:
        raise ViewError(f"{spec.name}: fitting needs at least one library view")
    return spec.with_fitted(spec.impl.fit(spec, views))


def stack_values(items, what: str = "descriptors") -> np.ndarray:
    """Descriptor values as one (n, M) float64 array.

    Parameters
    ----------
    items : (n, M) array, or a sequence of :class:`Descriptor` or of (M,) arrays
        What the API hands out: a stacked array, :func:`heatdata.describe`'s or
        :func:`heatdata.descriptors.sources.candidate_descriptors`'s list of descriptors.
    what : str
        Named in errors.

    Raises
    ------
    HeatdataError
        Nothing to stack, descriptors of different kinds or lengths, or not 2-D.
    """
    if isinstance(items, Descriptor):
        items = [items]
    if isinstance(items, np.ndarray):
        values = items
    else:
        items = list(items)
        if not items:
            raise HeatdataError(f"{what}: nothing to stack (an empty list)")
        kinds = {d.kind for d in items if isinstance(d, Descriptor)}
        if len(kinds) > 1:
            raise HeatdataError(f"{what}: descriptors of several kinds ({', '.join(sorted(kinds))}); stack one kind")
        rows = [np.asarray(d.values if isinstance(d, Descriptor) else d, dtype=np.float64) for d in items]
        lengths = sorted({r.shape for r in rows})
        if len(lengths) > 1:
            raise HeatdataError(f"{what}: descriptors of different shapes {lengths}; sample them at one length")
        values = np.stack(rows)
    values = np.asarray(values, dtype=np.float64)
    if values.ndim != 2 or values.shape[0] == 0:
        raise HeatdataError(f"{what}: expected descriptors (n, M) with n >= 1, got shape {values.shape}")
    return values


def _evenly_sampled(d: Descriptor) -> bool:
    """Whether ``d`` was sampled at a fixed number of evenly spaced positions (or bins), not once per vertex."""
    m = len(d.positions)
    return m > 0 and np.allclose(d.positions, np.arange(m) / m)


def distance(a: Descriptor, b: Descriptor) -> float:
    """The kind's own distance between two descriptors of one kind (eq. 3.1, 5.14 or a histogram distance).

    Parameters
    ----------
    a, b : Descriptor
        Two descriptors of one kind, sampling and colour map, and of one number of samples (unless both were
        sampled once per boundary vertex, ``samples=None``).

    Returns
    -------
    float
        Their distance under the kind's :meth:`Kind.distance_matrix`.

    Raises
    ------
    HeatdataError
        The descriptors differ in kind, sampling, colour map or number of samples.
    """
    if a.kind != b.kind:
        raise HeatdataError(
            f"no distance between {article(a.kind)} {a.kind} and {article(b.kind)} {b.kind} "
            "descriptor: compare one kind"
        )
    for field_name in ("sampling", "color_map"):
        if getattr(a, field_name) != getattr(b, field_name):
            raise HeatdataError(
                f"no distance between {a.kind} descriptors of {field_name} {getattr(a, field_name)!r} and "
                f"{getattr(b, field_name)!r}: describe both with one spec"
            )
    if len(a.values) != len(b.values) and (_evenly_sampled(a) or _evenly_sampled(b)):
        raise HeatdataError(
            f"no distance between {a.kind} descriptors of {len(a.values)} and {len(b.values)} samples: "
            "describe both with one number of samples"
        )
    impl = kind_of(a.kind)
    weights = {}
    if impl.weighted and a.weights is not None and b.weights is not None:
        weights = dict(query_weights=np.atleast_2d(a.weights), library_weights=np.atleast_2d(b.weights))
    return float(impl.distance_matrix(np.atleast_2d(a.values), np.atleast_2d(b.values), **weights)[0, 0])
