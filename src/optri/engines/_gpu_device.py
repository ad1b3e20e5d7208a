"""CUDA device functions of the GPU engine: built-in triangle weights and ``combine``.

Every built-in weight of :mod:`optri.weights` is computed here from vertex
coordinates, selected by its integer code, so one kernel serves them all. The
arithmetic follows the Python weights term by term (same sides, same order of
additions) so both agree to a few ulps (``tests/test_weights.py`` checks every
weight code, under the CUDA simulator). Built lazily: importing this module does
not import numba.
"""

from __future__ import annotations

import functools
from types import SimpleNamespace

from ..weights import WeightCode

__all__ = ["OBJ_MAX", "OBJ_SUM", "device_functions"]

#: Objective codes passed to the kernels.
OBJ_SUM = 0
OBJ_MAX = 1


@functools.cache
def device_functions() -> SimpleNamespace:
    """Compile-on-first-use device functions ``dist``, ``edge``, ``weight``, ``combine``.

    ``pts`` is an ``(n, 3)`` float64 array (z = 0 for planar input; x holds the
    value of 1-D input), ``dim`` the input's dimension (1, 2 or 3).
    """
    import math

    from numba import cuda

    inf = math.inf
    pi = math.pi
    # plain ints, frozen into the kernels (the codes of optri.weights.WeightCode)
    PERIMETER, DIAGONAL = int(WeightCode.PERIMETER), int(WeightCode.DIAGONAL)
    AREA = int(WeightCode.AREA)
    PRODUCT, ASPECT_RATIO = int(WeightCode.PRODUCT), int(WeightCode.ASPECT_RATIO)
    MAX_ANGLE, MIN_ANGLE = int(WeightCode.MAX_ANGLE), int(WeightCode.MIN_ANGLE)

    @cuda.jit(device=True)
    def dist(pts, a, b):
        dx = pts[a, 0] - pts[b, 0]
        dy = pts[a, 1] - pts[b, 1]
        dz = pts[a, 2] - pts[b, 2]
        return math.sqrt(dx * dx + dy * dy + dz * dz)

    @cuda.jit(device=True)
    def edge(code, n, pts, a, b):
        # e(a, b) of the edge-decomposable weights; "diagonal" skips polygon sides
        d = dist(pts, a, b)
        if code == DIAGONAL:
            lo = min(a, b)
            hi = max(a, b)
            if hi - lo == 1 or (lo == 0 and hi == n - 1):
                return 0.0
            return 0.5 * d
        return d

    @cuda.jit(device=True)
    def angle(x, y, z):
        # angle opposite side x (law of cosines, clamped as in optri.weights)
        den = 2.0 * y * z
        if den == 0.0:
            return pi
        return math.acos(max(-1.0, min(1.0, (y * y + z * z - x * x) / den)))

    @cuda.jit(device=True)
    def area(dim, pts, i, k, j):
        ux = pts[k, 0] - pts[i, 0]
        uy = pts[k, 1] - pts[i, 1]
        vx = pts[j, 0] - pts[i, 0]
        vy = pts[j, 1] - pts[i, 1]
        if dim == 2:
            return 0.5 * abs(ux * vy - uy * vx)
        uz = pts[k, 2] - pts[i, 2]
        vz = pts[j, 2] - pts[i, 2]
        cx = uy * vz - uz * vy
        cy = uz * vx - ux * vz
        cz = ux * vy - uy * vx
        return 0.5 * math.sqrt(cx * cx + cy * cy + cz * cz)

    @cuda.jit(device=True)
    def weight(code, dim, n, pts, i, k, j):
        if code == PERIMETER or code == DIAGONAL:
            return edge(code, n, pts, i, k) + edge(code, n, pts, k, j) + edge(code, n, pts, i, j)
        if code == AREA:
            return area(dim, pts, i, k, j)
        if code == PRODUCT:
            return pts[i, 0] * pts[k, 0] * pts[j, 0]
        a = dist(pts, k, j)
        b = dist(pts, i, j)
        c = dist(pts, i, k)
        if code == ASPECT_RATIO:
            s = 0.5 * (a + b + c)
            q = (s - a) * (s - b) * (s - c)
            if q <= 0.0:
                return inf
            return a * b * c / (8.0 * q)
        ta = angle(a, b, c)
        tb = angle(b, c, a)
        tc = angle(c, a, b)
        if code == MAX_ANGLE:
            return max(ta, max(tb, tc))
        if code == MIN_ANGLE:
            return -min(ta, min(tb, tc))
        return inf

    @cuda.jit(device=True)
    def combine(obj, a, b, w):
        if obj == OBJ_SUM:
            return a + b + w
        return max(max(a, b), w)

    @cuda.jit(device=True)
    def candidate(tab, pts, dim, n, code, obj, eform, i, k, j):
        # cost of splitting chord (i, j) at k, read from the table: row i is
        # contiguous in k above the diagonal, row j holds column j transposed
        a = tab[i, k]
        b = tab[j, k]
        if eform:
            return a + b
        return combine(obj, a, b, weight(code, dim, n, pts, i, k, j))

    @cuda.jit(device=True)
    def scan(tab, pts, dim, n, code, obj, eform, i, j, first, step):
        # best split of (i, j) over k = first, first + step, ... < j; ties to the
        # smallest k (strict less), -1 when every candidate is infinite
        best = inf
        arg = -1
        for k in range(first, j, step):
            v = candidate(tab, pts, dim, n, code, obj, eform, i, k, j)
            if v < best:
                best = v
                arg = k
        return best, arg

    return SimpleNamespace(
        dist=dist,
        edge=edge,
        weight=weight,
        combine=combine,
        candidate=candidate,
        scan=scan,
    )
