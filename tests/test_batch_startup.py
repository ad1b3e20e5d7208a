"""What a batch's workers start with: preloaded modules, the parent's parsed CRS."""

from __future__ import annotations

import json

import numpy as np
import pytest

pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")
shapely = pytest.importorskip("shapely")
pytest.importorskip("pyproj")

from batch_polys import write_arrow_layer  # noqa: E402
from optri.batch import partwork, runner  # noqa: E402
from optri.batch.driver import batch  # noqa: E402
from optri.batch.layer import Layer, projjson, projjson_text  # noqa: E402
from optri.batch.partwork import LayerRows, ReadTask  # noqa: E402

GEOMS = [shapely.box(0, 0, 20, 10), None, shapely.box(30, 0, 34, 3)]


def _layer(path):
    wkb = pa.array(shapely.to_wkb(np.array(GEOMS, object)), pa.binary())
    return write_arrow_layer(path, pa.table({"name": ["a", "b", "c"], "geometry": wkb}))


def _part_crs(path):
    return json.loads(pq.read_schema(path).metadata[b"geo"])["columns"]["geometry"]["crs"]


def _task(src, part, crs_json):
    rows = LayerRows(str(src), "parquet", len(GEOMS), row_groups=(len(GEOMS),))
    return ReadTask(
        0, rows, 0, len(GEOMS), "geometry", None, {}, "parquet", False, str(part),
        "EPSG:32633", crs_json,
    )  # fmt: skip


def test_a_worker_writes_the_crs_the_parent_parsed(tmp_path):
    src = _layer(tmp_path / "in.parquet")
    marker = {"type": "ProjectedCRS", "name": "parsed by the parent"}
    _, written = partwork.solve_read(_task(src, tmp_path / "a.parquet", json.dumps(marker)))
    assert written.rows == 3 and written.ok == 2
    assert _part_crs(tmp_path / "a.parquet") == marker  # taken as given, not parsed again
    partwork.solve_read(_task(src, tmp_path / "b.parquet", None))  # none given: parsed here
    assert _part_crs(tmp_path / "b.parquet") == projjson("EPSG:32633")
    assert _part_crs(tmp_path / "b.parquet")["id"] == {"authority": "EPSG", "code": 32633}


def test_layer_projjson_prefers_the_text_it_was_given():
    assert Layer("parquet", crs="EPSG:4326", crs_json='{"a": 1}').projjson() == {"a": 1}
    assert Layer("parquet", crs="EPSG:4326").projjson() == projjson("EPSG:4326")
    assert Layer("parquet").projjson() is None and projjson_text(None) is None


def test_the_parent_hands_every_task_its_parsed_crs(tmp_path, monkeypatch):
    src = _layer(tmp_path / "in.parquet")
    seen = []
    real = runner.solve_read
    monkeypatch.setattr(runner, "solve_read", lambda t: (seen.append(t.crs_json), real(t))[1])
    batch(src, tmp_path / "out" / "", workers=1, chunk_size=2, out_fmt="parquet")
    assert seen == [projjson_text("EPSG:32633")] * 2
    for part in sorted((tmp_path / "out").glob("part-*.parquet")):
        assert _part_crs(part) == projjson("EPSG:32633")


def test_pool_workers_start_with_the_preloaded_modules():
    if runner._pool_context().get_start_method() != "forkserver":
        pytest.skip("no forkserver on this platform")
    wanted = ("pyarrow.parquet", "shapely")
    probe = f"[m for m in {wanted!r} if m in __import__('sys').modules]"
    runner.start_pool_server("local", 2)
    with runner.open_backend("local", 2) as pool:
        assert pool.workers == 2
        # eval: a builtin, so unpickling the call imports nothing itself
        assert pool.executor.submit(eval, probe).result() == list(wanted)
    for scheduler, workers in (("dask", 2), ("local", 1)):  # nothing to start: no error
        runner.start_pool_server(scheduler, workers)
