"""What the histogram baselines of thesis 3.6.1 share: a fixed number of bins, the chi-square distance,
and a clear error for a view too small to fill a histogram."""

from __future__ import annotations

import numpy as np

from heatdata.core.distances import chi_square_matrix
from heatdata.descriptors.base import Descriptor, DescriptorSpec, Kind, article
from heatdata.errors import ViewError

MIN_POINTS = 50  # fewer view vertices than this give histograms of noise (or none): an error


class HistogramKind(Kind):
    """A whole-view histogram descriptor, compared by the chi-square distance."""

    #: bins of the histogram (``values`` has this length)
    bins: int = 0
    distance_name = "chi-square distance"
    index_space = "hellinger"
    value_label = "fraction of the histogram"

    def size(self, spec: DescriptorSpec, view) -> int:
        return self.bins

    def distance_matrix(self, queries, library, *, query_weights=None, library_weights=None):
        """The chi-square distance between normalized histograms (:func:`heatdata.core.distances.chi_square_matrix`)."""
        return chi_square_matrix(queries, library)

    def check_points(self, view, count: int | None = None) -> None:
        count = view.n_vertices if count is None else count
        if count < MIN_POINTS:
            raise ViewError(
                f"{view.name}: {count} vertices are too few for {article(self.name)} {self.name} histogram "
                f"(it needs {MIN_POINTS})"
            )

    def histogram(
        self, spec: DescriptorSpec, counts: np.ndarray, view, *, lambda2: float = float("nan"), repairs: tuple = ()
    ) -> Descriptor:
        """The descriptor of a histogram of ``counts`` (normalized to sum 1 here)."""
        counts = np.asarray(counts, dtype=np.float64)
        total = counts.sum()
        bins = self.size(spec, view)
        if counts.shape != (bins,) or not np.isfinite(total) or total <= 0:
            raise ViewError(f"{view.name}: the {self.name} histogram is empty or not finite")
        return Descriptor(
            kind=self.name,
            values=counts / total,
            positions=np.arange(bins) / bins,
            source=-1,
            time=float("nan"),
            lambda2=lambda2,
            sampling=None,
            repairs=repairs,
        )
