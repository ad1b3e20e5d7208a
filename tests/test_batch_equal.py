"""batch() gives, polygon by polygon, what triangulate() gives: pool and Dask."""

from __future__ import annotations

import pytest

import optri
from batch_polys import mixed_polygons, write_ndjson
from optri.batch import BatchInputError, iter_records
from optri.batch.records import solve_chunk


def _expected(rows, **kw):
    out = {}
    for r in rows:
        try:
            t = optri.triangulate(r["coordinates"], **kw)
        except optri.OptriError as exc:
            out[r["id"]] = ("error", " ".join(str(exc).split()))
        else:
            t.check()
            out[r["id"]] = ("ok", t.weight, t.triangles.tolist(), t.diagonals.tolist())
    return out


def _got(path):
    got = {}
    for rec in iter_records(path):
        if rec["status"] == "ok":
            got[rec["id"]] = ("ok", rec["cost"], rec["triangles"], rec["diagonals"])
        else:
            got[rec["id"]] = ("error", rec["reason"])
    return got


def _same(expected, got):
    assert list(got) == list(expected)  # every polygon, in input order
    for key, exp in expected.items():
        g = got[key]
        assert g[0] == exp[0], key
        if exp[0] == "ok":
            assert g[1] == pytest.approx(exp[1], rel=1e-12)
            assert g[2:] == exp[2:]
        else:
            assert g[1] == exp[1]


@pytest.fixture(scope="module")
def rows():
    return mixed_polygons(60, seed=3)


def test_pool_matches_triangulate(tmp_path, rows):
    src = write_ndjson(tmp_path / "in.ndjson", rows)
    calls = []
    s = optri.batch(
        src, tmp_path / "out", workers=2, chunk_size=7, progress=lambda *a: calls.append(a)
    )
    assert s.total == 60 and s.ok + s.errors == 60 and s.partitions == 9
    assert calls[0] == (0, 60) and calls[-1] == (60, 60) and len(calls) == 10
    _same(_expected(rows), _got(tmp_path / "out"))


def test_inline_max_objective_and_other_weight(tmp_path, rows):
    src = write_ndjson(tmp_path / "in.ndjson", rows[:20])
    optri.batch(src, tmp_path / "o.ndjson", workers=1, weight="min_angle", objective="max")
    _same(_expected(rows[:20], weight="min_angle", objective="max"), _got(tmp_path / "o.ndjson"))


def test_lexicographic_cost_is_a_list(tmp_path, rows):
    src = write_ndjson(tmp_path / "in.ndjson", rows[:3])
    optri.batch(
        src, tmp_path / "o", workers=1, weight=("max_angle", "perimeter"), objective=("max", "sum")
    )
    rec = next(iter_records(tmp_path / "o"))
    t = optri.triangulate(
        rows[0]["coordinates"], weight=("max_angle", "perimeter"), objective=("max", "sum")
    )
    assert rec["cost"] == pytest.approx(list(t.weight))


def test_dask_local_cluster_matches_triangulate(tmp_path, rows):
    distributed = pytest.importorskip("distributed")
    src = write_ndjson(tmp_path / "in.ndjson", rows)
    with (
        distributed.LocalCluster(
            n_workers=2,
            threads_per_worker=1,
            processes=False,
            dashboard_address=None,
            protocol="tcp",
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        s = optri.batch(src, tmp_path / "out.geojson", scheduler=client, chunk_size=11)
        # the same cluster reached by address, as `--scheduler dask://host:port` does
        address = "dask://" + cluster.scheduler_address.split("://")[1]
        optri.batch(src, tmp_path / "out2", scheduler=address, chunk_size=13)
    assert s.total == 60
    _same(_expected(rows), _got(tmp_path / "out.geojson"))
    _same(_expected(rows), _got(tmp_path / "out2"))


def test_chunk_function_keeps_input_order():
    from optri.batch.records import ChunkTask, Item

    items = [Item(i, r["coordinates"]) for i, r in enumerate(mixed_polygons(5))]
    index, recs = solve_chunk(ChunkTask(4, items))
    assert index == 4 and [r["id"] for r in recs] == [0, 1, 2, 3, 4]


def test_custom_weight_in_process_and_a_clear_error_for_a_pool(tmp_path, rows):
    src = write_ndjson(tmp_path / "in.ndjson", rows[:4])
    s = optri.batch(src, tmp_path / "o", workers=1, weight=lambda i, k, j: 1.0)
    assert s.total == 4
    rec = next(iter_records(tmp_path / "o"))
    assert rec["status"] == "ok" and rec["cost"] == rec["n"] - 2  # n - 2 triangles of weight 1
    with pytest.raises(BatchInputError, match="workers=1"):
        optri.batch(src, tmp_path / "p", workers=2, weight=lambda i, k, j: 1.0)
