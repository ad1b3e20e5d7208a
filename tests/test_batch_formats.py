"""CLI round trip on every input format and every output format."""

from __future__ import annotations

import json

import numpy as np
import pytest
from click.testing import CliRunner

import optri
from batch_polys import mixed_polygons, write_feature_collection, write_ndjson
from optri.batch import iter_records, readers
from optri.cli import main

ROWS = mixed_polygons(12, seed=5)


def _expected():
    out = []
    for r in ROWS:
        try:
            out.append(optri.triangulate(r["coordinates"]).triangles.tolist())
        except optri.OptriError:
            out.append(None)
    return out


def shoelace(tri):
    (ax, ay), (bx, by), (cx, cy) = tri
    return ((bx - ax) * (cy - ay) - (by - ay) * (cx - ax)) / 2


def _run(*args):
    res = CliRunner().invoke(main, ["batch", *map(str, args), "-q", "-j", "1"])
    assert res.exit_code == 0, res.output
    return res


def _check(out, ids=None):
    recs = list(iter_records(out))
    assert [r["triangles"] for r in recs] == _expected()
    if ids is not None:
        assert [r["id"] for r in recs] == ids


def _geodataframe():
    gpd = pytest.importorskip("geopandas")
    shapely = pytest.importorskip("shapely")
    geoms = [shapely.Polygon(r["coordinates"]) for r in ROWS]
    return gpd.GeoDataFrame({"id": [r["id"] for r in ROWS]}, geometry=geoms)


def test_ndjson_in(tmp_path):
    _run(write_ndjson(tmp_path / "in.jsonl", ROWS), "-o", tmp_path / "out")
    _check(tmp_path / "out", [r["id"] for r in ROWS])


def test_geojson_in_geojson_out_is_valid_geojson(tmp_path):
    src = write_feature_collection(tmp_path / "in.geojson", ROWS)
    _run(src, "-o", tmp_path / "out.geojson", "--chunk-size", "5")
    _check(tmp_path / "out.geojson", [r["id"] for r in ROWS])
    fc = json.loads((tmp_path / "out.geojson").read_text())
    assert fc["type"] == "FeatureCollection" and len(fc["features"]) == len(ROWS)
    feat = next(f for f in fc["features"] if f["geometry"])
    assert feat["geometry"]["type"] == "GeometryCollection"
    parts = feat["geometry"]["geometries"]
    assert {p["type"] for p in parts} == {"Polygon"}
    assert len(parts) == feat["properties"]["n"] - 2
    shapely = pytest.importorskip("shapely")
    for f in fc["features"]:  # valid as shapely reads it
        assert f["geometry"] is None or shapely.from_geojson(json.dumps(f["geometry"])).is_valid


def test_geojson_directory_parts_are_each_valid(tmp_path):
    src = write_feature_collection(tmp_path / "in.geojson", ROWS)
    _run(src, "-o", tmp_path / "out", "--out-format", "geojson", "--chunk-size", "5")
    parts = sorted((tmp_path / "out").glob("part-*.geojson"))
    assert len(parts) == 3
    assert sum(len(json.loads(p.read_text())["features"]) for p in parts) == len(ROWS)
    _check(tmp_path / "out", [r["id"] for r in ROWS])


@pytest.mark.parametrize("block", [1, 7, 64])
def test_feature_collection_is_streamed_across_block_edges(tmp_path, monkeypatch, block):
    monkeypatch.setattr(optri.config, "BATCH_READ_BLOCK", block)
    src = write_feature_collection(tmp_path / "in.geojson", ROWS[:4])
    data = json.loads(src.read_text())
    data = {
        "bbox": [0, 0, 1, 1],
        "features": data["features"],
        "type": "FeatureCollection",
        "n": 123456,
    }
    src.write_text(json.dumps(data, indent=2))
    items = list(readers.read_items(src))
    assert [it.coords.tolist() for it in items] == [r["coordinates"] for r in ROWS[:4]]


def test_geoparquet_in_and_out(tmp_path):
    gdf = _geodataframe()
    pytest.importorskip("pyarrow")
    gdf.to_parquet(tmp_path / "in.parquet")
    _run(tmp_path / "in.parquet", "-o", tmp_path / "out.parquet", "--chunk-size", "4")
    _check(tmp_path / "out.parquet", [r["id"] for r in ROWS])
    gpd = pytest.importorskip("geopandas")
    back = gpd.read_parquet(tmp_path / "out.parquet")
    ok = back[back.status == "ok"]
    areas = [
        abs(optri.polygon.signed_area(__import__("numpy").array(ROWS[i]["coordinates"])))
        for i in ok.index
    ]
    assert ok.geometry.area.tolist() == pytest.approx(areas)


def test_geoparquet_small_row_groups(tmp_path, monkeypatch):

    monkeypatch.setattr(optri.config, "BATCH_ROWS_PER_READ", 5)
    _geodataframe().to_parquet(tmp_path / "in.parquet", row_group_size=3)
    _run(tmp_path / "in.parquet", "-o", tmp_path / "out")
    _check(tmp_path / "out", [r["id"] for r in ROWS])


def test_geopackage_in(tmp_path, monkeypatch):
    pytest.importorskip("pyogrio")

    monkeypatch.setattr(optri.config, "BATCH_ROWS_PER_READ", 5)  # several pages
    gdf = _geodataframe()
    gdf.set_crs("EPSG:3857").to_file(tmp_path / "in.gpkg", driver="GPKG", engine="pyogrio")
    _run(tmp_path / "in.gpkg", "-o", tmp_path / "out.ndjson")
    _check(tmp_path / "out.ndjson", [r["id"] for r in ROWS])


def test_parquet_that_is_not_a_polygon_layer(tmp_path):
    pa = pytest.importorskip("pyarrow")
    pq = pytest.importorskip("pyarrow.parquet")
    pq.write_table(pa.table({"x": [1, 2]}), tmp_path / "t.parquet")
    res = CliRunner().invoke(
        main, ["batch", str(tmp_path / "t.parquet"), "-o", str(tmp_path / "o")]
    )
    assert res.exit_code == 2 and "not a polygon layer" in res.output
    assert not (tmp_path / "o").exists()  # a bad input leaves no output behind
    (tmp_path / "junk.parquet").write_text("not parquet")
    res = CliRunner().invoke(
        main, ["batch", str(tmp_path / "junk.parquet"), "-o", str(tmp_path / "o")]
    )
    assert res.exit_code == 2 and "junk.parquet" in res.output and "Traceback" not in res.output


def test_holes_in_geoparquet_are_triangulated(tmp_path):
    gpd = pytest.importorskip("geopandas")
    shapely = pytest.importorskip("shapely")
    holed = shapely.Polygon([[0, 0], [4, 0], [4, 4], [0, 4]], [[[1, 1], [2, 1], [1, 2]]])
    outside = shapely.Polygon([[0, 0], [4, 0], [4, 4], [0, 4]], [[[5, 1], [6, 1], [5, 2]]])
    gpd.GeoDataFrame(geometry=[holed, shapely.box(0, 0, 1, 1), outside]).to_parquet(
        tmp_path / "h.parquet"
    )
    _run(tmp_path / "h.parquet", "-o", tmp_path / "o.ndjson")
    recs = list(iter_records(tmp_path / "o.ndjson"))
    want = optri.triangulate(holed)
    # 7 vertices (exterior first, then the hole), 7 + 2 - 2 triangles, the optimum of triangulate
    assert recs[0]["status"] == "ok" and recs[0]["n"] == 7 and len(recs[0]["triangles"]) == 7
    assert recs[0]["cost"] == want.weight and recs[0]["triangles"] == want.triangles.tolist()
    assert recs[1]["status"] == "ok" and recs[1]["id"] == 1
    assert recs[2]["status"] == "error" and "outside the exterior ring" in recs[2]["reason"]


def test_holes_in_ndjson_and_geojson(tmp_path):
    square = [[0, 0], [3, 0], [3, 3], [0, 3], [0, 0]]
    hole = [[1, 1], [1, 2], [2, 2], [2, 1], [1, 1]]
    geom = {"type": "Polygon", "coordinates": [square, hole]}
    (tmp_path / "h.ndjson").write_text(
        json.dumps({"id": "court", "geometry": geom, "type": "Feature"}) + "\n"
    )
    _run(tmp_path / "h.ndjson", "-o", tmp_path / "o.geojson")
    feat = json.loads((tmp_path / "o.geojson").read_text())["features"][0]
    want = optri.triangulate((square, [hole]))
    assert feat["properties"]["status"] == "ok"
    assert feat["properties"]["cost"] == want.weight
    tris = [p["coordinates"] for p in feat["geometry"]["geometries"]]
    assert len(tris) == 8  # 8 vertices, one hole: 8 + 2 - 2 triangles
    area = sum(abs(shoelace(t[0][:3])) for t in tris)
    assert area == 9 - 1  # the square less its hole


def test_import_loads_no_optional_batch_dependency():
    from cli_run import run_python

    code = (
        "import sys, optri, optri.batch.driver; "
        "print(sorted(m for m in ('dask', 'distributed', 'pyarrow', 'geopandas', 'pyogrio',"
        " 'shapely', 'rich', 'concurrent.futures.process') if m in sys.modules))"
    )
    out = run_python("-c", code)
    assert out.returncode == 0 and out.stdout.strip() == "[]", out.stderr


def test_triangulate_many_takes_ring_pairs():
    square, hole = [[0, 0], [3, 0], [3, 3], [0, 3]], [[1, 1], [2, 1], [2, 2], [1, 2]]
    outside = [[4, 1], [5, 1], [5, 2]]
    out = optri.triangulate_many([(square, [hole]), square, (square, [outside])])
    assert out[0].rings == (4, 4) and len(out[0].triangles) == 8
    assert out[0].weight == optri.triangulate((square, [hole])).weight
    assert len(out[1].triangles) == 2
    assert isinstance(out[2], optri.InvalidPolygonError) and "outside" in str(out[2])


def test_holes_survive_the_worker_pool(tmp_path):
    square = [[0, 0], [3, 0], [3, 3], [0, 3], [0, 0]]
    hole = [[1, 1], [1, 2], [2, 2], [2, 1], [1, 1]]
    lines = [
        {"type": "Feature", "id": k, "properties": {},
         "geometry": {"type": "Polygon", "coordinates": [square, hole] if k % 2 else [square]}}
        for k in range(6)
    ]  # fmt: skip
    (tmp_path / "h.ndjson").write_text("".join(json.dumps(x) + "\n" for x in lines))
    summary = optri.batch(tmp_path / "h.ndjson", tmp_path / "o.ndjson", workers=2, chunk_size=2)
    recs = list(iter_records(tmp_path / "o.ndjson"))
    assert summary.ok == 6 and [r["n"] for r in recs] == [4, 8] * 3
    assert [len(r["triangles"]) for r in recs] == [2, 8] * 3


def test_all_holes_kept_in_order_from_pairs_and_shapely():
    # two holes: the vertices are the exterior, then each hole, as optri.triangulate numbers them
    ext = [[0, 0], [6, 0], [6, 5], [0, 5]]
    holes = [[[1, 1], [2, 1], [2, 2], [1, 2]], [[4, 3], [5, 3], [4.5, 4]]]
    want = optri.triangulate((ext, holes))
    sources = [(ext, holes)]
    shapely = pytest.importorskip("shapely")
    sources.append(shapely.Polygon(ext, holes))
    for got in optri.triangulate_many(sources):
        assert isinstance(got, optri.Triangulation), got
        assert got.rings == (4, 4, 3) and len(got.triangles) == 11 + 2 * 2 - 2
        assert got.vertices.tolist() == [[float(x), float(y)] for x, y in ext + holes[0] + holes[1]]
        assert got.weight == want.weight and got.triangles.tolist() == want.triangles.tolist()
        got.check()


def test_projected_holes_keep_their_rings():
    pytest.importorskip("pyproj")
    from optri.batch.project import local_projector

    ext = [[10.0, 50.0], [10.003, 50.0], [10.003, 50.003], [10.0, 50.003]]
    hole = [[10.001, 50.001], [10.001, 50.002], [10.002, 50.002], [10.002, 50.001]]
    (got,) = optri.triangulate_many([(ext, [hole])], project=True, crs="EPSG:4326")
    assert isinstance(got, optri.Triangulation), got
    assert got.rings == (4, 4) and len(got.triangles) == 8
    assert got.vertices.tolist() == ext + hole  # the input's degrees again
    xy = local_projector("EPSG:4326")(np.array(ext + hole))  # one projection per polygon
    want = optri.triangulate((xy[:4], [xy[4:]]))
    assert 1000 < want.weight < 10000  # metres (some 215 m by 333 m), not degrees
    assert got.weight == pytest.approx(want.weight, rel=1e-12)
    assert got.triangles.tolist() == want.triangles.tolist()
