"""JASNOM's default weights (thesis 7.2, eq. 7.2-7.4), apart from the cost so that the command line reads them
without importing the meshes' readers."""

#: weight of the edge term J1 against the interpenetration J2 (beta) in the search
ALPHA = 4.0
#: weight of the interpenetration term J2
BETA = 1.0
#: weight of the crease term J3 (off by default)
GAMMA = 0.0
#: how far along the boundary normal J2 reaches, in units of the boundary's sample spacing
ALONG = 1.0
#: ``along`` and ``robust`` for two depth scans from opposite sides (``stitch(scans=True)``)
SCAN_ALONG, SCAN_ROBUST = 0.1, 0.05
