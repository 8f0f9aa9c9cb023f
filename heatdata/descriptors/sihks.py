"""Scale-Invariant Heat Kernel Signature as a bag of geometric words (Bronstein & Kokkinos 2010; thesis 3.6.1).

Per vertex x, the heat kernel signature ``h(x, t) = sum_k exp(-lambda_k t) phi_k(x)^2``
from the view's ``modes`` smallest eigenpairs (eq. 2.6, the same Laplacian as the
PVHK's) at ``t = t0 2^(tau)``, tau = 0, 1/4, ..., 47/4 (12 octaves, from
``t0 = 1 / lambda_modes``, the shortest time the modes resolve). A change of scale
shifts ``log h`` in log-time and multiplies it by a constant; the derivative of
``log h`` in tau removes the constant and the magnitude of its Fourier transform the
shift. The first ``frequencies`` magnitudes are the vertex's SI-HKS.

As in the thesis, geometric words are found by k-means (scikit-learn, seeded) on the
standardized SI-HKS of vertices of the library views (:func:`heatdata.fit_spec`, at
most ``fit_vertices`` per view), and a view is its normalized histogram of nearest
words. Compared by the chi-square distance. The view's largest connected component
is used (a repair when there are several).
"""

from __future__ import annotations

import logging

import numpy as np

from heatdata.core.spectrum import eigen_spectrum
from heatdata.descriptors.base import DescriptorSpec, Option, integer, register
from heatdata.descriptors.histograms import HistogramKind
from heatdata.descriptors.work import ViewWork
from heatdata.errors import SpecError, ViewError

log = logging.getLogger(__name__)

TIME_STEPS = 48  # samples of log2-time
TIME_STEP = 0.25  # octaves between samples


def signatures(work: ViewWork, modes: int, frequencies: int) -> tuple[np.ndarray, float, tuple]:
    """(n, frequencies) SI-HKS of the vertices of the view's largest component, its lambda_2, repairs."""
    view = work.largest()
    op = work.operator(view, None)
    spectrum = work.spectrum(op, modes) if modes <= op.n - 2 else eigen_spectrum(op, op.n - 2)
    times = np.exp2(np.arange(TIME_STEPS) * TIME_STEP) / spectrum.values[-1]
    hks = (spectrum.vectors**2) @ np.exp(-np.outer(spectrum.values, times))  # (n, T)
    derivative = np.diff(np.log(np.maximum(hks, np.finfo(float).tiny)), axis=1)
    magnitude = np.abs(np.fft.rfft(derivative, axis=1))[:, :frequencies]
    return magnitude, spectrum.lambda2, tuple(view.repairs[len(work.view.repairs) :])


class SIHKS(HistogramKind):
    name = "si-hks"
    summary = "Scale-Invariant Heat Kernel Signature, bag of k-means words fitted on library views (thesis 3.6.1)"
    fitted = True
    options = (
        Option("words", 32, "geometric words (k-means clusters); the histogram's bins", integer(2, 1024)),
        Option("modes", 100, "eigenpairs of the heat kernel signature", integer(8, 1000)),
        Option("frequencies", 6, "Fourier magnitudes kept per vertex", integer(1, TIME_STEPS // 2)),
        Option("fit_vertices", 200, "vertices per library view the codebook is fitted on", integer(1, 10**5)),
        Option("seed", 0, "seed of the vertex sample and of k-means", integer(0)),
    )

    def size(self, spec: DescriptorSpec, view) -> int:
        return spec.words

    def fitted_shapes(self, spec: DescriptorSpec) -> dict[str, tuple[int, ...]]:
        return {"words": (spec.words, spec.frequencies), "mean": (spec.frequencies,), "scale": (spec.frequencies,)}

    def fit(self, spec: DescriptorSpec, views: list) -> dict[str, np.ndarray]:
        from sklearn.cluster import KMeans

        rng = np.random.default_rng(spec.seed)
        samples = []
        for view in views:
            features, _, _ = signatures(ViewWork(view), spec.modes, spec.frequencies)
            keep = rng.choice(len(features), size=min(spec.fit_vertices, len(features)), replace=False)
            samples.append(features[keep])
        sample = np.concatenate(samples)
        if len(sample) < spec.words:
            raise ViewError(f"si-hks: {len(sample)} library vertices cannot make {spec.words} words")
        mean, scale = sample.mean(axis=0), sample.std(axis=0)
        scale[scale == 0] = 1.0
        kmeans = KMeans(n_clusters=spec.words, n_init=4, random_state=spec.seed).fit((sample - mean) / scale)
        log.info(
            "si-hks: %d words from %d vertices of %d library views (inertia %.3g)",
            spec.words,
            len(sample),
            len(views),
            kmeans.inertia_,
        )
        return {"words": kmeans.cluster_centers_, "mean": mean, "scale": scale}

    def compute(self, work: ViewWork, spec: DescriptorSpec, **context):
        from scipy.spatial import cKDTree

        if spec.fitted is None:
            raise SpecError(
                f"{work.view.name}: an si-hks must be fitted on library views first "
                "(spec = heatdata.fit_spec(spec, library_views))"
            )
        words = spec.fitted["words"]  # of the spec's shape (DescriptorSpec checks a fit)
        self.check_points(work.largest())
        features, lam2, repairs = signatures(work, spec.modes, spec.frequencies)
        _, nearest = cKDTree(words).query((features - spec.fitted["mean"]) / spec.fitted["scale"])
        counts = np.bincount(nearest, minlength=spec.words)
        return [self.histogram(spec, counts, work.view, lambda2=lam2, repairs=repairs)]


register(SIHKS())
