"""Recognition (thesis ch. 3, 4, 6): nearest neighbours, evaluation, precision, compact libraries, multi-view."""
