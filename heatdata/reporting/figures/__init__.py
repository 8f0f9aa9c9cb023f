"""Figures a person would rather look at than read (thesis Fig. 2.3/2.4, 2.11, 3.5, 3.7, 5.7).

The object confusion matrix, the view-angle confusion of Fig. 3.5, precision against
library size, Isomaps of the library descriptors, and partial views coloured by
temperature with the source marked.
"""
