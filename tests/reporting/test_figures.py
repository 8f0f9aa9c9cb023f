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


@pytest.mark.parametrize("objects, legend", [(3, ["o0", "o1", "o2"]), (58, ["median of 58 objects (grey: each)"])])
def test_the_per_object_panel_names_a_few_objects_and_sums_up_many(monkeypatch, tmp_path, objects, legend):
    drawn = []
    monkeypatch.setattr(recognition, "_save", lambda fig, path, note=common.RENDERED_NOTE: drawn.append(fig))
    recognition.plot_precision(precision_rows(objects), tmp_path / "precision.png", "d")
    right = drawn[0].axes[1]
    assert [t.get_text() for t in right.get_legend().get_texts()] == legend
    if objects > common.MAX_LEGEND_OBJECTS:  # the median line: 0.5 * (objects - 1) / objects at each size
        median = right.get_lines()[-1].get_ydata()
        assert median == pytest.approx([100 * (objects - 1) / objects / 2] * 2)
