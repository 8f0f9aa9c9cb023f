"""Segmentation of a frame into the objects on its support plane (the step thesis 2.1 leaves outside its scope):
the plane (:mod:`.plane`), the surfaces cut where objects meet (:mod:`.surfaces`), the segments as views
(:mod:`.segment`) with their settings (:mod:`.settings`), and their scores against labelled truth (:mod:`.score`)."""
