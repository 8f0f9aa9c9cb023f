"""JASNOM's default weights (thesis 7.2, eq. 7.2-7.4), apart from the cost so that the command line reads them
without importing the meshes' readers."""

#: steepness of the interpenetration penalty: it switches on over ``h / ALPHA`` (h: the sample spacing)
ALPHA = 4.0
#: weight of the interpenetration term J2 (eq. 7.4)
BETA = 1.0
#: weight of the crease term J3
GAMMA = 0.0
#: weight of the edge component along the seam's continuation direction in J1 (1: the squared length)
ALONG = 1.0
#: ``along`` and ``robust`` for two depth scans (``stitch(..., scans=True)``): a band of unseen surface lies between
#: them, along the seam's continuation, and parts of either boundary (self-occlusions) have no partner
SCAN_ALONG, SCAN_ROBUST = 0.1, 0.05
#: the fewest and most boundary samples of the alignment: 4,096 peaked at 2.03 GB in 140 s (two halves of a sphere,
#: ``heatdata stitch --samples 4096``), so the most is half that
MIN_SAMPLES, MAX_SAMPLES = 8, 2048
#: weight of the support-plane term for scans of an object on a table (:mod:`heatdata.jasnom.table`)
TABLE = 10.0
#: weight of the free-space term for two depth scans without tables (:class:`heatdata.jasnom.align.Witnesses`): on the
#: opposite bunny scans from random starts, 0 leaves the answer 6.2 deg and 7.7% of the size off, 30 4.7 deg and 5.4%,
#: 100 3.8-4.4 deg and 4.7-5.4% (``scripts/scan_pairs.py --free-space``)
FREE_SPACE = 100.0
#: the largest weight, steepness or width a JASNOM option takes: far beyond the defaults, and where one term would swamp
#: every other and the costs overflow (1e300 reached the k-d tree as infinity)
MAX_WEIGHT = 1000.0
