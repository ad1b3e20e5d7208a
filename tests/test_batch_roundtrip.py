"""Every output format gives back what went in: MultiPolygons, holes, Z, nulls, empties, dates.

Each output is read back by the next tool a GIS user has (geopandas / pyogrio,
which opens ``.ndjson`` through GDAL's GeoJSONSeq driver) and by
:func:`optri.batch.iter_records`; every triangulated geometry must be valid.
"""

from __future__ import annotations

import datetime
import json

import numpy as np
import pytest

gpd = pytest.importorskip("geopandas")
pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")
pyogrio = pytest.importorskip("pyogrio")
shapely = pytest.importorskip("shapely")
pytest.importorskip("scipy")  # polygons with holes

from optri import triangulate  # noqa: E402
from optri.batch import iter_records  # noqa: E402
from optri.batch.driver import batch  # noqa: E402

PLUS2 = datetime.timezone(datetime.timedelta(hours=2))
SQUARE = shapely.box(0, 0, 20, 10)
Z_POLY = shapely.Polygon([(30, 0, 1), (34, 0, 2), (34, 3, 3), (30, 3, 4)])
MULTI = shapely.MultiPolygon([shapely.box(40, 0, 41, 1), shapely.box(43, 0, 45, 2)])
HOLED = shapely.Polygon(shapely.box(50, 0, 60, 10).exterior, [shapely.box(52, 2, 54, 4).exterior])
GEOMS = [SQUARE, Z_POLY, MULTI, HOLED, None, shapely.Polygon()]
STATUS = ["ok", "ok", "ok", "ok", "error", "error"]
OUTPUTS = [".parquet", ".gpkg", ".fgb", ".geojson", ".ndjson"]


NAMES = [f"f{k}" for k in range(len(GEOMS))]


def _table():
    rows = range(len(GEOMS))
    return pa.table(
        {
            "name": NAMES,
            "day": pa.array([datetime.date(2020, 1, k + 1) for k in rows], pa.date32()),
            "naive": pa.array(
                [datetime.datetime(2020, 1, 1, 12, k) for k in rows], pa.timestamp("ms")
            ),
            "aware": pa.array(
                [datetime.datetime(2020, 1, 1, 12, k, tzinfo=PLUS2) for k in rows],
                pa.timestamp("ms", tz="+02:00"),
            ),
            "geometry": pa.array(shapely.to_wkb(np.array(GEOMS, object)), pa.binary()),
        }
    )


def _input(tmp_path, suffix):
    path = tmp_path / f"in{suffix}"
    if suffix == ".parquet":
        column = {"encoding": "WKB", "geometry_types": [], "crs": "EPSG:32633"}
        geo = {"version": "1.1.0", "primary_column": "geometry", "columns": {"geometry": column}}
        pq.write_table(_table().replace_schema_metadata({b"geo": json.dumps(geo)}), path)
    else:
        pyogrio.write_arrow(
            _table(),
            path,
            driver="GPKG",
            geometry_name="geometry",
            geometry_type="Unknown",
            crs="EPSG:32633",
        )
    return path


def _read_back(path):
    if path.suffix == ".parquet":
        return gpd.read_parquet(path)
    return pyogrio.read_dataframe(path)


@pytest.mark.parametrize("source", [".parquet", ".gpkg"])
@pytest.mark.parametrize("suffix", OUTPUTS)
def test_round_trip(tmp_path, source, suffix):
    out = tmp_path / f"out{suffix}"
    s = batch(_input(tmp_path, source), out, workers=1, chunk_size=4)
    assert (s.ok, s.errors) == (4, 2)
    recs = list(iter_records(out))
    assert [r["status"] for r in recs] == STATUS
    assert recs[2]["n"] == 8 and len(recs[2]["triangles"]) == 4  # two squares, one row
    back = _read_back(out)
    assert len(back) == len(GEOMS)
    geoms = back.geometry.values
    ok = np.array([s == "ok" for s in STATUS])
    assert shapely.is_valid(geoms[ok]).all()
    assert shapely.is_missing(geoms[~ok]).all()
    # the triangles cover each polygon exactly (area of the union, holes left out)
    for g, src in zip(geoms[ok], np.array(GEOMS, object)[ok]):
        assert abs(shapely.union_all(shapely.get_parts(g)).area - src.area) < 1e-9
    assert shapely.has_z(geoms[1])
    assert sorted(shapely.get_coordinates(geoms[1], include_z=True)[:, 2].tolist())[0] == 1.0
    _check_dates(recs, suffix)


def _check_dates(recs, suffix):
    for k, r in enumerate(recs):
        day = datetime.date(2020, 1, k + 1)
        naive = datetime.datetime(2020, 1, 1, 12, k)
        aware = datetime.datetime(2020, 1, 1, 12, k, tzinfo=PLUS2)
        if suffix in (".geojson", ".ndjson"):  # JSON has no date type: ISO 8601 text
            assert r["day"] == day.isoformat()
            assert datetime.datetime.fromisoformat(r["naive"]) == naive
            got = datetime.datetime.fromisoformat(r["aware"])
            assert got.tzinfo is not None and got == aware
            continue
        if suffix == ".fgb":  # FlatGeobuf has no date type: a datetime at midnight
            assert r["day"] in (day, datetime.datetime.combine(day, datetime.time()))
        else:
            assert r["day"] == day and type(r["day"]) is datetime.date
        assert r["naive"] == naive and r["naive"].tzinfo is None
        assert r["aware"].tzinfo is not None and r["aware"] == aware


def test_ndjson_is_a_geojson_text_sequence(tmp_path):
    out = tmp_path / "out.ndjson"
    batch(_input(tmp_path, ".parquet"), out, workers=1)
    lines = out.read_text().splitlines()
    assert len(lines) == len(GEOMS)
    feats = [json.loads(line) for line in lines]
    assert all(f["type"] == "Feature" for f in feats)
    assert pyogrio.read_info(out)["driver"] == "GeoJSONSeq"
    back = pyogrio.read_dataframe(out)
    assert back["status"].tolist() == STATUS and back["name"].tolist() == NAMES


def test_multipolygon_is_solved_part_by_part(tmp_path):
    out = tmp_path / "out.parquet"
    batch(_input(tmp_path, ".parquet"), out, workers=1, weight="perimeter", objective="max")
    rec = list(iter_records(out))[2]
    a, b = (triangulate(np.asarray(p.exterior.coords), objective="max") for p in MULTI.geoms)
    assert rec["status"] == "ok" and rec["cost"] == pytest.approx(max(a.weight, b.weight))
    assert rec["triangles"] == a.triangles.tolist() + (b.triangles + 4).tolist()


def test_table_outputs_declare_geometry_collections(tmp_path):
    out = tmp_path / "out.gpkg"
    batch(_input(tmp_path, ".parquet"), out, workers=1)
    assert pyogrio.read_info(out)["geometry_type"].startswith("GeometryCollection")


def test_geo_extra_installs_what_a_real_layer_needs():
    import pathlib
    import re

    import tomllib

    root = pathlib.Path(__file__).resolve().parents[1]
    extras = tomllib.loads((root / "pyproject.toml").read_text())["project"][
        "optional-dependencies"
    ]

    def names(extra):
        return {re.split(r"[<>=\[ ]", req)[0] for req in extras[extra]}

    # scipy: the holes of a holed feature; the rest: reading, writing, CRSs
    assert {"geopandas", "pyogrio", "pyarrow", "pyproj", "shapely", "scipy"} <= names("geo")
    assert "dask-geopandas" in names("dask")
    assert {"geo", "dask", "holes"} <= set(re.findall(r"\w[\w-]*", extras["all"][0].split("[")[1]))
