"""Partial views (thesis 2.1): the :class:`View` container, rendered by a virtual Kinect or built from depth frames."""
