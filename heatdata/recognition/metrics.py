"""Precision and confusion of predictions (thesis 3.5): the one place they are counted."""

from __future__ import annotations

import numpy as np
import pandas as pd


def confusion_matrix(true: pd.Series, predicted: pd.Series, labels: list | None = None) -> pd.DataFrame:
    """Counts of (true, predicted) pairs: rows are true objects, columns predicted.

    Parameters
    ----------
    true, predicted : (N,) pandas.Series
        Labels (objects or classes).
    labels : list, optional
        Rows and columns, in this order; default the sorted union of both.

    Returns
    -------
    pandas.DataFrame
        (L, L) int counts.
    """
    labels = sorted(set(true) | set(predicted)) if labels is None else labels
    table = pd.crosstab(pd.Categorical(true, labels), pd.Categorical(predicted, labels), dropna=False)
    table.index.name, table.columns.name = "true", "predicted"
    return table


def precision_by(true: pd.Series, predicted: pd.Series) -> pd.Series:
    """Precision: the fraction of correct predictions per true label, plus ``"all"``.

    Parameters
    ----------
    true, predicted : (N,) pandas.Series
        Labels; precision is counted per value of ``true``.

    Returns
    -------
    pandas.Series
        Fraction correct per label, and ``"all"`` over every prediction.
    """
    correct = pd.Series(np.asarray(true) == np.asarray(predicted), index=np.asarray(true))
    per = correct.groupby(level=0).mean()
    per["all"] = correct.mean()
    return per


def precision_table(predictions: pd.DataFrame) -> pd.DataFrame:
    """Precision per descriptor, library size and object, and per class (Fig. 3.7, 3.8, 5.13).

    Object precision: the fraction of an object's test views whose nearest library view
    is of that object. Class precision: the fraction whose nearest view has its class.
    Rows with ``group = "all"`` aggregate every test view.

    Parameters
    ----------
    predictions : pandas.DataFrame
        Rows of :data:`heatdata.io.tables.PREDICTION_SCHEMA`.

    Returns
    -------
    pandas.DataFrame
        ``level`` (object or class), ``group`` (an object, a class or ``all``), ``descriptor``,
        ``library_size``, ``precision``.
    """
    frames = []
    keys = ["descriptor", "library_size"]
    for level, column, truth in (("object", "object", "predicted_object"), ("class", "label", "predicted_label")):
        hit = predictions[column] == predictions[truth]
        per = hit.groupby([predictions[k] for k in keys] + [predictions[column]]).mean().rename("precision")
        per = per.reset_index().rename(columns={column: "group"})
        overall = hit.groupby([predictions[k] for k in keys]).mean().rename("precision").reset_index()
        frames += [per.assign(level=level), overall.assign(group="all", level=level)]
    return pd.concat(frames, ignore_index=True)[["level", "group", "descriptor", "library_size", "precision"]]


def precision_by_object(predictions: pd.DataFrame) -> pd.DataFrame:
    """Object precision per object (rows) for each descriptor (columns), with an ``all`` row.

    Parameters
    ----------
    predictions : pandas.DataFrame
        Rows of :data:`heatdata.io.tables.PREDICTION_SCHEMA` (one library size).

    Returns
    -------
    pandas.DataFrame
        (objects + 1, descriptors) precisions.
    """
    per = predictions.pivot_table(index="object", columns="descriptor", values="correct", aggfunc="mean")
    per.loc["all"] = predictions.groupby("descriptor")["correct"].mean()
    return per
