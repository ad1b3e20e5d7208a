"""A batch's serial work: what workers start with, a single output joined while solving."""

from __future__ import annotations

import contextlib
import json
import os

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")
shapely = pytest.importorskip("shapely")
pytest.importorskip("pyproj")

from batch_polys import write_arrow_layer  # noqa: E402
from optri import config  # noqa: E402
from optri.batch import driver, partwork, runner  # noqa: E402
from optri.batch.driver import batch  # noqa: E402
from optri.batch.layer import Layer, projjson, projjson_text  # noqa: E402
from optri.batch.partwork import LayerRows, ReadTask  # noqa: E402
from optri.batch.tablefiles import PartJoiner, assemble_tables  # noqa: E402
from optri.batch.tables import unify  # noqa: E402

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


def test_compiled_work_on_few_workers_runs_on_threads_of_this_process(monkeypatch):
    started = []
    monkeypatch.setattr(runner, "_pool_context", lambda: started.append(1))
    runner.start_pool_server("local", 2, threads=True)  # no forkserver to start
    with runner.open_backend("local", 2, threads=True) as backend:
        assert backend.workers == 2 and not backend.shared_fate
        assert backend.executor.submit(os.getpid).result() == os.getpid()
    assert started == []
    monkeypatch.undo()  # a real pool again, for more workers than threads may be
    monkeypatch.setattr(config, "BATCH_THREADS", 1)
    with runner.open_backend("local", 2, threads=True) as backend:
        assert backend.shared_fate and backend.executor.submit(os.getpid).result() != os.getpid()


@pytest.mark.parametrize(
    ("weight", "threads"),
    [("perimeter", True), ("min_angle", True), (("perimeter", "max_angle"), False)],
)
def test_threads_only_where_the_compiled_kernel_solves(tmp_path, monkeypatch, weight, threads):
    src = _layer(tmp_path / "in.parquet")
    seen = []
    real = runner.open_backend
    monkeypatch.setattr(
        driver, "open_backend", lambda *a, **k: (seen.append(k["threads"]), real(*a, **k))[1]
    )
    objective = ("sum", "sum") if isinstance(weight, tuple) else "sum"
    s = batch(src, tmp_path / "out.parquet", workers=2, weight=weight, objective=objective)
    assert seen == [threads] and (s.ok, s.errors) == (2, 1)


# --- a single GeoParquet output joined while its parts are solved ---------------------


def _parts_dir(tmp_path):
    src = _layer(tmp_path / "in.parquet")
    out = tmp_path / "parts"
    batch(src, str(out) + "/", workers=1, chunk_size=1, out_fmt="parquet")
    return sorted(out.glob("part-*.parquet"))


def test_a_joined_file_is_byte_for_byte_the_assembled_one(tmp_path):
    parts = _parts_dir(tmp_path)
    layer = Layer("parquet", crs="EPSG:32633")
    assert len(parts) == 3
    assemble_tables(parts, "parquet", tmp_path / "whole.parquet", layer, tmp_path)
    with PartJoiner(tmp_path / "joined.parquet", layer, lambda k: parts[k]) as joiner:
        for k in (2, 0, 1):  # in any order: each part waits for the ones before it
            joiner.ready(k)
        assert joiner.joined == parts
        assert joiner.finish(parts)
    assert (tmp_path / "joined.parquet").read_bytes() == (tmp_path / "whole.parquet").read_bytes()
    assert not list(tmp_path.glob(".joined*"))  # no temporary left


@pytest.mark.parametrize(("rows", "groups"), [(None, [3]), (2, [2, 1]), (1, [1, 1, 1])])
def test_a_single_output_holds_its_parts_in_row_groups_of_a_useful_size(
    tmp_path, monkeypatch, rows, groups
):
    if rows is not None:
        monkeypatch.setattr(config, "BATCH_ROW_GROUP_ROWS", rows)
    src = _layer(tmp_path / "in.parquet")
    for workers in (1, 2):
        out = tmp_path / f"out{workers}.parquet"
        batch(src, out, workers=workers, chunk_size=1)  # three parts of one row
        meta = pq.ParquetFile(out).metadata
        assert [meta.row_group(k).num_rows for k in range(meta.num_row_groups)] == groups
        assert pq.read_table(out).column("name").to_pylist() == ["a", "b", "c"]


def _part(path, values):
    pq.write_table(pa.table({"id": list(range(len(values))), "note": values}), path)
    return path


@pytest.mark.parametrize("case", ["types", "missing", "raised"])
def test_a_join_that_cannot_be_kept_leaves_nothing(tmp_path, case):
    first = _part(tmp_path / "p0.parquet", pa.nulls(2))  # a column of nulls only ...
    second = _part(tmp_path / "p1.parquet", ["a", "b"])  # ... then text: the schema changes
    parts = [first, second] if case == "types" else [first, _part(tmp_path / "p1.parquet", [None])]
    target = tmp_path / "out.parquet"
    with pytest.raises(KeyboardInterrupt) if case == "raised" else contextlib.nullcontext():
        with PartJoiner(target, Layer("parquet"), lambda k: parts[k]) as joiner:
            joiner.ready(0)
            if case == "raised":
                raise KeyboardInterrupt
            if case == "types":
                joiner.ready(1)
                assert joiner.broken and joiner.joined == [first]
            assert not joiner.finish(parts)  # "missing": part 1 never said ready
    assert not target.exists() and not list(tmp_path.glob(".out.parquet*"))


_SCHEMAS = [
    pa.schema([("id", pa.int64()), ("note", pa.null())]),
    pa.schema([("id", pa.int64()), ("note", pa.int32())]),
    pa.schema([("id", pa.int64()), ("note", pa.float64())]),
    pa.schema([("id", pa.int64()), ("note", pa.binary())]),
    pa.schema([("id", pa.int64()), ("other", pa.string())]),
    pa.schema([("id", pa.int64())], metadata={b"optri": json.dumps({"has_z": True})}),
    pa.schema([("id", pa.int64())], metadata={b"optri": json.dumps({"explode": True})}),
]


@given(st.lists(st.sampled_from(range(len(_SCHEMAS))), min_size=1, max_size=8))
@settings(max_examples=80, deadline=None)
def test_unify_depends_on_the_distinct_schemas_only(picks):
    # what PartJoiner relies on to keep one copy of a repeated part schema
    schemas = [_SCHEMAS[k] for k in picks]
    distinct = [_SCHEMAS[k] for k in dict.fromkeys(picks)]
    assert unify(schemas).equals(unify(distinct), check_metadata=True)


def test_a_join_keeps_one_copy_of_a_repeated_part_schema(tmp_path):
    layer = Layer("parquet")
    same = [_part(tmp_path / f"q{k}.parquet", v) for k, v in enumerate([[1, 2], [3], [4, 5]])]
    assemble_tables(same, "parquet", tmp_path / "whole2.parquet", layer, tmp_path)
    with PartJoiner(tmp_path / "joined2.parquet", layer, lambda k: same[k]) as joiner:
        for k in (0, 1, 2):
            joiner.ready(k)
        assert len(joiner._schemas) == 1 and joiner.finish(same)
    assert (tmp_path / "joined2.parquet").read_bytes() == (tmp_path / "whole2.parquet").read_bytes()


def test_a_run_joins_its_parts_without_assembling_them_after(tmp_path, monkeypatch):
    src = _layer(tmp_path / "in.parquet")
    ref = batch(src, tmp_path / "a.parquet", workers=1, chunk_size=1)
    monkeypatch.setattr(driver, "assemble", _no_assembly)
    got = batch(src, tmp_path / "b.parquet", workers=1, chunk_size=1)
    assert (got.total, got.ok) == (ref.total, ref.ok) == (3, 2)
    a, b = (pq.read_table(tmp_path / f"{x}.parquet").drop_columns(["seconds"]) for x in "ab")
    assert a.equals(b) and a.schema.metadata == b.schema.metadata
    monkeypatch.setattr(config, "BATCH_JOIN_WHILE_SOLVING", False)
    with pytest.raises(AssertionError, match="assembled"):
        batch(src, tmp_path / "c.parquet", workers=1, chunk_size=1)


def _no_assembly(*args, **kwargs):
    raise AssertionError("assembled after the run")


def test_a_resumed_run_joins_the_parts_it_kept(tmp_path, monkeypatch):
    src = _layer(tmp_path / "in.parquet")
    real = runner.solve_read
    calls = []

    def stop_at_the_third(task):  # the first two are recorded by then
        calls.append(task.index)
        if len(calls) == 3:
            raise KeyboardInterrupt
        return real(task)

    monkeypatch.setattr(runner, "solve_read", stop_at_the_third)
    with pytest.raises(KeyboardInterrupt):
        batch(src, tmp_path / "o.parquet", workers=1, chunk_size=1)
    assert not (tmp_path / "o.parquet").exists() and not list(tmp_path.glob(".o.parquet.*.tmp"))
    monkeypatch.setattr(runner, "solve_read", real)
    monkeypatch.setattr(driver, "assemble", _no_assembly)
    got = batch(src, tmp_path / "o.parquet", workers=1, chunk_size=1)
    assert (got.total, got.ok, got.reused) == (3, 2, 2)
