"""
JASNOM: two non-overlapping meshes into one model
=================================================

The embedded beer mug is cut in two by a wavy surface, and the lower half is turned and moved away: two meshes
that share no overlap, only a boundary. JASNOM (thesis ch. 7) finds the motion that brings the second mesh's
longest boundary onto the first's: it scores every shift along the loops in both orders by the boundary cost J1,
the interpenetration J2 and the crease J3, refines the best over the six degrees of freedom, and closes the
seam: vertices that coincide are welded, and a strip of triangles (red) bridges what is left. No motion is
given: the true one is used only to measure the error.
"""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import to_rgb
from scipy.spatial.transform import Rotation

import heatdata as hd
from heatdata.io.models import transformed
from heatdata.jasnom.cuts import closed_part

catalog = hd.read_catalog(hd.embedded_catalog())
row = catalog.set_index("object").loc["beer-mug"].to_dict() | {"object": "beer-mug"}
mug = closed_part(hd.load_catalog_model(row))  # its largest closed piece
top, bottom = hd.split_model(mug, [0.0, 1.0, 0.2], amplitude=0.03)  # a wavy cut
rotation = Rotation.from_rotvec([0.3, 1.0, 0.0]).as_matrix()
moved = transformed(bottom, rotation, [0.2, 0.0, 0.0])  # the second mesh, somewhere else

result = hd.stitch(top, moved)
a = result.alignment
angle_error = np.degrees(Rotation.from_matrix(a.rotation @ rotation).magnitude())  # the motion undoes ours
print(f"J at the pose found {a.cost:.2e}, at the runner-up {a.runner_up:.2e}; rotation error {angle_error:.2f} deg")
print(
    f"stitched: {result.loop_pairs} loop pair(s), {result.open_loops} open, {result.welded} vertex pairs welded, "
    f"{result.strip_faces} strip triangles"
)


def draw(ax, model, colours):
    """Faces in their ``colours`` (one per face), shaded by their orientation to a light."""
    light = np.array([0.3, 0.8, 0.5]) / np.linalg.norm([0.3, 0.8, 0.5])
    corners = model.vertices[model.faces]
    normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    shade = 0.35 + 0.65 * np.abs(normal @ light) / np.maximum(np.linalg.norm(normal, axis=1), 1e-30)
    surface = ax.plot_trisurf(*model.vertices.T, triangles=model.faces, linewidth=0, antialiased=False)
    surface.set_facecolors(np.column_stack([colours * shade[:, None], np.ones(len(colours))]))


def face_colours(*parts):
    """(count, colour) runs of faces, in the order the model holds them."""
    return np.vstack([np.tile(to_rgb(colour), (count, 1)) for count, colour in parts])


# the stitched model holds the first mesh's faces, then the second's, then the strip's
fig = plt.figure(figsize=(11, 5))
halves = len(top.faces), len(moved.faces)
panels = [
    (
        "before: two meshes, no overlap",
        [(top, face_colours((halves[0], "tab:blue"))), (moved, face_colours((halves[1], "tab:orange")))],
    ),
    (
        f"after: aligned and stitched, {result.welded} vertex pairs welded",
        [(result.model, face_colours((halves[0], "tab:blue"), (halves[1], "tab:orange"), (result.strip_faces, "red")))],
    ),
]


def show(ax, meshes):
    """(model, face colours) pairs drawn in one cube around them, seen from the same side as every panel."""
    for model, colours in meshes:
        draw(ax, model, colours)
    points = np.vstack([m.vertices for m, _ in meshes])
    middle, half = (points.min(0) + points.max(0)) / 2, np.ptp(points, axis=0).max() / 2
    ax.set(
        xlim=(middle[0] - half, middle[0] + half),
        ylim=(middle[1] - half, middle[1] + half),
        zlim=(middle[2] - half, middle[2] + half),
    )
    ax.view_init(elev=20, azim=-60, vertical_axis="y")
    ax.set_axis_off()


for k, (title, meshes) in enumerate(panels):
    ax = fig.add_subplot(1, 2, k + 1, projection="3d")
    show(ax, meshes)
    ax.set_title(title, fontsize=10)
fig.tight_layout()
plt.show()

# %%
# The gallery's thumbnail: one panel of the figure above, drawn to be read at a thumbnail's size.
# sphinx_gallery_thumbnail_number = 2
thumbnail = plt.figure(figsize=(4, 2.8))
ax = thumbnail.add_subplot(projection="3d")
show(ax, panels[1][1])  # the stitched model: the halves and the strip between them
ax.set_box_aspect(None, zoom=1.8)
thumbnail.tight_layout()
plt.show()
