"""The columnar path: ragged arrays in, columns out, equal to optri.triangulate row by row."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import optri
from optri import config
from optri.batch.columns import (
    ERROR,
    OK,
    ragged_from_arrow,
    ragged_from_shapely,
    solve_ragged,
    triangle_geojson,
    triangle_geometries,
    triangle_wkb,
)
from optri.batch.each import SolveOptions, one_line
from optri.batch.solver import solve_polygons
from simple_polys import simple_polygons, star_polygons
from strategies import convex_polygons

shapely = pytest.importorskip("shapely")
from domain_polys import small_domains  # noqa: E402  # needs shapely

RINGS = Path(__file__).parent / "data" / "rings"
SQUARE = [[0, 0], [1, 0], [1, 1], [0, 1]]
BOWTIE = [[0, 0], [2, 2], [2, 0], [0, 2]]

#: (weight, objective): the kernel's sum and max, and a pair only the per-polygon path takes.
OPTIONS = [
    ("perimeter", "sum"),
    ("area", "max"),
    (("max_angle", "perimeter"), ("max", "sum")),
]


def bits(cost: object) -> object:
    if isinstance(cost, tuple):
        return tuple(float(c).hex() for c in cost)
    return float(cost).hex()  # type: ignore[arg-type]


def parts_of(geom):
    """The (ring array | (exterior, holes)) inputs triangulate gets for each part of a row."""
    polys = list(geom.geoms) if geom.geom_type == "MultiPolygon" else [geom]
    out = []
    for p in polys:
        ext = np.asarray(p.exterior.coords)
        holes = [np.asarray(h.coords) for h in p.interiors]
        out.append((ext, holes) if holes else ext)
    return out


def expected_row(geom, weight, objective):
    """``(results or error, combined cost)`` of a row by optri.triangulate, part by part."""
    results = []
    for k, part in enumerate(parts_of(geom)):
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                results.append(optri.triangulate(part, weight=weight, objective=objective))
            results[-1].stats["noted"] = [str(w.message) for w in caught]
        except optri.OptriError as exc:
            many = geom.geom_type == "MultiPolygon" and len(geom.geoms) > 1
            return f"part {k}: {exc}" if many else str(exc), None
    obj = optri.objective.as_objective(objective)
    costs = [r.weight for r in results]
    if not obj.is_lex:
        total = costs[0]
        for c in costs[1:]:
            total = total + c if obj.components[0] == "sum" else max(total, c)
        return results, total
    folded = list(costs[0])
    for c in costs[1:]:
        folded = [
            a + b if rule == "sum" else max(a, b) for a, b, rule in zip(folded, c, obj.components)
        ]
    return results, tuple(folded)


def check_rows(geoms, weight="perimeter", objective="sum"):
    """solve_ragged on ``geoms`` equals optri.triangulate row by row; geometry valid."""
    ragged = ragged_from_shapely(geoms)
    solved = solve_ragged(ragged, SolveOptions(weight, objective))
    assert len(solved) == len(geoms)
    for i, geom in enumerate(geoms):
        if geom is None or not hasattr(geom, "geom_type") or geom.is_empty:
            assert solved.status[i] == ERROR and solved.reason[i]
            continue
        if geom.geom_type not in ("Polygon", "MultiPolygon"):
            assert solved.status[i] == ERROR and "is not a Polygon" in solved.reason[i]
            continue
        results, cost = expected_row(geom, weight, objective)
        if isinstance(results, str):
            assert solved.status[i] == ERROR, i
            assert solved.reason[i] == one_line(results)
            assert np.isnan(solved.cost[i]).all() and solved.cost_of(i) is None
            continue
        assert solved.status[i] == OK, solved.reason[i]
        assert bits(solved.cost_of(i)) == bits(cost)
        lo, hi = solved.triangle_offsets[i], solved.triangle_offsets[i + 1]
        want = np.concatenate([r.vertices[r.triangles] for r in results])
        width = want.shape[2]
        assert np.array_equal(ragged.coords[solved.triangles[lo:hi]][..., :width], want)
        assert solved.n[i] == sum(r.n for r in results)
        notes = list(dict.fromkeys(w for r in results for w in r.stats["noted"]))
        assert solved.reason[i] == (one_line("warning: " + "; ".join(notes)) if notes else None)
        shift = np.cumsum([0] + [r.n for r in results[:-1]])
        local = np.concatenate([r.triangles + k for r, k in zip(results, shift)])
        assert np.array_equal(solved.local_triangles()[lo:hi], local)
        assert np.array_equal(solved.row_vertices(i), np.concatenate([r.vertices for r in results]))
        lazy = solved.triangulation(i)
        for got, ref in zip(lazy if isinstance(lazy, list) else [lazy], results):
            assert bits(got.weight) == bits(ref.weight)
            assert np.array_equal(got.triangles, ref.triangles)
            assert np.array_equal(got.vertices, ref.vertices)
            assert got.orientation == ref.orientation
    check_geometry(ragged, solved, geoms)
    return ragged, solved


def check_geometry(ragged, solved, geoms):
    """Valid GeometryCollections (None for errors); exploded rows n + 2h - 2 per part."""
    coll, row = triangle_geometries(ragged, solved)
    assert row.tolist() == list(range(len(geoms)))
    tris, owner = triangle_geometries(ragged, solved, explode=True)
    assert shapely.is_valid(tris).all()
    assert all(g.geom_type == "Polygon" for g in tris)
    counts = np.bincount(owner, minlength=len(geoms))
    for i, g in enumerate(coll):
        if solved.status[i] != OK:
            assert g is None and counts[i] == 0
            continue
        assert g.geom_type == "GeometryCollection" and shapely.is_valid(g)
        if solved.reason[i] is not None:
            continue  # a warned row may leave a zero-area triangle out
        polys = list(geoms[i].geoms) if geoms[i].geom_type == "MultiPolygon" else [geoms[i]]
        rings = [[p.exterior, *p.interiors] for p in polys]
        expect = sum(sum(len(r.coords) - 1 for r in rs) + 2 * len(rs) - 4 for rs in rings)
        assert counts[i] == len(g.geoms) == expect
        assert g.area == pytest.approx(sum(p.area for p in polys), rel=1e-9)
    text, _ = triangle_geojson(ragged, solved)
    assert [t is None for t in text] == (solved.status != OK).tolist()
    assert shapely.equals_exact(shapely.from_geojson(text[solved.ok]), coll[solved.ok], 0).all()
    wkb, row = triangle_wkb(ragged, solved)
    back = shapely.from_wkb(wkb)
    assert np.array_equal(shapely.is_missing(back), solved.status != OK)
    assert shapely.equals_exact(back[solved.ok], coll[solved.ok], tolerance=0).all()


def _part(draw):
    kind = draw(st.sampled_from(["convex", "star", "simple", "holed", "bowtie"]))
    if kind == "holed":
        ext, holes = draw(small_domains(n_max=11))
        return shapely.Polygon(ext, holes)
    if kind == "bowtie":
        return shapely.Polygon(BOWTIE)
    strategy = {"convex": convex_polygons(3, 9), "star": star_polygons(4, 9)}.get(
        kind, simple_polygons(4, 8)
    )
    return shapely.Polygon(draw(strategy))


@st.composite
def rows(draw):
    kind = draw(st.sampled_from(["polygon", "multi", "none", "empty", "point"]))
    if kind == "none":
        return None
    if kind == "empty":
        return shapely.from_wkt(draw(st.sampled_from(["POLYGON EMPTY", "MULTIPOLYGON EMPTY"])))
    if kind == "point":
        return shapely.Point(0, 0)
    if kind == "polygon":
        return _part(draw)
    return shapely.MultiPolygon([_part(draw) for _ in range(draw(st.integers(1, 3)))])


@pytest.mark.parametrize("weight, objective", OPTIONS)
@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(layer=st.lists(rows(), min_size=1, max_size=6))
def test_equal_to_triangulate_row_by_row(layer, weight, objective):
    check_rows(layer, weight, objective)


def test_a_layer_of_only_bad_rows():
    geoms = [None, shapely.Point(1, 2), shapely.from_wkt("POLYGON EMPTY"), "text"]
    ragged, solved = check_rows(geoms[:3])
    assert solved.triangles.shape == (0, 3) and solved.n.tolist() == [0, 0, 0]
    r = ragged_from_shapely(geoms)
    assert r.reason[3] == "expected a shapely geometry, got str"
    assert r.reason[1] == "geometry type 'Point' is not a Polygon or MultiPolygon"
    assert isinstance(solve_ragged(r, SolveOptions()).error(3), optri.InvalidPolygonError)


def test_a_failing_part_fails_its_row_and_is_named():
    geoms = [shapely.MultiPolygon([shapely.Polygon(SQUARE), shapely.Polygon(BOWTIE)])]
    _, solved = check_rows(geoms)
    assert solved.reason[0].startswith("part 1: polygon is not simple")
    err = solved.error(0)
    assert isinstance(err, optri.InvalidPolygonError) and str(err) == solved.reason[0]
    with pytest.raises(optri.InvalidPolygonError, match="part 1"):
        solved.triangulation(0)
    assert solved.result(0) is err


def _natural_earth():
    rings = {
        r["name"]: r["ring"]
        for r in json.loads((RINGS / "natural_earth_countries_states.json").read_text())
    }
    zaf = shapely.get_geometry(
        shapely.from_geojson((RINGS / "natural_earth_zaf.geojson").read_text()), 0
    )
    alaska = shapely.MultiPolygon(
        [shapely.Polygon(v) for k, v in rings.items() if k.startswith("USA/AK")]
    )
    return [
        zaf,
        alaska,
        shapely.Polygon(rings["AFG"]),
        None,
        shapely.MultiPolygon([zaf, shapely.Polygon(rings["JAM"])]),
    ]


@pytest.mark.parametrize("weight, objective", OPTIONS[:2])
def test_natural_earth_countries(weight, objective):
    geoms = _natural_earth()
    assert len(geoms[0].interiors) == 1 and len(geoms[1].geoms) == 7  # Lesotho; Alaska's parts
    _, solved = check_rows(geoms, weight, objective)
    assert solved.status.tolist() == [OK, OK, OK, ERROR, OK]


def test_multipolygon_cost_combines_its_parts_by_the_objective():
    alaska = _natural_earth()[1]
    parts = [
        optri.triangulate(np.asarray(p.exterior.coords), objective="max") for p in alaska.geoms
    ]
    _, solved = check_rows([alaska], objective="max")
    assert solved.cost[0] == max(p.weight for p in parts)
    _, solved = check_rows([alaska])
    sums = [optri.triangulate(np.asarray(p.exterior.coords)).weight for p in alaska.geoms]
    assert solved.cost[0] == pytest.approx(sum(sums), rel=1e-15) and solved.cost[0] > max(sums)


def test_z_is_kept_and_measured():
    flat = shapely.Polygon([[0, 0], [4, 0], [4, 3], [0, 3]])
    tilted = shapely.Polygon([[0, 0, 0], [4, 0, 4], [4, 3, 4], [1, 4, 1], [0, 3, 0]])
    multi_z = shapely.MultiPolygon([tilted, shapely.Polygon([[9, 9, 1], [10, 9, 1], [9, 10, 2]])])
    court = shapely.Polygon(shapely.box(0, 0, 4, 4).exterior, [shapely.box(1, 1, 2, 2).exterior])
    geoms = [flat, tilted, None, multi_z, court]  # a 2-D holed row goes part by part
    ragged, solved = check_rows(geoms)
    assert ragged.has_z and ragged.row_z.tolist() == [False, True, False, True, False]
    assert solved.status.tolist() == [OK, OK, ERROR, OK, OK]
    assert solved.cost[1] == optri.triangulate(np.asarray(tilted.exterior.coords)).weight
    coll, _ = triangle_geometries(ragged, solved)
    assert shapely.has_z(coll[[0, 1, 3, 4]]).tolist() == [False, True, True, False]
    z = shapely.get_coordinates(coll[1], include_z=True)[:, 2]
    assert set(z.tolist()) <= {0.0, 1.0, 4.0}
    wkb, _ = triangle_wkb(ragged, solved, explode=True)
    assert shapely.has_z(shapely.from_wkb(wkb)).tolist() == [False] * 2 + [True] * 7 + [False] * 8


def test_an_upright_polygon_draws_no_flat_triangle():
    wall = shapely.Polygon([[0, 0, 0], [4, 0, 0], [4, 0, 3], [0, 0, 3]])  # a wall: flat in x-y
    roof = shapely.Polygon([[0, 0, 3], [4, 0, 3], [4, 2, 4], [0, 2, 4]])
    ragged = ragged_from_shapely([wall, roof])
    solved = solve_ragged(ragged, SolveOptions())
    assert solved.status.tolist() == [OK, OK] and len(solved.triangles) == 4
    assert solved.cost[0] == optri.triangulate(np.asarray(wall.exterior.coords)).weight
    coll, _ = triangle_geometries(ragged, solved)
    assert shapely.is_valid(coll).all() and coll[0].is_empty and len(coll[1].geoms) == 2
    tris, row = triangle_geometries(ragged, solved, explode=True)
    assert row.tolist() == [1, 1] and shapely.is_valid(tris).all()
    wkb, _ = triangle_wkb(ragged, solved)
    assert shapely.from_wkb(wkb[0]).is_empty


def test_chunks_and_progress(monkeypatch):
    monkeypatch.setattr(config, "MANY_KERNEL_CHUNK", 2)
    geoms = _natural_earth() + [shapely.Polygon(BOWTIE), shapely.box(0, 0, 2, 1)]
    seen = []
    ragged = ragged_from_shapely(geoms)
    chunked = solve_ragged(ragged, SolveOptions(), progress=seen.append)
    monkeypatch.setattr(config, "MANY_KERNEL_CHUNK", 8192)
    whole = solve_ragged(ragged, SolveOptions())
    assert seen[-1] == len(ragged.part_offsets) - 1 and seen == sorted(seen) and len(seen) > 3
    assert np.array_equal(chunked.triangles, whole.triangles)
    assert [bits(c) for c in chunked.cost[chunked.ok]] == [bits(c) for c in whole.cost[whole.ok]]
    assert chunked.reason.tolist() == whole.reason.tolist()
    assert (chunked.seconds >= 0).all() and chunked.seconds[chunked.ok].sum() > 0


def noisy(vertices, i, k, j):
    """A user weight that warns (only for triangles at vertex 0): 1 per triangle."""
    if i == 0:
        warnings.warn(f"noisy at {len(vertices)}", UserWarning, stacklevel=1)
    return 1.0


def test_warnings_of_ok_rows_are_their_reason():
    tri, square = shapely.Polygon([[0, 0], [1, 0], [0, 1]]), shapely.box(5, 5, 6, 6)
    geoms = [tri, shapely.MultiPolygon([tri, square, tri]), shapely.box(0, 0, 2, 1)]
    _, solved = check_rows(geoms, weight=noisy)
    assert solved.status.tolist() == [OK] * 3 and solved.cost.tolist() == [1.0, 4.0, 2.0]
    assert solved.reason[0] == "warning: noisy at 3"
    assert solved.reason[1] == "warning: noisy at 3; noisy at 4"  # each note once, in order


def test_from_arrow_wkb_equals_from_shapely():
    pa = pytest.importorskip("pyarrow")
    geoms = _natural_earth() + [shapely.Point(0, 0)]
    column = pa.array([None if g is None else shapely.to_wkb(g) for g in geoms] + [b"\x00junk"])
    got = ragged_from_arrow(pa.chunked_array([column]))
    want = ragged_from_shapely(geoms + [None])
    for name in ("coords", "ring_offsets", "part_offsets", "row_offsets", "row_z"):
        assert np.array_equal(getattr(got, name), getattr(want, name)), name
    assert got.reason.tolist() == want.reason.tolist()[:-1] + ["unreadable WKB"]
    with pytest.raises(optri.InvalidPolygonError, match="WKB"):
        ragged_from_arrow(pa.array([1, 2]))


def test_from_a_layer_read_by_pyogrio(tmp_path):
    pyogrio = pytest.importorskip("pyogrio")
    gpd = pytest.importorskip("geopandas")
    geoms = _natural_earth()
    gpd.GeoDataFrame({"k": range(len(geoms))}, geometry=geoms, crs="EPSG:4326").to_file(
        tmp_path / "world.gpkg"
    )
    meta, table = pyogrio.read_arrow(tmp_path / "world.gpkg")
    got = ragged_from_arrow(table.column(meta["geometry_name"] or "wkb_geometry"))
    want = ragged_from_shapely(geoms)
    assert np.array_equal(got.coords, want.coords) and got.reason.tolist() == want.reason.tolist()
    assert np.array_equal(got.part_offsets, want.part_offsets)
    assert solve_ragged(got, SolveOptions()).status.tolist() == [OK, OK, OK, ERROR, OK]


def test_project_equals_the_per_polygon_path():
    pytest.importorskip("pyproj")
    ring = [[13.40, 52.50], [13.401, 52.50], [13.4012, 52.5007], [13.4004, 52.5011]]
    hole = [[13.4005, 52.5002], [13.4006, 52.5004], [13.4008, 52.5003]]
    geoms = [shapely.Polygon(ring), shapely.MultiPolygon([shapely.Polygon(ring, [hole])])]
    options = SolveOptions(project="EPSG:4326")
    solved = solve_ragged(ragged_from_shapely(geoms), options)
    want = solve_polygons([np.asarray(ring), (np.asarray(ring), [np.asarray(hole)])], options)
    assert [bits(c) for c in solved.cost] == [bits(w.weight) for w in want]
    assert solved.triangulation(1).vertices.tolist() == want[1].vertices.tolist()
    assert 100 < solved.cost[0]  # metres, not degrees


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(layer=st.lists(rows(), min_size=1, max_size=8), z=st.booleans())
def test_ragged_arrays_are_shapelys(layer, z):
    """ragged_from_shapely lays rows out as shapely.to_ragged_array does (bad rows left out)."""
    if z:  # some rows get a Z coordinate
        layer = [
            shapely.force_3d(g, 7.0) if g is not None and k % 2 else g for k, g in enumerate(layer)
        ]
    ragged = ragged_from_shapely(layer)
    good = [g for g in layer if g is not None and g.geom_type in ("Polygon", "MultiPolygon")]
    good = [g for g in good if not g.is_empty]
    assert len(ragged) == len(layer)
    assert [r is None for r in ragged.reason] == [any(g is x for x in good) for g in layer]
    if not good:
        assert ragged.coords.shape[0] == 0 and ragged.row_offsets[-1] == 0
        return
    multi = [shapely.MultiPolygon([g]) if g.geom_type == "Polygon" else g for g in good]
    _, coords, (rings, parts, rows_) = shapely.to_ragged_array(multi)
    assert np.array_equal(ragged.coords, coords, equal_nan=True)
    assert ragged.ring_offsets.tolist() == rings.tolist()
    assert ragged.part_offsets.tolist() == parts.tolist()
    kept = ragged.row_offsets[
        np.r_[[i for i, r in enumerate(ragged.reason) if r is None], len(layer)]
    ]
    assert np.diff(kept).tolist() == np.diff(rows_).tolist()
    assert ragged.has_z == any(shapely.has_z(g) for g in good)
    assert ragged.row_z.tolist() == [
        r is None and bool(shapely.has_z(g)) for g, r in zip(layer, ragged.reason)
    ]
