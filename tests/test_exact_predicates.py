"""Every predicate against exact rational arithmetic, on inputs built to fool floats.

The oracle is :mod:`fractions` (``exact_oracle.sign_q``). Inputs: points on and within
a few ulps or 1e-15 of a line, at offsets up to 1e15; exactly collinear points at any
magnitude from subnormal to 1e300; coordinates spread over the whole exponent range
(the integer-limb stage). The Python form, the vectorized form and the compiled core's
(``src/core/predicates.hpp``, which the mask and many-polygon kernels inline, each of
its stages alone) must all give the oracle's sign.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from optri._core import predicates as core

from exact_oracle import between_q, ccw, exact_count, exact_mask, sign_q
from optri import as_polygon, count_triangulations
from optri.polygon import find_self_intersection
from optri.predicates import (
    following,
    on_open_segment,
    orient,
    orient_bigint,
    orient_exact,
    orient_sign,
    preceding,
    segment_pair_fault,
    strictly_between,
    turn_signs,
)
from optri.simple import valid_diagonals
from optri.simple.mask import valid_diagonals_compiled, valid_diagonals_numpy

OFFSETS = [0.0, 1.0, -3.5, 5e5, 4.6e6, 1e7, -1e7, 1e15]
small = st.floats(-10, 10, allow_nan=False)


def _nudge(v: float, ulps: int) -> float:
    for _ in range(abs(ulps)):
        v = math.nextafter(v, math.copysign(math.inf, ulps))
    return v


@st.composite
def near_line(draw) -> tuple[float, ...]:
    """c on the float line through a and b, moved by a few ulps or 1e-15, then offset."""
    ax, ay, bx, by = (draw(small) for _ in range(4))
    t = draw(st.floats(-3, 3))
    cx, cy = ax + t * (bx - ax), ay + t * (by - ay)
    cy = _nudge(cy, draw(st.integers(-2, 2))) + draw(st.sampled_from([0.0, 1e-15, -1e-15]))
    off = draw(st.sampled_from(OFFSETS))
    return tuple(v + off for v in (ax, ay, bx, by, cx, cy))


@st.composite
def exactly_collinear(draw) -> tuple[float, ...]:
    """a, b, c = p + t d on a line, integers times 2**e: exact at any magnitude."""
    e = draw(st.integers(-1074, 990))
    px, py, dx, dy = (draw(st.integers(-(2**20), 2**20)) for _ in range(4))
    t, u = draw(st.integers(-64, 64)), draw(st.integers(-64, 64))
    pts = (px, py, px + t * dx, py + t * dy, px + u * dx, py + u * dy)
    return tuple(math.ldexp(float(v), e) for v in pts)


@st.composite
def spread(draw) -> tuple[float, ...]:
    """a = 0, b = (B, s), c = (k B, k s + tiny): the sign is tiny's, B ~ 1e300, s ~ 1e-300."""
    big = math.ldexp(1.0 + draw(st.integers(0, 2**20)) / 2**20, draw(st.integers(800, 1000)))
    s = math.ldexp(1.0 + draw(st.integers(0, 2**20)) / 2**20, draw(st.integers(-1000, -800)))
    k = float(draw(st.integers(1, 4)))
    tiny = math.ldexp(float(draw(st.integers(-3, 3))), -1074)
    return (0.0, 0.0, big, s, k * big, k * s + tiny)


any_float = st.floats(allow_nan=False, allow_infinity=False)
anything = st.tuples(*(any_float for _ in range(6)))
triples = st.one_of(near_line(), exactly_collinear(), spread(), anything)


@settings(max_examples=400, deadline=None)
@given(triples)
def test_orient_matches_fractions(t):
    expected = sign_q(*t)
    assert orient_sign(*t) == expected
    assert orient_exact(*t) == expected
    assert orient_bigint(*t) == expected
    a, b, c = (np.array([t[m : m + 2]]) for m in (0, 2, 4))
    assert orient(a, b, c).tolist() == [expected]
    row = np.array([t])
    for stage in (core.orient_sign, core.orient_exact, core.orient_bigint):
        assert stage(row).tolist() == [expected]


@settings(max_examples=200, deadline=None)
@given(st.one_of(exactly_collinear(), near_line()))
def test_strictly_between_matches_fractions(t):
    assume(sign_q(*t) == 0)  # only defined for collinear points
    a, b, c = t[0:2], t[2:4], t[4:6]
    assume(a != b)
    expected = between_q(*t)
    assert strictly_between(*t) == expected
    assert core.strictly_between(np.array([t])).tolist() == [expected]
    assert on_open_segment(np.array(a), np.array(b), np.array(c)) == expected


def _adversarial_batch(seed: int, m: int) -> np.ndarray:
    """(m, 6) triples from every family above, numpy-generated (for the compiled form)."""
    rng = np.random.default_rng(seed)
    ab = rng.uniform(-10, 10, (m, 4))
    t = rng.uniform(-3, 3, m)
    c = ab[:, :2] + t[:, None] * (ab[:, 2:] - ab[:, :2])
    c[:, 1] += rng.choice([0.0, 1e-15, -1e-15, 5e-324], m)
    near = np.column_stack((ab, c)) + rng.choice(OFFSETS, m)[:, None]
    ints = rng.integers(-(2**20), 2**20, (m, 6)).astype(float)
    ints[:, 4:] = ints[:, :2] + 3 * (ints[:, 2:4] - ints[:, :2])  # exactly collinear
    grid = np.ldexp(ints, rng.integers(-1074, 990, m)[:, None])
    wild = rng.standard_normal((m, 6)) * np.ldexp(1.0, rng.integers(-1070, 1000, (m, 6)))
    return np.concatenate((near, grid, wild))


def test_core_orient_matches_fractions():
    # the compiled core's predicates (the mask and many-polygon kernels call them)
    batch = _adversarial_batch(0, 3000)
    expected = [sign_q(*row) for row in batch.tolist()]
    assert core.orient_sign(batch).tolist() == expected
    assert core.orient_exact(batch).tolist() == expected
    assert core.orient_bigint(batch).tolist() == expected
    assert expected.count(0) > 1000  # the batch really is full of collinear triples


def test_core_filter_floor_and_subnormals():
    # determinants at the filter's floor or made of subnormal products: the exact stages
    # must decide them, and must agree with fractions
    rng = np.random.default_rng(1)
    base = rng.integers(-8, 9, (2000, 6)).astype(float)
    rows = np.ldexp(base, rng.integers(-1074, -1000, 2000)[:, None])
    rows[::3, 5] = np.nextafter(rows[::3, 5], np.inf)
    expected = [sign_q(*row) for row in rows.tolist()]
    assert core.orient_sign(rows).tolist() == expected
    assert len(set(expected)) == 3


#: Triples whose float determinant has the wrong sign although it exceeds eps (|l| + |r|)
#: (l, r its two products): only a filter bound of about 3 eps (Shewchuk's) sends them on
#: to the exact stage. Found by a random search against fractions.
FILTER_TRAPS = [
    (-0.23050944682142416, -0.4414810394724673, 0.6976704212683744,
     0.7059547798314745, 2.3535532490445483, 2.7529925733476563),
    (0.954208854853732, -0.6527965498165778, -0.5562518157461687,
     0.8758800421310686, 3.3034529817439697, -3.0303721964047696),
    (0.7780334359921015, -0.9883582252854579, -0.7308988144915094,
     0.5428570813027969, 3.2127753778598924, -3.4590550559652424),
]  # fmt: skip


@pytest.mark.parametrize("t", FILTER_TRAPS)
def test_filter_bound_sends_wrong_float_signs_to_the_exact_stage(t):
    ax, ay, bx, by, cx, cy = t
    left, right = (bx - ax) * (cy - ay), (by - ay) * (cx - ax)
    det, eps = left - right, 2.0**-53
    assert abs(det) > eps * (abs(left) + abs(right))  # past a filter bound of eps alone
    expected = sign_q(*t)
    assert expected != 0 and (det > 0) - (det < 0) == -expected  # floats get it wrong
    assert orient_sign(*t) == expected
    a, b, c = (np.array([t[m : m + 2]]) for m in (0, 2, 4))
    assert orient(a, b, c).tolist() == [expected]


def test_old_tolerance_cases():
    # a turn of 2**-51 is a turn; (0.1, 0.2) and (0.3, 0.6) are not on one line through 0
    assert orient_sign(0.0, 0.0, 1.0, 1.0, 3.0, 3.0 + 2.0**-51) == 1
    assert orient_sign(0.0, 0.0, 0.1, 0.2, 0.3, 0.6) == sign_q(0.0, 0.0, 0.1, 0.2, 0.3, 0.6)
    # a square scaled to the ends of the float range is not collinear
    for s in (1e-308, 5e-324 * 2**10, 1e154, 1e308):
        sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1]]) * s
        assert turn_signs(sq).tolist() == [1, 1, 1, 1]


@settings(max_examples=150, deadline=None)
@given(near_line(), near_line())
def test_segment_faults_match_fractions(s, t):
    a, b, c, d = np.array(s[0:2]), np.array(s[2:4]), np.array(t[0:2]), np.array(s[4:6])
    assume(len({tuple(a), tuple(b), tuple(c), tuple(d)}) == 4)
    o = [sign_q(*a, *b, *c), sign_q(*a, *b, *d), sign_q(*c, *d, *a), sign_q(*c, *d, *b)]
    cross = o[0] * o[1] < 0 and o[2] * o[3] < 0
    touch = any(
        o[m] == 0 and between_q(*p, *q, *r)
        for m, (p, q, r) in enumerate(((a, b, c), (a, b, d), (c, d, a), (c, d, b)))
    )
    hit = segment_pair_fault(a[None], b[None], c[None], d[None], np.array([False]))
    assert (hit is not None) == (cross or touch)
    if hit is not None:
        assert hit[1] == ("cross" if cross else "touch")


# --- polygons: convexity, simplicity, mask and counts against the exact oracle ----------


def _fan_on_lines(seed: int, off: float) -> np.ndarray:
    """A convex-looking polygon whose sides carry float points on the lines: ~collinear."""
    rng = np.random.default_rng(seed)
    corners = np.array([[0.0, 0.0], [7.0, 0.3], [6.1, 5.9], [0.2, 6.7]]) * rng.uniform(0.5, 2)
    pts = []
    for p, q in zip(corners, np.roll(corners, -1, axis=0)):
        for t in np.sort(rng.uniform(0, 1, rng.integers(1, 4))):
            pts.append(p)
            pts.append(p + t * (q - p))  # rounded: a hair off the line, either side
    ring = np.unique(np.array(pts), axis=0, return_index=True)[1]
    return np.array(pts)[np.sort(ring)] + off


@pytest.mark.parametrize("off", [0.0, 5e5, 4.6e6, 1e7])
@pytest.mark.parametrize("seed", range(12))
def test_near_collinear_polygons_match_exact_oracle(seed, off):
    pts = _fan_on_lines(seed, off)
    if find_self_intersection(pts) is not None:
        pytest.skip("rounding made this one non-simple")
    poly = as_polygon(pts)
    signs = [sign_q(*pts[i - 1], *pts[i], *pts[(i + 1) % len(pts)]) for i in range(len(pts))]
    assert turn_signs(pts).tolist() == signs
    assert poly.convex == all(s == sign_q(*pts[0], *pts[1], *pts[2]) for s in signs)
    expected = exact_mask(ccw(pts))
    assert np.array_equal(valid_diagonals(poly), expected) or poly.convex
    assert np.array_equal(valid_diagonals_numpy(poly.data), expected)
    assert np.array_equal(valid_diagonals_compiled(poly.data), expected)
    assert count_triangulations(pts) == exact_count(expected)


@pytest.mark.parametrize("d, count", [(1e-16, 5), (0.0, 3), (-1e-16, 3), (2.0**-1074, 5)])
def test_a_vertex_off_the_line_by_1e16(d, count):
    # strictly convex in exact arithmetic for d > 0: 5 triangulations; straight or reflex: 3
    pts = [[0, 0], [1, -d], [2, 0], [2, 2], [0, 2]]
    assert count_triangulations(pts) == count
    assert as_polygon(pts).convex == (d > 0)


@settings(max_examples=100, deadline=None)
@given(st.integers(1, 40), st.integers(1, 3), st.integers(0, 2**32 - 1))
def test_following_and_preceding_are_np_roll(n: int, cols: int, seed: int) -> None:
    # the cheap successor and predecessor of every vertex (validation runs them on each
    # call) are np.roll by -1 and +1, for rings of vertices and for 1-D columns
    a = np.random.default_rng(seed).integers(0, 9, (n, cols))
    for x in (a, a[:, 0]):
        assert np.array_equal(following(x), np.roll(x, -1, axis=0))
        assert np.array_equal(preceding(x), np.roll(x, 1, axis=0))
