"""Polygons with holes: invariants on random domains up to N = 60, limits, inputs, errors."""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

shapely = pytest.importorskip("shapely")
pytest.importorskip("scipy")

import optri  # noqa: E402
from optri import config  # noqa: E402
from optri.domains import as_domain, random_domain, triangulate_domain  # noqa: E402
from optri.errors import (  # noqa: E402
    EngineUnavailableError,
    InvalidPolygonError,
    WeightError,
)

CASES = [
    (n, h, seed)
    for n, h in ((14, 1), (24, 2), (40, 3), (60, 1), (60, 3), (60, 10))
    for seed in (0, 1)
]


def _tiles_exactly(tri, ext, holes):
    """Triangle count, areas, union equal to the polygon, no triangle in a hole (shapely)."""
    n, h = tri.n, len(holes)
    assert tri.triangles.shape == (n + 2 * h - 2, 3)
    poly = shapely.Polygon(ext, holes)
    pieces = [shapely.Polygon(tri.vertices[t]) for t in tri.triangles]
    assert all(p.area > 0 and p.exterior.is_ccw for p in pieces)
    assert math.isclose(sum(p.area for p in pieces), poly.area, rel_tol=1e-9)
    union = shapely.union_all(pieces)
    assert union.symmetric_difference(poly).area <= 1e-9 * poly.area
    for hole in holes:
        inner = shapely.Polygon(hole)
        assert all(p.intersection(inner).area <= 1e-12 * poly.area for p in pieces)


@pytest.mark.parametrize(("n", "h", "seed"), CASES)
def test_random_domains_tile_exactly(n, h, seed):
    ext, holes = random_domain(n, h, seed=seed)
    tri = optri.triangulate((ext, holes), weight="diagonal")
    tri.check()
    assert tri.optimality == "proven" and tri.gap == 0.0 and tri.bound == tri.weight
    assert tri.holes == h and tri.rings == (len(ext), *map(len, holes))
    _tiles_exactly(tri, ext, holes)
    assert len(tri.diagonals) == n + 3 * h - 3


@pytest.mark.parametrize("seed", range(3))
def test_decomposition_agrees_with_the_whole_program(seed):
    ext, holes = random_domain(36, 2, seed=seed)
    a = optri.triangulate((ext, holes), weight="perimeter", method="auto")
    b = optri.triangulate((ext, holes), weight="perimeter", method="ip")
    assert math.isclose(a.weight, b.weight, rel_tol=1e-9)


@pytest.mark.parametrize(("weight", "objective"), [("perimeter", "sum"), ("max_angle", "max")])
def test_bridged_heuristic_is_labelled_and_bounded(weight, objective):
    ext, holes = random_domain(60, 3, seed=4)
    exact = optri.triangulate((ext, holes), weight=weight, objective=objective)
    heur = optri.triangulate((ext, holes), weight=weight, objective=objective, method="bridge")
    heur.check()
    assert "bridge" in heur.method
    assert heur.bound <= exact.weight + 1e-9 <= heur.weight + 2e-9
    assert heur.gap == pytest.approx((heur.weight - heur.bound) / abs(heur.weight))
    # proven only where the bound meets the value (the relaxation proves the bridges right)
    assert (heur.optimality == "proven") == (heur.gap <= 1e-9)
    if objective == "max":  # the edge floor is far below: labelled, with its gap
        assert heur.optimality == "heuristic" and heur.gap > 0.05


def _exact_and_time_limited(domain, monkeypatch, **options):
    """The domain's optimum, and its search cut short at once (checked valid)."""
    exact = optri.triangulate(domain, **options)
    monkeypatch.setattr(config, "DOMAIN_MIN_SOLVER_SECONDS", 1e-6)
    tri = optri.triangulate(domain, time_limit=1e-9, **options)
    tri.check()
    return exact, tri


def test_time_limit_gives_a_labelled_heuristic_with_a_valid_bound(monkeypatch):
    domain = random_domain(60, 10, seed=5)
    exact, tri = _exact_and_time_limited(domain, monkeypatch, weight="perimeter")
    assert tri.optimality == "heuristic" and 0 < tri.gap < 1
    assert math.isfinite(tri.bound) and tri.bound <= exact.weight + 1e-9 <= tri.weight + 2e-9
    assert tri.gap == pytest.approx((tri.weight - tri.bound) / tri.weight)


def test_time_limited_max_is_labelled_and_bounded(monkeypatch):
    domain = random_domain(60, 3, seed=6)
    options = {"weight": "max_angle", "objective": "max"}
    exact, tri = _exact_and_time_limited(domain, monkeypatch, **options)
    assert tri.optimality == "heuristic"
    assert math.isfinite(tri.bound) and tri.bound <= exact.weight <= tri.weight


def _spiked(n, h, seed):
    """``random_domain`` with its first hull vertex replaced by a long thin spike.

    The spike's tip sees only its two neighbours, so the chord across the spike's base
    crosses no diagonal: forced, it cuts the domain into a triangle (a DP block) and the
    rest (with the holes).
    """
    from scipy.spatial import ConvexHull

    ext, holes = random_domain(n, h, seed=seed)
    ext = np.asarray(ext, dtype=float)
    i = int(ConvexHull(ext).vertices[0])
    p, prev, nxt = ext[i], ext[i - 1], ext[(i + 1) % len(ext)]
    out = (p - ext.mean(axis=0)) / np.linalg.norm(p - ext.mean(axis=0))
    tip = p + 0.5 * np.ptp(ext, axis=0).max() * out
    spike = [p + 0.05 * (prev - p), tip, p + 0.05 * (nxt - p)]
    return np.concatenate([ext[:i], spike, ext[i + 1 :]]), holes


def test_time_limit_with_a_proven_block_beside_an_unproven_one_stays_heuristic(monkeypatch):
    # one block proven (the spike, by DP) does not make the whole proven
    exact, tri = _exact_and_time_limited(_spiked(60, 10, seed=2), monkeypatch, weight="perimeter")
    st = tri.stats
    assert st["forced_diagonals"] >= 1 and st["dp_blocks"] >= 1 and st["ip_blocks"] >= 1, st
    assert tri.optimality == "heuristic" and tri.gap > 0
    assert tri.bound <= exact.weight + 1e-9 <= tri.weight + 2e-9


def test_geometry_inputs_agree():
    ext = [[0, 0], [6, 0], [6, 5], [0, 5]]
    holes = [[[1, 1], [2, 1], [2, 2], [1, 2]], [[4, 3], [5, 3], [4.5, 4]]]
    ref = optri.triangulate((ext, holes))
    poly = shapely.Polygon(ext, holes)
    for src in (poly, (np.array(ext), [np.array(h) for h in holes]), as_domain(ext, holes)):
        t = optri.triangulate(src)
        assert t.weight == pytest.approx(ref.weight)
        assert t.triangles.tolist() == ref.triangles.tolist()
    assert optri.triangulate((ext, [])).holes == 0  # no holes: the simple-polygon DP


def test_files_with_holes(tmp_path):
    ext = [[0, 0], [6, 0], [6, 5], [0, 5]]
    hole = [[1, 1], [2, 1], [2, 2], [1, 2]]
    poly = shapely.Polygon(ext, [hole])
    ref = optri.triangulate(poly)
    (tmp_path / "a.wkt").write_text(poly.wkt)
    (tmp_path / "b.geojson").write_text(json.dumps(shapely.geometry.mapping(poly)))
    (tmp_path / "c.json").write_text(json.dumps({"exterior": ext, "holes": [hole]}))
    for name in ("a.wkt", "b.geojson", "c.json"):
        assert optri.triangulate(tmp_path / name).weight == pytest.approx(ref.weight)
        assert optri.io.read_rings(tmp_path / name)[1].shape == (4, 2)
        with pytest.raises(InvalidPolygonError, match="read_rings"):
            optri.io.read_polygon(tmp_path / name)


def test_vertex_numbering_and_orientation():
    ext = [[0, 0], [0, 5], [6, 5], [6, 0]]  # clockwise exterior
    hole = [[1, 1], [1, 2], [2, 2], [2, 1], [1, 1]]  # closing vertex dropped
    t = optri.triangulate((ext, [hole]))
    assert t.orientation == "cw" and t.n == 8 and t.rings == (4, 4)
    p = t.vertices
    a, b, c = (p[t.triangles[:, m]] for m in range(3))
    cross = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    assert (cross > 0).all()  # counter-clockwise triangles whatever the rings' orientation
    assert t.to_dict()["optimality"] == "proven" and t.to_dict()["rings"] == [4, 4]


@pytest.mark.parametrize(
    ("ext", "holes", "match"),
    [
        ([[0, 0], [4, 0], [0, 4]], [[[3, 3], [4, 3], [3, 4]]], "outside the exterior"),
        (
            [[0, 0], [9, 0], [9, 9], [0, 9]],
            [[[1, 1], [8, 1], [8, 8], [1, 8]], [[3, 3], [4, 3], [3, 4]]],
            "inside hole 1",
        ),
        ([[0, 0], [4, 0], [4, 4], [0, 4]], [[[1, 1], [5, 2], [1, 2]]], "meet"),
        ([[0, 0], [4, 0], [4, 4], [0, 4]], [[[0, 0], [2, 1], [1, 2]]], "repeats vertex 0"),
        ([[0, 0], [4, 0], [4, 4], [0, 4]], [[[1, 1], [2, 2], [1, 2], [2, 1]]], "not simple"),
        ([[0, 0], [4, 0], [4, 4], [0, 4]], [[[1, 1], [2, 2], [3, 3]]], "no area"),
        ([[0, 0], [4, 0], [4, 4], [0, 4]], [[[1, 1], [2, 2]]], "hole 1: a polygon needs"),
    ],
)
def test_bad_domains_are_refused_by_name(ext, holes, match):
    with pytest.raises(InvalidPolygonError, match=match):
        optri.triangulate((ext, holes))


def test_refusals_name_the_fix():
    ext, holes = random_domain(14, 1, seed=0)
    with pytest.raises(WeightError, match="must come last"):
        optri.triangulate((ext, holes), weight=("perimeter", "max_angle"), objective=("sum", "max"))
    with pytest.raises(WeightError, match="vertex values"):
        optri.triangulate((ext, holes), weight="product")
    with pytest.raises(EngineUnavailableError, match="auto, ip, bridge"):
        optri.triangulate((ext, holes), method="memo")
    with pytest.raises(InvalidPolygonError, match="optri.triangulate takes"):
        optri.count_triangulations(shapely.Polygon(ext, holes))


def test_nan_weight_is_named():
    ext, holes = random_domain(14, 1, seed=0)
    with pytest.raises(WeightError, match="NaN"):
        triangulate_domain(ext, holes, weight=lambda i, k, j: math.nan)


def test_check_catches_broken_triangulations():
    ext = [[0, 0], [3, 0], [3, 3], [0, 3]]
    hole = [[1, 1], [2, 1], [2, 2], [1, 2]]
    good = optri.triangulate((ext, [hole]), weight="diagonal")
    good.check()
    tris = good.triangles.copy()
    broken = [
        tris[:-1],  # a triangle missing
        np.concatenate([tris[:-1], tris[-1:, ::-1]]),  # one clockwise
        np.concatenate([tris[:-1], [[4, 5, 6]]]),  # one inside the hole
        np.concatenate([tris[:-2], [[0, 1, 5], [0, 5, 3]]]),  # overlapping
    ]
    for t in broken:
        bad = dataclasses.replace(good, triangles=np.asarray(t, dtype=np.int64), _recompute=None)
        with pytest.raises(AssertionError, match="Triangulation.check"):
            bad.check()
    # each fault named by its own check
    named = [
        (np.concatenate([tris[:-1], tris[:1]]), "used 2 times in the same direction"),
        (np.concatenate([tris[:-1], [[4, 5, 6]]]), "unmatched"),
    ]
    for t, fault in named:
        bad = dataclasses.replace(good, triangles=np.asarray(t, dtype=np.int64), _recompute=None)
        with pytest.raises(AssertionError, match=fault):
            bad.check()
    # the right triangles with the wrong cost: the recomputed cost differs
    wrong = dataclasses.replace(good, weight=good.weight * (1 + 1e-6))
    with pytest.raises(AssertionError, match="recomputed"):
        wrong.check()


def test_walk_chords_may_not_cross_a_bridge():
    from optri.domains import find_candidates
    from optri.domains.pieces import walk_mask
    from optri.domains.reduce import trace_walk

    d = as_domain([[0, 0], [3, 0], [3, 3], [0, 3]], [[[1, 1], [2, 1], [2, 2], [1, 2]]])
    cand = find_candidates(d)
    usable = np.zeros((d.n, d.n), dtype=bool)
    usable[cand.edges[:, 0], cand.edges[:, 1]] = True
    usable |= usable.T
    bridge = np.array([[0, 5]])  # (0, 0)-(2, 1); diagonal 1-4, (3, 0)-(1, 1), crosses it
    k = np.arange(d.n)
    walk = trace_walk(
        d.vertices, np.concatenate([np.column_stack((k, d.nxt)), bridge, bridge[:, ::-1]])
    )
    assert walk is not None and len(walk) == d.n + 2
    pos = {v: i for i, v in enumerate(walk) if v in (1, 4)}
    assert walk_mask(d.vertices, usable, walk)[pos[1], pos[4]]  # inside, if not for the bridge
    assert not walk_mask(d.vertices, usable, walk, bridge)[pos[1], pos[4]]
