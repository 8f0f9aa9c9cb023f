"""People's poses and colour twins (thesis 3.4)."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from heatdata.errors import HeatdataError
from heatdata.recognition.metrics import confusion_matrix
from heatdata.reporting.figures.common import _draw_counts, _draw_mesh, _save


def plot_pose_isomap(embeddings: list[tuple], examples: list[tuple], path: str | Path, title: str) -> None:
    """Fig. 3.11: 2D Isomaps of people's descriptors coloured by pose, and example views.

    Parameters
    ----------
    embeddings : list of (embedding (N, 2), groups (N,), title)
        One panel each, e.g. one body's pose sequence and Reallusion's posed people.
    examples : list of (View, title)
        Views drawn beside them (e.g. two frames of each group).
    """
    if not embeddings:
        raise HeatdataError("no Isomap to draw")
    fig = plt.figure(figsize=(4.6 * len(embeddings) + 1.7 * len(examples), 4.6))
    grid = fig.add_gridspec(
        1, 2 * len(embeddings) + len(examples), width_ratios=[2.7] * (2 * len(embeddings)) + [2.0] * len(examples)
    )
    for k, (embedding, groups, heading) in enumerate(embeddings):
        ax = fig.add_subplot(grid[0, 2 * k : 2 * k + 2])
        groups = np.asarray(groups)
        for colour, group in zip(plt.get_cmap("tab10").colors, dict.fromkeys(groups), strict=False):
            chosen = groups == group
            ax.scatter(
                *embedding[chosen].T,
                s=22,
                color=colour,
                label=f"{group} ({chosen.sum()})",
                edgecolors="black",
                linewidths=0.3,
            )
        ax.legend(fontsize=7)
        ax.set_title(heading, fontsize=8)
        ax.set_xlabel("Isomap 1", fontsize=7)
        ax.set_ylabel("Isomap 2", fontsize=7)
    for k, (view, heading) in enumerate(examples):
        _draw_mesh(fig.add_subplot(grid[0, 2 * len(embeddings) + k]), view, heading)
    fig.suptitle(title, fontsize=9)
    _save(fig, path)


def plot_twins(predictions: pd.DataFrame, examples: dict, path: str | Path, title: str) -> None:
    """Fig. 3.12: for each twin pair, its people's views and one person confusion matrix per descriptor.

    Parameters
    ----------
    predictions : pandas.DataFrame
        ``pair, descriptor, person, predicted`` per test view
        (:func:`heatdata.experiments.people.twin_predictions` with a ``pair`` column).
    examples : dict
        Pair -> list of (View, title): a view of each of its people.
    """
    pairs = list(dict.fromkeys(predictions["pair"]))
    names = list(dict.fromkeys(predictions["descriptor"]))
    shown = max(len(examples.get(pair, [])) for pair in pairs)
    fig, axes = plt.subplots(
        len(pairs), shown + len(names), figsize=(2.0 * shown + 3.3 * len(names), 3.4 * len(pairs)), squeeze=False
    )
    for row, pair in enumerate(pairs):
        for k, ax in enumerate(axes[row, :shown]):
            if k < len(examples.get(pair, [])):
                _draw_mesh(ax, *examples[pair][k])
            else:
                ax.set_axis_off()
        for ax, name in zip(axes[row, shown:], names, strict=True):
            rows = predictions[(predictions["pair"] == pair) & (predictions["descriptor"] == name)]
            people = list(dict.fromkeys(rows["person"]))
            _draw_counts(ax, confusion_matrix(rows["person"], rows["predicted"], people).to_numpy(), people)
            ax.set_title(
                f"{pair}:\n{name}\nprecision {rows['correct'].mean():.0%} of {len(rows)} test views", fontsize=8
            )
            ax.set_xlabel("predicted (nearest library view)", fontsize=7)
    fig.suptitle(title, fontsize=9)
    _save(fig, path)
