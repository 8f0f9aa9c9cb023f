"""Multi-view recognition (thesis ch. 4): appearance models, the learned similarity and the particle filter.

A robot circling an object collects views one stop at a time and knows only how far it
moved (odometry). Algorithm 4.1 keeps hypotheses ``s = (object, view angle)`` as
particles, weighs them by the appearance model of 4.3, and, when it drops unlikely
particles, re-populates them at the library views that *look like* the survivors
(the similarity bootstrap of 4.4.6), so that an object whose views resemble another's
never vanishes while the observations are ambiguous. Beyond the thesis,
:meth:`ParticleFilter.best_move` chooses the next step that is expected to reduce the
posterior entropy over objects most (active recognition), and :class:`ExhaustiveFilter`
scores every object at every degree: the exact posterior the particles approximate.

Every distance is the descriptor kind's own (:meth:`heatdata.descriptors.Kind.distance_matrix`),
so any kind works; library tables are rows of ``descriptors.parquet`` (columns
``object``, ``azimuth``, ``values`` and optionally ``kind``).
"""
