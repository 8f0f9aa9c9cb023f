"""describe (heatdata.descriptors.compute): one call shares the work between kinds and answers as single calls."""

import numpy as np

import heatdata as hd


def test_describe_shares_work_and_matches_single_calls(mug):
    view = hd.render_view(mug, 200.0, 30.0, 1.4, seed=6)
    specs = [hd.DescriptorSpec("pvhk", 64, s, p) for s in ("closest", "center") for p in ("arclength", "polar")]
    specs.append(hd.DescriptorSpec("c-pvhk", 64, "center", "polar", "c3"))
    together = hd.describe(view, specs)
    for spec, d in zip(specs, together, strict=True):
        if spec.kind == "pvhk":
            alone = hd.pvhk(view, 64, spec.source, sampling=spec.sampling)
        else:
            alone = hd.c_pvhk(view, 64, "c3", spec.source, sampling=spec.sampling)
        assert np.array_equal(d.values, alone.values)
    assert specs[-1].name == "c-pvhk/polar/center/64/c3"
