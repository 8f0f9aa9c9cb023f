"""Fast Point Feature Histograms (Rusu et al. 2009; thesis 9.1), pooled into one histogram per view.

open3d's ``compute_fpfh_feature`` gives each vertex a 33-bin FPFH (three 11-bin
histograms of the angles between its normal, a neighbour's normal and the line
joining them, over the neighbours within ``radius``, at most ``max_nn``). The normals
are the view mesh's vertex normals, oriented towards the camera. A view's descriptor
is the sum of its vertices' FPFHs normalized to sum 1, i.e. their mean: a bag of
local features with no codebook. Compared by the chi-square distance.
"""

from __future__ import annotations

import numpy as np

from heatdata.descriptors.base import DescriptorSpec, Option, integer, number, register
from heatdata.descriptors.histograms import HistogramKind


class FPFH(HistogramKind):
    name = "fpfh"
    summary = "Fast Point Feature Histograms (open3d), summed over the view's vertices (thesis 9.1)"
    bins = 33
    options = (
        Option("radius", 0.015, "neighbourhood radius, metres", number(0.0, 1.0)),
        Option("max_nn", 100, "at most this many neighbours", integer(3, 10000)),
    )

    def compute(self, work, spec: DescriptorSpec, **context):
        import open3d as o3d

        view = work.view
        self.check_points(view)
        points = np.array(view.vertices, np.float64)  # a copy: open3d refuses read-only arrays (views from Parquet)
        cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
        cloud.normals = o3d.utility.Vector3dVector(work.normals())
        search = o3d.geometry.KDTreeSearchParamHybrid(radius=spec.radius, max_nn=spec.max_nn)
        features = np.asarray(o3d.pipelines.registration.compute_fpfh_feature(cloud, search).data)  # (33, n)
        return [self.histogram(spec, features.sum(axis=1), view)]


register(FPFH())
