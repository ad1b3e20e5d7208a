"""Polygons with holes for the tests: generators and a brute-force oracle (not collected).

The oracle shares nothing with optri.domains: exact rational geometry
(``fractions.Fraction``), its own validity tests, and an enumeration of every
triangulation by covering, edge after edge, the open side of the front.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import shapely
from hypothesis import assume
from hypothesis import strategies as st

from optri.weights import WEIGHTS, triangle_weight

#: Built-in weights a polygon with holes takes (every one that reads coordinates).
SUM_WEIGHTS = sorted(w for w, spec in WEIGHTS.items() if spec.needs == "points")


# --- generators -----------------------------------------------------------------------


def _star(rng, m, centre, radius, lo=0.55):
    ang = 2 * np.pi * (np.arange(m) + rng.uniform(-0.3, 0.3, m)) / m + rng.uniform(0, 2 * np.pi)
    r = radius * rng.uniform(lo, 1.0, m)
    return np.column_stack((centre[0] + r * np.cos(ang), centre[1] + r * np.sin(ang)))


def valid_rings(ext, holes) -> bool:
    """shapely's opinion: a valid polygon whose rings are pairwise apart, vertices distinct."""
    poly = shapely.Polygon(ext, holes)
    if not poly.is_valid or poly.area <= 0:
        return False
    rings = [shapely.LinearRing(ext)] + [shapely.LinearRing(h) for h in holes]
    if any(not r.is_simple for r in rings):
        return False
    for i in range(len(rings)):
        for j in range(i + 1, len(rings)):
            if rings[i].distance(rings[j]) <= 0:
                return False
    pts = np.concatenate([ext, *holes])
    return len(np.unique(pts, axis=0)) == len(pts)


@st.composite
def small_domains(draw, n_max: int = 12, holes: tuple[int, int] = (1, 2), grid: bool | None = None):
    """An exterior of 4-9 vertices and 1-2 holes of 3-4 vertices; N <= ``n_max``.

    ``grid``: integer coordinates (exact arithmetic, collinear triples), else
    floats; None draws either.
    """
    h = draw(st.integers(*holes))
    sizes = [draw(st.integers(3, 4)) for _ in range(h)]
    m = draw(st.integers(4, max(4, n_max - sum(sizes))))
    assume(m + sum(sizes) <= n_max)
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    on_grid = draw(st.booleans()) if grid is None else grid
    scale = 20.0 if on_grid else 1.0
    ext = _star(rng, m, (0.0, 0.0), scale, lo=0.7)
    centres = [rng.uniform(-0.35, 0.35, 2) * scale for _ in range(h)]
    rings = [
        _star(rng, k, c, scale * rng.uniform(0.12, 0.25), lo=0.6)[::-1]
        for k, c in zip(sizes, centres)
    ]
    if on_grid:
        ext, rings = np.round(ext), [np.round(r) for r in rings]
    assume(valid_rings(ext, rings))
    return ext, rings


# --- the oracle -----------------------------------------------------------------------


def _orient(a, b, c) -> int:
    v = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    return (v > 0) - (v < 0)


class BruteDomain:
    """Every triangulation of a small polygon with holes, by exact enumeration."""

    def __init__(self, ext, holes):
        rings = [np.asarray(ext, float)] + [np.asarray(h, float) for h in holes]
        self.sizes = [len(r) for r in rings]
        self.points = np.concatenate(rings)
        self.q = [(Fraction(x), Fraction(y)) for x, y in self.points.tolist()]
        self.n = n = len(self.q)
        self._rows = [tuple(r) for r in self.points.tolist()]
        self._weights: dict[tuple, float] = {}
        # every turn's sign, exactly, once
        self.o = [
            [[_orient(self.q[a], self.q[b], self.q[c]) for c in range(n)] for b in range(n)]
            for a in range(n)
        ]
        self.inner = set()  # directed boundary edges, domain on the left
        start = 0
        for k, m in enumerate(self.sizes):
            ring = self.q[start : start + m]
            area2 = sum(
                ring[i][0] * ring[(i + 1) % m][1] - ring[(i + 1) % m][0] * ring[i][1]
                for i in range(m)
            )
            forward = (area2 > 0) == (k == 0)
            for i in range(m):
                a, b = start + i, start + (i + 1) % m
                self.inner.add((a, b) if forward else (b, a))
            start += m

    def _cross(self, a, b, x, y) -> bool:
        """Segments ab and xy (four distinct vertices) cross properly."""
        o = self.o
        return o[a][b][x] * o[a][b][y] < 0 and o[x][y][a] * o[x][y][b] < 0

    def _inside(self, p) -> bool:
        """p strictly inside the domain (p on no boundary edge is assumed by callers)."""
        wind = 0
        for a, b in self.inner:  # inner edges: winding 1 inside the domain, 0 outside
            pa, pb = self.q[a], self.q[b]
            if pa[1] <= p[1] < pb[1] and _orient(pa, pb, p) > 0:
                wind += 1
            elif pb[1] <= p[1] < pa[1] and _orient(pa, pb, p) < 0:
                wind -= 1
        return wind == 1

    def _segment_ok(self, a, b) -> bool:
        if (a, b) in self.inner:
            return True
        if (b, a) in self.inner:
            return False
        pa, pb = self.q[a], self.q[b]
        for v in range(self.n):
            if v not in (a, b) and self.o[a][b][v] == 0 and min(pa, pb) < self.q[v] < max(pa, pb):
                return False  # a vertex on the open segment (lexicographic order on the line)
        if any(self._cross(a, b, x, y) for x, y in self.inner if len({x, y, a, b}) == 4):
            return False
        mid = ((pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2)
        return self._inside(mid)

    def triangles(self) -> list[tuple[int, int, int]]:
        """Every empty counter-clockwise triangle with valid sides, inside the domain."""
        n, o = self.n, self.o
        ok = {(a, b): self._segment_ok(a, b) for a in range(n) for b in range(n) if a != b}
        out = []
        for a in range(n):
            for b in range(a + 1, n):
                for c in range(a + 1, n):
                    if c == b or o[a][b][c] <= 0 or not (ok[a, b] and ok[b, c] and ok[c, a]):
                        continue
                    if any(
                        o[a][b][v] >= 0 and o[b][c][v] >= 0 and o[c][a][v] >= 0
                        for v in range(n)
                        if v not in (a, b, c)
                    ):
                        continue  # a vertex inside or on the triangle
                    pa, pb, pc = self.q[a], self.q[b], self.q[c]
                    if self._inside(((pa[0] + pb[0] + pc[0]) / 3, (pa[1] + pb[1] + pc[1]) / 3)):
                        out.append((a, b, c))
        return out

    def _overlap(self, t, u) -> bool:
        """Interiors of two empty triangles meet: a shared directed side, or sides crossing."""
        st = {(t[0], t[1]), (t[1], t[2]), (t[2], t[0])}
        su = {(u[0], u[1]), (u[1], u[2]), (u[2], u[0])}
        if st & su:
            return True
        return any(self._cross(a, b, x, y) for a, b in st for x, y in su if len({a, b, x, y}) == 4)

    def triangulations(self) -> list[list[tuple[int, int, int]]]:
        """Every triangulation, each once.

        Depth-first: the open edge (a directed edge whose left side must still
        be covered) with the fewest usable triangles is branched on; triangles
        overlapping a chosen one are excluded by precomputed bit masks.
        """
        tris = self.triangles()
        by_edge: dict[tuple[int, int], int] = {}
        for m, (a, b, c) in enumerate(tris):
            for e in ((a, b), (b, c), (c, a)):
                by_edge[e] = by_edge.get(e, 0) | (1 << m)
        clash = [sum(1 << v for v, u in enumerate(tris) if self._overlap(t, u)) for t in tris]
        out: list[list[tuple[int, int, int]]] = []

        def bits(mask):
            while mask:
                low = mask & -mask
                yield low.bit_length() - 1
                mask ^= low

        def grow(open_, banned, chosen):
            if not open_:
                out.append([tris[m] for m in chosen])
                return
            options = {e: by_edge.get(e, 0) & ~banned for e in open_}
            e = min(open_, key=lambda k: (bin(options[k]).count("1"), k))
            for m in bits(options[e]):
                a, b, c = tris[m]
                nxt = set(open_)
                for x, y in ((a, b), (b, c), (c, a)):
                    if (x, y) in nxt:
                        nxt.discard((x, y))
                    else:
                        nxt.add((y, x))
                grow(nxt, banned | clash[m], chosen + [m])

        grow(set(self.inner), 0, [])
        return out

    # --- weights, computed here from the formulas' definitions ---

    def weight(self, name, tri) -> float:
        """Weight ``name`` of a triangle: ``diagonal`` by its definition, others by formula."""
        a, b, c = sorted(tri)
        key = (name, a, b, c)
        if key not in self._weights:
            rows = self._rows
            if name == "diagonal":
                value = 0.0
                for x, y in ((a, b), (b, c), (a, c)):
                    if (x, y) not in self.inner and (y, x) not in self.inner:
                        value += 0.5 * math.dist(rows[x], rows[y])
            else:
                value = triangle_weight(WEIGHTS[name].code, rows, a, b, c)
            self._weights[key] = value
        return self._weights[key]

    def best(self, triangulations, name, objective="sum") -> float:
        """Optimal value of ``name`` under ``objective`` over ``triangulations``."""
        cache: dict[tuple[int, int, int], float] = {}

        def w(t):
            if t not in cache:
                cache[t] = self.weight(name, t) if isinstance(name, str) else name(*sorted(t))
            return cache[t]

        fold = math.fsum if objective == "sum" else max
        return min(fold([w(t) for t in tr]) for tr in triangulations)
