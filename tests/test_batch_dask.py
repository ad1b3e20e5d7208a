"""The Dask path: lazy ``triangulate_many`` on a dask GeoDataFrame, and ``dask_layer``.

The oracle is the in-memory :func:`optri.triangulate_many` on the same rows.
Layers on a LocalCluster of two worker processes (one cluster for the module,
its start is most of the time), one of them killed mid-run: every row comes
back exactly once.
"""

from __future__ import annotations

import importlib
import logging
import os
from pathlib import Path

import numpy as np
import pytest

dg = pytest.importorskip("dask_geopandas")
distributed = pytest.importorskip("distributed")
gpd = pytest.importorskip("geopandas")
shapely = pytest.importorskip("shapely")

import optri  # noqa: E402
from batch_polys import mixed_polygons  # noqa: E402
from dask_helpers import MARKER_ENV, dies_once  # noqa: E402
from optri.batch.dasklayer import dask_layer, wants_dask_layer  # noqa: E402
from optri.errors import BatchInputError  # noqa: E402

BOWTIE = [[0, 0], [1, 1], [1, 0], [0, 1]]


def _layer(count: int = 40, seed: int = 1) -> gpd.GeoDataFrame:
    """Real-looking rows: polygons of 4-10 vertices, a bow-tie, a null, attributes with nulls."""
    rows = mixed_polygons(count, seed=seed)
    geoms = [shapely.Polygon(r["coordinates"]) for r in rows]
    geoms[3] = shapely.Polygon(BOWTIE)
    if count > 7:
        geoms[7] = None
    note = [None if i % 4 else f"n{i}" for i in range(count)]
    return gpd.GeoDataFrame(
        {"name": [r["id"] for r in rows], "note": note, "height": np.arange(count) * 1.5},
        geometry=geoms,
        crs="EPSG:32633",
    )


def _same_rows(got, expected) -> None:
    """Row by row: attributes, status, cost, reason and triangles (as sets of polygons)."""
    assert len(got) == len(expected)
    assert list(got["name"]) == list(expected["name"])
    assert list(got["status"]) == list(expected["status"])
    for a, b in zip(got["cost"], expected["cost"], strict=True):
        assert (a != a and b != b) or a == b  # NaN for error rows, else bit-equal
    assert [r if r == r else None for r in got["reason"]] == [
        r if r == r else None for r in expected["reason"]
    ]
    for a, b in zip(got.geometry, expected.geometry, strict=True):
        assert (a is None and b is None) or shapely.equals_exact(a, b, 0)
    assert got.crs == expected.crs


# --- triangulate_many on a dask GeoDataFrame (no cluster: the synchronous scheduler) ---


def test_triangulate_many_on_dask_is_lazy_and_equals_in_memory():
    gdf = _layer()
    lazy = optri.triangulate_many(dg.from_geopandas(gdf, npartitions=3))
    assert isinstance(lazy, dg.GeoDataFrame) and lazy.npartitions == 3
    got = lazy.compute(scheduler="sync")
    _same_rows(got, optri.triangulate_many(gdf))
    assert list(got.index) == list(gdf.index)
    # the meta promised what every partition delivers
    assert list(lazy._meta.columns) == list(got.columns)
    assert dict(lazy._meta.dtypes) == dict(got.dtypes)
    assert lazy._meta["cost"].dtype == np.float64
    assert got["status"].tolist().count("error") == 2  # the bow-tie and the null


def test_lon_lat_warns_once_and_threaded_partitions_leave_the_filters_alone():
    import warnings

    from optri.errors import GeographicCRSWarning

    gdf = _layer(24).to_crs(4326)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        filters = list(warnings.filters)
        lazy = optri.triangulate_many(dg.from_geopandas(gdf, npartitions=6))
        assert [w.category for w in caught] == [GeographicCRSWarning]  # once, for the frame
        got = lazy.compute(scheduler="threads", num_workers=3)
        assert warnings.filters == filters  # no partition touched the process's filters
        assert [w.category for w in caught] == [GeographicCRSWarning]  # none per partition
    assert got["status"].tolist().count("ok") == 22


def test_explode_on_dask_gives_one_row_per_triangle_like_in_memory():
    gdf = _layer()
    lazy = optri.triangulate_many(dg.from_geopandas(gdf, npartitions=3), explode=True)
    got = lazy.compute(scheduler="sync")
    expected = optri.triangulate_many(gdf, explode=True)
    _same_rows(got, expected)
    assert list(got.index) == list(expected.index)
    assert len(got) > len(gdf)  # exploded: several rows per polygon


def test_dask_meta_holds_for_a_partition_of_only_error_rows():
    gdf = _layer(6)
    gdf.loc[:, "geometry"] = [shapely.Polygon(BOWTIE)] * 3 + list(gdf.geometry[3:])
    lazy = optri.triangulate_many(dg.from_geopandas(gdf, npartitions=2))
    parts = [p.compute(scheduler="sync") for p in lazy.partitions]
    assert set(parts[0]["status"]) == {"error"}
    for part in parts:  # cost stays a float column even where every row failed
        assert dict(part.dtypes) == dict(lazy._meta.dtypes)


def test_lexicographic_cost_is_an_object_column_of_pairs():
    gdf = _layer(5)
    lazy = optri.triangulate_many(
        dg.from_geopandas(gdf, npartitions=2),
        weight=("max_angle", "perimeter"),
        objective=("max", "sum"),
    )
    assert lazy._meta["cost"].dtype == object
    got = lazy.compute(scheduler="sync")
    t = optri.triangulate(
        gdf.geometry[0], weight=("max_angle", "perimeter"), objective=("max", "sum")
    )
    assert list(got["cost"][0]) == pytest.approx(list(t.weight))


def test_bad_options_are_refused_before_any_task():
    with pytest.raises(optri.errors.WeightError):
        optri.triangulate_many(dg.from_geopandas(_layer(4), npartitions=1), weight="nope")


def test_which_runs_go_to_the_dask_layer():
    assert wants_dask_layer("dask", "a.parquet", "b/", None, "parquet")
    assert wants_dask_layer("tcp://10.0.0.1:8786", "a.fgb", "b.parquet", None, None)
    assert not wants_dask_layer("dask", "a.parquet", "b/", None, None)  # NDJSON parts
    assert not wants_dask_layer("dask", "a.geojson", "b.parquet", None, None)
    assert not wants_dask_layer(None, "a.parquet", "b.parquet", None, None)


def test_refusals_leave_nothing_behind(tmp_path):
    src = tmp_path / "in.parquet"
    _layer(4).to_parquet(src)
    with pytest.raises(BatchInputError, match="unknown scheduler"):
        dask_layer(src, tmp_path / "out.parquet", scheduler="carrier-pigeon")
    with pytest.raises(BatchInputError, match="not ndjson"):
        dask_layer(tmp_path / "in.ndjson", tmp_path / "out.parquet")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["in.parquet"]
    (tmp_path / "out.parquet").write_bytes(b"earlier")
    with pytest.raises(BatchInputError, match="exists"):
        dask_layer(src, tmp_path / "out.parquet", scheduler="carrier-pigeon")
    assert (tmp_path / "out.parquet").read_bytes() == b"earlier"


# --- layers on a LocalCluster of two processes -------------------------------------------


@pytest.fixture(scope="module")
def client(tmp_path_factory):
    marker = tmp_path_factory.mktemp("marker") / "died"
    os.environ[MARKER_ENV] = str(marker)  # inherited by the worker processes
    import dask

    with (
        dask.config.set({"distributed.scheduler.allowed-failures": 3}),
        distributed.LocalCluster(
            n_workers=2,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
            silence_logs=logging.ERROR,
        ) as cluster,
        distributed.Client(cluster) as c,
    ):
        c.marker = marker
        yield c
    del os.environ[MARKER_ENV]


def _parts(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


@pytest.mark.slow
def test_geoparquet_directory_equals_in_memory(client, tmp_path):
    gdf = _layer(60)
    gdf["blob"] = [b"\x00\x01" if i < 15 else None for i in range(60)]  # null after part 0
    src = tmp_path / "in.parquet"
    gdf.to_parquet(src, row_group_size=15)  # four row groups: four partitions
    s = dask_layer(src, tmp_path / "out", scheduler=client)
    assert (s.total, s.ok, s.errors, s.partitions) == (60, 58, 2, 4)
    out = tmp_path / "out"
    assert _parts(out) == ["_SUCCESS"] + [f"part.{k:05d}.parquet" for k in range(4)]
    assert not list(tmp_path.glob(".*"))  # no staging folder, no lock left
    import pyarrow.parquet as pq

    schemas = {pq.read_schema(p).remove_metadata() for p in out.glob("part.*")}
    assert len(schemas) == 1  # one dataset, one schema: "blob" is binary in every part
    _same_rows(gpd.read_parquet(out), optri.triangulate_many(gdf))
    assert len(dg.read_parquet(out).compute()) == 60  # Dask opens the dataset too


@pytest.mark.slow
def test_batch_gpkg_to_one_file_through_the_cli(client, tmp_path):
    from click.testing import CliRunner

    from optri.cli import main

    gdf = _layer(50, seed=3)
    src = tmp_path / "in.gpkg"
    gdf.to_file(src)
    address = client.scheduler.address
    res = CliRunner().invoke(
        main,
        [
            "batch",
            str(src),
            "-o",
            str(tmp_path / "out.parquet"),
            "--scheduler",
            address,
            "--chunk-size",
            "20",
            "-q",
            "--json",
        ],
    )
    assert res.exit_code == 0, res.output
    assert '"partitions": 3' in res.output and '"total": 50' in res.output
    got = gpd.read_parquet(tmp_path / "out.parquet")
    _same_rows(got, optri.triangulate_many(gpd.read_file(src)))
    # the file's GeoParquet metadata speaks for all its parts: bounding box, geometry types
    import json

    import pyarrow.parquet as pq

    geo = json.loads(pq.read_schema(tmp_path / "out.parquet").metadata[b"geo"])
    column = geo["columns"][got.geometry.name]
    assert column["bbox"] == pytest.approx(list(got.total_bounds))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["in.gpkg", "out.parquet"]


@pytest.mark.slow
def test_a_worker_killed_mid_run_loses_no_row_and_writes_none_twice(client, tmp_path):
    gdf = _layer(36, seed=5)
    gdf.loc[:, "geometry"] = [
        g if i != 20 else shapely.Polygon(mixed_polygons(1, seed=9, lo=7, hi=7)[0]["coordinates"])
        for i, g in enumerate(gdf.geometry)
    ]
    src = tmp_path / "in.parquet"
    gdf.to_parquet(src, row_group_size=6)
    assert not client.marker.exists()
    s = dask_layer(src, tmp_path / "out.parquet", weight=dies_once, scheduler=client)
    assert client.marker.exists()  # a worker process did die, in the middle of the run
    got = gpd.read_parquet(tmp_path / "out.parquet")
    assert s.total == len(got) == 36 and s.partitions == 6
    assert sorted(got["name"]) == sorted(gdf["name"])  # every row, each once
    _same_rows(got, optri.triangulate_many(gdf, weight=dies_once))
    assert got["status"][20] == "ok" and got["cost"][20] == 5.0  # the heptagon: 5 triangles


@pytest.mark.slow
def test_a_dataset_of_files_with_differing_types_is_one_schema(client, tmp_path):
    gdf = _layer(30)
    src = tmp_path / "in.parquet"  # a directory: a GeoParquet dataset
    src.mkdir()
    first, second = gdf.iloc[:12].copy(), gdf.iloc[12:].copy()
    first["blob"] = None  # a null column in this file, binary in the other
    second["blob"] = [b"\x07"] * len(second)
    first.to_parquet(src / "a.parquet")
    second.to_parquet(src / "b.parquet", row_group_size=9)
    s = dask_layer(src, tmp_path / "out.parquet", scheduler=client)
    assert (s.total, s.partitions) == (30, 3)  # a file, then two row groups
    got = gpd.read_parquet(tmp_path / "out.parquet")
    _same_rows(got, optri.triangulate_many(gpd.GeoDataFrame(gpd.pd.concat([first, second]))))
    assert got["blob"].tolist() == [None] * 12 + [b"\x07"] * 18


@pytest.mark.slow
def test_lexicographic_costs_and_bounds_of_the_ok_rows_only(client, tmp_path):
    gdf = _layer(20)
    far = shapely.affinity.translate(shapely.Polygon(BOWTIE), 1e6, 1e6)
    gdf.loc[:, "geometry"] = [far if i == 3 else g for i, g in enumerate(gdf.geometry)]
    src = tmp_path / "in.parquet"
    gdf.to_parquet(src, row_group_size=7)
    options = {"weight": ("max_angle", "perimeter"), "objective": ("max", "sum")}
    seen = []
    dask_layer(
        src,
        tmp_path / "out.parquet",
        scheduler=client,
        progress=lambda done, total: seen.append((done, total)),
        **options,
    )
    got = gpd.read_parquet(tmp_path / "out.parquet")
    expected = optri.triangulate_many(gdf, **options)
    assert [None if c is None else list(c) for c in got["cost"]] == [
        None if c is None else list(c) for c in expected["cost"]
    ]
    assert got["status"][3] == "error"
    import json

    import pyarrow.parquet as pq

    geo = json.loads(pq.read_schema(tmp_path / "out.parquet").metadata[b"geo"])
    bbox = geo["columns"][got.geometry.name]["bbox"]
    assert bbox == pytest.approx(list(got.total_bounds))  # the far bow-tie drew nothing
    assert sorted(seen) == seen and seen[-1] == (20, 20) and len(seen) == 3  # per partition


def test_an_empty_layer_gives_an_empty_valid_file(tmp_path):
    import pyarrow.parquet as pq

    _layer(4).iloc[:0].to_parquet(tmp_path / "empty.parquet")
    src = tmp_path / "in.parquet"  # no row group at all (the other holds one of 0 rows)
    pq.ParquetWriter(src, pq.read_schema(tmp_path / "empty.parquet")).close()
    assert pq.ParquetFile(src).num_row_groups == 0
    from optri.batch.dasklayer import plan_parts, solve_part

    frame, parts = plan_parts(src, tmp_path)
    assert [(p.first, p.count) for p in parts] == [(0, 0)]
    done = solve_part(parts[0], frame)
    assert (done.rows, done.ok, done.bbox) == (0, 0, None)
    back = gpd.read_parquet(tmp_path / "part.00000.parquet")
    assert list(back.columns) == ["name", "note", "height", "geometry", "status", "cost", "reason"]
    assert len(back) == 0 and back.crs == "EPSG:32633"


def test_partitions_cut_by_rows_or_count_within_each_file(tmp_path):
    from optri.batch.dasklayer import plan_parts

    src = tmp_path / "in.parquet"
    _layer(40).to_parquet(src, row_group_size=25)
    spans = lambda **kw: [(p.first, p.count) for p in plan_parts(src, tmp_path, **kw)[1]]  # noqa: E731
    assert spans() == [(0, 25), (25, 15)]  # row groups
    assert spans(chunksize=10) == [(0, 10), (10, 10), (20, 10), (30, 10)]
    assert spans(npartitions=3) == [(0, 14), (14, 14), (28, 12)]
    assert spans(npartitions=100) == [(k, 1) for k in range(40)]


@pytest.mark.slow
def test_the_cluster_made_for_a_run_forks_its_workers_from_a_server(tmp_path):
    from optri.batch.runner import dask_client

    with dask_client("dask", 1, 3) as c:
        parents = set(c.run(os.getppid).values())
        assert len(parents) == 1 and os.getpid() not in parents  # not spawned by this process


def test_a_run_the_kernel_solves_gets_worker_threads_in_this_process(tmp_path):
    from optri.batch.runner import cluster_threads, dask_client

    with dask_client("dask", 2, 3, threads=True) as c:
        assert set(c.run(os.getpid).values()) == {os.getpid()}  # no worker process
        assert cluster_threads(c) == 2  # one worker, two threads: two tasks at once
    gdf = _layer(30)
    gdf.to_parquet(tmp_path / "in.parquet", row_group_size=7)
    s = dask_layer(tmp_path / "in.parquet", tmp_path / "out.parquet", workers=2)
    assert (s.total, s.partitions) == (30, 5)
    _same_rows(gpd.read_parquet(tmp_path / "out.parquet"), optri.triangulate_many(gdf))


def test_a_cluster_made_for_a_run_does_not_warn_of_a_busy_dashboard_port():
    import socket
    import warnings

    from optri.batch.runner import dask_client

    with socket.socket() as busy:
        try:
            busy.bind(("", 8787))  # Dask's default dashboard port, taken
        except OSError:
            pass  # taken already
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            with dask_client("dask", 1, 3, threads=True) as c:
                assert c.submit(sum, [1, 2]).result() == 3


@pytest.mark.slow
def test_more_threads_than_the_cap_or_a_python_weight_get_processes(monkeypatch):
    from optri import config
    from optri.batch.dasklayer import _run
    from optri.batch.runner import dask_client

    monkeypatch.setattr(config, "BATCH_THREADS", 1)
    with dask_client("dask", 2, 3, threads=True) as c:
        assert os.getpid() not in set(c.run(os.getpid).values())
    seen = []

    class Spy:  # what _run asks of the cluster, for a Python weight
        def __init__(self, *a, threads):
            seen.append(threads)

        def __enter__(self):
            raise RuntimeError("enough")

        def __exit__(self, *a):
            return False

    dasklayer = importlib.import_module("optri.batch.dasklayer")  # optri.batch: a function
    from optri.batch.dasklayer import Frame

    monkeypatch.setattr(dasklayer, "dask_client", Spy)
    from optri.batch.each import SolveOptions

    for weight in (dies_once, "perimeter"):
        options = SolveOptions(weight=weight, threads=1)
        frame = Frame("geometry", None, (), options, False, None, ".", False, None)
        with pytest.raises(RuntimeError, match="enough"):
            _run([], frame, None, 2, None)
    assert seen == [False, True]


@pytest.mark.slow
def test_native_geoarrow_geoparquet_is_read_as_wkb(client, tmp_path):
    gdf = _layer(20)
    src = tmp_path / "in.parquet"
    gdf.to_parquet(src, geometry_encoding="geoarrow", row_group_size=8)
    s = dask_layer(src, tmp_path / "out.parquet", scheduler=client)
    assert (s.total, s.partitions) == (20, 3)
    _same_rows(gpd.read_parquet(tmp_path / "out.parquet"), optri.triangulate_many(gdf))
