"""A metric learned on heatdata's own histograms, against their nearest neighbour, on a run's library views.

    .venv/bin/python scripts/learned_metric.py results/chairs_learned --size 8 \\
        --out docs/results/chairs_learned_metric.csv

The cheaper way to learn from the library views, with no new framework: the histogram kinds' chi-square distance
made linear by scikit-learn's ``AdditiveChi2Sampler`` (its explicit feature map of the additive chi-square
kernel), then a logistic regression that names the object, trained on the ``--size`` library views per object
(its strength chosen among :data:`CS` by 4-fold cross-validation on those views, seeded), and scored on the run's
test views beside each kind's nearest library view. Rendered views, not real sensor data.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
import pandas as pd
from sklearn.kernel_approximation import AdditiveChi2Sampler
from sklearn.linear_model import LogisticRegressionCV
from sklearn.model_selection import StratifiedKFold
from sklearn.pipeline import make_pipeline

from heatdata.descriptors import kind_of
from heatdata.descriptors.histograms import HistogramKind
from heatdata.io.tables import read_table
from heatdata.recognition.evaluate import classify, library_subset

CS = (1.0, 10.0, 100.0, 1000.0, 10000.0)  #: the regularization strengths cross-validated on the library views


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run", type=Path, help="a run's results folder (descriptors.parquet)")
    parser.add_argument("--size", type=int, default=8, help="library views per object (8)")
    parser.add_argument("--out", type=Path, required=True, help="the table to write (.csv)")
    args = parser.parse_args()
    table, _ = read_table(args.run / "descriptors.parquet")
    out = []
    for descriptor in sorted(set(table["descriptor"])):
        rows = table[table["descriptor"] == descriptor]
        if not isinstance(kind_of(rows["kind"].iloc[0]), HistogramKind):
            continue
        library = library_subset(rows[rows["split"] == "train"], args.size)
        tests = rows[rows["split"] == "test"]
        nearest = classify(pd.concat([library, tests], ignore_index=True), descriptor)["correct"].mean()
        folds = StratifiedKFold(4, shuffle=True, random_state=0)
        regression = LogisticRegressionCV(
            Cs=CS, cv=folds, scoring="accuracy", max_iter=2000, random_state=0, use_legacy_attributes=False
        )
        model = make_pipeline(AdditiveChi2Sampler(), regression)
        start = time.perf_counter()
        model.fit(np.stack(library["values"].to_numpy()), library["object"].to_numpy())
        seconds = time.perf_counter() - start
        learned = np.mean(model.predict(np.stack(tests["values"].to_numpy())) == tests["object"].to_numpy())
        out.append(
            {
                "descriptor": descriptor,
                "size": args.size,
                "nearest": float(nearest),
                "chi2_logistic": float(learned),
                "C": float(np.ravel(regression.C_)[0]),
                "train_seconds": round(seconds, 1),
            }
        )
        print(out[-1])
    args.out.parent.mkdir(parents=True, exist_ok=True)
    pd.DataFrame(out).round(4).to_csv(args.out, index=False)


if __name__ == "__main__":
    main()
