"""The jobs of ``heatdata demo``: the workflow's stages on a catalogue, in one process."""

from __future__ import annotations

import pandas as pd

from heatdata.descriptors import (
    DEFAULT_KIND,
    DescriptorSpec,
)
from heatdata.experiments.describe import describe_object
from heatdata.io.catalog import load_catalog_model
from heatdata.log import setup_logging
from heatdata.recognition.evaluate import (
    classify,
)

DEMO_SPECS = [
    DescriptorSpec(DEFAULT_KIND, 64, source, sampling)
    for source in ("closest", "center")
    for sampling in ("arclength", "polar")
]


def _one_thread() -> None:
    """Worker initializer: one BLAS thread per process, so jobs do not oversubscribe cores."""
    from threadpoolctl import threadpool_limits

    threadpool_limits(1)
    setup_logging(verbose=False)


def _describe_catalog_object(job: tuple) -> pd.DataFrame:
    row, plan, specs, noise = job
    return describe_object(load_catalog_model(row), plan, specs, noise=noise)


def _classify_job(job: tuple) -> pd.DataFrame:
    return classify(*job)
