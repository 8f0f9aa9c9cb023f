"""Type aliases of heatdata's API, in the spirit of trimesh's ``typed``: arrays by dtype, paths, numbers.

Array shapes are not types: the numpy docstrings give them (``vertices : (n, 3) float``).
"""

from os import PathLike
from typing import TypeAlias

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["ArrayLike", "BoolArray", "FloatArray", "IntArray", "NDArray", "Number", "PathLike", "StrPath"]

#: float64 arrays: vertices, descriptors' values, distances
FloatArray: TypeAlias = NDArray[np.float64]
#: integer arrays: faces, indices, labels of vertices
IntArray: TypeAlias = NDArray[np.int64]
#: boolean masks
BoolArray: TypeAlias = NDArray[np.bool_]
#: a real number as Python or numpy gives it
Number: TypeAlias = int | float | np.integer | np.floating
#: a file name: a string or a path
StrPath: TypeAlias = str | PathLike[str]
