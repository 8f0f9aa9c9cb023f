"""Hypothesis's mutants of index files through the loader, in a process of its own (run by test_index_file.py).

Each mutant of a flat or an IVF-Flat index file (bytes flipped, an 8-byte field overwritten with a large number, the
file cut short) is loaded as the index beside a library's values. The load must give an index whose answers are the
exact search's, or refuse the file with a HeatdataError; any other exception fails the run. The process's address
space is capped at 8 GB, so a file that claims gigabytes fails here rather than filling the machine; its own peak
resident memory is printed, with the counts: ``mutants=N loaded=L rebuilt=R peak_mb=P``.
"""

import resource
import struct
import sys
from pathlib import Path

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

resource.setrlimit(resource.RLIMIT_AS, (8 << 30, 8 << 30))

from heatdata.errors import HeatdataError  # noqa: E402
from heatdata.recognition import index as ix  # noqa: E402

FOLDER = Path(sys.argv[1])
VALUES = np.random.default_rng(0).dirichlet(np.full(16, 0.5), size=120)
QUERIES = np.random.default_rng(1).dirichlet(np.full(16, 0.5), size=8)
counts = {"mutants": 0, "loaded": 0, "rebuilt": 0}


def original(kind: str) -> bytes:
    ix.FLAT_ROWS = 50 if kind == "ivf" else 50_000
    path = FOLDER / f"{kind}.faiss"
    ix.build_index(VALUES, "hellinger").write(path)
    return path.read_bytes()


ORIGINALS = {kind: original(kind) for kind in ("flat", "ivf")}
TRUTH = ix.build_index(VALUES, "hellinger").candidates(QUERIES, 1)[:, 0]


@st.composite
def mutants(draw) -> bytes:
    data = bytearray(ORIGINALS[draw(st.sampled_from(sorted(ORIGINALS)))])
    for _ in range(draw(st.integers(1, 4))):
        how = draw(st.sampled_from(["byte", "field", "cut"]))
        if how == "byte" and data:
            data[draw(st.integers(0, len(data) - 1))] = draw(st.integers(0, 255))
        elif how == "field" and len(data) > 8:
            at = draw(st.integers(0, len(data) - 8))
            struct.pack_into("<Q", data, at, draw(st.sampled_from([2**30, 2**34, 2**62, 2**64 - 1, 0, 7])))
        else:
            data = data[: draw(st.integers(0, len(data)))]
    return bytes(data)


@settings(max_examples=1500, deadline=None, database=None, suppress_health_check=list(HealthCheck))
@given(mutants())
def test_mutant(data: bytes) -> None:
    counts["mutants"] += 1
    path = FOLDER / "mutant.faiss"
    path.write_bytes(data)
    try:
        index = ix.read_index(path, VALUES, "hellinger")
    except HeatdataError:
        counts["rebuilt"] += 1
        return
    counts["loaded"] += 1
    assert np.array_equal(index.candidates(QUERIES, 1)[:, 0], TRUTH), "a mutant loaded and answered otherwise"


if __name__ == "__main__":
    test_mutant()
    # this process's own peak (VmHWM): ru_maxrss also counts the parent's resident set at the exec
    status = Path("/proc/self/status").read_text().split("\n")
    peak = next(int(line.split()[1]) for line in status if line.startswith("VmHWM:")) // 1024
    print(" ".join(f"{key}={value}" for key, value in counts.items()), f"peak_mb={peak}")
