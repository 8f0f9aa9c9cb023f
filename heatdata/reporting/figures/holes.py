"""Descriptors against hole size (thesis 3.6)."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from heatdata.reporting.figures.common import _save


def plot_holes(summary: pd.DataFrame, path: str | Path) -> None:
    """Fig. 3.14-3.15: holed boxes recognized among solid boxes, and how far holes move each descriptor."""
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 0.9 + 0.42 * len(summary)))
    y = np.arange(len(summary))
    left.barh(y, 100 * summary["precision"], color="tab:blue")
    left.set_yticks(y, summary["descriptor"], fontsize=8)
    left.set_xlim(0, 100)
    left.set_xlabel("holed-box views whose nearest solid view is their own box (%)")
    right.barh(y, summary["median_ratio"], color="tab:orange")
    right.axvline(1.0, color="0.3", lw=0.8, ls="--")
    right.set_xscale("log")
    right.set_yticks(y, [])
    right.set_xlabel("median d(solid, holed) / d(solid, next view angle)")
    for ax in (left, right):
        ax.invert_yaxis()
        ax.grid(axis="x", alpha=0.3)
    fig.suptitle(
        "Boxes with a round hole cut in every face, against the same boxes solid (cf. thesis Fig. 3.15)", fontsize=9
    )
    _save(fig, path, note="Views are rendered from 3D models without sensor noise, not real sensor data.")
