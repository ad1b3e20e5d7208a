"""Valid-diagonal masks and simplicity checks against shapely and brute force."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from optri._core import simple as core

from optri import InvalidPolygonError, as_polygon, config
from optri.engines.brute import all_index_triangulations
from optri.engines.problem import chord_rows
from optri.enumeration.counting import count_table
from optri.polygon import require_simple
from optri.simple import allowed_chords, valid_diagonals
from optri.simple.mask import _set_sides, valid_diagonals_compiled, valid_diagonals_numpy
from simple_polys import (
    ccw_of,
    is_simple_polygon,
    oracle_mask,
    random_star,
    simple_polygons,
    star_polygons,
)

shapely = pytest.importorskip("shapely")

polygons = st.one_of(star_polygons(4, 11), simple_polygons(4, 11))


@settings(max_examples=60, deadline=None)
@given(polygons, st.booleans())
def test_mask_equals_shapely_oracle(coords, reverse):
    if reverse:
        coords = coords[::-1]
    poly = as_polygon(coords)
    require_simple(poly)
    expected = oracle_mask(ccw_of(np.asarray(poly.vertices)))
    # internal order is CCW from input vertex 0: same as ccw_of
    assert np.array_equal(valid_diagonals(poly), expected)
    assert np.array_equal(valid_diagonals_numpy(poly.data), expected)
    assert np.array_equal(valid_diagonals_compiled(poly.data), expected)
    assert np.array_equal(_parallel_mask(poly.data), expected)


def _parallel_mask(points: np.ndarray) -> np.ndarray:
    """valid_diagonals_compiled on its large-polygon path (watched, rows on every thread)."""
    old = config.MASK_WATCH_MIN_N
    config.MASK_WATCH_MIN_N = 0
    try:
        return valid_diagonals_compiled(points)
    finally:
        config.MASK_WATCH_MIN_N = old


@settings(max_examples=40, deadline=None)
@given(polygons)
def test_counts_equal_brute_force(coords):
    poly = as_polygon(coords)
    ok = valid_diagonals_compiled(poly.data)
    brute = sum(1 for _ in all_index_triangulations(poly.n, ok.tolist()))
    assert count_table(chord_rows(ok))[0][-1] == brute
    assert brute >= 1  # every simple polygon has a triangulation


@pytest.mark.parametrize(
    "coords, count",
    [
        ([[0, 0], [4, 0], [1, 1], [0, 4]], 1),  # a dart: only the chord from its reflex vertex
        ([[0, 0], [1, 0], [2, 0], [2, 2], [0, 2]], 3),  # square with a straight vertex: 5 - 2
        ([[0, 0], [2, 0], [2, 2], [0, 2]], 2),
        ([[0, 0], [3, 0], [3, 3], [2, 1], [1, 3], [0, 3]], 2),  # a notch: chord 1-5 grazes vertex 3
    ],
)
def test_known_counts(coords, count):
    ok = allowed_chords(as_polygon(coords))
    ok = np.ones((len(coords),) * 2, bool) if ok is None else ok
    assert count_table(chord_rows(ok))[0][-1] == count


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize("kind", ["star", "near_convex", "grid"])
def test_compiled_paths_agree(kind, seed):
    rng = np.random.default_rng(seed)
    if kind == "star":
        pts = random_star(120, seed)
    elif kind == "near_convex":
        a = np.linspace(0, 2 * np.pi, 90, endpoint=False)
        pts = np.column_stack((np.cos(a), np.sin(a)))
        pts[rng.integers(90, size=3)] *= 0.6
    else:  # integer star with many collinear triples
        ang = np.sort(rng.choice(360, 80, replace=False)) * np.pi / 180
        r = rng.integers(5, 9, 80)
        pts = np.column_stack((np.round(r * np.cos(ang) * 4), np.round(r * np.sin(ang) * 4)))
        pts = np.unique(pts, axis=0)[np.argsort(np.arctan2(*np.unique(pts, axis=0)[:, ::-1].T))]
        if not is_simple_polygon(pts):
            pytest.skip("rounded star not simple")
    poly = as_polygon(pts)
    require_simple(poly)
    fast = valid_diagonals(poly)
    scan = core.valid_mask(poly.data[:, 0].copy(), poly.data[:, 1].copy())
    ref = valid_diagonals_numpy(poly.data)
    off = ~np.eye(poly.n, dtype=bool)
    sides = ref & ~scan & off
    assert np.array_equal(fast, ref)
    assert np.array_equal(_parallel_mask(poly.data), ref)
    assert np.array_equal(scan | sides, ref)  # the scan kernel leaves sides unset


def _arc_and_chord():
    # 50 consecutive vertices of a wavy star, closed by the chord back to the first:
    # the waves cross that chord. Ear clipping succeeds on it; the walk then stops.
    rng = np.random.default_rng(0)
    ang = np.linspace(0, 2 * np.pi, 2000, endpoint=False)[:50]
    r = 1 + 0.3 * rng.random(2000)[:50]
    return np.column_stack((r * np.cos(ang), r * np.sin(ang)))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 6), st.integers(0, 6)), min_size=4, max_size=10))
def test_valid_diagonals_of_a_boundary_that_is_not_simple_is_an_error(coords):
    try:
        poly = as_polygon(np.array(coords, dtype=float))
    except InvalidPolygonError:
        assume(False)
    assume(not is_simple_polygon(poly.data))
    with pytest.raises(InvalidPolygonError, match="not simple: edges"):
        valid_diagonals(poly)


def test_waves_across_the_closing_chord_are_named_not_an_internal_error():
    # the walk then stopped with "internal error ... please report"; the compiled mask
    # alone (which does not check) now falls back to the direct scan
    poly = as_polygon(_arc_and_chord())
    with pytest.raises(InvalidPolygonError, match="edges 45-46 and 49-0 cross"):
        valid_diagonals(poly)
    scan = core.valid_mask(poly.data[:, 0].copy(), poly.data[:, 1].copy())
    _set_sides(scan)  # as the compiled path completes the scan's mask
    assert np.array_equal(valid_diagonals_compiled(poly.data), scan)


def test_convex_needs_no_mask_but_straight_vertex_does():
    assert allowed_chords(as_polygon([[0, 0], [2, 0], [2, 2], [0, 2]])) is None
    ok = allowed_chords(as_polygon([[0, 0], [1, 0], [2, 0], [2, 2], [0, 2]]))
    assert ok is not None and not ok[0, 2]  # along the boundary through vertex 1


@pytest.mark.parametrize(
    "coords, message",
    [
        ([[0, 0], [1, 1], [1, 0], [0, 1]], "edges 0-1 and 2-3 cross"),
        ([[0, 0], [4, 0], [4, 4], [2, 0], [0, 4]], "edges 0-1 and 2-3 touch"),
        ([[0, 0], [4, 0], [4, 2], [4, 1], [0, 4]], "edges 1-2 and 2-3 overlap"),  # a spike
        ([[0, 0], [2, 0], [1, 1], [2, 2], [0, 2], [1, 1]], "repeats"),
        ([[0, 0], [1, 0], [np.nan, 1]], "non-finite"),
    ],
)
def test_invalid_polygons_are_named(coords, message):
    with pytest.raises(InvalidPolygonError, match=message):
        allowed_chords(as_polygon(coords))


def _named_edges_cross(coords):
    import re

    with pytest.raises(InvalidPolygonError) as info:
        require_simple(coords)
    e0, e1, f0, f1 = map(
        int, re.search(r"edges (\d+)-(\d+) and (\d+)-(\d+) cross", str(info.value)).groups()
    )
    n = len(coords)
    assert (e1, f1) == ((e0 + 1) % n, (f0 + 1) % n)
    seg = [shapely.LineString(coords[[a, b]]) for a, b in ((e0, e1), (f0, f1))]
    return bool(seg[0].crosses(seg[1]))


def test_error_names_input_indices_for_clockwise_input():
    ccw = np.array([[0, 0], [6, 0], [6, 6], [3, 6], [3, -1], [0, 6]], float)
    cw = np.concatenate([ccw[:1], ccw[:0:-1]])  # same edges, input indices reversed
    assert _named_edges_cross(ccw) and _named_edges_cross(cw)
    bowtie = np.array([[0, 0], [2, 2], [2, 0], [0, 2]], float)  # one crossing: named exactly
    with pytest.raises(InvalidPolygonError, match=r"edges 0-1 and 2-3 cross"):
        require_simple(bowtie)
    with pytest.raises(InvalidPolygonError, match=r"edges 1-2 and 3-0 cross"):
        require_simple(np.concatenate([bowtie[:1], bowtie[:0:-1]]))


def _polygon_or_none(coords):
    try:
        return as_polygon(coords)
    except InvalidPolygonError:
        return None


@settings(max_examples=80, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 6), st.integers(0, 6)), min_size=4, max_size=8))
def test_simplicity_agrees_with_shapely(pts):
    coords = np.array(pts, float)
    poly = _polygon_or_none(coords)
    assume(poly is not None)  # duplicates or all collinear: refused earlier
    ours = True
    try:
        require_simple(poly)
    except InvalidPolygonError:
        ours = False
    assert ours == bool(shapely.LinearRing(coords).is_simple)


@pytest.mark.parametrize("seed", range(20))
def test_float_stars_match_oracle(seed):
    pts = random_star(5 + seed % 7, seed)
    poly = as_polygon(pts)
    expected = oracle_mask(ccw_of(pts))
    assert np.array_equal(valid_diagonals(poly), expected)
    assert np.array_equal(valid_diagonals_compiled(poly.data), expected)


def test_the_parallel_walk_stops_when_asked_and_answers_as_the_serial_one():
    pts = random_star(300, 1)
    x, y = np.ascontiguousarray(pts[:, 0]), np.ascontiguousarray(pts[:, 1])
    go, stop = np.zeros(1, dtype=np.int64), np.ones(1, dtype=np.int64)
    tris, ok = core.ear_clip(x, y, go)
    assert ok and tris.shape == (298, 3)
    assert not core.ear_clip(x, y, stop)[1]
    mask, ok = core.visibility(x, y, tris, go, 2)
    assert ok and mask.any()
    assert not core.visibility(x, y, tris, stop, 2)[1]
    assert not core.diagonals(x, y, stop, 2)[1]
    assert np.array_equal(mask, core.visibility(x, y, tris, go, 1)[0])
    whole, ok = core.diagonals(x, y, go, 3)  # ear clipping and the walk in one call
    assert ok and np.array_equal(whole, mask)
    broken = tris.copy()
    broken[7] = broken[8]  # a triangle twice, one missing: whatever the serial walk says
    got, want = core.visibility(x, y, broken, go, 2), core.visibility(x, y, broken, go, 1)
    assert got[1] == want[1] and (not got[1] or np.array_equal(got[0], want[0]))
    broken[7, 0] = 300  # no such vertex
    assert not core.visibility(x, y, broken, go, 2)[1]
