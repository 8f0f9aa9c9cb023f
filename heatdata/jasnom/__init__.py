"""JASNOM (thesis ch. 7): one closed model from two non-overlapping meshes, aligned and stitched by their boundaries.

Two scans of an object (standing, then flipped; or two opposite cameras) cover it
together without overlapping, so overlap-based registration cannot align them. JASNOM
aligns them by their boundary loops, B1 and B2, and stitches the gap between them with a
triangle strip (7.4). Loops that pass a vertex twice (a pinch) are split there, so two
meshes that share a boundary see the same loops. Before the loops are traced, vertices
that coincide within a thousandth of the median edge are merged (recorded as a repair):
an STL file gives every triangle its own vertices, and many cutting tools give each
side of a cut its own copies, so such a mesh would otherwise be open along every edge.

**The cost** (eq. 7.2-7.4, made continuous). Each mesh's loops are resampled uniformly by
arc length (7.5): ``samples`` points on the longest, proportionally many on the others.
Each sample is paired with the *closest point* on the other mesh's loops (after the
motion), both ways, so J is continuous in the rotation and translation: there is no
discrete shift in it, and at the true motion of two halves that share their boundary
every pair is at distance 0. The pair's edge vector ``xi`` points from B2 to B1 (eq.
7.1). Every term is divided by ``s^2`` (``s``: the RMS radius of B1's samples about their
centroid) and averaged over the pairs, so the weights are unitless whatever the object's
size and sampling:

- **J1, the edges** (eq. 7.2): ``|xi_across|^2 + along * |xi_along|^2``. ``xi_along`` is
  the component along the seam's continuation ``m = (n2 - n1) / |n2 - n1|``, where ``n1``,
  ``n2`` are the boundary normals (Fig. 7.3: in the boundary face's plane, perpendicular
  to the boundary, pointing away from the mesh). With ``along = 1`` it is the squared
  edge length of eq. 7.2. A surface that leaves B2 along ``n2`` and arrives at B1 along
  ``-n1`` on a circular arc has its chord along ``m``; ``along < 1`` tolerates such a band
  of unseen surface between two scans without letting the boundaries slide.
- **J2, the interpenetration** (replacing the logistic of eq. 7.3): how far a boundary
  lies *over* the other mesh. ``d1 = xi . n1 > 0`` when B2's point lies on mesh 1's side of
  B1, and ``d2 = -xi . n2 > 0`` when B1's point lies on mesh 2's side of B2. Each costs
  ``(d / s)^2 * logistic(alpha * d / h)`` (``h``: the mean sample spacing): nothing when the
  boundaries meet exactly (``xi = 0``, where eq. 7.3's logistic of a random direction gave
  about 0.5), growing with the square of the depth, and switching on over a width of
  ``h / alpha``, relative to the sampling rather than absolute.
- **J3, the crease**: ``|n1 + n2|^2 / 4`` is 0 where the surface continues straight across
  the seam and 1 where the meshes fold onto each other. Its default weight is 0: on
  coarse models cut along sharp edges the crease at the truth is large, and a nonzero
  weight pulled the optimum off it (measured by ``scripts/jasnom_cuts.py``).

``J = J1 + beta * J2 + gamma * J3`` (eq. 7.4), optionally through a soft-L1 loss
(``robust``), for boundaries with parts that have no partner.

**The orientation constraint** (7.3). Poses where the meshes lie on the same side of the
seam (the mean cosine of paired boundary normals above 0: the second mesh on top of the
first) have J = +inf. Two depth scans are different: a silhouette cut where the depth
jumps keeps faces that are not grazing, and their boundary normals point outwards from
the object in both scans (their mean cosine at the truth is +0.2 to +0.5 on the embedded
objects). With ``scans``, the constraint is instead that each scan lies on the far side of
the object from the other's camera (:class:`ScanSurface`).

**The search** (eq. 7.5-7.6). Every shift tau of B2's resampled origin, in both orders
(the thesis's reversed order of 7.3, and the mirrored order of a mesh wound the other
way round the object, whose faces are then reversed with a warning), gives a
correspondence of the longest loops; its closed-form rigid alignment (Kabsch) is a
candidate. J is evaluated at all ``2 * samples`` candidates, and the cheapest ``refine``
that are at least 10 deg or 5% of the size apart are refined over all six degrees of
freedom (scipy's trust-region least squares on J's residuals, then closest-point Kabsch
steps while J decreases). The best is kept; the best *different* refined pose (more than
2 deg or 1% of the size away) is the runner-up, whose J says whether the answer is
ambiguous (:attr:`Alignment.ambiguous`): a symmetric boundary, such as a circle, fits as
well at other turns.

**Scans on a table** (7.5's acquisition, :mod:`heatdata.jasnom.table`). With the two frames'
table planes, J gains the support-plane term T (scan 2's bottom touches table 1 and scan
1's top the moved table 2; no point below either; no point in front of what the other
camera measured), and the search a second family of candidates: the 72 half-turns that
put table 2 onto table 1 upside down, each slid along the table onto the other boundary.
Every candidate of either family is set on the table first, and the best ``refine`` of
each family are refined, so that T cannot push the boundary family's near-truth pose out.

**The stitch** (7.4). At the motion, each vertex of B2 is assigned its nearest vertex of
B1, made monotone along the loops (the order constraint of eq. 7.7), and the strip of
7.4 walks both loops; the other loops are paired by their mean distance and similar length.
Strip edges shorter than a hundredth of the seam's median edge join vertices that
coincide: they are welded and the strip's degenerate triangles dropped, so two halves
that share a boundary become one watertight, consistently wound mesh, also when a reader
merges coincident vertices. The output stays in the first mesh's frame.
"""
