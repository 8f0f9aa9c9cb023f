"""
A compact library: one heat source per library view
====================================================

Thesis ch. 6 describes each library view from many candidate sources (6.2) and keeps one per view, chosen around
the view circle by a linear program (eq. 6.7-6.11): neighbouring views should keep sources whose descriptors
agree (the cost c of eq. 6.6), and each kept descriptor should lie far from every other object's candidates
(the reward rho of Alg. 6.3). Here the coffee cup's 8 library views, 45 degrees apart, each offer 20 candidate
sources (grey); the LP's choice is the star. The plastic cup and the beer mug, its look-alikes, are the other
objects that rho keeps the choice away from. The views are rendered, not real sensor data.
"""

import matplotlib.pyplot as plt
import numpy as np

import heatdata as hd
from heatdata.descriptors.sources import candidate_descriptors, candidate_sources
from heatdata.recognition.compact import combined_costs, consecutive_costs, other_object_distances, select_sources

catalog = hd.read_catalog(hd.embedded_catalog())
objects = ["coffee-cup", "plastic-cup", "beer-mug"]
models = {row["object"]: hd.load_catalog_model(row) for row in catalog.to_dict("records") if row["object"] in objects}
spec = hd.DescriptorSpec("pvhk", 64, "center", "polar")
azimuths = range(0, 360, 45)

views = {o: [hd.render_view(models[o], azimuth=a, elevation=30.0, seed=a) for a in azimuths] for o in objects}
sources = {o: [candidate_sources(v, 20) for v in vs] for o, vs in views.items()}  # (20,) vertex ids per view
candidates = {  # per object, per view: (20, 64), one PVHK per candidate source (one eigenbasis per view)
    o: [np.array([d.values for d in candidate_descriptors(v, s, spec)]) for v, s in zip(views[o], sources[o])]
    for o in objects
}

rho = other_object_distances(candidates)  # Alg. 6.3: each candidate's distance to the nearest other object
costs = consecutive_costs(candidates["coffee-cup"])  # eq. 6.6 between neighbouring library views
choice, total = select_sources(combined_costs(costs, rho["coffee-cup"], alpha=0.75))  # eq. 6.11 by LP
print("the coffee cup's compact library: candidate", choice.tolist(), "of each view; cost", round(total, 4))


def draw_sources(ax, view, ids, chosen, scale=1.0):
    """A library view in grey, its candidate sources (dots) and the one the LP keeps (star); ``scale`` enlarges
    the marks."""
    p, loop = view.pixels, np.append(view.boundary, view.boundary[0])
    ax.tripcolor(p[:, 0], p[:, 1], view.faces, np.zeros(view.n_vertices), cmap="Greys", vmin=-1, vmax=3)
    ax.plot(p[ids, 0], p[ids, 1], "o", color="grey", ms=3 * scale)
    ax.plot(*p[ids[chosen]], "*", color="red", ms=14 * scale, mec="black")
    ax.plot(p[loop, 0], p[loop, 1], color="tab:cyan", lw=0.8 * scale)
    ax.set_aspect("equal")
    ax.invert_yaxis()
    ax.set_axis_off()


fig, axes = plt.subplots(2, 4, figsize=(12, 6))
for ax, view, ids, chosen, azimuth in zip(axes.ravel(), views["coffee-cup"], sources["coffee-cup"], choice, azimuths):
    draw_sources(ax, view, ids, chosen)
    ax.set_title(f"azimuth {azimuth} deg: candidate {chosen}", fontsize=9)
fig.suptitle("Coffee cup: 20 candidate sources per library view (grey), the one the LP keeps (star)")
fig.tight_layout()
plt.show()

# %%
# The gallery's thumbnail: one panel of the figure above, drawn to be read at a thumbnail's size.
# sphinx_gallery_thumbnail_number = 2
thumbnail, ax = plt.subplots(figsize=(4, 2.8))
draw_sources(ax, views["coffee-cup"][0], sources["coffee-cup"][0], choice[0], scale=1.6)
thumbnail.tight_layout()
plt.show()
