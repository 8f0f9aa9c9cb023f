"""
Partial views coloured by temperature
=====================================

A virtual Kinect sees four embedded objects from one pose. On each partial view a heat pulse starts at the
source vertex (the star: the vertex nearest the image centre, eq. 2.8) and diffuses over the surface for
:math:`t_s = 1/\\lambda_2` (thesis 2.3). The PVHK is the temperature read along the outer boundary (cyan), from
its first sample (the dot) counter-clockwise; the lower row plots it.

The views are rendered from CC0 CAD models with simulated Kinect noise: they are not real sensor data.
"""

import matplotlib.pyplot as plt
import numpy as np

import heatdata as hd
from heatdata.descriptors import heat_kernel

catalog = hd.read_catalog(hd.embedded_catalog())
objects = ["beer-mug", "coffee-cup", "milk-carton", "wood-toy"]
rows = catalog.set_index("object").loc[objects].reset_index()


def draw_heat(ax, view, temperature, source, scale=1.0):
    """The view coloured by ``temperature`` (n,), its boundary (cyan), first sample (dot) and source (star), in
    image coordinates; ``scale`` enlarges the marks. Returns the coloured mesh, for a colour bar."""
    p = view.pixels  # (n, 2) image coordinates of the vertices
    image = ax.tripcolor(p[:, 0], p[:, 1], view.faces, temperature, shading="gouraud", cmap="inferno")
    loop = np.append(view.boundary, view.boundary[0])
    ax.plot(p[loop, 0], p[loop, 1], color="cyan", lw=0.8 * scale)
    ax.plot(*p[view.boundary[0]], "o", color="cyan", ms=4 * scale)
    ax.plot(*p[source], "*", color="lime", ms=12 * scale, mec="black")
    ax.set_aspect("equal")
    ax.invert_yaxis()
    ax.set_axis_off()
    return image


fig, axes = plt.subplots(2, len(objects), figsize=(12, 5.6), height_ratios=[3, 1.4])
for column, row in enumerate(rows.to_dict("records")):
    view = hd.render_view(hd.load_catalog_model(row), azimuth=30.0, elevation=30.0, distance=1.0, seed=0)
    d = hd.pvhk(view, samples=64, source="center", sampling="polar")
    temperature = heat_kernel(view, source=d.source, times=[d.time])[0]  # (n,), equilibrium = 1

    ax = axes[0, column]
    image = draw_heat(ax, view, temperature, d.source)
    ax.set_title(f"{row['object']}: {view.n_vertices} vertices", fontsize=9)
    fig.colorbar(image, ax=ax, fraction=0.04, pad=0.02)

    axes[1, column].plot(np.linspace(0, 360, len(d.values), endpoint=False), d.values, color="tab:red")
    axes[1, column].set_xlabel("polar angle of the boundary sample (deg)", fontsize=8)
    axes[1, column].set_ylabel("PVHK", fontsize=8)

fig.suptitle("Temperature at t_s = 1/lambda_2 after a pulse at the star; the PVHK along the boundary below")
fig.tight_layout()
plt.show()

# %%
# The gallery's thumbnail: one panel of the figure above, drawn to be read at a thumbnail's size.
# sphinx_gallery_thumbnail_number = 2
thumbnail, ax = plt.subplots(figsize=(4, 2.8))
draw_heat(ax, view, temperature, d.source, scale=1.5)  # the last object's view
thumbnail.tight_layout()
plt.show()
