"""A learned kind: a PointNet trained on the library views, whose embedding is the descriptor (not in the thesis).

The thesis's descriptors are training-free: heat diffuses over the view and the result is compared. Its implicit
question, whether a model learned from the same views does better, is asked by this kind (the learned kind's
page, docs/guide/learned.md). A view is ``points`` of its vertices, drawn with a fixed seed, in the canonical
frame that faces the segment (:attr:`heatdata.views.view.View.canonical_vertices`, eq. 2.8) and centred on
their mean, in metres; with ``color: rgb`` each point also carries its colour (minus 1/2). The network is
Qi et al.'s PointNet (CVPR 2017) without its input transforms: a shared per-point MLP (:data:`POINT_WIDTHS`, then
``width``), a max pool over the points, two dense layers (:data:`HIDDEN`, then ``embedding`` values).

:func:`heatdata.fit_spec` trains it on the library views, with a classifier on the embedding for the library's
objects (cross-entropy; AdamW with a cosine schedule), ``steps`` batches of :data:`BATCH` views whose points are
drawn again at every step, scaled by up to 5%, turned by up to 6 deg about the vertical and jittered by 2 mm.
The classifier is then dropped: a view's descriptor is its embedding, compared by the Euclidean distance to the
library's rows, so a library answers the way every other kind's does (nearest library view, confidence,
unknown). Training is seeded and uses JAX's default device (a GPU when ``jax`` is installed with CUDA, else the
CPU); describing a view is numpy alone. What is learned is a set of float arrays stored in the library file
like any fitted kind's, with a digest of the objects it was trained on, so a library refuses weights trained on
other objects.
"""

from __future__ import annotations

import hashlib
import itertools
import logging
import time

import numpy as np
from scipy.spatial.distance import cdist

from heatdata.descriptors.base import Descriptor, DescriptorSpec, Kind, Option, integer, one_of, register
from heatdata.errors import SpecError, ViewError

log = logging.getLogger(__name__)

POINT_WIDTHS = (64, 128)  #: the shared per-point MLP before its last layer, ``width`` wide
HIDDEN = 256  #: the dense layer between the pool and the embedding
BATCH = 32  #: views per training step
POOL = 4096  #: points kept per training view, of which each step draws ``points``
LEARNING_RATE = 1e-3
WEIGHT_DECAY = 1e-4
SCALE, TURN, JITTER = 0.05, 0.1, 0.002  #: augmentation: relative scale, radians about the vertical, metres
DIGEST = 32  #: bytes of the trained objects' SHA-256, stored as floats
COLORS = ("rgb", "none")


def objects_digest(objects) -> np.ndarray:
    """(32,) float64: the SHA-256 of the sorted object names, what the weights record they were trained on."""
    text = "\n".join(sorted({str(o) for o in objects}))
    return np.frombuffer(hashlib.sha256(text.encode()).digest(), np.uint8).astype(np.float64)


def layer_shapes(spec: DescriptorSpec) -> dict[str, tuple[int, ...]]:
    """The network's arrays for ``spec``: ``point0..2`` and ``dense0..1``, each a weight ``_w`` and a bias ``_b``."""
    widths = [6 if spec.color == "rgb" else 3, *POINT_WIDTHS, spec.width, HIDDEN, spec.embedding]
    shapes: dict[str, tuple[int, ...]] = {}
    for k, (a, b) in enumerate(itertools.pairwise(widths)):
        name = f"point{k}" if k <= len(POINT_WIDTHS) else f"dense{k - len(POINT_WIDTHS) - 1}"
        shapes[f"{name}_w"], shapes[f"{name}_b"] = (a, b), (b,)
    return shapes


def embed(params: dict, clouds, xp=np):
    """(B, embedding) embeddings of (B, P, C) point clouds: ``xp`` is numpy to describe, ``jax.numpy`` to train."""
    h = clouds
    for k in range(len(POINT_WIDTHS) + 1):
        h = xp.maximum(h @ params[f"point{k}_w"] + params[f"point{k}_b"], 0.0)
    h = xp.max(h, axis=1)
    h = xp.maximum(h @ params["dense0_w"] + params["dense0_b"], 0.0)
    return h @ params["dense1_w"] + params["dense1_b"]


def view_points(view, spec: DescriptorSpec, count: int, seed: int) -> np.ndarray:
    """(count, 3 or 6) float32: ``count`` vertices drawn with ``seed`` (with replacement when the view has fewer),
    canonical and centred, in metres, then their colours minus 1/2 for ``color: rgb``."""
    x = np.asarray(view.canonical_vertices, np.float64)
    if len(x) < 3:
        raise ViewError(f"{view.name}: {len(x)} vertices are too few for a pointnet")
    pick = np.random.default_rng(seed).choice(len(x), count, replace=len(x) < count)
    points = x[pick] - x.mean(axis=0)
    if spec.color == "rgb":
        points = np.column_stack([points, np.asarray(view.colors, np.float64)[pick] - 0.5])
    return points.astype(np.float32)


class PointNet(Kind):
    name = "pointnet"
    summary = "PointNet embedding trained on the library views (Qi et al. 2017), nearest by Euclidean distance; learned"
    fitted = True
    learned = True
    distance_name = "Euclidean distance"
    index_space = "l2"
    value_label = "embedding"
    options = (
        Option("points", 1024, "vertices drawn per view", integer(64, 4096)),
        Option("color", "rgb", "each point's colour too (rgb) or its position alone (none)", one_of(COLORS)),
        Option("width", 256, "features per point pooled over the view (the shared MLP's last layer)", integer(8, 4096)),
        Option("embedding", 128, "values of the descriptor (the network's last layer)", integer(8, 1024)),
        Option("steps", 3000, "training steps of 32 views", integer(1, 10**6)),
        Option("train_views", 8, "library views per object it trains on, evenly spaced in azimuth", integer(1, 3600)),
        Option("seed", 0, "seed of the weights, the batches, the augmentation and each view's points", integer(0)),
    )

    def unavailable(self) -> str | None:
        import importlib.util

        missing = [m for m in ("jax", "optax") if importlib.util.find_spec(m) is None]
        return f"training needs {' and '.join(missing)} (pip install -r requirements.txt)" if missing else None

    def size(self, spec: DescriptorSpec, view) -> int:
        return spec.embedding

    def fitted_shapes(self, spec: DescriptorSpec) -> dict[str, tuple[int, ...]]:
        return {**layer_shapes(spec), "objects": (DIGEST,)}

    def foreign_fit(self, spec: DescriptorSpec, objects: list[str]) -> str | None:
        if spec.fitted is not None and not np.array_equal(spec.fitted["objects"], objects_digest(objects)):
            return f"its {self.name} weights were trained on other objects than the library's {len(objects)}"
        return None

    def compute(self, work, spec: DescriptorSpec, **context) -> list[Descriptor]:
        if spec.fitted is None:
            raise SpecError(
                "a pointnet must be trained on library views first (spec = heatdata.fit_spec(spec, library_views))"
            )
        view = work.view
        points = view_points(view, spec, spec.points, spec.seed)
        params = {k: np.asarray(v, np.float32) for k, v in spec.fitted.items()}
        values = embed(params, points[None])[0].astype(np.float64)
        return [
            Descriptor(
                kind=self.name,
                values=values,
                positions=np.arange(len(values)) / len(values),
                source=-1,
                time=float("nan"),
                lambda2=float("nan"),
                sampling=None,
                repairs=(),
            )
        ]

    def distance_matrix(self, queries, library, *, query_weights=None, library_weights=None):
        """(Q, N) Euclidean distances between embeddings."""
        return cdist(np.asarray(queries, np.float64), np.asarray(library, np.float64))

    def fit(self, spec: DescriptorSpec, views: list) -> dict[str, np.ndarray]:
        """Train the network on ``views`` labelled by their ``object_id`` (see the module docstring)."""
        labels = [v.object_id for v in views]
        objects = sorted(set(labels))
        if len(objects) < 2 or "" in objects:
            raise ViewError(
                f"a pointnet learns to tell objects apart: it needs views of 2 objects or more, got {objects}"
            )
        weights = train(
            spec, [view_points(v, spec, POOL, spec.seed) for v in views], [objects.index(o) for o in labels]
        )
        return {**weights, "objects": objects_digest(objects)}


def train(spec: DescriptorSpec, pools: list[np.ndarray], labels: list[int]) -> dict[str, np.ndarray]:
    """The network's arrays after ``spec.steps`` steps on ``pools`` ((POOL, C) points per view) of ``labels``."""
    logging.getLogger("jax._src.xla_bridge").setLevel(logging.WARNING)  # it lists the backends it did not find
    import jax
    import jax.numpy as jnp
    import optax

    classes = max(labels) + 1
    shapes = {**layer_shapes(spec), "head_w": (spec.embedding, classes), "head_b": (classes,)}
    key = jax.random.PRNGKey(spec.seed)
    params = {}
    for name, shape in shapes.items():
        key, sub = jax.random.split(key)
        params[name] = jax.random.normal(sub, shape) * np.sqrt(2.0 / shape[0]) if len(shape) == 2 else jnp.zeros(shape)

    def loss(params, clouds, y):
        hidden = jnp.maximum(embed(params, clouds, jnp), 0.0)
        logits = hidden @ params["head_w"] + params["head_b"]
        return optax.softmax_cross_entropy_with_integer_labels(logits, y).mean()

    optimizer = optax.adamw(optax.cosine_decay_schedule(LEARNING_RATE, spec.steps), weight_decay=WEIGHT_DECAY)

    @jax.jit
    def step(params, state, clouds, y):
        value, grads = jax.value_and_grad(loss)(params, clouds, y)
        updates, state = optimizer.update(grads, state, params)
        return optax.apply_updates(params, updates), state, value

    rng = np.random.default_rng(spec.seed)
    pools_array, labels_array = np.stack(pools), np.asarray(labels)
    state = optimizer.init(params)
    start, order = time.perf_counter(), np.empty(0, np.int64)
    log.info(
        "training a pointnet on %d views of %d objects: %d steps on %s",
        len(pools),
        classes,
        spec.steps,
        jax.default_backend(),
    )
    for count in range(1, spec.steps + 1):
        if len(order) < BATCH:
            order = np.concatenate([order, rng.permutation(len(pools))])
        batch, order = order[:BATCH], order[BATCH:]
        params, state, value = step(params, state, augmented(pools_array[batch], spec.points, rng), labels_array[batch])
        if count % 500 == 0 or count == spec.steps:
            log.info(
                "pointnet step %d/%d: loss %.3f, %.0f s", count, spec.steps, float(value), time.perf_counter() - start
            )
    return {name: np.asarray(params[name], np.float64) for name in layer_shapes(spec)}


def augmented(pools: np.ndarray, points: int, rng: np.random.Generator) -> np.ndarray:
    """(B, points, C) float32: each view's points drawn again, scaled, turned about the vertical and jittered."""
    out = np.empty((len(pools), points, pools.shape[2]), np.float32)
    for k, pool in enumerate(pools):
        p = pool[rng.choice(len(pool), points, replace=False)].copy()
        angle = rng.uniform(-TURN, TURN)
        c, s = np.cos(angle), np.sin(angle)
        turn = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]], np.float32)
        p[:, :3] = (p[:, :3] * rng.uniform(1 - SCALE, 1 + SCALE)) @ turn.T + rng.normal(0, JITTER, (points, 3))
        out[k] = p
    return out


register(PointNet())
