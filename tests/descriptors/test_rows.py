"""Batch description: a view's failure is a NaN row with its reason; a spec's mistake stops the batch."""

import numpy as np
import pandas as pd
import pytest
from conftest import square_view

import heatdata as hd
from heatdata.descriptors.rows import descriptor_rows


def plan(count: int) -> pd.DataFrame:
    return pd.DataFrame({"split": ["train"] * count, "seed": range(count)})


def test_a_view_too_small_for_a_kind_is_a_nan_row_that_says_why():
    views = [square_view(21), square_view(6)]  # 36 vertices: too few for a histogram of 50
    rows = descriptor_rows(views, plan(2), [hd.DescriptorSpec("hgd")])
    assert np.all(np.isfinite(rows["values"].iloc[0]))
    assert np.all(np.isnan(rows["values"].iloc[1]))
    assert any("too few for an hgd" in r for r in rows["repairs"].iloc[1])


def test_an_unfitted_kind_is_the_caller_s_mistake_and_stops_the_batch():
    views = [square_view(21), square_view(21)]
    with pytest.raises(hd.SpecError, match="fitted on library views first"):  # not two silent NaN rows
        descriptor_rows(views, plan(2), [hd.DescriptorSpec("hgd"), hd.DescriptorSpec("si-hks")])
