"""Kinds combined: several descriptors of one view under one distance, each on its own learned scale.

Not in the thesis. Each part is a registered kind with its own distance (eq. 3.1 for the
boundary kinds, chi-square for the histograms). Their distances are in different units,
so they are learned on library views before use (:attr:`Kind.fitted`, rule
``fit_descriptor``):

1. every part describes each library view the fit is given;
2. a part's scale ``s_k`` is the median, over those views, of the distance to the
   nearest other one (so a part's typical nearest-neighbour distance becomes 1);
3. with ``how: learned`` (the default), weights ``w_k`` on a grid of the simplex
   (steps of :data:`WEIGHT_STEP`) are chosen by leave-one-out precision among the same
   library views (each against all the others; no test view is seen); ``how: sum``
   takes ``w_k = 1``.

The distance is ``sum_k (w_k / s_k) d_k``. The weights must be learned: the plain sum of ESF and
log-time PVST was below the ESF alone on 58 chairs.

A descriptor's values are self-describing, so that any code holding a table's rows can
compare them: a header ``[K, n_1..n_K, code_1..code_K, c_1..c_K]`` (part count, part
lengths, each part's kind as its index in :func:`part_codes`, coefficients
``c_k = w_k / s_k``), then the parts' values in order. Parts must be neither fitted,
time-scaled, weighted nor combined themselves.
"""

from __future__ import annotations

import itertools
import logging
from collections.abc import Mapping

import numpy as np

from heatdata.descriptors.base import (
    KINDS,
    Descriptor,
    DescriptorSpec,
    Kind,
    Option,
    article,
    kind_of,
    one_of,
    register,
)
from heatdata.errors import HeatdataError, SpecError, ViewError

log = logging.getLogger(__name__)

WEIGHT_STEP = 0.1
HOWS = ("learned", "sum")


def part_codes() -> list[str]:
    """The kinds a part may be, in the order their codes count (sorted names)."""
    return sorted(name for name, kind in KINDS.items() if not (kind.fitted or kind.time_scaled or kind.weighted))


def checked_parts(value) -> tuple[DescriptorSpec, ...]:
    """Parts as specs: each a DescriptorSpec or a mapping ``{kind: ..., options...}``; two or more."""
    if isinstance(value, (str, bytes, Mapping)) or not hasattr(value, "__iter__"):
        raise TypeError(f"must be a list of descriptors ({{kind: ..., options}}), got {value!r}")
    parts = []
    for item in value:
        if isinstance(item, Mapping):
            options = dict(item)
            if "kind" not in options:
                raise ValueError(f"a part needs a kind, got {item!r}")
            item = DescriptorSpec(options.pop("kind"), **options)
        if not isinstance(item, DescriptorSpec):
            raise TypeError(f"a part must be a descriptor, got {item!r}")
        impl = item.impl
        if impl.fitted or impl.time_scaled or impl.weighted:
            raise ValueError(f"{item.name} cannot be a part (fitted, time-scaled and part-weighted kinds cannot)")
        parts.append(item)
    if len(parts) < 2:
        raise ValueError(f"needs two or more parts, got {len(parts)}")
    if len({p.name for p in parts}) < len(parts):
        raise ValueError(f"the same part twice in {[p.name for p in parts]}")
    return tuple(parts)


def simplex_grid(count: int, step: float = WEIGHT_STEP) -> list[tuple[float, ...]]:
    """Weight vectors of ``count`` non-negative multiples of ``step`` summing to 1."""
    ticks = round(1 / step)
    return [tuple(k / ticks for k in w) for w in itertools.product(range(ticks + 1), repeat=count) if sum(w) == ticks]


def header(spec: DescriptorSpec, sizes: list[int]) -> np.ndarray:
    codes = part_codes()
    return np.concatenate(
        [
            [len(sizes)],
            sizes,
            [codes.index(p.kind) for p in spec.parts],
            np.asarray(spec.fitted["coefficients"], np.float64),
        ]
    )


def layout(values: np.ndarray) -> tuple[list[Kind], list[slice], np.ndarray]:
    """The part kinds, the slices of their values and their coefficients, read from a row's header."""
    count = int(values[0])
    sizes = values[1 : 1 + count].astype(int)
    codes = part_codes()
    kinds = [kind_of(codes[int(c)]) for c in values[1 + count : 1 + 2 * count]]
    coefficients = values[1 + 2 * count : 1 + 3 * count]
    starts = 1 + 3 * count + np.concatenate([[0], np.cumsum(sizes)])
    return kinds, [slice(a, b) for a, b in itertools.pairwise(starts)], coefficients


def leave_one_out(among: list[np.ndarray], coefficients: np.ndarray, objects: np.ndarray) -> float:
    """Share of views whose nearest other view, under ``sum_k c_k d_k``, is of their object (parts of c = 0 unread)."""
    total = sum(c * d for c, d in zip(coefficients, among, strict=True) if c > 0)
    return float(np.mean(objects[np.argmin(total, axis=1)] == objects))


class Combined(Kind):
    name = "combined"
    summary = "several kinds of one view, each distance over its learned nearest-neighbour scale"
    fitted = True
    distance_name = "sum of the parts' scaled distances"
    value_label = "the parts' values, after a header"
    options = (
        Option("parts", None, "required: two or more descriptors ({kind: ..., options})", checked_parts),
        Option("how", "learned", "learned: weights by leave-one-out among the library views; sum: all 1", one_of(HOWS)),
    )

    def validate(self, options: dict) -> dict:
        if options["parts"] is None:
            raise SpecError("combined: option parts is needed (two or more descriptors)")
        return options

    def label(self, options: Mapping) -> str:
        how = "" if options["how"] == "learned" else f"how={options['how']}/"
        return f"combined/{how}" + "+".join(p.name for p in options["parts"])

    def unavailable(self) -> str | None:
        return None

    def size(self, spec: DescriptorSpec, view) -> int:
        sizes = [p.impl.size(p, view) for p in spec.parts]
        return 1 + 3 * len(sizes) + sum(sizes)

    def fit(self, spec: DescriptorSpec, views: list) -> dict[str, np.ndarray]:
        from heatdata.descriptors.compute import describe

        if len(views) < 2:
            raise ViewError(f"{spec.name}: fitting needs two or more library views")
        values = [
            np.stack(v)
            for v in zip(*([d.values for d in describe(view, list(spec.parts))] for view in views), strict=True)
        ]
        objects = np.array([view.object_id for view in views])
        among = []
        for part, rows in zip(spec.parts, values, strict=True):
            d = np.nan_to_num(part.impl.distance_matrix(rows, rows), nan=np.inf)  # a NaN row is never nearest
            np.fill_diagonal(d, np.inf)  # a view is not its own neighbour
            among.append(d)
        scales = np.array([np.median(d.min(axis=1)) for d in among])
        if not np.all(np.isfinite(scales) & (scales > 0)):
            raise ViewError(
                f"{spec.name}: a part's nearest-neighbour scale is {scales}; the library views are too few or identical"
            )
        grid = simplex_grid(len(among)) if spec.how == "learned" else [(1.0,) * len(among)]
        scored = np.array([leave_one_out(among, np.asarray(w) / scales, objects) for w in grid])
        # among equally good weights, the most even (nearest the plain sum)
        spread = np.array([np.ptp(w) for w in grid])
        weights = np.array(grid[int(np.lexsort((spread, -scored))[0])])
        log.info(
            "%s: scales %s, weights %s (leave-one-out %.1f%% over %d library views)",
            spec.name,
            np.round(scales, 4),
            weights,
            100 * max(scored),
            len(views),
        )
        return {
            "scales": scales,
            "weights": weights,
            "coefficients": weights / scales,
            "leave_one_out": np.array(scored.max()),
        }

    def fitted_shapes(self, spec: DescriptorSpec) -> dict[str, tuple[int, ...]]:
        parts = (len(spec.parts),)
        return {"scales": parts, "weights": parts, "coefficients": parts, "leave_one_out": ()}

    def compute(self, work, spec: DescriptorSpec, **context) -> list[Descriptor]:
        if spec.fitted is None:
            raise SpecError(
                f"{work.view.name}: {article(self.name)} {self.name} must be fitted on library views "
                "first (spec = heatdata.fit_spec(spec, library_views))"
            )
        parts = [d for part in spec.parts for d in part.impl.compute(work, part, **context)]
        sizes = [len(d.values) for d in parts]
        values = np.concatenate([header(spec, sizes)] + [d.values for d in parts])
        repairs = tuple(dict.fromkeys(r for d in parts for r in d.repairs))
        return [
            Descriptor(
                kind=self.name,
                values=values,
                positions=np.arange(len(values)) / len(values),
                source=parts[0].source,
                time=float("nan"),
                lambda2=parts[0].lambda2,
                sampling=None,
                repairs=repairs,
            )
        ]

    def distance_matrix(self, queries, library, *, query_weights=None, library_weights=None) -> np.ndarray:
        """``sum_k c_k d_k`` over the parts named in the rows' header (the library's first row)."""
        queries, library = np.atleast_2d(queries), np.atleast_2d(library)
        reference = library[0] if len(library) else queries[0]
        kinds, slices, coefficients = layout(reference)
        head = slices[0].start
        if queries.shape[1] != library.shape[1] or not (
            np.array_equal(queries[:, :head], np.broadcast_to(reference[:head], (len(queries), head)))
            and np.array_equal(library[:, :head], np.broadcast_to(reference[:head], (len(library), head)))
        ):
            raise HeatdataError(
                "combined descriptors of different parts, lengths or fits: compare one spec, fitted once"
            )
        return sum(
            c * kind.distance_matrix(queries[:, s], library[:, s])
            for kind, s, c in zip(kinds, slices, coefficients, strict=True)
            if c > 0
        )  # a weight 0: unread


register(Combined())
