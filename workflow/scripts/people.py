"""People (rule people, thesis 3.5): one body's poses in the PVHK's Isomap and colour twins told apart."""

from pathlib import Path

import numpy as np
import pandas as pd

from heatdata.descriptors import DescriptorSpec
from heatdata.experiments.people import (
    CLOTHES,
    kind_distances,
    pose_measures,
    pose_summary,
    reallusion_experiment,
    reallusion_people,
    twin_experiment,
)
from heatdata.log import setup_logging
from heatdata.reporting.figures.people import plot_pose_isomap, plot_twins
from heatdata.reporting.pages import people_page
from heatdata.views.view import kinect_intrinsics

setup_logging(path=snakemake.log[0])
s = snakemake.params.settings
specs = [DescriptorSpec.from_dict(d) for d in s["descriptors"]]
render = {
    "distance": s["distance"],
    "elevation": s["elevation"],
    "noise": s["noise"],
    "intrinsics": kinect_intrinsics(s["image_scale"]),
}
body = {"weight": s["weight"], "muscle": s["muscle"], "gender": s["gender"]}
predictions, values, frames, views = twin_experiment(
    specs, frames=s["frames"], body=body, turn=s["turn"], seed=s["seed"], **render
)
first = frames["person"] == frames["person"].iloc[0]  # Fig. 3.11: the first person's sequence
distances = kind_distances(specs)
poses, isomaps = {}, []
for spec in specs:
    chosen = values[spec.name][first.to_numpy()]
    poses[spec.name] = pose_measures(
        distances[spec.name](chosen, chosen), frames.loc[first, "group"], n_neighbors=s["n_neighbors"]
    )
shape = specs[0].name
isomaps.append(
    (
        poses[shape]["embedding"],
        frames.loc[first, "group"],
        f"{shape}:\none MakeHuman body's {first.sum()} frames, nearest view's group "
        f"{poses[shape]['nearest_accuracy']:.0%}",
    )
)
frames.loc[first, ["isomap1", "isomap2"]] = poses[shape]["embedding"]
index = np.flatnonzero(first.to_numpy())
examples = [(views[index[k]], f"frame {k}: {frames['group'].iloc[index[k]]}") for k in range(min(4, len(index)))]
twin_examples = {"MakeHuman": [(views[np.flatnonzero((frames["person"] == p).to_numpy())[0]], p) for p in CLOTHES]}
summaries = [pose_summary(poses, "MakeHuman sequence")]
if s["reallusion"]:
    people = reallusion_people(s["reallusion"], str(Path(snakemake.output.table).parent / "reallusion"))
    azimuths = np.linspace(-s["turn"], s["turn"], s["reallusion_views"])
    r_values, r_views, r_predictions, r_examples = reallusion_experiment(
        specs, people, azimuths=azimuths, twin=s["twin"], hue=s["hue"], twin_views=s["frames"], seed=s["seed"], **render
    )
    d = distances[shape](r_values[shape], r_values[shape])
    reallusion = pose_measures(d, r_views["pose"], owners=r_views["object"], n_neighbors=s["n_neighbors"])
    summaries.append(pose_summary({shape: reallusion}, "Reallusion people"))
    r_views[["isomap1", "isomap2"]] = reallusion["embedding"]
    isomaps.append(
        (
            reallusion["embedding"],
            r_views["pose"],
            f"{shape}:\nReallusion's {r_views['object'].nunique()} people, nearest other person's pose "
            f"{reallusion['nearest_accuracy']:.0%}",
        )
    )
    predictions = pd.concat([predictions, r_predictions], ignore_index=True)
    twin_examples.update(r_examples)
    r_views.to_csv(snakemake.output.reallusion, index=False)
else:
    pd.DataFrame(columns=["object", "pose", "azimuth", "isomap1", "isomap2"]).to_csv(
        snakemake.output.reallusion, index=False
    )
frames.to_csv(snakemake.output.table, index=False)
pd.concat(summaries, ignore_index=True).to_csv(snakemake.output.poses_table, index=False)
predictions.to_csv(snakemake.output.predictions, index=False)
plot_pose_isomap(
    isomaps,
    examples,
    snakemake.output.poses,
    "People's poses in the descriptor's 2D Isomap (thesis Fig. 3.11): arms close to the body against arms away from it",
)
plot_twins(
    predictions,
    twin_examples,
    snakemake.output.twins,
    "Twins of one shape in different colours (thesis Fig. 3.12): which person is the nearest library view's?",
)
with open(snakemake.output.page, "w") as out:
    out.write(people_page(summaries, predictions, s))
