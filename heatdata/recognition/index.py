"""A search index beside a library's exact search: a shortlist in milliseconds, re-ranked by the kind's own distance.

The exact search of Alg. 3.1 compares a query with every library view. At 10,000 objects x 40 views that is 400,000
distances per query, seconds in all. The index finds the library views nearest the query in a space where FAISS
(Johnson, Douze & Jegou 2019, ``faiss-cpu``) searches fast, and the kind's own distance then re-ranks every library
view of the objects it found. Each kind says which space (:attr:`heatdata.descriptors.Kind.index_space`):

``"hellinger"``
    The chi-square histograms (HGD, ESF, FPFH, VFH, SI-HKS). The map is the square root of each bin (the Hellinger
    map), and the squared Euclidean distance between the maps is the squared Hellinger distance
    ``H^2 = sum_k (sqrt(a_k) - sqrt(b_k))^2``. Per bin, ``(a - b)^2 / (a + b) = (sqrt(a) - sqrt(b))^2
    (sqrt(a) + sqrt(b))^2 / (a + b)`` and the last factor lies in [1, 2], so ``H^2 / 2 <= chi^2 <= H^2``
    (chi-square as :func:`heatdata.core.distances.chi_square_matrix` defines it, with its 1/2): the nearest in the
    index are near in chi-square, within a factor 2.
``"l2"``
    The Euclidean embeddings of a learned kind: the values themselves.
``"l1"``
    The boundary curves compared by the MHD (eq. 3.1): the L1 norm of Alg. 6.1's shortlist, an upper bound of the MHD.
None
    A time-scaled kind (the FT-PVHK): a query is described at each object's own time scale (Alg. 5.2), so there is no
    one query vector to look up; such a library answers by the exact search. So does a combined kind's, whose
    distance sums its parts' scaled distances.

Below :data:`FLAT_ROWS` library views the index is a flat one (every view compared in the mapped space); above, an
IVF-Flat index (Jegou, Douze & Schmid 2011: ``sqrt(N)`` k-means lists, :data:`PROBES` of them searched). A query's
nearest views in the index (:data:`SHORTLIST_OBJECTS` times the library size, at least :data:`CANDIDATE_ROWS`) give
up to :data:`SHORTLIST_OBJECTS` objects, in the order found, and every
library view of those objects is compared by the exact distance. So the answer's objects, their nearest views and
distances, and the confidence (the nearest object's distance and the nearest other object's) are exactly the exact
search's whenever the exact search's nearest objects are on the shortlist. ``benchmarks/bench_scale.py`` measures how
often, against the exact search, at 10^4 to 4 x 10^5 library views.

The index is written beside the library file (``name.faiss`` beside ``name.parquet``) in FAISS's own binary format,
which holds arrays and no code. A file beside a library is a cache, never an authority: :func:`read_index` reads it
only as a regular file of a bounded size and of a layout heatdata writes, and checks that every vector it holds is
the library's own mapped row; a file that fails, or that FAISS cannot read, is rebuilt in memory with one warning.
"""

from __future__ import annotations

import errno
import logging
import os
import stat
import struct
import time
from pathlib import Path

import numpy as np
import pandas as pd

from heatdata.descriptors.base import Kind
from heatdata.errors import HeatdataError
from heatdata.io.files import atomic
from heatdata.typing import StrPath

log = logging.getLogger(__name__)

#: the spaces an index compares in (FAISS compares "l1" by its L1 metric, the others by L2)
SPACES = ("hellinger", "l2", "l1")
#: library views up to which the index is flat (exact in its space: a few ms per query at this size)
FLAT_ROWS = 50_000
#: inverted lists searched per query in an IVF index (of ``sqrt(N)``)
PROBES = 24
#: the fewest library views taken from the index per query
CANDIDATE_ROWS = 256
#: objects of the candidates whose every library view the exact distance re-ranks
SHORTLIST_OBJECTS = 32
#: k-means training vectors per inverted list, and its iterations
TRAINING_PER_LIST = 64
TRAINING_ITERATIONS = 20
#: what a library's index file is named by, beside the library file
SUFFIX = ".faiss"
#: FAISS's four-character codes of the indexes heatdata writes: flat (L2, another metric) and IVF-Flat
WRITTEN_TYPES = (b"IxF2", b"IxFl", b"IwFl")


def index_path(library: StrPath) -> Path:
    """The index file of a library file: ``name.faiss`` beside ``name.parquet``.

    Parameters
    ----------
    library : str or Path

    Returns
    -------
    Path
    """
    return Path(library).with_suffix(SUFFIX)


def mapped(values: np.ndarray, space: str) -> np.ndarray:
    """Library or query values in the index's space, as the float32 rows FAISS takes.

    Parameters
    ----------
    values : (N, M) float
        Descriptor values (non-finite values count 0).
    space : {"hellinger", "l2", "l1"}

    Returns
    -------
    (N, M) float32, C-contiguous
    """
    if space not in SPACES:
        raise HeatdataError(f"unknown index space {space!r} (use {', '.join(SPACES)})")
    values = np.array(np.atleast_2d(values), dtype=np.float32, order="C")  # one copy, mapped in place
    if not np.isfinite(values).all():
        np.nan_to_num(values, copy=False, nan=0.0, posinf=0.0, neginf=0.0)
    if space == "hellinger":
        np.sqrt(np.maximum(values, 0.0, out=values), out=values)
    return values


def _metric(space: str) -> int:
    import faiss

    return faiss.METRIC_L1 if space == "l1" else faiss.METRIC_L2


class SearchIndex:
    """A FAISS index over a library's mapped views (:func:`build_index`, :func:`read_index`).

    Parameters
    ----------
    index : faiss.Index
        Its rows are the library views, in the library's order.
    space : {"hellinger", "l2", "l1"}
    """

    def __init__(self, index, space: str):
        self.index = index
        self.space = space

    def __len__(self) -> int:
        return int(self.index.ntotal)

    def __repr__(self) -> str:
        return f"SearchIndex({self.description}, {len(self)} views, {self.space})"

    @property
    def description(self) -> str:
        """``"flat"`` or ``"IVF-Flat, L lists, P probed"``."""
        lists = getattr(self.index, "nlist", None)
        return "flat" if lists is None else f"IVF-Flat, {lists} lists, {self.index.nprobe} probed"

    def candidates(self, queries: np.ndarray, count: int = CANDIDATE_ROWS) -> np.ndarray:
        """The library views nearest each query in the index's space, nearest first (one FAISS search for all).

        Parameters
        ----------
        queries : (Q, M) or (M,) float
            Descriptor values.
        count : int

        Returns
        -------
        (Q, min(count, N)) int
            Positions of library views; -1 where an IVF index's probed lists hold fewer.
        """
        _, rows = self.index.search(mapped(queries, self.space), min(int(count), len(self)))
        return rows

    def write(self, path: StrPath) -> None:
        """Write the index in FAISS's binary format (whole, then renamed).

        Parameters
        ----------
        path : str or Path
        """
        import faiss

        with atomic(Path(path)) as temporary:
            faiss.write_index(self.index, str(temporary))


def candidate_count(library_size: int) -> int:
    """How many candidate views a query takes from the index: enough for :data:`SHORTLIST_OBJECTS` objects of
    ``library_size`` views each, and at least :data:`CANDIDATE_ROWS`.

    Parameters
    ----------
    library_size : int
        Library views per object.

    Returns
    -------
    int
    """
    return max(CANDIDATE_ROWS, SHORTLIST_OBJECTS * int(library_size))


def object_positions(objects: np.ndarray | pd.Series) -> tuple[np.ndarray, list[str], list[np.ndarray]]:
    """Each library view's object as a code, the objects by name, and each object's views.

    Parameters
    ----------
    objects : (N,) str
        The library views' objects, in the library's order.

    Returns
    -------
    codes : (N,) int
        Position of each view's object in ``names``.
    names : list of str
        The objects, sorted.
    positions : list of (n_o,) int
        The views of each object of ``names``, in the library's order.
    """
    codes, names = pd.factorize(np.asarray(objects), sort=True)
    order = np.argsort(codes, kind="stable")
    positions = np.split(order, np.flatnonzero(np.diff(codes[order])) + 1) if len(codes) else []
    return codes, [str(name) for name in names], positions


def shortlist(candidates: np.ndarray, codes: np.ndarray, positions: list[np.ndarray]) -> np.ndarray:
    """Every library view of the first :data:`SHORTLIST_OBJECTS` objects one query's candidates name.

    Parameters
    ----------
    candidates : (K,) int
        One row of :meth:`SearchIndex.candidates` (-1: none).
    codes, positions
        As :func:`object_positions` gives them.

    Returns
    -------
    (n,) int
        Library views, in the library's order (so that the first of equal distances is the exact search's).
    """
    found = codes[candidates[candidates >= 0]]
    _, first = np.unique(found, return_index=True)
    objects = found[np.sort(first)][:SHORTLIST_OBJECTS]
    return np.sort(np.concatenate([positions[code] for code in objects])) if len(objects) else np.zeros(0, np.int64)


def nearest_through_index(
    kind: Kind,
    search: SearchIndex,
    queries: np.ndarray,
    library: np.ndarray,
    codes: np.ndarray,
    positions: list[np.ndarray],
    library_size: int,
    *,
    chunk: int = 1024,
) -> tuple[np.ndarray, np.ndarray]:
    """Each query's nearest library view by the kind's own distance, among the views of the objects the index
    shortlists (:func:`shortlist`; every view when it shortlists none): the exact search's answer whenever the
    nearest view's object is on the list.

    Memory is set by ``chunk`` queries' candidates, not by the library.

    Parameters
    ----------
    kind : Kind
        Whose :meth:`~heatdata.descriptors.Kind.distance_matrix` ranks the shortlist.
    search : SearchIndex
        An index of ``library``'s rows.
    queries : (Q, M) float
    library : (N, M) float
    codes, positions
        The library rows' objects, as :func:`object_positions` gives them.
    library_size : int
        Library views per object (:func:`candidate_count`).
    chunk : int
        Queries searched in FAISS at once.

    Returns
    -------
    index : (Q,) int
        Position of each query's nearest library row.
    distance : (Q,) float
    """
    if len(search) != len(library):
        raise HeatdataError(f"an index of {len(search)} views does not fit a library of {len(library)}")
    count = candidate_count(library_size)
    index, distance = np.zeros(len(queries), np.int64), np.full(len(queries), np.inf)
    for start in range(0, len(queries), chunk):
        block = queries[start : start + chunk]
        for offset, candidates in enumerate(search.candidates(block, count)):
            rows = shortlist(candidates, codes, positions)
            if not len(rows):  # an IVF index's probed lists held nothing: every view
                rows = np.arange(len(library))
            d = kind.distance_matrix(block[offset][None], library[rows])[0]
            best = int(np.argmin(d))
            index[start + offset], distance[start + offset] = rows[best], d[best]
    return index, distance


def build_index(values: np.ndarray, space: str, *, what: str = "library") -> SearchIndex:
    """An index over library values: flat up to :data:`FLAT_ROWS` views, IVF-Flat above (seeded k-means).

    Parameters
    ----------
    values : (N, M) float
        The library views' values, in the library's order.
    space : {"hellinger", "l2", "l1"}
    what : str
        The library, for the progress line.

    Returns
    -------
    SearchIndex
    """
    import faiss

    vectors = mapped(values, space)
    count, dimension = vectors.shape
    metric = _metric(space)
    tic = time.perf_counter()
    if count <= FLAT_ROWS:
        index: faiss.Index = faiss.IndexFlat(dimension, metric)
    else:
        lists = round(np.sqrt(count))
        log.info("%s: building an IVF-Flat index of %d views (%d lists) ...", what, count, lists)
        quantizer = faiss.IndexFlat(dimension, metric)
        ivf = faiss.IndexIVFFlat(quantizer, dimension, lists, metric)
        ivf.cp.niter = TRAINING_ITERATIONS
        ivf.cp.seed = 0
        sample = np.random.default_rng(0).choice(count, min(count, TRAINING_PER_LIST * lists), replace=False)
        ivf.train(vectors[np.sort(sample)])
        ivf.nprobe = PROBES
        index = ivf
    index.add(vectors)
    found = SearchIndex(index, space)
    log.info("%s: %s index of %d views built in %.1f s", what, found.description, count, time.perf_counter() - tic)
    return found


def _header(data: bytes, at: int) -> tuple[int, int, int, int, int]:
    """FAISS's index header at ``at``: its dimension, count and metric, and where the next field starts."""
    dimension, count = struct.unpack_from("<iq", data, at + 4)
    trained, metric = struct.unpack_from("<?i", data, at + 4 + 4 + 8 + 16)
    end = at + 4 + 4 + 8 + 16 + 1 + 4 + (4 if metric > 1 else 0)  # an argument follows a metric other than L2, IP
    return dimension, count, metric, int(trained), end


def check_layout(data: bytes, count: int, dimension: int, space: str) -> None:
    """Check that ``data`` is laid out as an index :func:`build_index` writes, before FAISS reads any of it.

    Only two layouts are read: a flat index (:data:`WRITTEN_TYPES`), and an IVF-Flat one over a flat quantizer with
    its lists in memory (an on-disk list names another file, which FAISS would open). Their headers must hold this
    library's count, dimension and metric, and the sizes of what follows.

    Parameters
    ----------
    data : bytes
        The file's bytes.
    count, dimension : int
        The library views and their values.
    space : {"hellinger", "l2", "l1"}

    Raises
    ------
    HeatdataError
        Another layout, or other sizes; the message never quotes the file's bytes.
    """
    try:
        kind = data[:4]
        if kind not in WRITTEN_TYPES:
            raise HeatdataError("not an index that heatdata writes (a flat or an IVF-Flat FAISS index)")
        d, n, metric, trained, at = _header(data, 0)
        if (n, d, metric) != (count, dimension, _metric(space)) or not trained:
            raise HeatdataError(f"an index of {n} views of {d} values, not of this library's {count} x {dimension}")
        if kind == b"IwFl":
            lists, _ = struct.unpack_from("<QQ", data, at)
            if not 1 <= lists <= count or data[at + 16 : at + 20] not in WRITTEN_TYPES[:2]:
                raise HeatdataError("an IVF index whose lists are not what heatdata writes")
            qd, qn, qmetric, _, at = _header(data, at + 16)
            (size,) = struct.unpack_from("<Q", data, at)
            if (qd, qn, qmetric, size) != (dimension, lists, metric, lists * dimension):  # a size in floats
                raise HeatdataError("an IVF index whose centroids do not fit its lists")
            at += 8 + 4 * size
            direct, entries = struct.unpack_from("<bQ", data, at)
            if direct != 0 or entries != 0 or data[at + 9 : at + 13] != b"ilar":
                raise HeatdataError("an IVF index whose lists are not held in the file (heatdata writes them in it)")
            _check_lists(data, at + 13, lists, count, dimension)
        elif struct.unpack_from("<Q", data, at)[0] != count * dimension:
            raise HeatdataError("a flat index whose vectors are not this library's size")
        elif len(data) != at + 8 + 4 * count * dimension:
            raise struct.error("not the size its header says")
    except (struct.error, ValueError):  # a field past the end of the file
        raise HeatdataError("a truncated index file, or one longer than its header says") from None


def _check_lists(data: bytes, at: int, lists: int, count: int, dimension: int) -> None:
    """Check an IVF index's in-memory lists from ``at`` (after their ``ilar``): every list's size is read before
    FAISS allocates it, so their sizes must add up to the library's views, and the file must end where they do."""
    held, width = struct.unpack_from("<QQ", data, at)
    kind, length = data[at + 16 : at + 20], struct.unpack_from("<Q", data, at + 20)[0]
    if held != lists or width != 4 * dimension or kind not in (b"full", b"sprs") or length > 2 * lists:
        raise HeatdataError("an IVF index whose lists are not what heatdata writes")
    numbers = np.frombuffer(data, "<u8", length, at + 28)
    sizes = numbers if kind == b"full" else numbers[1::2]  # sparse: (list, size) pairs
    named = numbers[0::2]
    if kind == b"sprs" and (length % 2 or np.any(named >= lists) or len(np.unique(named)) != len(named)):
        raise HeatdataError("an IVF index whose lists are not what heatdata writes")
    if (kind == b"full" and length != lists) or np.any(sizes > count) or int(sizes.sum()) != count:
        raise HeatdataError("an IVF index whose lists do not hold the library's views")
    if len(data) != at + 28 + 8 * length + count * (width + 8):
        raise struct.error("not the size its lists say")


def _read_bytes(path: Path, largest: int) -> bytes:
    """A regular file's bytes, read without following a link or waiting on a pipe, if it holds at most ``largest``."""
    try:
        handle = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK)
    except OSError as error:
        if error.errno == errno.ELOOP:
            raise HeatdataError(f"{path}: a link, not a regular file: an index is read only as one") from None
        raise HeatdataError(f"{path}: cannot be read ({error.strerror})") from None
    status = os.fstat(handle)
    if not stat.S_ISREG(status.st_mode):
        os.close(handle)
        raise HeatdataError(f"{path}: not a regular file (a folder, a pipe or a device): an index is read only as one")
    with os.fdopen(handle, "rb") as file:
        if status.st_size > largest:
            raise HeatdataError(f"{path}: {status.st_size} bytes, more than an index of these views can hold")
        return file.read(largest + 1)


def _held(index, count: int, dimension: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The vectors an index holds, the library row of each and its inverted list: a flat index's rows in order (all
    in list 0); an IVF index's lists, each vector with its id."""
    import faiss

    if isinstance(index, faiss.IndexFlat):
        flat = faiss.vector_to_array(index.codes).view(np.float32).reshape(count, dimension)
        return flat, np.arange(count), np.zeros(count, np.int64)
    lists = faiss.downcast_InvertedLists(index.invlists)
    ids, numbers = [np.zeros(0, np.int64)], [np.zeros(0, np.int64)]
    vectors = [np.zeros((0, dimension), np.float32)]
    for number in range(index.nlist):
        size = lists.list_size(number)
        if size:
            ids.append(faiss.rev_swig_ptr(lists.get_ids(number), size).copy())
            codes = faiss.rev_swig_ptr(lists.get_codes(number), size * dimension * 4)
            vectors.append(np.frombuffer(codes, np.float32).reshape(size, dimension).copy())
            numbers.append(np.full(size, number, np.int64))
    return np.concatenate(vectors), np.concatenate(ids), np.concatenate(numbers)


def read_index(path: StrPath, values: np.ndarray, space: str) -> SearchIndex:
    """Read an index file and check that it indexes ``values``, every vector of it.

    An index is a cache, never an authority: a file beside a library may have been written by anyone. It is read only
    when it is a regular file (not a link, a pipe or a device) no larger than an index of these views can be, laid
    out as heatdata writes it (:func:`check_layout`), with FAISS's own bound on what it allocates
    (``faiss.set_deserialization_vector_byte_limit``). Then every vector it holds must be the library's own mapped
    row, each row held once; in an IVF index each row must sit in the list of its nearest centroid, where a search
    looks for it.

    Parameters
    ----------
    path : str or Path
        A file :meth:`SearchIndex.write` wrote.
    values : (N, M) float
        The library views it must index, in order.
    space : {"hellinger", "l2", "l1"}

    Returns
    -------
    SearchIndex

    Raises
    ------
    HeatdataError
        Not a regular file, larger than an index of these views can be, another layout, or an index of other views.
        The message never quotes the file's bytes.
    """
    import faiss

    path = Path(path)
    values = np.atleast_2d(values)
    count, dimension = values.shape
    largest = 2 * (count * (dimension * 4 + 8) + 4 * count * dimension) + 2**20  # vectors, ids, centroids, headers
    data = _read_bytes(path, largest)
    try:
        check_layout(data, count, dimension, space)
    except HeatdataError as exc:
        raise HeatdataError(f"{path}: {exc}") from None
    bound = faiss.get_deserialization_vector_byte_limit()
    faiss.set_deserialization_vector_byte_limit(largest)
    try:
        index = faiss.deserialize_index(np.frombuffer(data, np.uint8))
    except (RuntimeError, MemoryError) as exc:
        raise HeatdataError(f"{path}: not a readable FAISS index ({type(exc).__name__})") from None
    finally:
        faiss.set_deserialization_vector_byte_limit(bound)
    own = mapped(values, space)
    held, rows, lists = _held(index, count, dimension)
    if len(rows) != count or np.any((rows < 0) | (rows >= count)) or np.any(np.bincount(rows, minlength=count) != 1):
        raise HeatdataError(f"{path}: an index that does not hold each library view once")
    if not np.array_equal(held, own[rows]):
        raise HeatdataError(f"{path}: an index of other views (built for another library, or an older one)")
    if isinstance(index, faiss.IndexIVFFlat):
        _, nearest = index.quantizer.search(own, 1)
        if not np.array_equal(nearest[rows, 0], lists):
            raise HeatdataError(f"{path}: an IVF index whose lists do not hold the views nearest their centroids")
        index.nprobe = PROBES
    return SearchIndex(index, space)
