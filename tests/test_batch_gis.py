"""GIS layers in and out untouched: CRS, attribute columns, order, ids, error rows, formats."""

from __future__ import annotations

import datetime
import json
import os

import numpy as np
import pytest
from click.testing import CliRunner

gpd = pytest.importorskip("geopandas")
pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")
pyogrio = pytest.importorskip("pyogrio")
pyproj = pytest.importorskip("pyproj")
shapely = pytest.importorskip("shapely")

import optri  # noqa: E402
from batch_polys import convex_polygon, star_polygon  # noqa: E402
from optri.batch import GeographicCRSWarning, iter_records  # noqa: E402
from optri.cli import main  # noqa: E402

BOWTIE = [[0, 0], [2, 2], [2, 0], [0, 2]]
# where each CRS's polygons sit, and how big they are (metres / degrees)
PLACES = {"EPSG:32633": ((390000.0, 5820000.0), 40.0), "EPSG:4326": ((13.4, 52.5), 0.0005)}


def _rings(crs: str) -> list:
    """Polygons (lists of vertices) in ``crs``, with three bad rows among them."""
    (x0, y0), size = PLACES[crs]
    rng = np.random.default_rng(7)
    rings: list = []
    for i in range(9):
        shape = star_polygon(rng, 7) if i % 2 else convex_polygon(rng, 6)
        pts = np.asarray(shape) - np.mean(shape, axis=0)
        rings.append((pts / np.abs(pts).max() * size + [x0 + i * 3 * size, y0]).tolist())
    bowtie = (np.asarray(BOWTIE, float) * size + [x0, y0]).tolist()
    rings[2], rings[5], rings[7] = bowtie, None, "hole"
    return rings


def _geometry(ring, crs):
    if ring is None:
        return None
    if ring == "hole":
        (x0, y0), size = PLACES[crs]
        box = shapely.box(x0, y0, x0 + 4 * size, y0 + 4 * size)
        # a hole outside its exterior ring: a bad row (holes inside are triangulated)
        outside = shapely.box(x0 + 5 * size, y0 + size, x0 + 6 * size, y0 + 2 * size)
        return shapely.Polygon(box.exterior, [outside.exterior])
    return shapely.Polygon(ring)


def _table(crs: str, with_id: bool):
    """An Arrow table: int, float and text columns, each with a null, and WKB polygons."""
    rings = _rings(crs)
    n = len(rings)
    cols = {
        "code": pa.array([None if i == 3 else 100 + i for i in range(n)], pa.int64()),
        "height": pa.array([None if i == 4 else 2.5 * i for i in range(n)], pa.float64()),
        "name": pa.array([None if i == 1 else f"bldg {i}" for i in range(n)], pa.string()),
        # a narrower integer and a date: types a writer guessing from values would change
        "floors": pa.array([None if i == 2 else i % 5 for i in range(n)], pa.int32()),
        "built": pa.array([None if i == 6 else datetime.date(1990 + i, 1, 2) for i in range(n)]),
    }
    if with_id:
        cols = {"id": pa.array([f"f{i}" for i in range(n)], pa.string()), **cols}
    geoms = [_geometry(r, crs) for r in rings]
    cols["geometry"] = pa.array([None if g is None else shapely.to_wkb(g) for g in geoms])
    return pa.table(cols), rings


def _write_input(path, crs, with_id):
    table, rings = _table(crs, with_id)
    if path.suffix == ".parquet":
        geo = {
            "version": "1.1.0",
            "primary_column": "geometry",
            "columns": {
                "geometry": {
                    "encoding": "WKB",
                    "geometry_types": ["Polygon"],
                    "crs": json.loads(pyproj.CRS(crs).to_json()),
                }
            },
        }
        pq.write_table(table.replace_schema_metadata({"geo": json.dumps(geo)}), path)
    elif path.suffix == ".geojson":
        feats = []
        for row, geom in zip(table.drop_columns(["geometry"]).to_pylist(), table["geometry"]):
            g = geom.as_py()
            fid = row.pop("id", None)
            feats.append(
                {
                    "type": "Feature",
                    **({"id": fid} if fid is not None else {}),
                    "properties": row,
                    "geometry": None
                    if g is None
                    else shapely.geometry.mapping(shapely.from_wkb(g)),
                }
            )
        fc = {"type": "FeatureCollection", "features": feats}
        if crs != "EPSG:4326":
            fc = {
                "type": "FeatureCollection",
                "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::32633"}},
                "features": feats,
            }
        path.write_text(json.dumps(fc, default=str))
    else:
        pyogrio.write_arrow(
            table,
            path,
            geometry_name="geometry",
            geometry_type="Polygon",
            crs=crs,
            layer_options={"SPATIAL_INDEX": "NO"} if path.suffix == ".fgb" else None,
        )
    return table, rings


def _expected(ring):
    if not isinstance(ring, list):
        return None
    try:
        return optri.triangulate(np.asarray(ring))
    except optri.OptriError:
        return None


def _check_layer(out, table, rings, crs, with_id, first_id, in_suffix=".gpkg"):
    """The output layer read back with pyogrio/pyarrow: CRS, columns, order, ids, triangles."""
    if out.suffix == ".parquet":
        back = pq.read_table(out)
        meta = json.loads(back.schema.metadata[b"geo"])
        got_crs = pyproj.CRS.from_json_dict(meta["columns"]["geometry"]["crs"])
    else:
        # GDAL's own FlatGeobuf Arrow reader garbles null geometries: read through SQLite
        sql = {"sql": "SELECT * FROM out", "sql_dialect": "SQLITE"} if out.suffix == ".fgb" else {}
        meta, back = pyogrio.read_arrow(out, **sql)
        got_crs = pyproj.CRS.from_user_input(meta["crs"])
        geom = meta["geometry_name"] or back.column_names[-1]
        back = back.rename_columns([("geometry" if c == geom else c) for c in back.column_names])
    # a GeoJSON without "crs" is OGC:CRS84: EPSG:4326 but for the axis order
    assert got_crs.equals(pyproj.CRS(crs), ignore_axis_order=True), got_crs
    for name in ("code", "height", "name"):  # values and nulls, same order
        assert back[name].to_pylist() == table[name].to_pylist(), name
    assert back["floors"].to_pylist() == table["floors"].to_pylist()
    if out.suffix != ".geojson":  # GeoJSON keeps numbers, not Arrow types
        assert back.schema.field("code").type == pa.int64()
        assert back.schema.field("height").type == pa.float64()
    if out.suffix != ".geojson" and in_suffix != ".geojson":  # types come from the layer
        assert back.schema.field("floors").type == pa.int32()
    if out.suffix in (".gpkg", ".parquet") and in_suffix in (".gpkg", ".parquet"):
        assert back.schema.field("built").type == pa.date32()
        assert back["built"].to_pylist() == table["built"].to_pylist()
    if out.suffix == ".geojson":  # GDAL turns integer feature ids into FIDs: read them here
        got = [f["id"] for f in json.loads(out.read_text())["features"]]
    else:
        got = back["id"].to_pylist()
    n = len(rings)
    assert got == (table["id"].to_pylist() if with_id else list(range(first_id, first_id + n)))
    geoms = shapely.from_wkb(back["geometry"].to_numpy(zero_copy_only=False))
    for k, (ring, status, geom) in enumerate(zip(rings, back["status"].to_pylist(), geoms)):
        tri = _expected(ring)
        if tri is None:
            assert status == "error" and geom is None and back["reason"][k].as_py(), k
            continue
        assert status == "ok", (k, back["reason"][k])
        assert back["cost"][k].as_py() == pytest.approx(tri.weight, rel=1e-12)
        assert geom.geom_type == "GeometryCollection" and len(geom.geoms) == len(rings[k]) - 2
        assert geom.is_valid and {t.geom_type for t in geom.geoms} == {"Polygon"}
        assert geom.area == pytest.approx(shapely.Polygon(ring).area, rel=1e-9)
        corners = {tuple(c) for t in geom.geoms for c in t.exterior.coords}
        assert corners <= {tuple(c) for c in ring}


def _run(*args):
    res = CliRunner().invoke(main, ["batch", *map(str, args), "-j", "1"])
    assert res.exit_code == 0, res.output
    return res


@pytest.mark.parametrize("crs, with_id", [("EPSG:32633", True), ("EPSG:4326", False)])
@pytest.mark.parametrize("out_suffix", [".gpkg", ".fgb", ".parquet", ".geojson"])
def test_gpkg_round_trips_through_every_table_format(tmp_path, crs, with_id, out_suffix):
    src = tmp_path / "in.gpkg"
    table, rings = _write_input(src, crs, with_id)
    out = tmp_path / f"out{out_suffix}"
    _run(src, "-o", out, "--chunk-size", "4")
    _check_layer(out, table, rings, crs, with_id, first_id=1)  # GeoPackage FIDs from 1
    # the output and its receipt (the job it was made for) only
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        ["in.gpkg", out.name, f".{out.name}.optri.json"]
    )


@pytest.mark.parametrize("crs, with_id", [("EPSG:32633", True), ("EPSG:4326", False)])
@pytest.mark.parametrize("in_suffix", [".parquet", ".geojson", ".fgb"])
def test_other_inputs_into_geopackage(tmp_path, crs, with_id, in_suffix):
    src = tmp_path / f"in{in_suffix}"
    table, rings = _write_input(src, crs, with_id)
    out = tmp_path / "out.gpkg"
    _run(src, "-o", out, "--chunk-size", "3")
    _check_layer(out, table, rings, crs, with_id, first_id=0, in_suffix=in_suffix)


@pytest.mark.parametrize("crs", ["EPSG:32633", "EPSG:4326"])
def test_ndjson_output_keeps_attributes_order_ids_and_errors(tmp_path, crs):
    src = tmp_path / "in.gpkg"
    table, rings = _write_input(src, crs, True)
    _run(src, "-o", tmp_path / "o.ndjson", "--chunk-size", "4")
    recs = list(iter_records(tmp_path / "o.ndjson"))
    assert [r["id"] for r in recs] == table["id"].to_pylist()
    attrs = table.drop_columns(["geometry"]).to_pylist()  # every attribute, "id" included
    for row in attrs:  # JSON has no dates: ISO 8601 text
        row["built"] = row["built"] and row["built"].isoformat()
    fields = ("status", "n", "cost", "triangles", "diagonals", "reason", "seconds")
    assert [{k: v for k, v in r.items() if k not in fields} for r in recs] == attrs
    for rec, ring in zip(recs, rings):
        tri = _expected(ring)
        assert rec["status"] == ("ok" if tri is not None else "error")
        if tri is not None:
            assert rec["triangles"] == tri.triangles.tolist()


def test_a_parquet_layer_of_json_features_unifies_column_types_across_parts(tmp_path):
    sq = [[0, 0], [1, 0], [1, 1], [0, 1]]
    rows = [
        {"id": 1, "coordinates": sq, "properties": {"a": None, "b": 1}},
        {"id": 2, "coordinates": sq, "properties": {"a": None, "b": 2.5}},
        {"id": 3, "coordinates": sq, "properties": {"a": 7, "b": "x", "c": [1, 2]}},
    ]
    src = tmp_path / "in.ndjson"
    src.write_text("".join(json.dumps(r) + "\n" for r in rows))
    for suffix in (".parquet", ".gpkg"):
        out = tmp_path / f"o{suffix}"
        optri.batch(src, out, workers=1, chunk_size=1)
        back = pq.read_table(out) if suffix == ".parquet" else pyogrio.read_arrow(out)[1]
        assert back["a"].to_pylist() == [None, None, 7]
        assert back["b"].to_pylist() == ["1", "2.5", "x"]  # int, float, text: text
        assert back["c"].to_pylist() == [None, None, "[1,2]"]
        assert back["id"].to_pylist() == [1, 2, 3]


def test_unknown_suffix_is_refused_and_nothing_is_made(tmp_path):
    src = tmp_path / "in.gpkg"
    _write_input(src, "EPSG:32633", True)
    for out in ("out.csv", "out.gpkg2", "results.v2"):
        res = CliRunner().invoke(main, ["batch", str(src), "-o", str(tmp_path / out)])
        assert res.exit_code == 2 and res.output.count("\n") == 1, res.output
        assert "unknown output suffix" in res.output and "Traceback" not in res.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["in.gpkg"]
    (tmp_path / "taken.gpkg").mkdir()
    res = CliRunner().invoke(main, ["batch", str(src), "-o", str(tmp_path / "taken.gpkg")])
    assert res.exit_code == 2 and "is a directory" in res.output
    os.mkfifo(tmp_path / "fifo.ndjson")  # an output replaces regular files only
    res = CliRunner().invoke(main, ["batch", str(src), "-o", str(tmp_path / "fifo.ndjson")])
    assert res.exit_code == 2 and "is not a regular file" in res.output
    (tmp_path / "fifo.ndjson").unlink()
    # --out-format overrides a suffix, and an explicit directory stays a directory
    _run(src, "-o", tmp_path / "out.dat", "--out-format", "gpkg")
    assert pyogrio.read_info(tmp_path / "out.dat")["driver"] == "GPKG"
    _run(src, "-o", f"{tmp_path / 'parts.v2'}/", "--out-format", "parquet", "--chunk-size", "4")
    assert len(list((tmp_path / "parts.v2").glob("part-*.parquet"))) == 3


def test_geographic_layers_are_warned_about_once(tmp_path):
    src = tmp_path / "in.gpkg"
    _write_input(src, "EPSG:4326", False)
    res = CliRunner().invoke(main, ["batch", str(src), "-o", str(tmp_path / "o.gpkg"), "-j", "1"])
    assert res.exit_code == 0
    assert (
        res.output.count("optri: warning: the layer's CRS is geographic (WGS 84 (EPSG:4326))") == 1
    )
    with pytest.warns(GeographicCRSWarning, match=r"EPSG:4326.*--project"):
        optri.batch(src, tmp_path / "p.ndjson", workers=1)
    proj = tmp_path / "utm.gpkg"
    _write_input(proj, "EPSG:32633", False)
    res = CliRunner().invoke(main, ["batch", str(proj), "-o", str(tmp_path / "u.gpkg"), "-j", "1"])
    assert "warning" not in res.output
    res = CliRunner().invoke(
        main, ["batch", str(src), "-o", str(tmp_path / "m.gpkg"), "-j", "1", "--project"]
    )
    assert "warning" not in res.output


def _hand_projected(ring, crs):
    """The polygon in the aeqd projection centred on its mean longitude/latitude (by pyproj)."""
    to_ll = pyproj.Transformer.from_crs(crs, "EPSG:4326", always_xy=True)
    lon, lat = to_ll.transform(*np.asarray(ring).T)
    aeqd = pyproj.CRS.from_proj4(
        f"+proj=aeqd +lat_0={float(np.mean(lat))!r} +lon_0={float(np.mean(lon))!r} "
        "+datum=WGS84 +units=m"
    )
    x, y = pyproj.Transformer.from_crs("EPSG:4326", aeqd, always_xy=True).transform(lon, lat)
    return np.column_stack([x, y])


@pytest.mark.parametrize("crs", ["EPSG:4326", "EPSG:32633"])
def test_project_measures_in_metres_like_a_hand_projected_polygon(tmp_path, crs):
    src = tmp_path / "in.gpkg"
    table, rings = _write_input(src, crs, True)
    _run(src, "-o", tmp_path / "o.gpkg", "--project")
    meta, back = pyogrio.read_arrow(tmp_path / "o.gpkg")
    plain = optri.batch(src, tmp_path / "plain.ndjson", workers=1)
    assert plain.ok == back["status"].to_pylist().count("ok")
    for k, ring in enumerate(rings):
        if _expected(ring) is None:
            continue
        hand = optri.triangulate(_hand_projected(ring, crs))
        assert back["cost"][k].as_py() == pytest.approx(hand.weight, rel=1e-9, abs=1e-6)
        assert json.loads(back["triangles"][k].as_py()) == hand.triangles.tolist()
        geom = shapely.from_wkb(back[meta["geometry_name"]][k].as_py())
        assert geom.area == pytest.approx(shapely.Polygon(ring).area, rel=1e-9)  # input coords
    if crs == "EPSG:4326":  # degrees without --project: a million times smaller
        costs = [r["cost"] for r in iter_records(tmp_path / "plain.ndjson") if r["cost"]]
        assert max(costs) < 0.01 < min(c for c in back["cost"].to_pylist() if c)


def test_project_needs_a_crs(tmp_path):
    src = tmp_path / "in.ndjson"
    src.write_text('{"id": 1, "coordinates": [[0, 0], [1, 0], [0, 1]]}\n')
    res = CliRunner().invoke(
        main, ["batch", str(src), "-o", str(tmp_path / "o.ndjson"), "--project"]
    )
    assert res.exit_code == 2 and "--project needs the layer's CRS" in res.output
    assert not (tmp_path / "o.ndjson").exists()
