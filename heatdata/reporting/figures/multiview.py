"""Algorithm 4.1's posterior against the number of views (thesis 4.5)."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import pandas as pd
from matplotlib.ticker import PercentFormatter

from heatdata.reporting.figures.common import _save


def plot_multiview(summary: pd.DataFrame, path: str | Path, title: str) -> None:
    """Thesis Fig. 4.8, 4.10: accuracy, identification, degrees travelled and comparisons against particles.

    ``summary`` is :func:`heatdata.experiments.multiview.trial_summary`; one line per library size,
    bootstrap and policy, and a black reference line for the exhaustive filter's rows.
    """
    fig, (acc, ident, deg, comp) = plt.subplots(1, 4, figsize=(18, 4.2))
    styles = {size: style for size, style in zip(sorted(summary["library_views"].unique()), ["-", "--", ":", "-."])}
    colours = {
        ("similarity", "fixed"): "tab:blue",
        ("angular", "fixed"): "tab:orange",
        ("similarity", "active"): "tab:green",
        ("angular", "active"): "tab:red",
    }
    exact = summary[summary["bootstrap"] == "exhaustive"]
    summary = summary[summary["bootstrap"] != "exhaustive"]
    for row in exact.itertuples():  # the exact filter has no particle count: a reference line
        style = dict(color="black", ls=styles[row.library_views], lw=1)
        acc.axhline(
            100 * row.accuracy,
            **style,
            label=f"exhaustive filter ({row.particles} hypotheses), {row.library_views} library views",
        )
        ident.axhline(100 * row.identified, **style)
        deg.axhline(row.degrees, **style)
    for (size, boot, policy), rows in summary.groupby(["library_views", "bootstrap", "policy"]):
        rows = rows.sort_values("particles")
        label = f"{boot} bootstrap, {policy} steps, {size} library views"
        style = dict(color=colours[(boot, policy)], ls=styles[size], marker="o", ms=3, label=label)
        acc.plot(rows["particles"], 100 * rows["accuracy"], **style)
        ident.plot(rows["particles"], 100 * rows["identified"], **style)
        deg.plot(rows["particles"], rows["degrees"], **style)
        comp.plot(rows["particles"], rows["comparisons"], **style)
        if boot == "similarity" and policy == "fixed":
            comp.plot(
                rows["particles"],
                rows["exhaustive"],
                color="grey",
                ls=styles[size],
                lw=1,
                label=f"exhaustive search, {size} library views",
            )
    acc.set_ylabel("accuracy: converged on the true object (%)")
    ident.set_ylabel("identified: true object most probable at the end (%)")
    for ax in (acc, ident):
        ax.yaxis.set_major_formatter(PercentFormatter(100, decimals=0))
    deg.set_ylabel("degrees travelled (mean)")
    comp.set_ylabel("view comparisons (particles x stops, mean)")
    for ax in (acc, ident, deg, comp):
        ax.set_xscale("log")
        ticks = sorted(summary["particles"].unique())
        ax.set_xticks(ticks, [str(t) for t in ticks])
        ax.set_xlabel("particles")
        ax.grid(alpha=0.3)
    acc.legend(fontsize=6)
    comp.legend(fontsize=6)
    fig.suptitle(title, fontsize=9)
    _save(fig, path)
