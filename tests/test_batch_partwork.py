"""Workers read, solve and write their own parts: the same output as the parent reading them."""

from __future__ import annotations

import datetime
import json

import numpy as np
import pytest

pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")
pyogrio = pytest.importorskip("pyogrio")
shapely = pytest.importorskip("shapely")
pytest.importorskip("scipy")

from batch_polys import killer, write_arrow_layer  # noqa: E402
from optri import config  # noqa: E402
from optri.batch import iter_records, partwork, strip_timing  # noqa: E402
from optri.batch.driver import batch  # noqa: E402
from optri.batch.layout import file_sha256  # noqa: E402
from optri.batch.summary import id_hash  # noqa: E402

HEPT = shapely.Polygon([(np.cos(a), np.sin(a)) for a in np.linspace(0, 6, 7)])
GEOMS = [
    shapely.box(0, 0, 20, 10),
    shapely.Polygon([(30, 0, 1), (34, 0, 2), (34, 3, 3), (30, 3, 4)]),
    shapely.MultiPolygon([shapely.box(40, 0, 41, 1), shapely.box(43, 0, 45, 2)]),
    shapely.Polygon(shapely.box(50, 0, 60, 10).exterior, [shapely.box(52, 2, 54, 4).exterior]),
    None,
    shapely.Polygon([(0, 0), (2, 2), (2, 0), (0, 2)]),  # a bow-tie
    shapely.Polygon([(0, 0), (3, 0), (3, 1), (1, 1), (1, 2), (0, 2)]),
    shapely.box(5, 5, 6, 7),
    shapely.Point(1, 2),
    shapely.box(7, 5, 9, 7),
]
DAY = datetime.datetime(2020, 1, 1, 12, 0)


def _write(path, ids=None):
    n = len(GEOMS)
    cols = {"name": [f"f{k}" for k in range(n)]}
    cols["when"] = pa.array(
        [DAY + datetime.timedelta(days=k) for k in range(n)], pa.timestamp("ms")
    )
    if ids is not None:
        cols["id"] = ids
    cols["geometry"] = pa.array(shapely.to_wkb(np.array(GEOMS, object)), pa.binary())
    return write_arrow_layer(path, pa.table(cols), row_group_size=3)


def _records(out):
    return [strip_timing(r) for r in iter_records(out)]


def _spy(monkeypatch):
    calls = []
    real = partwork.read_rows
    monkeypatch.setattr(
        partwork, "read_rows", lambda s, a, n: (calls.append((a, n)), real(s, a, n))[1]
    )
    return calls


@pytest.mark.parametrize("source", [".parquet", ".gpkg", ".fgb"])
@pytest.mark.parametrize("ids", [None, [7, None, *range(9, 17)]])
@pytest.mark.parametrize("out", ["o.parquet", "o.gpkg", "parts/"])
def test_workers_read_their_rows_and_write_the_parents_parts(
    tmp_path, monkeypatch, source, ids, out
):
    src = _write(tmp_path / f"in{source}", ids)
    calls = _spy(monkeypatch)
    fmt = "parquet" if out.endswith("/") else None
    a = batch(src, str(tmp_path / "a" / out), workers=1, chunk_size=4, out_fmt=fmt)
    assert calls == [(0, 4), (4, 4), (8, 2)]  # each task read its own rows (row groups of 3)
    monkeypatch.setattr(config, "BATCH_WORKERS_READ", False)
    b = batch(src, str(tmp_path / "b" / out), workers=1, chunk_size=4, out_fmt=fmt)
    assert len(calls) == 3  # the parent read them
    assert _records(tmp_path / "a" / out) == _records(tmp_path / "b" / out)
    assert (a.total, a.ok, a.errors) == (b.total, b.ok, b.errors) == (10, 7, 3)
    if out.endswith("/"):  # ledger lines that vouch for the parts the workers wrote
        ledger = (tmp_path / "a" / out / "_parts.ndjson").read_text().splitlines()
        for entry in map(json.loads, ledger):
            assert entry["sha256"] == file_sha256(tmp_path / "a" / out / entry["part"])


def test_parts_written_by_workers_resume(tmp_path, monkeypatch):
    src = _write(tmp_path / "in.parquet")
    out = tmp_path / "parts"
    whole = batch(src, out, workers=2, chunk_size=3, out_fmt="parquet")
    first = _records(out)
    (out / "part-00002.parquet").unlink()
    (out / "_SUCCESS").unlink()
    calls = _spy(monkeypatch)
    s = batch(src, out, workers=1, chunk_size=3, out_fmt="parquet")
    assert calls == [(6, 3)]  # only the missing part is read again
    assert (s.reused, s.partitions, s.total, s.ok) == (3, 4, whole.total, whole.ok)
    assert _records(out) == first


def test_a_chunk_that_kills_its_worker_is_read_row_by_row(tmp_path):
    geoms = [HEPT if i == 4 else shapely.box(i, 0, i + 1, 1) for i in range(6)]
    table = pa.table(
        {"k": list(range(6)), "geometry": pa.array(shapely.to_wkb(geoms), pa.binary())}
    )
    src = tmp_path / "in.gpkg"
    pyogrio.write_arrow(
        table,
        src,
        driver="GPKG",
        geometry_name="geometry",
        geometry_type="Polygon",
        crs="EPSG:32633",
    )
    s = batch(src, tmp_path / "out.parquet", weight=killer, workers=2, chunk_size=3)
    recs = list(iter_records(tmp_path / "out.parquet"))
    assert (s.ok, s.errors, s.total) == (5, 1, 6)
    assert [r["k"] for r in recs] == list(range(6))
    assert "worker process died" in recs[4]["reason"] and "5" in recs[4]["reason"]  # FID 5


def test_duplicate_ids_are_found_across_workers(tmp_path):
    src = _write(tmp_path / "in.parquet", ["a", "b", "c", "a", "d", "e", "f", "b", "g", "h"])
    with pytest.warns(Warning, match=r"2 record\(s\) repeat an earlier id"):
        s = batch(src, tmp_path / "o.parquet", workers=2, chunk_size=3)
    assert s.duplicates == 2


def test_worker_threads_enter_catch_warnings_only_under_the_lock(tmp_path, monkeypatch):
    import threading
    import warnings

    from optri.batch.each import WARNINGS_LOCK

    entered = []
    real = warnings.catch_warnings.__enter__

    def enter(self):  # catch_warnings is process-wide: threads may not interleave in it
        if threading.current_thread() is not threading.main_thread():
            entered.append(WARNINGS_LOCK._is_owned())
        return real(self)

    monkeypatch.setattr(warnings.catch_warnings, "__enter__", enter)
    src = _write(tmp_path / "in.parquet")  # Z, holes, a bow-tie: per-polygon and checked rows
    with warnings.catch_warnings():
        warnings.simplefilter("default")
        filters, show = list(warnings.filters), warnings.showwarning
        batch(src, tmp_path / "o.parquet", workers=2, chunk_size=1)
        assert warnings.filters == filters and warnings.showwarning is show
    assert len(entered) >= 3 and all(entered)


def test_in_a_fresh_process_no_worker_thread_imports_into_catch_warnings(tmp_path):
    import subprocess
    import sys

    src = _write(tmp_path / "in.parquet")
    code = f"""
import threading, warnings
from optri.batch.each import WARNINGS_LOCK
real = warnings.catch_warnings.__enter__
bad = []
def enter(self):
    if threading.current_thread() is not threading.main_thread() and not WARNINGS_LOCK._is_owned():
        bad.append(1)
    return real(self)
warnings.catch_warnings.__enter__ = enter
from optri.batch.driver import batch
batch({str(src)!r}, {str(tmp_path / "o.parquet")!r}, workers=2, chunk_size=1)
print(len(bad))
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split()[-1] == "0"  # pandas, say, imported before the threads start


def test_id_hash_is_the_same_in_every_process():
    import subprocess
    import sys

    code = "from optri.batch.summary import id_hash; print(id_hash('bldg-7'), id_hash(12))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == [str(id_hash("bldg-7")), str(id_hash(12))]


def _unit(vertices, i, k, j):
    return 1.0


def test_compiled_chunks_are_larger(tmp_path):
    src = _write(tmp_path / "in.parquet")
    batch(src, tmp_path / "a", workers=1, out_fmt="parquet")
    batch(src, tmp_path / "b", workers=1, out_fmt="parquet", weight=_unit)  # per polygon
    manifests = {d: json.loads((tmp_path / d / "_manifest.json").read_text()) for d in "ab"}
    size = {d: m["chunk_size"] for d, m in manifests.items()}
    assert size == {"a": config.BATCH_CHUNK_MAX, "b": 635}  # the per-polygon budget
