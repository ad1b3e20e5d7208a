"""Numerics over the whole float range, centred geometry, and the one input validator."""

from __future__ import annotations

import json
import math
from fractions import Fraction

import numpy as np
import pytest
from click.testing import CliRunner

import optri
from batch_polys import write_feature_collection, write_ndjson
from optri import InvalidPolygonError, NoTriangulationError
from optri.batch import iter_records
from optri.batch.records import Item, solve_item
from optri.cli import main
from optri.polygon import normalize_vertices, signed_area
from simple_polys import random_star

SQUARE = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
PY_ENGINES = ["memo", "table", "brute"]


# --- centred geometry: check() at projected-coordinate offsets -------------------------


@pytest.mark.parametrize("offset", [(500000.0, 4600000.0), (1e7, -1e7), (-3e6, 9.9e6)])
def test_check_holds_at_utm_offsets(offset):
    # 40 random simple polygons of a few hundred metres at UTM-like offsets: every
    # result must pass check() (the raw shoelace cancelled catastrophically here)
    for seed in range(40):
        pts = random_star(8 + seed % 9, seed) * 300.0 + np.array(offset)
        t = optri.triangulate(pts, method="table")
        t.check()
        assert t.stats["zero_area_triangles"] == 0


def test_check_holds_with_the_compiled_engine_at_offsets():
    pts = random_star(200, 7) * 150.0 + np.array([500000.0, 4600000.0])
    optri.triangulate(pts, method="fast").check()


def test_signed_area_is_accurate_at_offsets():
    for seed in range(20):
        pts = random_star(12, seed) * 300 + np.array([500000.0, 4600000.0])
        x, y = ([Fraction(v) for v in col] for col in pts.T)
        n = len(pts)
        exact = sum(x[i] * y[(i + 1) % n] - x[(i + 1) % n] * y[i] for i in range(n)) / 2
        assert signed_area(pts) == pytest.approx(float(exact), rel=1e-12)


def test_check_still_catches_a_clockwise_triangle():
    t = optri.triangulate(random_star(10, 3) + 5e6, method="table")
    t.triangles = t.triangles[:, [0, 2, 1]]
    with pytest.raises(AssertionError, match="clockwise"):
        t.check()


# --- the whole float range ----------------------------------------------------------------


@pytest.mark.parametrize("method", [*PY_ENGINES, "fast"])
@pytest.mark.parametrize("scale", [1e154, 1e200, 1e-154, 1e-308, 2.0**-1060])
def test_scaled_square_gets_its_finite_answer(scale, method):
    t = optri.triangulate(SQUARE * scale, "perimeter", method=method)
    assert t.weight == pytest.approx((4 + 2 * math.sqrt(2)) * scale, rel=1e-12)
    t.check()
    angle = optri.triangulate(SQUARE * scale, "max_angle", "max", method=method)
    assert angle.weight == pytest.approx(math.pi / 2, rel=1e-12)
    ratio = optri.triangulate(SQUARE * scale, "aspect_ratio", method=method)
    assert ratio.weight == pytest.approx(2 * (1 + math.sqrt(2)) / 2, rel=1e-12)  # 2 x R/2r


@pytest.mark.parametrize("method", [*PY_ENGINES, "fast"])
def test_square_at_1e308(method):
    big = SQUARE * 1e308
    assert optri.as_polygon(big).convex  # not "collinear"
    angle = optri.triangulate(big, "max_angle", "max", method=method)
    assert angle.weight == pytest.approx(math.pi / 2)
    with pytest.raises(NoTriangulationError, match="overflow float64"):
        optri.triangulate(big, "perimeter", method=method)  # 6.8e308: refused, never inf
    with pytest.raises(NoTriangulationError, match="not a finite number|overflow"):
        optri.triangulate(big, "area", method=method)


def test_infinite_weights_are_refused_not_returned():
    def forbid(i, k, j):
        return math.inf

    for method in PY_ENGINES:
        with pytest.raises(NoTriangulationError):
            optri.triangulate(SQUARE, forbid, method=method)


@pytest.mark.parametrize(
    "data, words",
    [
        ([[0, 0], [10**400, 0], [0, 1]], "too large for float64"),
        ([[0, 0], [1, 0], [0, 10**309]], "too large for float64"),
        (np.array([[0, 0], [1, 0], [0, 1]], dtype=complex), "complex"),
        ([[0, 0], [1 + 2j, 0], [0, 1]], "complex"),
        (np.array([[0, 0], [1, 0], [0, "x"]], dtype=object), "not a real number"),
        (np.array([[0, 0], [1, 0], [0, None]], dtype=object), "not a real number"),
        (np.array([[True, False], [False, True], [True, True]]), "booleans"),
        ([[0, 0], [1, 0], [0, 1e400]], "non-finite"),
    ],
)
def test_unusable_numbers_are_refused(data, words):
    with pytest.raises(InvalidPolygonError, match=words):
        optri.triangulate(data)


def test_big_but_finite_python_ints_are_read():
    t = optri.triangulate([[0, 0], [10**300, 0], [10**300, 10**300], [0, 10**300]], "max_angle")
    assert t.weight == pytest.approx(math.pi)  # two right angles


# --- 3-D: planarity and simplicity ------------------------------------------------------


def _tilt(points2: np.ndarray, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    q, _ = np.linalg.qr(rng.standard_normal((3, 3)))
    return np.column_stack((points2, np.zeros(len(points2)))) @ q.T + rng.uniform(-5, 5, 3)


@pytest.mark.parametrize("seed", range(4))
def test_planar_3d_bow_tie_is_refused(seed):
    bow = np.array([[0.0, 0.0], [2.0, 2.0], [2.0, 0.0], [0.0, 2.0]])
    with pytest.raises(InvalidPolygonError, match="not simple"):
        optri.triangulate(_tilt(bow, seed))
    with pytest.raises(InvalidPolygonError, match="not simple"):
        optri.triangulate(np.column_stack((bow, np.ones(4))))


def test_planar_3d_polygon_equals_its_2d_self():
    notch = np.array([[0, 0], [3, 0], [3, 3], [2, 1], [1, 3], [0, 3]], float)
    for seed in range(3):
        t3 = optri.triangulate(_tilt(notch, seed), method="table")
        t2 = optri.triangulate(notch, method="table")
        assert t3.weight == pytest.approx(t2.weight, rel=1e-12)
        assert sorted(map(sorted, t3.triangles.tolist())) == sorted(
            map(sorted, t2.triangles.tolist())
        )


def test_skew_3d_polygon_is_still_a_surface():
    skew = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 1], [0, 1, 0]], float)
    assert optri.triangulate(skew).n == 4


# --- one validator: closing vertices, everywhere ------------------------------------------


PENTAGON = [[0, 0], [4, 0], [5, 3], [2, 5], [-1, 3]]


@pytest.mark.parametrize("closing", [0, 1, 2, 5])
def test_closing_vertices_dropped_by_the_api(closing):
    ring = PENTAGON + [PENTAGON[0]] * closing
    assert normalize_vertices(ring).tolist() == np.array(PENTAGON, float).tolist()
    t = optri.triangulate(ring)
    assert t.n == 5 and t.weight == pytest.approx(optri.triangulate(PENTAGON).weight)


@pytest.mark.parametrize("closing", [1, 2, 3])
def test_closing_vertices_dropped_by_batch_and_cli(tmp_path, closing):
    ring = PENTAGON + [PENTAGON[0]] * closing
    want = optri.triangulate(PENTAGON)
    rec = solve_item(Item("r", ring))
    assert rec["status"] == "ok" and rec["n"] == 5, rec
    src = write_ndjson(tmp_path / "in.ndjson", [{"id": "r", "coordinates": ring}])
    optri.batch(src, tmp_path / "out.ndjson", workers=1)
    (got,) = iter_records(tmp_path / "out.ndjson")
    assert got["status"] == "ok" and got["cost"] == pytest.approx(want.weight), got
    layer = write_feature_collection(tmp_path / "in.geojson", [{"id": 1, "coordinates": ring}])
    optri.batch(layer, tmp_path / "out2.ndjson", workers=1)
    (got,) = iter_records(tmp_path / "out2.ndjson")
    assert got["status"] == "ok" and got["n"] == 5, got
    path = tmp_path / "ring.geojson"
    path.write_text(json.dumps({"type": "Polygon", "coordinates": [ring]}))
    res = CliRunner().invoke(main, ["solve", str(path), "--json"])
    assert res.exit_code == 0, res.output
    assert json.loads(res.stdout)["n"] == 5
    assert json.loads(res.stdout)["weight"] == pytest.approx(want.weight)
