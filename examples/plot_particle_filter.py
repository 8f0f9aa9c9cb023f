"""
A particle filter circling an object
====================================

A robot walks around an unknown object and takes a view every 30 degrees. Each view alone may look like another
object: the coffee cup, the plastic cup and the beer mug are look-alikes. Algorithm 4.1 (thesis ch. 4) keeps
particles, hypotheses of (object, view angle), weighs them by how well the view matches the library view at their
angle (eq. 4.4-4.5), turns them with the robot's odometry (eq. 4.7), and re-populates weak hypotheses with
library views that look like the survivors (4.4.6, learned from independent views, eq. 4.6). The exhaustive
filter scores every object at every degree: the exact posterior that the particles approximate.

The views are rendered with simulated Kinect noise, not real sensor data.
"""

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

import heatdata as hd
from heatdata.recognition.multiview.appearance import learn_similarity
from heatdata.recognition.multiview.filters import ExhaustiveFilter, ParticleFilter

catalog = hd.read_catalog(hd.embedded_catalog())
objects = ["coffee-cup", "plastic-cup", "beer-mug"]
models = {row["object"]: hd.load_catalog_model(row) for row in catalog.to_dict("records") if row["object"] in objects}
spec = hd.DescriptorSpec("pvhk", 64, "closest", "arclength")  # the weaker rules of 2.3: more ambiguity


def descriptor(obj: str, azimuth: float, seed: int) -> np.ndarray:
    return hd.describe(hd.render_view(models[obj], azimuth=azimuth, elevation=30.0, seed=seed), [spec])[0].values


# the library: 12 views per object, 30 degrees apart; independent views between them teach the similarity
library = pd.DataFrame(
    [{"object": o, "azimuth": float(a), "values": descriptor(o, a, seed=1)} for o in objects for a in range(0, 360, 30)]
)
independent = pd.DataFrame(
    [
        {"object": o, "azimuth": a + 15.0, "values": descriptor(o, a + 15.0, seed=2)}
        for o in objects
        for a in range(0, 360, 30)
    ]
)
similarity = learn_similarity(library, independent)

particles = ParticleFilter(library, similarity, particles=30, seed=0)
exact = ExhaustiveFilter(library)
true_object, start, step = "coffee-cup", 260.0, 30.0  # from 260 degrees the cup looks like the mug
history = []
for stop in range(5):
    seen = [descriptor(true_object, start + stop * step, seed=10 + stop)]  # what the robot sees at this stop
    move = step if stop else 0.0  # odometry since the last stop
    particles.step(seen, move)
    exact.step(seen, move)
    history.append((particles.posterior(), exact.posterior(), particles.object.copy(), particles.azimuth.copy()))
    print(
        f"stop {stop + 1}: particles say {particles.estimate}, the exact filter {exact.estimate}"
        f" ({exact.posterior()[exact.estimate]:.0%}); particles converged: {particles.converged}"
    )

fig = plt.figure(figsize=(11, 4.6))
polar = fig.add_subplot(1, 2, 1, projection="polar")
colours = dict(zip(objects, ["tab:blue", "tab:orange", "tab:green"]))
for k, (_, _, obj, azimuth) in enumerate(history):
    for i, o in enumerate(particles.objects):  # obj indexes the filter's own (sorted) list of objects
        mine = obj == i
        polar.scatter(
            np.radians(azimuth[mine]), np.full(mine.sum(), k + 1), s=12, color=colours[o], label=o if k == 0 else None
        )
polar.set_rticks(range(1, len(history) + 1))
polar.set_title("particles (object, view angle) at each stop (radius)", fontsize=9)
polar.legend(loc="lower left", fontsize=8, bbox_to_anchor=(-0.25, -0.12))

ax = fig.add_subplot(1, 2, 2)
stops = np.arange(1, len(history) + 1)
for o in objects:
    ax.plot(stops, [h[0][o] for h in history], "-o", color=colours[o], label=f"{o} (particles)")
    ax.plot(stops, [h[1][o] for h in history], "--", color=colours[o], label=f"{o} (exact)")
ax.set_xlabel("stop (30 degrees apart)")
ax.set_ylabel("posterior probability of the object")
ax.set_ylim(-0.02, 1.02)
ax.set_xticks(stops)
ax.legend(fontsize=7)
fig.suptitle(f"The robot circles the {true_object}")
fig.tight_layout()
plt.show()

# %%
# The gallery's thumbnail: one panel of the figure above, drawn to be read at a thumbnail's size.
# sphinx_gallery_thumbnail_number = 2
thumbnail, ax = plt.subplots(figsize=(4, 2.8))
for o in objects:
    ax.plot(stops, [h[0][o] for h in history], "-o", color=colours[o], lw=2.5, ms=8)
ax.set_ylim(-0.02, 1.02)
ax.set_xticks(stops)
ax.set_yticks([0, 1])
ax.set_title(f"the {true_object}, stop by stop", fontsize=14)
thumbnail.tight_layout()
plt.show()
