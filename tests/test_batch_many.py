"""triangulate_many: geopandas in, geopandas out; sequences in, results out; bad rows as rows."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import optri
from simple_polys import simple_polygons, star_polygons
from strategies import convex_polygons

SQUARE = [[0, 0], [1, 0], [1, 1], [0, 1]]


def _same(result, polygon, **kw):
    expected = optri.triangulate(polygon, **kw)
    assert isinstance(result, optri.Triangulation), result
    assert result.weight == expected.weight
    assert result.triangles.tolist() == expected.triangles.tolist()


@settings(max_examples=40, deadline=None)
@given(
    st.lists(
        st.one_of(convex_polygons(3, 12), star_polygons(4, 10), simple_polygons(4, 9)),
        min_size=1,
        max_size=6,
    )
)
def test_equal_to_triangulate_polygon_by_polygon(polygons):
    results = optri.triangulate_many(polygons)
    assert len(results) == len(polygons)
    for res, poly in zip(results, polygons):
        _same(res, poly)


@pytest.mark.parametrize(
    "kw",
    [
        {"weight": "area", "objective": "max"},
        {"weight": ("max_angle", "perimeter"), "objective": ("max", "sum")},
    ],
)
def test_options_are_those_of_triangulate(kw):
    polys = [np.array(SQUARE, float), np.array([[0, 0], [4, 0], [5, 3], [2, 5], [-1, 3]], float)]
    for res, poly in zip(optri.triangulate_many(polys, **kw), polys):
        _same(res, poly, **kw)


BAD = {
    "none": None,
    "two_vertices": [[0, 0], [1, 1]],
    "ragged": [[0, 0], [1], [0, 1, 2]],
    "strings": [["a", "b"], [1, 0], [0, 1]],
    "nan": [[0, 0], [1, 0], [np.nan, 1]],
    "bowtie": [[0, 0], [2, 2], [2, 0], [0, 2]],
    "flat": np.zeros(6),
    "scalar": 5,
}


def test_bad_rows_become_error_results_never_exceptions():
    rows = [SQUARE, *BAD.values(), SQUARE]
    out = optri.triangulate_many(rows)
    assert isinstance(out[0], optri.Triangulation) and isinstance(out[-1], optri.Triangulation)
    for key, res in zip(BAD, out[1:-1]):
        assert isinstance(res, optri.OptriError), key
        assert str(res) and "\n" not in str(res)


def test_argument_errors_are_raised_up_front():
    with pytest.raises(optri.WeightError):
        optri.triangulate_many([SQUARE], weight="nope")
    with pytest.raises(optri.EngineUnavailableError):
        optri.triangulate_many([SQUARE], method="nope")
    with pytest.raises(optri.OptriError, match="needs a CRS"):
        optri.triangulate_many([SQUARE], project=True)


def test_a_raising_user_weight_fails_its_row_only():
    def weight(vertices, i, k, j):
        if len(vertices) == 5:
            raise KeyError("boom")
        return 1.0

    out = optri.triangulate_many([SQUARE, [[0, 0], [4, 0], [5, 3], [2, 5], [-1, 3]]], weight=weight)
    assert out[0].weight == 2.0
    assert isinstance(out[1], optri.WeightError)
    assert str(out[1]).startswith("weight 'custom' raised KeyError on triangle (")
    assert str(out[1]).endswith(": 'boom'")
    assert isinstance(out[1].__cause__, KeyError)


shapely = pytest.importorskip("shapely")
gpd = pytest.importorskip("geopandas")
pyproj = pytest.importorskip("pyproj")
pd = pytest.importorskip("pandas")


def _shapes():
    hole = shapely.Polygon(shapely.box(0, 0, 4, 4).exterior, [shapely.box(1, 1, 2, 2).exterior])
    return [
        shapely.Polygon(SQUARE),
        None,
        shapely.Point(0, 0),
        hole,
        shapely.MultiPolygon([shapely.box(0, 0, 1, 1), shapely.box(2, 0, 3, 1)]),
        shapely.MultiPolygon([shapely.box(5, 5, 6, 7)]),
        shapely.Polygon([[0, 0], [4, 0], [5, 3], [2, 5], [-1, 3]]),
        shapely.from_wkt("POLYGON EMPTY"),
    ]


STATUS = ["ok", "error", "error", "ok", "ok", "ok", "ok", "error"]


def _reference(shape):
    """optri.triangulate on each part: (cost combined by "sum", triangle count)."""
    parts = [optri.triangulate(p) for p in getattr(shape, "geoms", [shape])]
    return sum(p.weight for p in parts[1:]) + parts[0].weight, sum(len(p.triangles) for p in parts)


def test_geoseries_keeps_index_and_crs():
    index = ["b", "a", 7, "x", "y", "z", 3.5, "e"]
    s = gpd.GeoSeries(_shapes(), index=index, crs="EPSG:32633")
    out = optri.triangulate_many(s)
    assert isinstance(out, gpd.GeoDataFrame)
    assert list(out.index) == index and out.crs == s.crs
    assert list(out.columns) == ["status", "cost", "reason", "geometry"]
    assert out["status"].tolist() == STATUS
    for k, shape in enumerate(_shapes()):
        row = out.iloc[k]
        if STATUS[k] == "error":
            assert row.geometry is None and row.reason and np.isnan(row.cost)
            continue
        cost, count = _reference(shape)
        assert row.cost == cost and pd.isna(row.reason)
        assert row.geometry.geom_type == "GeometryCollection" and row.geometry.is_valid
        assert len(row.geometry.geoms) == count  # n - 2, n + 2h - 2 with holes, per part
        assert row.geometry.area == pytest.approx(shape.area)
    assert out.iloc[3].cost == optri.triangulate(_shapes()[3]).weight  # exterior, then the hole
    unit = optri.triangulate(shapely.box(0, 0, 1, 1)).weight
    assert out.iloc[4].cost == 2 * unit  # two unit squares: one MultiPolygon row, costs added


def test_geodataframe_keeps_its_attributes_and_renames_clashing_columns():
    shapes = _shapes()
    gdf = gpd.GeoDataFrame(
        {"name": [f"n{i}" for i in range(len(shapes))], "status": ["built"] * len(shapes)},
        geometry=shapes,
        index=range(100, 100 + len(shapes)),
        crs="EPSG:3857",
    )
    with pytest.warns(optri.errors.BatchWarning, match="'status' -> 'status_input'"):
        out = optri.triangulate_many(gdf)
    assert list(out.columns) == ["name", "status_input", "geometry", "status", "cost", "reason"]
    assert out["name"].tolist() == gdf["name"].tolist() and list(out.index) == list(gdf.index)
    assert out["status"].tolist() == STATUS and out.crs == gdf.crs
    assert out.geometry.name == "geometry" and gdf.geometry.iloc[0].geom_type == "Polygon"


def test_numpy_array_of_shapely_polygons():
    arr = np.array([shapely.Polygon(SQUARE), shapely.Polygon([[0, 0], [2, 0], [0, 2]])])
    out = optri.triangulate_many(arr)
    assert isinstance(out, list) and [r.n for r in out] == [4, 3]


def _hand(poly_lonlat):
    lon, lat = np.asarray(poly_lonlat).T
    aeqd = pyproj.CRS.from_proj4(
        f"+proj=aeqd +lat_0={float(lat.mean())!r} +lon_0={float(lon.mean())!r} +datum=WGS84"
    )
    x, y = pyproj.Transformer.from_crs("EPSG:4326", aeqd, always_xy=True).transform(lon, lat)
    return np.column_stack([x, y])


def test_project_measures_in_metres_and_keeps_input_coordinates():
    ring = [[13.40, 52.50], [13.401, 52.50], [13.4012, 52.5007], [13.4004, 52.5011]]
    s = gpd.GeoSeries([shapely.Polygon(ring)], crs="EPSG:4326")
    with pytest.warns(optri.errors.GeographicCRSWarning, match="EPSG:4326"):
        degrees = optri.triangulate_many(s)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        metres = optri.triangulate_many(s, project=True)
    hand = optri.triangulate(_hand(ring))
    assert metres.cost.iloc[0] == pytest.approx(hand.weight, rel=1e-9)
    assert 100 < metres.cost.iloc[0] and degrees.cost.iloc[0] < 0.01
    assert metres.geometry.iloc[0].area == pytest.approx(shapely.Polygon(ring).area)
    listed = optri.triangulate_many([ring], project=True, crs="EPSG:4326")
    assert listed[0].weight == pytest.approx(hand.weight, rel=1e-9)
    assert listed[0].vertices.tolist() == ring  # triangles index the input coordinates
    assert listed[0].triangles.tolist() == hand.triangles.tolist()


def test_project_centres_each_polygon_on_its_mean_position():
    # a polygon a degree across: the centre of the projection shows in the fifth digit
    ring = [[13.0, 52.0], [14.0, 52.1], [14.2, 52.9], [13.5, 53.2], [12.8, 52.6]]
    out = optri.triangulate_many([ring], project=True, crs="EPSG:4326")[0]
    assert out.weight == pytest.approx(optri.triangulate(_hand(ring)).weight, rel=1e-9)


def test_apply_triangulate_pattern_stops_at_the_first_bad_row():
    s = gpd.GeoSeries(_shapes()[:2])
    with pytest.raises(optri.OptriError):
        s.apply(optri.triangulate)  # the documented contrast: one bad row ends it
    assert optri.triangulate_many(s)["status"].tolist() == ["ok", "error"]


def test_explode_gives_one_row_per_triangle_with_its_source():
    gdf = gpd.GeoDataFrame(
        {"name": [f"n{i}" for i in range(len(_shapes()))]},
        geometry=_shapes(),
        index=range(10, 10 + len(_shapes())),
        crs="EPSG:3857",
    )
    whole = optri.triangulate_many(gdf)
    out = optri.triangulate_many(gdf, explode=True)
    per_row = [len(g.geoms) if g is not None else 1 for g in whole.geometry]
    assert out.index.tolist() == np.repeat(gdf.index, per_row).tolist()
    assert out["name"].tolist() == np.repeat(gdf["name"], per_row).tolist()
    ok = out["status"] == "ok"
    assert (out.geometry[ok].geom_type == "Polygon").all() and out.geometry[ok].is_valid.all()
    assert out.geometry[~ok].isna().all() and out.crs == gdf.crs
    assert out["cost"].tolist()[:2] == [whole["cost"].iloc[0]] * 2
    areas = out.geometry[ok].area.groupby(level=0).sum()
    assert np.allclose(areas, gdf.geometry[areas.index].area)
    with pytest.raises(optri.OptriError, match="explode"):
        optri.triangulate_many([SQUARE], explode=True)


def test_lexicographic_costs_are_tuples():
    s = gpd.GeoSeries([shapely.Polygon(SQUARE), None])
    out = optri.triangulate_many(s, weight=("max_angle", "perimeter"), objective=("max", "sum"))
    want = optri.triangulate(SQUARE, weight=("max_angle", "perimeter"), objective=("max", "sum"))
    assert out["cost"].iloc[0] == want.weight and out["cost"].iloc[1] is None
