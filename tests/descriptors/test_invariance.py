"""Where an object stands in the frame does not change its answer, for every registered kind (eq. 2.8, 2.3.3).

The same objects are rendered centred, shifted by a fraction of a pixel, and 15 cm off the optical axis at 1 m (the
camera turned 8.5 deg), without noise, and recognized against one library: every kind with its default options
(but the learned kind, trained in its own test),
and the PVHK and C-PVHK from the centre of the image (eq. 2.8), which before the canonical frame lost half their
answers off the axis. A kind's answer may change under any resampling of the surface by the pixel grid: the
sub-pixel shift measures that floor (83-96% of the answers kept for the heat kinds, 100% for the ESF, FPFH and
HGD). Off the axis, no kind loses more than five of the 54 views in precision, or changes its answer in five
views more than that floor (without the canonical frame, the PVHK from the image centre changed 26); and the kinds
whose answers resampling does not change keep them in at least 99% of the views.
"""

import numpy as np
import pandas as pd
import pytest
from conftest import ROOT

import heatdata as hd
from heatdata.descriptors import KINDS, available, fit_spec
from heatdata.descriptors.rows import descriptor_rows
from heatdata.experiments.describe import time_scale_table
from heatdata.experiments.views import render_views, view_plan
from heatdata.recognition.evaluate import classify
from heatdata.views.view import kinect_intrinsics

OBJECTS = ["beer-mug", "milk-carton", "bread"]
OPTIONS = {  # every kind, with the options that make it cheap (or that it needs)
    "c-pvhk": {"color_map": "c3"},
    "pvst": {"source": "interior", "samples": 32},
    "esf": {"triplets": 4000},
    "si-hks": {"words": 16, "modes": 30},
    "combined": {"parts": [{"kind": "hgd"}, {"kind": "pvhk"}]},
}


@pytest.mark.slow
def test_an_object_anywhere_in_the_frame_gets_the_answer_it_gets_at_the_centre():
    assert set(OPTIONS) - {"combined"} <= set(KINDS)
    catalog = hd.read_catalog(ROOT / "data/models/catalog.csv")
    models = {r["object"]: hd.load_catalog_model(r) for r in catalog.to_dict("records") if r["object"] in OBJECTS}
    camera = kinect_intrinsics(0.5)
    library, library_plan, tests, test_plan = [], [], {"centred": [], "sub-pixel": [], "off-axis": []}, []
    shifts = {"centred": (0.0, 0.0), "sub-pixel": (0.3, 0.4), "off-axis": (0.15 * camera["fx"], 0.0)}
    for obj, model in models.items():
        plan = view_plan([obj], 12, 18, seed=0)
        train, test = plan[plan["split"] == "train"], plan[plan["split"] == "test"]
        library += render_views(model, train, noise=False, intrinsics=camera)
        library_plan.append(train)
        for name, shift in shifts.items():
            offsets = np.tile(shift, (len(test), 1))
            tests[name] += render_views(model, test, noise=False, intrinsics=camera, offsets=offsets)
        test_plan.append(test)
    learned = {kind for kind, impl in KINDS.items() if impl.learned}  # trained: its own test, test_pointnet.py
    specs = [
        hd.DescriptorSpec(kind, **OPTIONS.get(kind, {}))
        for kind, why in available().items()
        if why is None and kind not in learned
    ]
    assert len(specs) >= len(KINDS) - len(learned) - 1  # VFH needs Debian's pcl-tools, which the test set-up installs
    specs += [
        hd.DescriptorSpec("pvhk", 64, "center", "polar"),
        hd.DescriptorSpec("c-pvhk", 64, "center", "polar", "c3"),
    ]
    specs = [fit_spec(spec, library) for spec in specs]
    library_plan, test_plan = pd.concat(library_plan), pd.concat(test_plan)
    scales = time_scale_table(library, library_plan, specs)
    rows = descriptor_rows(library, library_plan, specs, time_scales=scales)
    answers = {}
    for name, views in tests.items():
        table = pd.concat([rows, descriptor_rows(views, test_plan, specs, time_scales=scales)])
        answers[name] = {s.name: classify(table, s.name)["predicted_object"].to_numpy() for s in specs}
    report = []
    truth = np.repeat(OBJECTS, 18)
    for spec in specs:
        centred, moved = answers["centred"][spec.name], answers["off-axis"][spec.name]
        floor = np.mean(answers["sub-pixel"][spec.name] == centred)
        same = np.mean(moved == centred)
        report.append((spec.name, floor, same, np.mean(centred == truth), np.mean(moved == truth)))
        slack = 5 / len(centred) + 1e-9
        assert report[-1][4] >= report[-1][3] - slack, report[-1]
        assert same >= floor - slack, report[-1]
        if floor >= 0.99:
            assert same >= 0.99, report[-1]
    assert sum(floor >= 0.99 for _, floor, *_ in report) >= 3, report  # the histograms of the whole view at least
