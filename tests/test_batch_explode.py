"""``batch(..., explode=True)``: one valid Polygon row per triangle, in every format and path."""

from __future__ import annotations

import json
import logging

import numpy as np
import pytest

pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")
pyogrio = pytest.importorskip("pyogrio")
shapely = pytest.importorskip("shapely")
gpd = pytest.importorskip("geopandas")
pytest.importorskip("scipy")

from batch_polys import killer  # noqa: E402
from optri import config  # noqa: E402
from optri.batch import iter_records, strip_timing  # noqa: E402
from optri.batch.dasklayer import plan_parts, solve_part  # noqa: E402
from optri.batch.driver import batch  # noqa: E402
from optri.batch.many import triangulate_many  # noqa: E402
from optri.errors import BatchInputError  # noqa: E402

HEPT = shapely.Polygon([(np.cos(a), np.sin(a)) for a in np.linspace(0, 6, 7)])
# name -> (geometry, triangles per ok row: n + 2h - 2 summed over the parts; None: error row)
ROWS = {
    "box": (shapely.box(0, 0, 20, 10), 2),
    "quad z": (shapely.Polygon([(30, 0, 1), (34, 0, 2), (34, 3, 3), (30, 3, 4)]), 2),
    "two parts": (shapely.MultiPolygon([shapely.box(40, 0, 41, 1), shapely.box(43, 0, 45, 2)]), 4),
    "holed": (
        shapely.Polygon(shapely.box(50, 0, 60, 10).exterior, [shapely.box(52, 2, 54, 4).exterior]),
        8,
    ),
    "null": (None, None),
    "empty": (shapely.Polygon(), None),
    "bow-tie": (shapely.Polygon([(0, 0), (2, 2), (2, 0), (0, 2)]), None),
    "ell": (shapely.Polygon([(0, 0), (3, 0), (3, 1), (1, 1), (1, 2), (0, 2)]), 4),
    "point": (shapely.Point(1, 2), None),
}
NAMES = list(ROWS)
EXPECTED = sum(t if t is not None else 1 for _, t in ROWS.values())  # 20 triangles + 4 errors


def _layer(path):
    geoms = np.array([g for g, _ in ROWS.values()], dtype=object)
    table = pa.table(
        {
            "name": NAMES,
            "id": [f"r{k}" for k in range(len(NAMES))],
            "geometry": pa.array(shapely.to_wkb(geoms), pa.binary()),
        }
    )
    if path.suffix == ".parquet":
        column = {"encoding": "WKB", "geometry_types": [], "crs": "EPSG:32633"}
        geo = {"version": "1.1.0", "primary_column": "geometry", "columns": {"geometry": column}}
        pq.write_table(table.replace_schema_metadata({b"geo": json.dumps(geo)}), path)
        return path
    # GeoJSON text sequence: the record path (points and empties as GeoJSON too)
    lines = []
    for k, (name, (geom, _)) in enumerate(ROWS.items()):
        g = None if geom is None else json.loads(shapely.to_geojson(geom))
        feat = {"type": "Feature", "id": f"r{k}", "geometry": g, "properties": {"name": name}}
        lines.append(json.dumps(feat))
    path.write_text("\n".join(lines) + "\n")
    return path


def _geometries(out):
    """Every row's geometry and name, read back by GDAL / pyarrow (not by optri)."""
    import pandas as pd

    files = sorted(out.glob("part-*")) if out.is_dir() else [out]
    read = [gpd.read_parquet(f) if f.suffix == ".parquet" else gpd.read_file(f) for f in files]
    return pd.concat([r.set_crs(None, allow_override=True) for r in read], ignore_index=True)


def _check(out, summary):
    assert (summary.total, summary.ok, summary.errors) == (9, 5, 4)  # features, not triangles
    recs = list(iter_records(out))
    assert len(recs) == EXPECTED
    by_name: dict[str, list[dict]] = {}
    for r in recs:
        by_name.setdefault(r["name"], []).append(r)
    assert list(by_name) == NAMES  # input order, each feature's rows together
    for k, (name, (_, tris)) in enumerate(ROWS.items()):
        rows = by_name[name]
        assert {r["id"] for r in rows} == {f"r{k}"}
        assert "triangles" not in rows[0] and "diagonals" not in rows[0]
        if tris is None:
            assert [(r["status"], r["triangle"]) for r in rows] == [("error", None)]
        else:
            assert [r["triangle"] for r in rows] == list(range(tris))
            assert {r["status"] for r in rows} == {"ok"} and len({r["cost"] for r in rows}) == 1
    if out.suffix in (".gpkg", ".fgb"):  # the layer says Polygon, as its rows are
        assert pyogrio.read_info(out)["geometry_type"] == "Polygon Z"
    if out.suffix == ".parquet":
        geo = json.loads(pq.read_schema(out).metadata[b"geo"])
        assert geo["columns"]["geometry"]["geometry_types"] == ["Polygon Z"]
    gdf = _geometries(out)
    assert len(gdf) == EXPECTED
    drawn = gdf.geometry[~gdf.geometry.isna()]
    assert len(drawn) == 20
    assert set(drawn.geom_type) == {"Polygon"}
    assert bool(drawn.is_valid.all())
    assert (shapely.get_num_coordinates(drawn.values) == 4).all()  # triangles, closed
    z = gdf[gdf["name"] == "quad z"].geometry
    assert bool(z.has_z.all())  # Z kept on the 3-D row's triangles
    # the triangles cover their feature exactly
    for name, (geom, tris) in ROWS.items():
        if tris is not None:
            union = shapely.union_all(gdf[gdf["name"] == name].geometry.values)
            assert shapely.equals(union.normalize(), shapely.force_2d(geom).normalize())


@pytest.mark.parametrize("source", ["in.parquet", "in.ndjson"])
@pytest.mark.parametrize("out", ["o.parquet", "o.gpkg", "o.fgb", "o.geojson", "o.ndjson", "d/"])
def test_explode_round_trips(tmp_path, source, out):
    src = _layer(tmp_path / source)
    target = tmp_path / out
    fmt = "parquet" if out.endswith("/") else None
    s = batch(src, str(target), workers=1, chunk_size=4, explode=True, out_fmt=fmt)
    _check(target, s)
    again = batch(src, str(target), workers=1, chunk_size=4, explode=True, out_fmt=fmt)
    assert (again.total, again.ok) == (9, 5)  # reused, still counted by feature


def test_explode_when_the_parent_reads_the_chunks(tmp_path, monkeypatch):
    monkeypatch.setattr(config, "BATCH_WORKERS_READ", False)
    src = _layer(tmp_path / "in.parquet")
    _check(tmp_path / "o.parquet", batch(src, tmp_path / "o.parquet", workers=1, explode=True))


def test_columnar_and_record_paths_write_the_same_rows(tmp_path, monkeypatch):
    src = _layer(tmp_path / "in.parquet")
    batch(src, tmp_path / "a.parquet", workers=1, chunk_size=4, explode=True)
    monkeypatch.setattr(config, "BATCH_COLUMNAR", False)
    batch(src, tmp_path / "b.parquet", workers=1, chunk_size=4, explode=True)
    a = [strip_timing(r) for r in iter_records(tmp_path / "a.parquet")]
    b = [strip_timing(r) for r in iter_records(tmp_path / "b.parquet")]
    assert a == b
    ga, gb = gpd.read_parquet(tmp_path / "a.parquet"), gpd.read_parquet(tmp_path / "b.parquet")
    assert list(ga.geometry.to_wkb()) == list(gb.geometry.to_wkb())


@pytest.mark.parametrize("out", ["o.parquet", "d/"])
def test_an_output_written_without_explode_is_not_reused(tmp_path, out):
    src = _layer(tmp_path / "in.parquet")
    target = str(tmp_path / out)
    opts = dict(workers=1, chunk_size=4, out_fmt="parquet")
    batch(src, target, **opts)
    with pytest.raises(BatchInputError, match="explode"):
        batch(src, target, explode=True, **opts)
    s = batch(src, target, explode=True, overwrite=True, **opts)
    _check(tmp_path / out, s)
    with pytest.raises(BatchInputError, match="explode"):
        batch(src, target, **opts)


def test_an_interrupted_exploded_run_resumes(tmp_path, monkeypatch):
    src = _layer(tmp_path / "in.ndjson")
    out = tmp_path / "d"
    batch(src, out, workers=1, chunk_size=4, explode=True, out_fmt="geojson")
    (out / "part-00001.geojson").unlink()  # as if the run had stopped before this part
    (out / "_SUCCESS").unlink()
    s = batch(src, out, workers=1, chunk_size=4, explode=True, out_fmt="geojson")
    assert s.reused == 2 and s.partitions == 3
    _check(out, s)


def test_a_killed_worker_gives_one_error_row(tmp_path):
    geoms = [HEPT if i == 3 else shapely.box(i, 0, i + 1, 1) for i in range(6)]
    wkb = pa.array(shapely.to_wkb(geoms), pa.binary())
    table = pa.table({"k": list(range(6)), "geometry": wkb})
    src = tmp_path / "in.parquet"
    pq.write_table(table, src)
    s = batch(src, tmp_path / "o.parquet", weight=killer, workers=2, chunk_size=2, explode=True)
    recs = list(iter_records(tmp_path / "o.parquet"))
    assert (s.ok, s.errors) == (5, 1)
    assert [r["k"] for r in recs] == [0, 0, 1, 1, 2, 2, 3, 4, 4, 5, 5]
    assert "worker process died" in recs[6]["reason"] and recs[6]["triangle"] is None


def test_duplicate_ids_are_features_not_triangles(tmp_path):
    src = tmp_path / "in.ndjson"
    square = [[0, 0], [1, 0], [1, 1], [0, 1]]
    src.write_text("".join(json.dumps({"id": i, "coordinates": square}) + "\n" for i in (1, 2, 1)))
    with pytest.warns(Warning, match=r"1 record\(s\) repeat an earlier id \('1' x2\)"):
        s = batch(src, tmp_path / "o.ndjson", workers=1, explode=True)
    assert s.duplicates == 1


def test_cli_has_the_flag(tmp_path):
    from click.testing import CliRunner

    from optri.cli import main

    assert "--explode" in CliRunner().invoke(main, ["batch", "--help"]).output
    src = _layer(tmp_path / "in.ndjson")
    res = CliRunner().invoke(main, ["batch", str(src), "-o", str(tmp_path / "o.gpkg"), "--explode"])
    assert res.exit_code == 0, res.output
    assert len(gpd.read_file(tmp_path / "o.gpkg")) == EXPECTED


def test_a_dask_partition_counts_features(tmp_path):
    gdf = gpd.GeoDataFrame(
        {"name": NAMES}, geometry=[g for g, _ in ROWS.values()], crs="EPSG:32633"
    )
    gdf.to_parquet(tmp_path / "in.parquet")
    frame, parts = plan_parts(tmp_path / "in.parquet", tmp_path, explode=True)
    done = solve_part(parts[0], frame)
    assert (done.number, done.rows, done.ok) == (0, 9, 5)  # features, not triangles
    back = gpd.read_parquet(tmp_path / "part.00000.parquet")
    assert len(back) == EXPECTED and bool(back.geometry.dropna().is_valid.all())
    expected = triangulate_many(gdf, explode=True)
    assert list(back["name"]) == list(expected["name"])
    assert all(
        a.equals_exact(b, 0) for a, b in zip(back.geometry.dropna(), expected.geometry.dropna())
    )


@pytest.mark.slow
def test_explode_on_a_dask_cluster(tmp_path):
    distributed = pytest.importorskip("distributed")
    pytest.importorskip("dask_geopandas")
    from optri.batch import dask_layer

    gdf = gpd.GeoDataFrame(
        {"name": NAMES}, geometry=[g for g, _ in ROWS.values()], crs="EPSG:32633"
    )
    src = tmp_path / "in.parquet"
    gdf.to_parquet(src, row_group_size=4)
    with (
        distributed.LocalCluster(
            n_workers=1, processes=False, dashboard_address=None, silence_logs=logging.ERROR
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        s = dask_layer(src, tmp_path / "o.parquet", scheduler=client, explode=True)
    assert (s.total, s.ok, s.errors, s.partitions) == (9, 5, 4, 3)
    got = gpd.read_parquet(tmp_path / "o.parquet")
    assert len(got) == EXPECTED and list(dict.fromkeys(got["name"])) == NAMES
    assert set(got.geometry.dropna().geom_type) == {"Polygon"}
    assert bool(got.geometry.dropna().is_valid.all())
