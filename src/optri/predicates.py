"""Geometric predicates: the one place where optri decides the sign of a turn, exactly.

Every yes/no question geometry asks (does the boundary turn left here, do two
segments cross or touch, does a chord start into the polygon, does it pass
through a vertex) is answered here, vectorized with numpy over leading axes. The compiled core's
kernels (the valid-diagonal mask, the many-polygon kernel) use its C++ twin,
``src/core/predicates.hpp``: the same three stages, written out operation by
operation, held to exact rational arithmetic by the same tests.

The guarantee
-------------
Every sign is the sign exact (rational) arithmetic gives for the float64
coordinates as stored, for **every finite input**: a vertex is collinear
only if it is exactly collinear, and a turn of 1e-300 radians is a turn.
There is no tolerance anywhere. Three stages decide a turn a -> b -> c:

1. **Float filter.** ``det = (bx-ax)(cy-ay) - (by-ay)(cx-ax)`` in floats; its
   sign is certain when ``|det| > (3 + 32 eps) eps (|l| + |r|)`` (``l`` and
   ``r`` the two products, ``eps = 2**-53``): Shewchuk's bound for orient2d
   (``ccwerrboundA = (3 + 16 eps) eps``) with the ``eps**2`` term doubled, so
   that it also absorbs the absolute error of an underflowing product whenever
   ``|det| > 2**-960`` (below that the filter never answers). A NaN or
   infinite intermediate (overflow) never passes. Almost every turn of real
   data is decided here, at the cost of the old tolerance test.
2. **Expansion arithmetic** (:func:`orient_exact`). The six coordinates are
   scaled by one power of two (exact) so the largest has exponent 450; when
   then every non-zero coordinate is at least ``2**-400``, the differences are
   split exactly (``two_diff``), the products taken exactly (Dekker's
   ``two_product``) and summed into a non-overlapping expansion (Shewchuk's
   Grow-Expansion with zero elimination), whose largest component carries
   the sign. When the differences are already exact (integer and grid data,
   and by Sterbenz's lemma any two coordinates within a factor 2 of each
   other) two ``two_product`` pairs are compared directly.
3. **Integer arithmetic** (:func:`orient_bigint`), for the rest: coordinates
   whose magnitudes differ by more than ``2**849`` within one triple. Each
   double is an integer times a power of two; the determinant's six products
   are summed exactly in 26-bit limbs.

References: J. R. Shewchuk, "Adaptive Precision Floating-Point Arithmetic and
Fast Robust Geometric Predicates", Discrete Comput. Geom. 18, 1997; T. J.
Dekker, "A floating-point technique for extending the available precision",
Numer. Math. 18, 1971.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "ORIENT_FILTER",
    "chord_clear",
    "following",
    "in_cone",
    "on_open_segment",
    "orient",
    "orient_bigint",
    "orient_exact",
    "orient_sign",
    "preceding",
    "segment_pair_fault",
    "strictly_between",
    "turn_signs",
    "two_diff",
    "two_product",
    "two_sum",
]

Array = NDArray[np.float64]

_EPS = 2.0**-53
#: Relative error bound of the float filter (Shewchuk's ccwerrboundA, eps^2 term doubled).
ORIENT_FILTER = (3.0 + 32.0 * _EPS) * _EPS
#: The filter never answers for |det| at or below this (products may have underflowed).
_FILTER_FLOOR = 2.0**-960
_SPLITTER = 134217729.0  # 2**27 + 1: Dekker's split of a double into two 26-bit halves
_TOP = 450  # stage 2 scales the largest coordinate to [2**449, 2**450)
_SPREAD = 849  # ... and needs every non-zero one >= 2**-400 then: a spread <= 2**849
_LIMB = 26  # stage 3: bits per limb
_MASK = (1 << _LIMB) - 1
_LIMBS = 170  # 26 * 170 bits hold any sum of products of two doubles, times 2**2252
_OFFSET = 1126  # -(smallest exponent of a double's integer mantissa): 1074 + 52


# --- scalar code (src/core/predicates.hpp is its C++ twin) ---------------------------


def two_sum(a, b):  # type: ignore[no-untyped-def]
    """``(x, y)`` with ``x = fl(a + b)`` and ``x + y == a + b`` exactly (Knuth)."""
    x = a + b
    bv = x - a
    av = x - bv
    return x, (a - av) + (b - bv)


def two_diff(a, b):  # type: ignore[no-untyped-def]
    """``(x, y)`` with ``x = fl(a - b)`` and ``x + y == a - b`` exactly.

    >>> two_diff(1.0, 2.0**-60)
    (1.0, -8.673617379884035e-19)
    """
    x = a - b
    bv = a - x
    av = x + bv
    return x, (a - av) + (bv - b)


def _split(a):  # type: ignore[no-untyped-def]
    """Dekker's split: ``a == hi + lo`` with both halves of at most 26 significant bits."""
    c = _SPLITTER * a
    hi = c - (c - a)
    return hi, a - hi


def two_product(a, b):  # type: ignore[no-untyped-def]
    """``(x, y)`` with ``x = fl(a * b)`` and ``x + y == a * b`` exactly.

    Exact when ``|a|, |b| < 2**995`` and no partial product underflows
    (:func:`orient_exact` scales its input so both hold).

    >>> two_product(1.0 + 2.0**-30, 1.0 - 2.0**-30)
    (1.0, -8.673617379884035e-19)
    """
    x = a * b
    ah, al = _split(a)
    bh, bl = _split(b)
    err = ((x - ah * bh) - al * bh) - ah * bl
    return x, al * bl - err


def _grow(h, m, b):  # type: ignore[no-untyped-def]
    """Add ``b`` to the non-overlapping expansion ``h[:m]`` in place; returns its new length.

    Shewchuk's Grow-Expansion with zero elimination: components stay in
    increasing order of magnitude, so the last one carries the sign.
    """
    q = b
    out = 0
    for idx in range(m):
        q, e = two_sum(q, h[idx])
        if e != 0.0:
            h[out] = e
            out += 1
    if q != 0.0:
        h[out] = q
        out += 1
    return out


def _sign_of_products(ux, uxt, uy, uyt, vx, vxt, vy, vyt):  # type: ignore[no-untyped-def]
    """Sign of ``(ux+uxt)(vy+vyt) - (uy+uyt)(vx+vxt)`` from exact products and sums."""
    h = np.zeros(16)
    m = 0
    for p, q, s in (
        (ux, vy, 1.0), (ux, vyt, 1.0), (uxt, vy, 1.0), (uxt, vyt, 1.0),
        (uy, vx, -1.0), (uy, vxt, -1.0), (uyt, vx, -1.0), (uyt, vxt, -1.0),
    ):  # fmt: skip
        if p != 0.0 and q != 0.0:
            x, y = two_product(p, q)
            m = _grow(h, m, s * y)
            m = _grow(h, m, s * x)
    if m == 0:
        return 0
    return 1 if h[m - 1] > 0.0 else -1


def orient_exact(ax, ay, bx, by, cx, cy):  # type: ignore[no-untyped-def]
    """Exact sign of the turn a -> b -> c (stages 2 and 3 of the module docstring).

    >>> orient_exact(0.0, 0.0, 1.0, 1.0, 3.0, 3.0 + 2.0**-51)
    1
    """
    big = max(max(abs(ax), abs(ay)), max(max(abs(bx), abs(by)), max(abs(cx), abs(cy))))
    if big == 0.0:
        return 0
    top = math.frexp(big)[1]
    low = top
    for v in (ax, ay, bx, by, cx, cy):
        if v != 0.0:
            low = min(low, math.frexp(v)[1])
    if top - low > _SPREAD:
        return orient_bigint(ax, ay, bx, by, cx, cy)
    s = _TOP - top  # one power of two for all six: exact, no overflow, no underflow
    ax, ay, bx, by = math.ldexp(ax, s), math.ldexp(ay, s), math.ldexp(bx, s), math.ldexp(by, s)
    cx, cy = math.ldexp(cx, s), math.ldexp(cy, s)
    ux, uxt = two_diff(bx, ax)
    uy, uyt = two_diff(by, ay)
    vx, vxt = two_diff(cx, ax)
    vy, vyt = two_diff(cy, ay)
    if uxt == 0.0 and uyt == 0.0 and vxt == 0.0 and vyt == 0.0:
        # exact differences: compare the two products; rounding is monotone, so
        # fl(l) > fl(r) implies l > r, and on equal heads the tails decide
        lh, lt = two_product(ux, vy)
        rh, rt = two_product(uy, vx)
        if lh != rh:
            return 1 if lh > rh else -1
        if lt != rt:
            return 1 if lt > rt else -1
        return 0
    return _sign_of_products(ux, uxt, uy, uyt, vx, vxt, vy, vyt)


def _mantissa(x):  # type: ignore[no-untyped-def]
    """``(m, e)`` with ``x == m * 2**e``, ``m`` an integer below ``2**53`` in magnitude."""
    f, e = math.frexp(x)
    return np.int64(f * 9007199254740992.0), e - 53


def _add_shifted(acc, v, pos, sign):  # type: ignore[no-untyped-def]
    """``acc += sign * v * 2**pos`` for ``0 <= v < 2**54``, limb by limb (no carries yet)."""
    limb = pos // _LIMB
    r = pos % _LIMB
    while v > 0:
        w = (v & _MASK) << r  # < 2**52
        acc[limb] += sign * (w & _MASK)
        acc[limb + 1] += sign * (w >> _LIMB)
        v >>= _LIMB
        limb += 1


def _add_product(acc, x, y, sign):  # type: ignore[no-untyped-def]
    """``acc += sign * x * y`` exactly, in units of ``2**-2252``."""
    if x == 0.0 or y == 0.0:
        return
    mx, ex = _mantissa(x)
    my, ey = _mantissa(y)
    if mx < 0:
        mx, sign = -mx, -sign
    if my < 0:
        my, sign = -my, -sign
    a1, a0 = mx >> _LIMB, mx & _MASK
    b1, b0 = my >> _LIMB, my & _MASK
    pos = ex + ey + 2 * _OFFSET
    _add_shifted(acc, a0 * b0, pos, sign)
    _add_shifted(acc, a0 * b1 + a1 * b0, pos + _LIMB, sign)
    _add_shifted(acc, a1 * b1, pos + 2 * _LIMB, sign)


def orient_bigint(ax, ay, bx, by, cx, cy):  # type: ignore[no-untyped-def]
    """Exact sign of the turn a -> b -> c in integer arithmetic; any finite doubles.

    ``det = bx cy - bx ay - ax cy - by cx + by ax + ay cx``, each product an
    integer times a power of two, summed in 26-bit limbs.

    >>> orient_bigint(0.0, 0.0, 1e300, 1e-300, 2e300, 3e-300)
    1
    """
    acc = np.zeros(_LIMBS, dtype=np.int64)
    _add_product(acc, bx, cy, 1)
    _add_product(acc, bx, ay, -1)
    _add_product(acc, ax, cy, -1)
    _add_product(acc, by, cx, -1)
    _add_product(acc, by, ax, 1)
    _add_product(acc, ay, cx, 1)
    carry = 0
    for k in range(_LIMBS):
        t = acc[k] + carry
        carry = t >> _LIMB  # floor division: every limb ends in [0, 2**26)
        acc[k] = t - (carry << _LIMB)
    if carry != 0:
        return 1 if carry > 0 else -1
    for k in range(_LIMBS):
        if acc[k] != 0:
            return 1
    return 0


def orient_sign(ax, ay, bx, by, cx, cy):  # type: ignore[no-untyped-def]
    """Exact sign of the turn a -> b -> c: +1 left, -1 right, 0 exactly collinear.

    The float filter, then :func:`orient_exact` for the few turns it cannot
    certify.

    >>> orient_sign(0.0, 0.0, 1.0, 0.0, 1.0, 1.0)
    1
    >>> orient_sign(0.0, 0.0, 1.0, 1.0, 3.0, 3.0 + 2.0**-51)   # a left turn, however slight
    1
    """
    ux = bx - ax
    uy = by - ay
    vx = cx - ax
    vy = cy - ay
    left = ux * vy
    right = uy * vx
    det = left - right
    bound = ORIENT_FILTER * (abs(left) + abs(right))
    if bound < _FILTER_FLOOR:
        bound = _FILTER_FLOOR
    if det > bound:
        return 1
    if det < -bound:
        return -1
    return orient_exact(ax, ay, bx, by, cx, cy)


def strictly_between(ax, ay, bx, by, cx, cy):  # type: ignore[no-untyped-def]
    """For c collinear with segment ab: whether c lies strictly between a and b.

    Comparisons only, so exact: on a line that is not vertical x orders the
    points, on a vertical line y does.

    >>> strictly_between(0.0, 0.0, 2.0, 2.0, 1.0, 1.0)
    True
    >>> strictly_between(0.0, 0.0, 2.0, 2.0, 2.0, 2.0)   # an endpoint
    False
    """
    if ax != bx:
        return min(ax, bx) < cx < max(ax, bx)
    return min(ay, by) < cy < max(ay, by)


# --- vectorized forms ------------------------------------------------------------------


def orient(a: Array, b: Array, c: Array) -> NDArray[np.int64]:
    """Exact sign of the turn a -> b -> c, broadcasting over leading axes.

    The float filter for all, then exact arithmetic for the undecided ones
    (vectorized where the differences are exact, else :func:`orient_exact`).

    >>> orient(np.array([0., 0.]), np.array([1., 0.]), np.array([[1., 1.], [2., 0.]])).tolist()
    [1, 0]
    >>> int(orient(np.array([0., 0.]), np.array([1., 0.]), np.array([2., 0.])))  # one triple
    0
    """
    a, b, c = np.broadcast_arrays(
        np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64),
        np.asarray(c, dtype=np.float64),
    )  # fmt: skip
    with np.errstate(all="ignore"):  # overflow and underflow are handled, not warned about
        ux, uy = b[..., 0] - a[..., 0], b[..., 1] - a[..., 1]
        vx, vy = c[..., 0] - a[..., 0], c[..., 1] - a[..., 1]
        left, right = ux * vy, uy * vx
        det = left - right
        bound = np.maximum(ORIENT_FILTER * (np.abs(left) + np.abs(right)), _FILTER_FLOOR)
        pos, neg = det > bound, det < -bound
    out = np.atleast_1d(pos.astype(np.int64) - neg.astype(np.int64))
    todo = np.atleast_1d(~(pos | neg))
    if todo.any():
        shape = out.shape + (2,)
        a, b, c = (x.reshape(shape) for x in (a, b, c))
        out[todo] = _exact_rows(a[todo], b[todo], c[todo])
    return out.reshape(pos.shape)


def _exact_rows(a: Array, b: Array, c: Array) -> NDArray[np.int64]:
    """:func:`orient_exact` of rows ``(m, 2)``, vectorized where the differences are exact."""
    pts = np.concatenate((a, b, c), axis=1)  # (m, 6): ax ay bx by cx cy
    mag = np.abs(pts)
    big = mag.max(axis=1)
    top = np.frexp(big)[1]
    low = np.where(mag > 0, np.frexp(mag)[1], top[:, None]).min(axis=1)
    with np.errstate(all="ignore"):
        p = np.ldexp(pts, (_TOP - top)[:, None])
        u, ut = _two_diff_np(p[:, 2:4], p[:, 0:2])
        v, vt = _two_diff_np(p[:, 4:6], p[:, 0:2])
        lh, lt = _two_product_np(u[:, 0], v[:, 1])
        rh, rt = _two_product_np(u[:, 1], v[:, 0])
        out = np.where(lh != rh, np.sign(lh - rh), np.sign(lt - rt)).astype(np.int64)
    exact = (top - low <= _SPREAD) & ~ut.any(axis=1) & ~vt.any(axis=1)
    out[big == 0] = 0
    for r in np.flatnonzero(~exact & (big > 0)):
        out[r] = orient_exact(*(float(t) for t in pts[r]))
    return out


def _two_diff_np(a: Array, b: Array) -> tuple[Array, Array]:
    x = a - b
    bv = a - x
    av = x + bv
    return x, (a - av) + (bv - b)


def _two_product_np(a: Array, b: Array) -> tuple[Array, Array]:
    x = a * b
    ca, cb = _SPLITTER * a, _SPLITTER * b
    ah, bh = ca - (ca - a), cb - (cb - b)
    al, bl = a - ah, b - bh
    return x, al * bl - (((x - ah * bh) - al * bh) - ah * bl)


def following(a: Array) -> Array:
    """Each row's successor in a closed ring: ``np.roll(a, -1, axis=0)``, a sixth of its cost.

    >>> following(np.array([1, 2, 3])).tolist()
    [2, 3, 1]
    """
    return np.concatenate((a[1:], a[:1]))


def preceding(a: Array) -> Array:
    """Each row's predecessor in a closed ring: ``np.roll(a, 1, axis=0)``.

    >>> preceding(np.array([1, 2, 3])).tolist()
    [3, 1, 2]
    """
    return np.concatenate((a[-1:], a[:-1]))


def turn_signs(points: Array) -> NDArray[np.int64]:
    """Exact sign of the turn at each vertex of a closed 2-D polygon (+1 left, -1 right, 0).

    >>> turn_signs(np.array([[0., 0.], [1., 0.], [2., 0.], [1., 1.]])).tolist()
    [1, 0, 1, 1]
    """
    return orient(preceding(points), points, following(points))


def on_open_segment(a: Array, b: Array, c: Array) -> NDArray[np.bool_]:
    """For points c collinear with segment ab: c strictly between a and b (comparisons only)."""
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    on = np.all((c >= lo) & (c <= hi), axis=-1)
    return on & ~np.all(c == a, axis=-1) & ~np.all(c == b, axis=-1)


def segment_pair_fault(
    a: Array, b: Array, c: Array, d: Array, adjacent: NDArray[np.bool_]
) -> tuple[int, str] | None:
    """First bad pair among segments ab, cd (rows): ``(row, how)`` or None.

    ``how`` is ``"cross"`` (proper crossing), ``"touch"`` (an endpoint on the
    other segment) or ``"overlap"`` (``adjacent`` segments folding back on each
    other). Segment endpoints are assumed distinct points. Exact.
    """
    o1, o2 = orient(a, b, c), orient(a, b, d)
    o3, o4 = orient(c, d, a), orient(c, d, b)
    cross = (o1 * o2 < 0) & (o3 * o4 < 0)
    touch = (
        ((o1 == 0) & on_open_segment(a, b, c))
        | ((o2 == 0) & on_open_segment(a, b, d))
        | ((o3 == 0) & on_open_segment(c, d, a))
        | ((o4 == 0) & on_open_segment(c, d, b))
    )
    bad = np.flatnonzero(cross | touch)
    if bad.size == 0:
        return None
    m = int(bad[0])
    return m, "overlap" if adjacent[m] else "cross" if cross[m] else "touch"


def in_cone(p: Array, i: NDArray[np.int64], j: NDArray[np.int64]) -> NDArray[np.bool_]:
    """Whether the chord from vertex i towards vertex j starts into the CCW polygon ``p``."""
    n = p.shape[0]
    prev, nxt = p[(i - 1) % n], p[(i + 1) % n]
    left_of_next = orient(p[i], nxt, p[j]) > 0
    left_of_prev = orient(prev, p[i], p[j]) > 0
    convex = orient(prev, p[i], nxt) > 0
    return np.where(convex, left_of_next & left_of_prev, left_of_next | left_of_prev)


def chord_clear(p: Array, i: NDArray[np.int64], j: NDArray[np.int64]) -> NDArray[np.bool_]:
    """No vertex on the open chord and no proper edge crossing, for chords (i, j) of ``p``."""
    n = p.shape[0]
    a, b = p[i][:, None], p[j][:, None]  # (C, 1, 2)
    v, w = p[None, :], following(p)[None, :]  # (1, n, 2)
    sv = orient(a, b, v)
    sw = np.roll(sv, -1, axis=1)
    through = (sv == 0) & on_open_segment(a, b, v)
    cross = (sv * sw < 0) & (orient(v, w, a) * orient(v, w, b) < 0)
    ends = np.arange(n)[None, :]
    at_end = (ends == i[:, None]) | (ends == j[:, None])
    at_end_next = np.roll(at_end, -1, axis=1)
    blocked = (through & ~at_end) | (cross & ~at_end & ~at_end_next)
    return ~blocked.any(axis=1)
