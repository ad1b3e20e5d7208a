"""Zero-area patch faces: none where a patch avoids them, the fewest otherwise, in every mode.

Oracles: exact rational arithmetic (``fractions.Fraction``) for collinearity, brute
force over every triangulation of small polylines with collinear runs, and for
libigl's ``bump-domain.obj`` a counting argument (below) for its unavoidable two.
"""

from __future__ import annotations

import functools
import math
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st

from optri import fill_polyline
from optri.cli import main
from optri.holes.boundary import trace_loops
from optri.holes.liepa import liepa_objective
from optri.holes.mesh import HoleRecord, _Edges, fill_holes
from optri.holes.modes import degenerate_count
from optri.holes.search import fewest_degenerate
from optri.io.meshes import read_mesh

MESHES = Path(__file__).parent / "data" / "meshes"
MODES = ("exact", "liepa", "delaunay", "auto")


def collinear(P, tri):
    """Exact: the cross product of two sides, in rationals, is the zero vector."""
    a, b, c = ([Fraction(float(x)) for x in P[i]] for i in tri)
    u = [b[t] - a[t] for t in range(3)]
    v = [c[t] - a[t] for t in range(3)]
    return u[1] * v[2] == u[2] * v[1] and u[2] * v[0] == u[0] * v[2] and u[0] * v[1] == u[1] * v[0]


def exact_count(P, tris, flat=None):
    """Collinear triangles among ``tris``; ``flat``: a dict caching each triple's answer."""
    flat = {} if flat is None else flat
    count = 0
    for t in np.asarray(tris).tolist():
        key = tuple(sorted(t))
        if key not in flat:
            flat[key] = collinear(P, key)
        count += flat[key]
    return count


@functools.cache
def triangulations(i, j):
    """Every triangulation of polygon i..j (index triples, i < k < j)."""
    if j - i < 2:
        return [()]
    return [
        ((i, k, j), *left, *right)
        for k in range(i + 1, j)
        for left in triangulations(i, k)
        for right in triangulations(k, j)
    ]


def patches(n, forbidden):
    bad = {frozenset(p) for p in forbidden}
    for tris in triangulations(0, n - 1):
        edges = {frozenset(e) for a, b, c in tris for e in ((a, b), (b, c), (a, c))}
        if not edges & bad:
            yield np.array(tris, dtype=np.int64)


# --- the exact predicate --------------------------------------------------------------


coord = st.floats(-1e3, 1e3, allow_nan=False, allow_infinity=False)


@settings(max_examples=300, deadline=None)
@given(st.lists(coord, min_size=6, max_size=6), st.floats(-2, 3), st.integers(0, 3))
def test_exact_collinearity_is_not_fooled_by_rounding(ends, t, kind):
    """Points on or a hair off a line through two float points, judged against rationals."""
    a, b = np.array(ends[:3]), np.array(ends[3:])
    if kind == 0:
        c = a + t * (b - a)  # rounded: usually a hair off the line, sometimes on it
    elif kind == 1:
        c = 0.5 * (a + b)  # the midpoint, rounded
    elif kind == 2:
        c = b + (b - a)  # often exact
    else:
        c = np.array([b[0], b[1], np.nextafter(b[2], np.inf)]) + (b - a)
    P = np.ascontiguousarray([a, b, c])
    assert degenerate_count(P, np.array([[0, 1, 2]])) == int(collinear(P, (0, 1, 2)))


def test_exact_collinearity_near_misses():
    """A point 1 ulp off a line is not collinear; a float area test would say it is."""
    P = np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [3.0, 3.0, np.nextafter(3.0, 4.0)]])
    assert degenerate_count(P, np.array([[0, 1, 2]])) == 0 == int(collinear(P, (0, 1, 2)))
    P[2, 2] = 3.0
    assert degenerate_count(P, np.array([[0, 1, 2]])) == 1 == int(collinear(P, (0, 1, 2)))
    for axis in range(3):  # a right triangle in each coordinate plane: one projection is flat
        flat = np.roll(np.array([[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]), axis, axis=1)
        assert degenerate_count(np.ascontiguousarray(flat), np.array([[0, 1, 2]])) == 0
    tiny = np.array([[0.0, 0.0, 0.0], [1e-300, 0.0, 0.0], [0.0, 1e-300, 0.0]])
    assert degenerate_count(tiny, np.array([[0, 1, 2]])) == 0  # tiny but not flat


# --- brute force over small polylines with collinear runs -----------------------------


@st.composite
def runs(draw):
    """The border of a w x h lattice rectangle (collinear runs), a few points lifted."""
    w, h = draw(st.integers(1, 3)), draw(st.integers(1, 2))
    if w + h > 4:  # at most 8 vertices: 132 triangulations
        w = 4 - h
    pts = [(x, 0) for x in range(w)] + [(w, y) for y in range(h)]
    pts += [(w - x, h) for x in range(w)] + [(0, h - y) for y in range(h)]
    P = np.array([(x, y, 0.0) for x, y in pts])
    n = len(P)
    lifts = draw(st.lists(st.integers(0, n - 1), max_size=2, unique=True))
    P[lifts, 2] = draw(st.sampled_from([1.0, 2.0, 0.5]))
    P = np.roll(P, draw(st.integers(0, n - 1)), axis=0)
    ears = [((i - 1) % n, (i + 1) % n) for i in range(n)]
    forbidden = [e for e in draw(st.lists(st.sampled_from(ears), max_size=3, unique=True)) if n > 4]
    return np.ascontiguousarray(P), forbidden


def _usable(P):
    centred = P - P.mean(axis=0)
    sv = np.linalg.svd(centred, compute_uv=False)
    return sv[1] > 1e-12 * sv[0]


def _best(P, forbidden, cost):
    """(fewest count, least cost among patches with that many) by brute force."""
    flat: dict = {}
    scored = [(exact_count(P, t, flat), cost(t)) for t in patches(len(P), forbidden)]
    if not scored:
        return None
    fewest = min(c for c, _ in scored)
    return fewest, min(v for c, v in scored if c == fewest)


@settings(max_examples=60, deadline=None)
@given(runs(), st.sampled_from(MODES))
def test_liepa_weight_fewest_then_best(case, mode):
    P, forbidden = case
    if not _usable(P):
        return
    n = len(P)
    try:
        t = fill_polyline(P, method=mode, forbidden=forbidden or None)
    except Exception as exc:  # every patch uses a forbidden chord
        assert type(exc).__name__ == "NoTriangulationError"
        assert _best(P, forbidden, lambda tris: 0) is None
        return
    best = _best(P, forbidden, lambda tris: t._recompute(tris))
    assert best is not None
    count = exact_count(P, t.triangles)
    assert count == t.stats["degenerate"] == best[0], (mode, n)
    assert t.stats["degenerate_unavoidable"] == (count > 0)
    if mode in ("exact", "auto") or count > 0:  # exact for the pair (count, objective)
        angle, area = t.weight
        assert angle == best[1][0]
        assert area <= best[1][1] * (1 + 1e-12)


def py_area(vertices, i, k, j):
    """A user callable: the 3-D area (zero on collinear points, which it therefore likes)."""
    v = np.asarray(vertices, dtype=float)
    return 0.5 * float(np.linalg.norm(np.cross(v[k] - v[i], v[j] - v[i])))


@settings(max_examples=40, deadline=None)
@given(runs(), st.sampled_from(MODES), st.sampled_from(["area", "perimeter", py_area]))
def test_triangle_weights_fewest_then_best(case, mode, weight):
    P, forbidden = case
    if not _usable(P):
        return
    try:
        t = fill_polyline(P, weight, method=mode, forbidden=forbidden or None)
    except Exception as exc:
        assert type(exc).__name__ == "NoTriangulationError"
        return
    best = _best(P, forbidden, lambda tris: t._recompute(tris))
    count = exact_count(P, t.triangles)
    assert count == t.stats["degenerate"] == best[0], (mode, weight)
    if mode != "delaunay" or count > 0:  # delaunay is exact over its candidates only
        assert t.weight <= best[1] * (1 + 1e-12) + 1e-15


@settings(max_examples=15, deadline=None)
@given(runs())
def test_pair_objective_gets_the_fewest(case):
    """A pair objective cannot take the count as a third component: the fewest, least area."""
    P, forbidden = case
    if not _usable(P):
        return
    try:
        t = fill_polyline(
            P, ("perimeter", "area"), objective=("max", "sum"), forbidden=forbidden or None
        )
    except Exception as exc:
        assert type(exc).__name__ == "NoTriangulationError"
        return
    best = _best(P, forbidden, lambda tris: 0.0)
    assert exact_count(P, t.triangles) == t.stats["degenerate"] == best[0]


def test_zero_area_face_is_worse_than_any_fold():
    """Points 0, 1, 2 collinear; the best patch without a flat face folds past 90 degrees.

    A search that let the flat face beat that fold would find a patch with it, and
    the fewest-flat-faces search would then return the least-area patch without one,
    which folds more: the optimum among patches without a flat face is this one.
    """
    P = np.array([[-3, -1, 1], [-1, 0.5, 2], [1, 2, 3], [-1, -3, 2], [0, 3, 0]], dtype=float)
    T = np.array([[-4, -4, 1], [0, 2.5, 4], [-1, 3, 5], [-3, -4, 4], [1, 3, 1]], dtype=float)
    t = fill_polyline(P, third_points=T)
    flat: dict = {}
    clean = [liepa_objective(P, tr, T) for tr in patches(5, []) if not exact_count(P, tr, flat)]
    assert t.stats["degenerate"] == 0 and t.weight == min(clean)
    assert t.weight[0] < max(angle for angle, _ in clean)  # the choice matters


def test_fewest_degenerate_kernel_against_brute_force():
    """The (count, area) search on a rectangle with collinear runs, corner ears forbidden."""
    side = [(0, 0), (1, 0), (2, 0), (3, 0), (3, 1), (3, 2), (2, 2), (1, 2), (0, 2), (0, 1)]
    P = np.array([(x, y, 0.0) for x, y in side])
    n = len(P)
    corners = [0, 3, 5, 8]
    forbidden = [((c - 1) % n, (c + 1) % n) for c in corners]
    allowed = np.ones((n, n), dtype=np.bool_)
    for a, b in forbidden:
        allowed[a, b] = allowed[b, a] = False
    count, tris = fewest_degenerate(P, P, n, allowed)
    best = _best(P, forbidden, lambda t: 0.0)
    assert count == best[0] == exact_count(P, tris) == 2
    free = fewest_degenerate(P, P, n, np.ones((n, n), dtype=np.bool_))
    assert free[0] == 0 == _best(P, [], lambda t: 0.0)[0]


def _area(P, tris):
    a, b, c = (P[np.asarray(tris)[:, t]] for t in range(3))
    return float(0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1).sum())


def test_fewest_degenerate_then_least_area():
    """On the saddle z = xy/4 (sides stay straight): the fewest flat faces differ in area."""
    side = [(0, 0), (1, 0), (2, 0), (3, 0), (3, 1), (3, 2), (2, 2), (1, 2), (0, 2), (0, 1)]
    P = np.array([(x, y, x * y / 4) for x, y in side], dtype=float)
    n = len(P)
    forbidden = [((c - 1) % n, (c + 1) % n) for c in (0, 3, 5, 8)]
    allowed = np.ones((n, n), dtype=np.bool_)
    for a, b in forbidden:
        allowed[a, b] = allowed[b, a] = False
    flat: dict = {}
    scored = [(exact_count(P, t, flat), _area(P, t)) for t in patches(n, forbidden)]
    fewest = min(c for c, _ in scored)
    areas = [a for c, a in scored if c == fewest]
    assert fewest > 0 and max(areas) > min(areas) * 1.01  # the area must decide
    count, tris = fewest_degenerate(P, P, n, allowed)
    assert count == fewest == exact_count(P, tris)
    assert math.isclose(_area(P, tris), min(areas), rel_tol=1e-12)
    t = fill_polyline(P, forbidden=forbidden)  # Liepa's weight, exact: the same patch
    assert t.stats["degenerate"] == fewest and t.stats["degenerate_unavoidable"]
    assert math.isclose(t.weight[1], min(areas), rel_tol=1e-12)


# --- libigl's planexy.off and bump-domain.obj -------------------------------------------


@pytest.mark.parametrize("mode", MODES)
def test_planexy_has_no_zero_area_face_in_any_mode(mode):
    mesh = read_mesh(MESHES / "planexy.off")
    v, f = np.asarray(mesh.vertices), np.asarray(mesh.faces)
    (v2, f2), rec = fill_holes((v, f), method=mode)
    assert [r.edges for r in rec] == [16]
    assert rec[0].degenerate == 0 and not rec[0].degenerate_unavoidable
    assert exact_count(v2, f2[len(f) :]) == 0


def _bump_domain():
    mesh = read_mesh(MESHES / "bump-domain.obj")
    return np.asarray(mesh.vertices), np.asarray(mesh.faces)


def test_bump_domain_needs_two():
    """Why two: every patch has at least two ears, and here every ear is flat.

    A triangulation of an n-gon has two more ears (two polygon sides) than
    triangles with no side. The hole is a square with 70 points inside each side:
    three consecutive vertices are collinear except at the four corners, and the
    mesh already joins the two neighbours of each corner, so no ear can be cut
    there. Every ear is then degenerate: at least two. The search finds two.
    """
    v, f = _bump_domain()
    loops = trace_loops(f)
    assert len(loops) == 1
    loop = loops[0].vertices
    n = len(loop)
    P = v[loop]
    turns = [i for i in range(n) if not collinear(P, ((i - 1) % n, i, (i + 1) % n))]
    assert n == 284 and len(turns) == 4
    joined = {frozenset(p) for p in _Edges(f, loops, len(v)).chords_of(loop).tolist()}
    assert all(frozenset(((c - 1) % n, (c + 1) % n)) in joined for c in turns)
    allowed = np.ones((n, n), dtype=np.bool_)
    for a, b in map(tuple, joined):
        allowed[a, b] = allowed[b, a] = False
    count, tris = fewest_degenerate(np.ascontiguousarray(P), np.ascontiguousarray(P), n, allowed)
    assert count == 2 == exact_count(P, tris)


@pytest.mark.parametrize("mode", ["liepa", "delaunay"])  # auto (= exact): the CLI test
def test_bump_domain_adds_the_two_unavoidable(mode):
    v, f = _bump_domain()
    (v2, f2), rec = fill_holes((v, f), method=mode)
    assert rec[0].status == "filled" and rec[0].faces_added == 282
    assert rec[0].degenerate == 2 and rec[0].degenerate_unavoidable
    assert exact_count(v2, f2[len(f) :]) == 2
    assert rec[0].weight[0] == math.pi  # a fold or a flat face is worth pi


def test_fill_command_reports_the_unavoidable_two(tmp_path):
    out = tmp_path / "filled.obj"
    res = CliRunner().invoke(main, ["fill", str(MESHES / "bump-domain.obj"), "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert "2 zero-area faces (no patch has fewer)" in res.output
    assert "(exact;" in res.output  # auto runs the exact search at 284 edges


def test_record_detail_says_whether_fewest_is_proven():
    rec = HoleRecord(0, 5, "filled", degenerate=1, degenerate_unavoidable=True)
    assert "1 zero-area faces (no patch has fewer)" in rec.detail()
    assert rec.to_dict()["degenerate_unavoidable"] is True
    assert "fewest found" in HoleRecord(0, 5, "filled", degenerate=1).detail()
