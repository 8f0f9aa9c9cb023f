"""The jobs of ``heatdata demo``: the workflow's stages on a catalogue, in one process."""

from __future__ import annotations

import logging
from multiprocessing import get_context

import pandas as pd

from heatdata.descriptors import (
    DEFAULT_KIND,
    DescriptorSpec,
)
from heatdata.experiments.describe import describe_object
from heatdata.io.catalog import load_catalog_model
from heatdata.log import progress, setup_logging
from heatdata.recognition.evaluate import (
    classify,
)

log = logging.getLogger(__name__)

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


def describe_and_classify(
    catalog: pd.DataFrame, plan: pd.DataFrame, specs: list[DescriptorSpec], *, noise: bool = True, jobs: int = 2
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Render and describe every planned view of the catalogue's objects, then classify the test views.

    The workflow's render, describe and classify stages in one process pool: one object per
    describe job, one descriptor per classify job, one BLAS thread per process.

    Parameters
    ----------
    catalog : pandas.DataFrame
        Catalogue rows (:func:`heatdata.read_catalog`).
    plan : pandas.DataFrame
        The views (:func:`heatdata.experiments.views.view_plan`).
    specs : list of DescriptorSpec
        The descriptors.
    noise : bool
        Simulated Kinect noise on the rendered views.
    jobs : int
        Worker processes.

    Returns
    -------
    descriptors, predictions : pandas.DataFrame
        Rows of ``descriptors.parquet`` and ``predictions.parquet``.
    """
    work = [(row.to_dict(), plan[plan["object"] == row["object"]], specs, noise) for _, row in catalog.iterrows()]
    log.info(
        "describing %d views of %d objects (%d descriptors each) with %d processes",
        len(plan),
        len(catalog),
        len(specs),
        jobs,
    )
    with get_context("spawn").Pool(jobs, initializer=_one_thread) as pool:
        described = pool.imap(_describe_catalog_object, work, chunksize=1)
        descriptors = pd.concat(
            progress(described, total=len(work), desc="describing", unit="object"), ignore_index=True
        )
        log.info(
            "classifying %d test views per descriptor against %d library views",
            (plan["split"] == "test").sum(),
            (plan["split"] == "train").sum(),
        )
        subsets = [(descriptors[descriptors["descriptor"] == spec.name], spec.name) for spec in specs]
        classified = pool.imap(_classify_job, subsets, chunksize=1)
        predictions = pd.concat(
            progress(classified, total=len(subsets), desc="classifying", unit="descriptor"), ignore_index=True
        )
    return descriptors, predictions
