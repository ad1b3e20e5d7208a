"""shapely in and out, GeoJSON and WKT files, and the CLI on simple polygons."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from click.testing import CliRunner

import optri
from optri import InvalidPolygonError
from optri.cli import main
from optri.io import read_polygon
from optri.io.geo import polygon_from_geojson, polygon_from_wkt

shapely = pytest.importorskip("shapely")

NOTCH = [[0, 0], [3, 0], [3, 3], [2, 1], [1, 3], [0, 3]]
RING = NOTCH + [NOTCH[0]]


def test_shapely_polygon_in_triangles_out():
    poly = shapely.Polygon(NOTCH)
    tri = optri.triangulate(poly, method="memo")
    ref = optri.triangulate(NOTCH, method="memo")
    assert tri.weight == ref.weight and tri.triangles.tolist() == ref.triangles.tolist()
    tri.check()
    out = tri.to_shapely()
    assert isinstance(out, shapely.GeometryCollection)
    assert len(out.geoms) == len(NOTCH) - 2
    assert math.isclose(shapely.union_all(out.geoms).area, poly.area)
    assert all(g.exterior.is_ccw and poly.covers(g) for g in out.geoms)


def test_shapely_hole_is_triangulated_not_dropped():
    holed = shapely.Polygon(
        [(0, 0), (10, 0), (10, 10), (0, 10)], [[(4, 4), (6, 4), (6, 6), (4, 6)]]
    )
    tri = optri.triangulate(holed)
    assert tri.holes == 1 and len(tri.triangles) == 8 + 2 - 2
    assert math.isclose(shapely.union_all(tri.to_shapely().geoms).area, holed.area)
    with pytest.raises(InvalidPolygonError, match="geo_polygon_rings"):
        optri.io.geo_polygon_coords(holed)  # the one-ring reader never drops a hole


def test_clockwise_shapely_ring():
    poly = shapely.Polygon(NOTCH[::-1])
    tri = optri.triangulate(poly, method="table")
    assert tri.orientation == "cw"
    tri.check()


def test_wkt_and_geojson_parsing():
    assert polygon_from_wkt(shapely.Polygon(NOTCH).wkt).tolist() == np.array(NOTCH, float).tolist()
    assert polygon_from_wkt("MULTIPOLYGON (((0 0, 1 0, 0 1, 0 0)))").shape == (3, 2)
    assert polygon_from_wkt("POLYGON Z ((0 0 1, 1 0 1, 0 1 1, 0 0 1))").shape == (3, 3)
    with pytest.raises(InvalidPolygonError, match="hole"):
        polygon_from_wkt("POLYGON ((0 0, 9 0, 9 9, 0 9, 0 0), (1 1, 2 1, 2 2, 1 1))")
    with pytest.raises(InvalidPolygonError, match="POLYGON"):
        polygon_from_wkt("LINESTRING (0 0, 1 1)")
    geom = {"type": "Polygon", "coordinates": [RING]}
    feature = {"type": "Feature", "properties": {}, "geometry": geom}
    for obj in (geom, feature, {"type": "FeatureCollection", "features": [feature]}):
        assert polygon_from_geojson(obj).tolist() == np.array(NOTCH, float).tolist()
    with pytest.raises(InvalidPolygonError, match="2 items"):
        polygon_from_geojson({"type": "FeatureCollection", "features": [feature, feature]})


def test_read_polygon_files(tmp_path):
    (tmp_path / "a.wkt").write_text(shapely.Polygon(NOTCH).wkt + "\n")
    (tmp_path / "b.geojson").write_text(
        json.dumps(shapely.geometry.mapping(shapely.Polygon(NOTCH)))
    )
    for name in ("a.wkt", "b.geojson"):
        assert read_polygon(tmp_path / name).tolist() == np.array(NOTCH, float).tolist()
    holed = {"type": "Polygon", "coordinates": [RING, [[1, 1], [2, 1], [1, 2], [1, 1]]]}
    (tmp_path / "h.geojson").write_text(json.dumps(holed))
    with pytest.raises(InvalidPolygonError, match="read_rings"):
        read_polygon(tmp_path / "h.geojson")


def test_cli_solves_geojson(tmp_path):
    path = tmp_path / "notch.geojson"
    path.write_text(
        json.dumps({"type": "Feature", "geometry": shapely.Polygon(NOTCH).__geo_interface__})
    )
    res = CliRunner().invoke(main, ["solve", str(path), "--json", "-m", "memo"])
    assert res.exit_code == 0, res.output
    out = json.loads(res.stdout)
    assert math.isclose(out["weight"], optri.triangulate(NOTCH, method="memo").weight)


@pytest.mark.parametrize(
    "text, suffix",
    [("0,0\n1,1\n1,0\n0,1\n", ".csv"), ("POLYGON ((0 0, 2 2, 2 0, 0 2, 0 0))", ".wkt")],
)
def test_cli_bow_tie_exits_2_with_one_line(tmp_path, text, suffix):
    path = tmp_path / f"bowtie{suffix}"
    path.write_text(text)
    res = CliRunner().invoke(main, ["solve", str(path)])
    assert res.exit_code == 2
    lines = res.stderr.strip().splitlines() if hasattr(res, "stderr") else res.output.splitlines()
    assert len(lines) == 1 and "edges 0-1 and 2-3 cross" in lines[0]
