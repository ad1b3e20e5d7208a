"""Hypothesis generators and shapely oracles for the simple-polygon tests (not collected)."""

from __future__ import annotations

import math
from functools import cache

import numpy as np
import pytest
from hypothesis import assume
from hypothesis import strategies as st

# an optional package: a test module importing these helpers is skipped without it
shapely = pytest.importorskip("shapely")

GRID = 12  # integer coordinates: exact arithmetic and many collinear triples


def _points(n_min: int, n_max: int) -> st.SearchStrategy[list[tuple[int, int]]]:
    pt = st.tuples(st.integers(0, GRID), st.integers(0, GRID))
    return st.lists(pt, min_size=n_min, max_size=n_max, unique=True)


def is_simple_polygon(coords: np.ndarray) -> bool:
    """shapely's opinion: a simple ring bounding a valid polygon of positive area."""
    ring = shapely.LinearRing(coords)
    poly = shapely.Polygon(coords)
    return bool(ring.is_simple and poly.is_valid and poly.area > 0)


@st.composite
def star_polygons(draw: st.DrawFn, n_min: int = 4, n_max: int = 10) -> np.ndarray:
    """Points sorted by angle around their centroid (star-shaped when simple)."""
    pts = np.array(draw(_points(n_min, n_max)), dtype=float)
    c = pts.mean(axis=0) + 0.01  # off-grid centre: no point sits on it
    ang = np.arctan2(pts[:, 1] - c[1], pts[:, 0] - c[0])
    dist = np.hypot(*(pts - c).T)
    poly = pts[np.lexsort((dist, ang))]
    assume(is_simple_polygon(poly))
    return poly


def _crosses(p, q, r, s) -> bool:
    def o(a, b, c):
        return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])

    return o(p, q, r) * o(p, q, s) < 0 and o(r, s, p) * o(r, s, q) < 0


@st.composite
def simple_polygons(draw: st.DrawFn, n_min: int = 4, n_max: int = 10) -> np.ndarray:
    """Random order untangled by 2-opt moves (each strictly shortens the tour)."""
    pts = [tuple(p) for p in draw(_points(n_min, n_max))]
    order = draw(st.permutations(range(len(pts))))
    ring = [pts[k] for k in order]
    n = len(ring)
    for _ in range(200):
        swap = None
        for e in range(n):
            for f in range(e + 2, n):
                if e == 0 and f == n - 1:
                    continue
                if _crosses(ring[e], ring[e + 1], ring[f], ring[(f + 1) % n]):
                    swap = (e, f)
                    break
            if swap:
                break
        if swap is None:
            break
        e, f = swap
        ring[e + 1 : f + 1] = ring[e + 1 : f + 1][::-1]
    poly = np.array(ring, dtype=float)
    assume(is_simple_polygon(poly))
    return poly


def oracle_mask(ccw: np.ndarray) -> np.ndarray:
    """Diagonals by shapely DE-9IM: the open chord lies in the polygon's interior."""
    n = len(ccw)
    poly = shapely.Polygon(ccw)
    ok = np.zeros((n, n), dtype=bool)
    for i in range(n):
        for j in range(i + 1, n):
            if j == i + 1 or (i == 0 and j == n - 1):
                ok[i, j] = ok[j, i] = True
                continue
            line = shapely.LineString([ccw[i], ccw[j]])
            ok[i, j] = ok[j, i] = shapely.relate_pattern(line, poly, "1FF******")
    return ok


def triangle_inside_fn(ccw: np.ndarray):
    """``inside(i, k, j)``: triangle of positive area covered by the polygon (shapely)."""
    poly = shapely.Polygon(ccw)

    @cache
    def inside(i: int, k: int, j: int) -> bool:
        tri = shapely.Polygon(ccw[[i, k, j]])
        return bool(tri.area > 0 and poly.covers(tri))

    return inside


def ccw_of(coords: np.ndarray) -> np.ndarray:
    """The same polygon in counter-clockwise order starting at vertex 0."""
    x, y = coords[:, 0], coords[:, 1]
    area = 0.5 * (np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))
    return coords if area > 0 else np.concatenate([coords[:1], coords[:0:-1]])


def random_star(n: int, seed: int) -> np.ndarray:
    """Float star polygon: sorted random angles, random radii in [0.3, 1]."""
    rng = np.random.default_rng(seed)
    ang = np.sort(rng.uniform(0, 2 * math.pi, n))
    r = rng.uniform(0.3, 1.0, n)
    return np.column_stack((r * np.cos(ang), r * np.sin(ang)))
