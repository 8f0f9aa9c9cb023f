"""The numerical core (thesis ch. 2, 3.2): mesh topology, the Laplace-Beltrami spectrum and heat, the MHD.

No module here reads a file or knows what a view or a model is: they take arrays.
"""
