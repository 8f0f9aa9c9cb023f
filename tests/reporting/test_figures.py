"""Figures: what a reader sees in them."""

import pandas as pd
import pytest

from heatdata.reporting.figures import common, recognition


def precision_rows(objects: int) -> pd.DataFrame:
    rows = [
        {"level": "object", "group": group, "descriptor": "d", "library_size": size, "precision": p}
        for size in (5, 40)
        for group, p in [("all", 0.5)] + [(f"o{k}", k / objects) for k in range(objects)]
    ]
    return pd.DataFrame(rows)


def test_a_few_objects_are_a_grid_of_numbers_and_many_their_median(monkeypatch, tmp_path):
    drawn = []
    monkeypatch.setattr(recognition, "_save", lambda fig, path, note=common.RENDERED_NOTE: drawn.append(fig))
    recognition.plot_precision(precision_rows(3), tmp_path / "few.png", "d")
    right = drawn[0].axes[1]
    assert [t.get_text() for t in right.get_yticklabels()] == ["o0", "o1", "o2"]
    assert sorted(t.get_text() for t in right.texts) == ["0", "0", "33", "33", "67", "67"]
    recognition.plot_precision(precision_rows(58), tmp_path / "many.png", "d")
    right = drawn[1].axes[1]
    assert [t.get_text() for t in right.get_legend().get_texts()] == ["median of 58 objects (grey: each)"]
    median = right.get_lines()[-1].get_ydata()  # 0.5 * (objects - 1) / objects at each size
    assert median == pytest.approx([100 * 57 / 58 / 2] * 2)


def test_precision_axes_stay_within_0_and_100_and_equal_lines_are_drawn_apart(monkeypatch, tmp_path):
    drawn = []
    monkeypatch.setattr(recognition, "_save", lambda fig, path, note=common.RENDERED_NOTE: drawn.append(fig))
    rows = precision_rows(58)
    rows = pd.concat([rows.assign(precision=1.0), rows.assign(descriptor="e", precision=1.0)])
    recognition.plot_precision(rows, tmp_path / "precision.png", "d")
    for ax in drawn[0].axes[:2]:
        low, high = ax.get_ylim()
        assert 0 <= low < high <= 100
    first, second = (line.get_xdata() for line in drawn[0].axes[0].get_lines())
    assert all(a != b for a, b in zip(first, second)) and len(set(drawn[0].axes[0].get_lines()[0].get_marker())) == 1
    legend = drawn[0].axes[0].get_legend()
    assert [t.get_text() for t in legend.get_texts()] == ["d", "e"]
