"""A stack of planar slices: checked contours, their nesting and their overlaps.

Each slice is a plane z = const holding closed, simple, pairwise disjoint
contours. A contour inside an odd number of others bounds a hole; contours are
stored counter-clockwise (seen from +z) when they bound material, clockwise
when they bound a hole, so one tiling rule orients every surface outward.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import InvalidPolygonError
from ..polygon import require_simple, signed_area
from ..predicates import orient
from .tiling import as_contour

__all__ = ["Slice", "as_slices", "contours_overlap"]


@dataclass
class Slice:
    """One plane of the stack: its height and its oriented contours (2-D, (k, 2))."""

    z: float
    contours: list[NDArray[np.float64]]
    depth: list[int] = field(default_factory=list)
    parent: list[int] = field(default_factory=list)


def as_slices(slices: Any) -> list[Slice]:
    """Check a stack and return its slices sorted by z, contours oriented and nested.

    ``slices`` is a sequence of ``(z, [contour, ...])`` pairs with 2-D
    contours, or a flat sequence of 3-D contours (each on one plane z = const),
    grouped by z.

    >>> sq = [[0, 0], [1, 0], [1, 1], [0, 1]]
    >>> [(s.z, len(s.contours)) for s in as_slices([(1.0, [sq]), (0.0, [sq[::-1]])])]
    [(0.0, 1), (1.0, 1)]
    """
    groups: dict[float, list[NDArray[np.float64]]] = {}
    items = list(slices)
    if not items:
        raise InvalidPolygonError("no slices: a stack needs at least one contour")
    for k, item in enumerate(items):
        if _is_pair(item):
            z = _height(item[0], f"slice {k}")
            for c, ring in enumerate(item[1]):
                pts = as_contour(ring, f"slice z={z:g}, contour {c}")
                groups.setdefault(z, []).append(pts[:, :2].copy())
        else:
            pts = as_contour(item, f"contour {k}")
            if np.asarray(item, dtype=float).shape[1] != 3:
                raise InvalidPolygonError(
                    f"contour {k}: a flat list of contours needs (k, 3) points (x, y, z); "
                    f"give 2-D contours as (z, [contour, ...]) pairs"
                )
            if not np.all(pts[:, 2] == pts[0, 2]):
                raise InvalidPolygonError(
                    f"contour {k} is not planar: its z runs from {pts[:, 2].min():g} to "
                    f"{pts[:, 2].max():g}; each contour must lie on one plane z = const"
                )
            groups.setdefault(float(pts[0, 2]), []).append(pts[:, :2].copy())
    return [_checked_slice(z, groups[z]) for z in sorted(groups)]


def _is_pair(item: Any) -> bool:
    return (
        isinstance(item, (tuple, list))
        and len(item) == 2
        and np.ndim(item[0]) == 0
        and isinstance(item[1], (list, tuple))
    )


def _height(z: Any, name: str) -> float:
    try:
        value = float(z)
    except (TypeError, ValueError) as exc:
        raise InvalidPolygonError(f"{name}: z must be a number, got {z!r}") from exc
    if not np.isfinite(value):
        raise InvalidPolygonError(f"{name}: z must be finite, got {value}")
    return value


def _checked_slice(z: float, rings: list[NDArray[np.float64]]) -> Slice:
    for c, ring in enumerate(rings):
        try:
            require_simple(ring)
        except InvalidPolygonError as exc:
            raise InvalidPolygonError(f"slice z={z:g}, contour {c}: {exc}") from None
    for c in range(len(rings)):
        for d in range(c + 1, len(rings)):
            if _edges_meet(rings[c], rings[d]):
                raise InvalidPolygonError(
                    f"slice z={z:g}: contours {c} and {d} cross or touch; contours of one "
                    f"slice must be disjoint (nested ones are holes)"
                )
    inside = [
        [d != c and point_inside(rings[c][0], rings[d]) for d in range(len(rings))]
        for c in range(len(rings))
    ]
    depth = [sum(row) for row in inside]
    parent = []
    for row in inside:
        holders = [d for d in range(len(rings)) if row[d]]
        parent.append(max(holders, key=lambda d: depth[d]) if holders else -1)
    oriented = []
    for c, ring in enumerate(rings):
        ccw = signed_area(ring) > 0
        want_ccw = depth[c] % 2 == 0
        oriented.append(ring if ccw == want_ccw else ring[::-1].copy())
    return Slice(z, oriented, depth, parent)


def _segments(p: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    return p, np.roll(p, -1, axis=0)


def _edges_meet(p: NDArray[np.float64], q: NDArray[np.float64]) -> bool:
    """Whether an edge of ``p`` crosses or touches an edge of ``q`` (exact)."""
    a, b = _segments(p)
    c, d = _segments(q)
    a, b = a[:, None, :], b[:, None, :]
    c, d = c[None, :, :], d[None, :, :]
    o1, o2 = orient(a, b, c), orient(a, b, d)
    o3, o4 = orient(c, d, a), orient(c, d, b)
    return bool(np.any((o1 * o2 <= 0) & (o3 * o4 <= 0) & _boxes_meet(a, b, c, d)))


def _boxes_meet(a: Any, b: Any, c: Any, d: Any) -> Any:
    lo1, hi1 = np.minimum(a, b), np.maximum(a, b)
    lo2, hi2 = np.minimum(c, d), np.maximum(c, d)
    return np.all((lo1 <= hi2) & (lo2 <= hi1), axis=-1)


def point_inside(pt: NDArray[np.float64], ring: NDArray[np.float64]) -> bool:
    """Even-odd test of a point not on the ring's boundary."""
    x, y = float(pt[0]), float(pt[1])
    a, b = _segments(ring)
    straddle = (a[:, 1] > y) != (b[:, 1] > y)
    if not straddle.any():
        return False
    a, b = a[straddle], b[straddle]
    # crossing to the right of pt: orientation of (a, b, pt) against the edge's direction
    s = orient(a, b, np.broadcast_to(np.array([x, y]), a.shape))
    up = b[:, 1] > a[:, 1]
    return bool(np.count_nonzero(np.where(up, s > 0, s < 0)) % 2)


def contours_overlap(p: NDArray[np.float64], q: NDArray[np.float64], method: str = "auto") -> bool:
    """Whether two simple 2-D contours' regions overlap with positive area.

    ``method="shapely"`` measures the intersection's area; ``"exact"`` tests
    exactly whether edges cross or a vertex of one lies strictly inside the
    other (regions that only touch along a boundary do not overlap); ``"auto"``
    is shapely when installed, else exact.

    >>> sq = np.array([[0., 0], [2, 0], [2, 2], [0, 2]])
    >>> contours_overlap(sq, sq + 1, "exact"), contours_overlap(sq, sq + 2, "exact")
    (True, False)
    """
    if method == "auto":
        try:
            import shapely  # noqa: F401
        except ImportError:
            method = "exact"
        else:
            method = "shapely"
    if method == "shapely":
        from shapely.geometry import Polygon

        return bool(Polygon(p).intersection(Polygon(q)).area > 0.0)
    a, b = _segments(p)
    c, d = _segments(q)
    a, b, c, d = a[:, None, :], b[:, None, :], c[None, :, :], d[None, :, :]
    o1, o2 = orient(a, b, c), orient(a, b, d)
    o3, o4 = orient(c, d, a), orient(c, d, b)
    if np.any((o1 * o2 < 0) & (o3 * o4 < 0)):
        return True
    if np.array_equal(_canonical(p), _canonical(q)):
        return True
    return any(_strictly_inside(v, q) for v in p) or any(_strictly_inside(v, p) for v in q)


def ring_within(p: NDArray[np.float64], q: NDArray[np.float64]) -> bool:
    """Whether ring ``p`` lies inside ring ``q`` (edges disjoint, a vertex inside)."""
    return not _edges_meet(p, q) and point_inside(p[0], q)


def _canonical(p: NDArray[np.float64]) -> NDArray[np.float64]:
    k = int(np.lexsort((p[:, 1], p[:, 0]))[0])
    r = np.roll(p, -k, axis=0)
    return r if signed_area(r) > 0 else np.roll(r[::-1], 1, axis=0)


def _strictly_inside(pt: NDArray[np.float64], ring: NDArray[np.float64]) -> bool:
    a, b = _segments(ring)
    on = orient(a, b, np.broadcast_to(pt, a.shape)) == 0
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    if np.any(on & np.all((pt >= lo) & (pt <= hi), axis=1)):
        return False
    return point_inside(pt, ring)


def nesting_rings(s: Slice, members: Sequence[int]) -> list[list[int]]:
    """Group contours ``members`` of a slice into caps: each an outer ring and its holes.

    A member whose parent is a member and the outer ring of a cap is a hole of
    that cap; otherwise (an island in a hole, say) it is the outer ring of a
    cap of its own.
    """
    chosen = set(members)
    outer: dict[int, bool] = {}
    caps: dict[int, list[int]] = {}
    for c in sorted(chosen, key=lambda c: (s.depth[c], c)):
        up = s.parent[c]
        outer[c] = not (up in chosen and outer[up])
        if outer[c]:
            caps[c] = [c]
        else:
            caps[up].append(c)
    return list(caps.values())
