"""
Recognition and its confusion matrix
====================================

Five embedded objects, three of them look-alikes (the coffee cup, the plastic cup and the beer mug), each with a
library of 4 views, one every 90 degrees of azimuth. Test views lie between the library's angles, and each is
recognized as the object of its nearest library view under the modified Hausdorff distance of eq. 3.1
(thesis 3.3, Alg. 3.1). The matrices count true objects (rows) against recognized ones (columns) for two choices
of the thesis (2.3.2-2.3.3): the source at the image centre with the boundary sampled at even polar angles, and
the source closest to the camera with the boundary sampled by arc length. The rendered views carry simulated
Kinect noise, but they are not real sensor data.
"""

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

import heatdata as hd
from heatdata.recognition.metrics import confusion_matrix
from heatdata.recognition.nearest import nearest_neighbors

catalog = hd.read_catalog(hd.embedded_catalog())
objects = ["coffee-cup", "plastic-cup", "beer-mug", "milk-carton", "speaker-small"]
models = {row["object"]: hd.load_catalog_model(row) for row in catalog.to_dict("records") if row["object"] in objects}
specs = [hd.DescriptorSpec("pvhk", 64, "center", "polar"), hd.DescriptorSpec("pvhk", 64, "closest", "arclength")]


def describe(obj: str, azimuth: float, seed: int) -> list[np.ndarray]:
    """Both descriptors of one rendered view (one call shares the view's factorization and lambda_2)."""
    view = hd.render_view(models[obj], azimuth=azimuth, elevation=30.0, seed=seed)
    return [d.values for d in hd.describe(view, specs)]  # each (64,)


library = [describe(obj, a, seed=1) for obj in objects for a in range(0, 360, 90)]
library_objects = np.repeat(objects, 4)
test_azimuths = np.arange(10.0, 360.0, 20.0)  # 18 test views per object, none at a library angle
truth = np.repeat(objects, len(test_azimuths))
tests = [describe(obj, a, seed=2) for obj in objects for a in test_azimuths]

fig, axes = plt.subplots(1, 2, figsize=(11, 4.8))
for k, (spec, ax) in enumerate(zip(specs, axes)):
    nearest = nearest_neighbors(np.array([t[k] for t in tests]), np.array([v[k] for v in library]))
    recognized = library_objects[nearest.index]  # the object of each test view's nearest library view
    precision = np.mean(recognized == truth)
    print(f"{spec.name}: {precision:.1%} of {len(truth)} test views")
    counts = confusion_matrix(pd.Series(truth), pd.Series(recognized), labels=objects).to_numpy()
    ax.imshow(counts, cmap="Blues", vmin=0, vmax=len(test_azimuths))
    for (i, j), n in np.ndenumerate(counts):
        ax.text(j, i, str(n), ha="center", va="center", color="white" if n > 9 else "black")
    ax.set_xticks(range(len(objects)), objects, rotation=45, ha="right")
    ax.set_yticks(range(len(objects)), objects)
    ax.set_xlabel("recognized as")
    ax.set_ylabel("true object")
    ax.set_title(f"{spec.name}: {precision:.0%}", fontsize=10)
fig.suptitle("4 library views per object, 18 test views between them")
fig.tight_layout()
plt.show()

# %%
# The gallery's thumbnail: one panel of the figure above, drawn to be read at a thumbnail's size.
# sphinx_gallery_thumbnail_number = 2
thumbnail, ax = plt.subplots(figsize=(4, 2.8))
ax.imshow(counts, cmap="Blues", vmin=0, vmax=len(test_azimuths))  # the last descriptor's confusion matrix
ax.set_axis_off()
ax.set_title(f"{precision:.0%} recognized", fontsize=16)
thumbnail.tight_layout()
plt.show()
