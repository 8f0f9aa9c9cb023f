"""View sets: which views of which objects to render, and their descriptor rows (thesis 3.3-3.4).

A view plan lists, per object, the training views (the library, evenly spaced in
azimuth) and the test views (offset by half a test step, so no test view repeats a
library angle), each with its own noise seed derived from the object id, split and
index - the same plan always renders the same views.
"""

from __future__ import annotations

import logging
import time
import zlib

import numpy as np
import pandas as pd

from .descriptors import DescriptorSpec, describe
from .errors import HeatdataError
from .models import Model
from .render import render_view

log = logging.getLogger(__name__)


def view_plan(objects: list[str], n_train: int = 40, n_test: int = 120, *, elevation: float = 30.0,
              distance: float = 1.0, seed: int = 0) -> pd.DataFrame:
    """One row per view to render: ``object, split, index, azimuth, elevation, distance, seed``.

    Training azimuths are ``360 k / n_train``; test azimuths ``360 (k + 1/2) / n_test``.
    """
    if n_train < 1 or n_test < 0:
        raise HeatdataError(f"need at least one training view and no negative test count ({n_train}, {n_test})")
    rows = []
    for obj in objects:
        for split, count in (("train", n_train), ("test", n_test)):
            offset = 0.0 if split == "train" else 0.5
            for k in range(count):
                view_seed = np.random.SeedSequence([seed, zlib.crc32(obj.encode()), int(split == "test"), k])
                rows.append({"object": obj, "split": split, "index": k,
                             "azimuth": round(360.0 * (k + offset) / count, 6), "elevation": float(elevation),
                             "distance": float(distance), "seed": int(view_seed.generate_state(1)[0])})
    return pd.DataFrame(rows)


def describe_object(model: Model, plan: pd.DataFrame, specs: list[DescriptorSpec], *, noise: bool = True,
                    progress_every: int = 40) -> pd.DataFrame:
    """Render every planned view of ``model`` and compute the descriptors of ``specs``.

    Returns
    -------
    pandas.DataFrame
        One row per view x descriptor, with the columns of
        :data:`heatdata.tables.DESCRIPTOR_SCHEMA`.
    """
    rows = []
    start = time.perf_counter()
    for count, view_row in enumerate(plan.itertuples(), 1):
        view_id = f"{model.name}/{view_row.split}/{view_row.index:03d}"
        tic = time.perf_counter()
        view = render_view(model, view_row.azimuth, view_row.elevation, view_row.distance, noise=noise,
                           seed=view_row.seed, view_id=view_id)
        descriptors = describe(view, specs)
        seconds = (time.perf_counter() - tic) / len(specs)
        for spec, d in zip(specs, descriptors, strict=True):
            rows.append({
                "object": model.name, "label": model.label, "view_id": view_id, "split": view_row.split,
                "azimuth": view_row.azimuth, "elevation": view_row.elevation, "distance": view_row.distance,
                "seed": view_row.seed, "n_vertices": view.n_vertices, "n_boundary": len(view.boundary),
                "descriptor": spec.name, "kind": spec.kind, "sampling": spec.sampling,
                "source_rule": str(spec.source), "color_map": d.color_map or "", "source": d.source,
                "time": d.time, "lambda2": d.lambda2, "values": d.values.tolist(),
                "positions": d.positions.tolist(), "repairs": list(view.repairs) + list(d.repairs),
                "seconds": seconds,
            })
        if count % progress_every == 0 or count == len(plan):
            log.info("%s: %d/%d views described (%.1f s)", model.name, count, len(plan), time.perf_counter() - start)
    table = pd.DataFrame(rows)
    repaired = table.drop_duplicates("view_id")["repairs"].map(len).gt(0)
    if repaired.any():
        log.info("%s: %d of %d views repaired (see the repairs column), e.g. %s", model.name, int(repaired.sum()),
                 len(repaired), "; ".join(table.loc[repaired[repaired].index[0], "repairs"]))
    return table
