"""Figures a person would rather look at than read, one module per chapter; none is imported by a stage below.

``recognition`` (precision, confusion, Fig. 3.5, Isomaps), ``views`` (temperature, Fig. 2.3/2.4, 5.7),
``holes`` (3.6), ``multiview`` (ch. 4), ``jasnom`` (ch. 7), ``rump`` (ch. 8), ``people`` (3.4-3.5);
``common`` holds their notes and saving.
"""
