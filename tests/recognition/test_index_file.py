"""The index file beside a library is a cache, never an authority: whatever is written there, a library loads, answers
as its exact search does, and says so in one warning that quotes none of the file."""

import logging
import os
import struct
import subprocess
import sys
import threading

import faiss
import numpy as np
import pandas as pd
import pytest
from conftest import ROOT
from test_index import histograms

from heatdata.errors import HeatdataError
from heatdata.recognition import index as ix

FUZZ_CHILD = ROOT / "tests" / "recognition" / "fuzz_index_child.py"


@pytest.fixture()
def values():
    return histograms(20, 10)[0]


def refused(path, values, match, space="hellinger"):
    with pytest.raises(HeatdataError, match=match) as caught:
        ix.read_index(path, values, space)
    return str(caught.value)


def flat_bytes(values, space="hellinger") -> bytearray:
    return bytearray(faiss.serialize_index(ix.build_index(values, space).index).tobytes())


def test_a_flat_index_with_one_row_changed_far_from_any_sample_is_refused(values, tmp_path):
    path = tmp_path / "a.faiss"
    crafted = values.copy()
    crafted[37] = crafted[120]  # a row the 64-row sample of old never looked at
    ix.build_index(crafted, "hellinger").write(path)
    refused(path, values, "index of other views")
    stale = values.copy()
    stale[np.random.default_rng(1).choice(len(values), 10, replace=False)] *= 1.001  # a stale index: 10 rows changed
    ix.build_index(stale, "hellinger").write(path)
    refused(path, values, "index of other views")


def test_an_ivf_index_must_hold_each_view_once_in_its_nearest_centroids_list(values, tmp_path, monkeypatch):
    monkeypatch.setattr(ix, "FLAT_ROWS", 50)
    path = tmp_path / "a.faiss"
    built = ix.build_index(values, "hellinger")
    built.write(path)
    assert "IVF-Flat" in ix.read_index(path, values, "hellinger").description
    lists = faiss.downcast_InvertedLists(built.index.invlists)
    full = [n for n in range(built.index.nlist) if lists.list_size(n) >= 2]
    ids = faiss.rev_swig_ptr(lists.get_ids(full[0]), 2)
    ids[0], ids[1] = ids[1], ids[0]  # two views' ids swapped: their vectors no longer the library's rows
    built.write(path)
    refused(path, values, "index of other views")
    ids[0], ids[1] = ids[1], ids[0]
    centroids = faiss.rev_swig_ptr(faiss.downcast_index(built.index.quantizer).get_xb(), built.index.nlist * 48)
    centroids[: 48 * built.index.nlist] = np.roll(centroids[: 48 * built.index.nlist].copy(), 48)  # lists moved
    built.write(path)
    refused(path, values, "nearest their centroids")


def test_an_index_of_a_type_heatdata_does_not_write_is_refused_before_faiss_reads_it(values, tmp_path):
    path = tmp_path / "a.faiss"
    mapped = ix.mapped(values, "hellinger")
    mapped_ids = faiss.IndexIDMap2(faiss.IndexFlatL2(mapped.shape[1]))
    mapped_ids.add_with_ids(mapped, np.arange(len(mapped)) + 10**12)  # ids beyond the library
    faiss.write_index(mapped_ids, str(path))
    refused(path, values, "not an index that heatdata writes")
    path.write_bytes(b"root:x:0:0:root:/root:/bin/bash\n")
    assert "root" not in refused(path, values, "not an index that heatdata writes").split(": ", 1)[1]


def test_a_size_field_that_claims_gigabytes_is_refused_without_allocating_them(values, tmp_path):
    data = flat_bytes(values)
    at = 4 + 4 + 8 + 16 + 1 + 4  # the flat index's header; then the count of its floats
    struct.pack_into("<Q", data, at, 2**30)
    path = tmp_path / "a.faiss"
    path.write_bytes(data)
    refused(path, values, "flat index whose vectors")
    struct.pack_into("<q", data, 8, 2**40)  # the header's count too
    path.write_bytes(data)
    refused(path, values, "an index of 1099511627776 views")
    path.write_bytes(bytes(10**7))
    refused(path, values, "more than an index")
    path.write_bytes(flat_bytes(values)[:50])
    refused(path, values, "truncated")


def test_an_ivf_list_size_that_claims_gigabytes_is_refused_before_faiss_reads_it(values, tmp_path, monkeypatch):
    monkeypatch.setattr(ix, "FLAT_ROWS", 50)
    data = bytearray(faiss.serialize_index(ix.build_index(values, "hellinger").index).tobytes())
    sizes = data.index(b"full") + 12  # the lists' sizes follow "full" and their count
    path = tmp_path / "a.faiss"
    for claim in (2**26, 2**40, 0):
        mutant = bytearray(data)
        struct.pack_into("<Q", mutant, sizes, claim)
        path.write_bytes(mutant)
        refused(path, values, "lists do not hold the library's views")
    path.write_bytes(data[:-8])
    refused(path, values, "truncated")


def test_a_link_a_pipe_or_a_folder_is_never_read(values, tmp_path):
    target = tmp_path / "passwd"
    target.write_text("root:x:0:0:root\n")
    link = tmp_path / "link.faiss"
    link.symlink_to(target)
    assert "root" not in refused(link, values, "a link, not a regular file").replace(str(tmp_path), "")
    fifo = tmp_path / "pipe.faiss"
    os.mkfifo(fifo)
    done = []
    reader = threading.Thread(target=lambda: done.append(refused(fifo, values, "not a regular file")), daemon=True)
    reader.start()
    reader.join(10)
    assert done, "reading a FIFO named like an index hung"
    (tmp_path / "dir.faiss").mkdir()
    refused(tmp_path / "dir.faiss", values, "not a regular file")


def test_whatever_reading_raises_the_library_rebuilds_its_index_with_one_warning(tmp_path, caplog, monkeypatch):
    from heatdata.recognition.library import library_index, load_library

    library_file = tmp_path / "hgd.parquet"
    library = _small_library(library_file)
    beside = ix.index_path(library_file)
    for error in (MemoryError("std::bad_alloc"), RuntimeError("make_direct_map"), IndexError("out of bounds")):

        def broken(*args, error=error):
            raise error

        ix.build_index(library._values, "hellinger").write(beside)
        monkeypatch.setattr(ix, "read_index", broken)
        monkeypatch.setattr("heatdata.recognition.library.read_index", broken)
        caplog.clear()
        with caplog.at_level(logging.WARNING, logger="heatdata"):
            rebuilt = library_index(library, library_file)
        assert len(rebuilt) == len(library.views)
        assert [r.levelname for r in caplog.records] == ["WARNING"]
        assert type(error).__name__ in caplog.text and "building one in memory" in caplog.text
    monkeypatch.undo()
    beside.unlink()
    beside.symlink_to("/etc/passwd")
    caplog.clear()
    with caplog.at_level(logging.WARNING, logger="heatdata"):
        assert load_library(library_file).index is not None
    assert "a link" in caplog.text and "root" not in caplog.text.replace("root/", "")


def _small_library(path):
    import pandas as pd

    import heatdata as hd
    from heatdata.descriptors.rows import descriptor_rows
    from heatdata.experiments.views import render_views, view_plan
    from heatdata.recognition.library import build_library, load_library, write_library

    spec = hd.DescriptorSpec("hgd")
    catalog = hd.read_catalog(ROOT / "data/models/catalog.csv")
    row = catalog[catalog["object"] == "coffee-cup"].to_dict("records")[0]
    plan = view_plan([row["object"]], 4, 2, elevation=30.0, distance=1.0, seed=0)
    rows = descriptor_rows(render_views(hd.load_catalog_model(row), plan), plan, [spec])
    write_library(*build_library(pd.concat([rows], ignore_index=True), spec, 4), path)
    return load_library(path, index=False)


def test_mutated_index_files_never_escape_the_loader(tmp_path):
    """Hypothesis mutates flat and IVF index files (bytes flipped, fields overwritten, cut short) and loads each beside
    a library in a child process: every load answers as the exact search does, peaks below 1 GB, and ends in time."""
    run = subprocess.run(
        [sys.executable, str(FUZZ_CHILD), str(tmp_path)], capture_output=True, text=True, timeout=120, cwd=ROOT
    )
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    report = dict(line.split("=", 1) for line in run.stdout.split() if "=" in line)
    assert int(report["mutants"]) >= 1000 and int(report["peak_mb"]) < 1000
    assert int(report["loaded"]) > 0 and int(report["rebuilt"]) > 0


def test_heatdata_index_never_writes_over_its_library(tmp_path):
    from heatdata.errors import OutputError
    from heatdata.recognition.library import write_library_index

    library_file = tmp_path / "lib.parquet"
    _small_library(library_file)
    named_like_its_index = library_file.rename(tmp_path / "lib.faiss")
    before = named_like_its_index.read_bytes()
    with pytest.raises(OutputError, match="is also an input"):
        write_library_index(named_like_its_index)
    assert named_like_its_index.read_bytes() == before


def test_a_library_written_with_its_index_is_never_its_own_index(tmp_path):
    from heatdata.errors import OutputError
    from heatdata.recognition.library import write_library

    library = _small_library(tmp_path / "lib.parquet")
    rows = pd.concat([library.views, library.independent], ignore_index=True)
    with pytest.raises(OutputError, match="is also an input"):
        write_library(rows, library.metadata, tmp_path / "other.faiss", index=True)
    assert not (tmp_path / "other.faiss").exists()


def test_an_ivf_index_with_most_lists_empty_is_read_from_faiss_s_sparse_layout(values, tmp_path):
    mapped = ix.mapped(values, "hellinger")
    lists = 14
    centroids = np.full((lists, mapped.shape[1]), 10.0, np.float32)  # far from every view: empty lists
    centroids[:3] = mapped[[0, 70, 140]]
    quantizer = faiss.IndexFlatL2(mapped.shape[1])
    quantizer.add(centroids)
    ivf = faiss.IndexIVFFlat(quantizer, mapped.shape[1], lists, faiss.METRIC_L2)
    ivf.is_trained = True
    ivf.add(mapped)
    path = tmp_path / "a.faiss"
    faiss.write_index(ivf, str(path))
    assert b"sprs" in path.read_bytes()
    assert len(ix.read_index(path, values, "hellinger")) == len(values)
    data = bytearray(path.read_bytes())
    struct.pack_into("<Q", data, data.index(b"sprs") + 12, lists + 5)  # a list beyond the index's
    path.write_bytes(data)
    refused(path, values, "lists are not what heatdata writes")
