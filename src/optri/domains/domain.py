"""A polygon with holes, validated: :class:`Domain` and :func:`as_domain`.

Vertices keep the caller's numbering: the exterior ring first, then each hole
in the order given, closing vertices dropped. Each ring may be given in either
orientation; :attr:`Domain.nxt` walks every ring with the domain on its left
(the exterior counter-clockwise, the holes clockwise), which is all the
algorithms need. Every sign is decided by :mod:`optri.predicates`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InvalidPolygonError
from ..polygon import find_self_intersection, normalize_vertices
from ..predicates import following, orient, segment_pair_fault

__all__ = ["Domain", "as_domain", "ring_names", "winding"]

#: Edges per block in the pairwise test of edges of different rings.
_BLOCK = 256


@dataclass(frozen=True)
class Domain:
    """A polygonal domain: one exterior ring and zero or more holes, checked.

    Attributes
    ----------
    vertices : ndarray of float64, shape (N, 2)
        All vertices, exterior ring first, then each hole (input order).
    sizes : tuple of int
        Vertices per ring: the exterior's first, then each hole's.
    nxt, prv : ndarray of int64, shape (N,)
        Boundary successor and predecessor: the domain lies to the left of
        every edge ``v -> nxt[v]``.
    orientation : {"ccw", "cw"}
        Orientation of the exterior ring as given.

    Examples
    --------
    >>> d = as_domain([[0, 0], [4, 0], [4, 4], [0, 4]], [[[1, 1], [2, 1], [2, 2], [1, 2]]])
    >>> d.n, d.holes, d.sizes, d.area
    (8, 1, (4, 4), 15.0)
    >>> d.nxt.tolist()              # the hole was counter-clockwise: walked backwards
    [1, 2, 3, 0, 7, 4, 5, 6]
    """

    vertices: NDArray[np.float64]
    sizes: tuple[int, ...]
    nxt: NDArray[np.int64]
    prv: NDArray[np.int64]
    orientation: str

    @property
    def n(self) -> int:
        """Number of vertices, all rings together."""
        return int(self.vertices.shape[0])

    @property
    def holes(self) -> int:
        """Number of holes."""
        return len(self.sizes) - 1

    @property
    def starts(self) -> NDArray[np.int64]:
        """Index of each ring's first vertex."""
        return np.concatenate(([0], np.cumsum(self.sizes)[:-1])).astype(np.int64)

    @property
    def ring(self) -> NDArray[np.int64]:
        """Ring of each vertex: 0 for the exterior, k for hole k."""
        return np.repeat(np.arange(len(self.sizes)), self.sizes).astype(np.int64)

    @property
    def area(self) -> float:
        """Area of the domain: the exterior's minus the holes'."""
        p = self.vertices
        return float(0.5 * np.sum(p[:, 0] * p[self.nxt, 1] - p[self.nxt, 0] * p[:, 1]))

    def is_side(self, a: NDArray[np.int64], b: NDArray[np.int64]) -> NDArray[np.bool_]:
        """Whether vertex pairs ``(a, b)`` are boundary edges (in either direction)."""
        a, b = np.asarray(a), np.asarray(b)
        return (self.nxt[a] == b) | (self.nxt[b] == a)


def ring_names(sizes: Sequence[object]) -> list[str]:
    """``["exterior", "hole 1", ...]``, one per ring: how messages name the rings."""
    return ["exterior"] + [f"hole {k}" for k in range(1, len(sizes))]


def as_domain(exterior: ArrayLike, holes: Sequence[ArrayLike] = ()) -> Domain:
    """Check an exterior ring and its holes and return a :class:`Domain`.

    Parameters
    ----------
    exterior : array_like, shape (n, 2)
        The outer ring, either orientation; a closing vertex equal to the
        first is dropped.
    holes : sequence of array_like
        The holes' rings, each as ``exterior``.

    Returns
    -------
    Domain

    Raises
    ------
    InvalidPolygonError
        A ring with fewer than 3 vertices, non-finite or repeated vertices
        (in any ring), a ring that is not simple or has no area, two rings that
        cross or touch, a hole outside the exterior or inside another hole.
        The message names the ring and the vertices by their domain indices.

    Examples
    --------
    >>> as_domain([[0, 0], [4, 0], [0, 4]], [[[3, 3], [4, 3], [3, 4]]])
    Traceback (most recent call last):
    ...
    optri.errors.InvalidPolygonError: hole 1 lies outside the exterior ring; ...
    """
    rings = [exterior, *holes]
    names = ring_names(rings)
    arrays = [_ring_array(r, name) for r, name in zip(rings, names)]
    sizes = tuple(len(a) for a in arrays)
    pts = np.concatenate(arrays)
    _require_distinct(pts, sizes)
    starts = np.concatenate(([0], np.cumsum(sizes)[:-1]))
    nxt = np.empty(len(pts), dtype=np.int64)
    orientation = "ccw"
    for k, (s, m) in enumerate(zip(starts, sizes)):
        ring = arrays[k]
        if _collinear(ring):
            raise InvalidPolygonError(f"{names[k]} has no area: its vertices are collinear")
        hit = find_self_intersection(ring)
        if hit is not None:
            e, f, how = hit
            raise InvalidPolygonError(
                f"{names[k]} is not simple: edges {_edge(s, m, e)} and {_edge(s, m, f)} {how}"
            )
        local = np.arange(m)
        ccw = _turns_left(ring)
        forward = ccw == (k == 0)  # exterior counter-clockwise, holes clockwise
        nxt[s + local] = s + ((local + 1) % m if forward else (local - 1) % m)
        if k == 0:
            orientation = "ccw" if ccw else "cw"
    prv = np.empty_like(nxt)
    prv[nxt] = np.arange(len(pts))
    domain = Domain(pts, sizes, nxt, prv, orientation)
    _require_apart(domain, names)
    _require_nested(domain, names)
    return domain


def _ring_array(ring: ArrayLike, name: str) -> NDArray[np.float64]:
    try:
        arr = normalize_vertices(ring, values=False)
    except InvalidPolygonError as exc:
        raise InvalidPolygonError(f"{name}: {exc}") from None
    if arr.shape[1] != 2:
        raise InvalidPolygonError(
            f"{name}: a polygon with holes needs 2-D vertices, got shape {arr.shape}"
        )
    return arr


def _turns_left(ring: NDArray[np.float64]) -> bool:
    """Whether a simple ring runs counter-clockwise (exact turn at its lowest-leftmost vertex)."""
    i = int(np.lexsort((ring[:, 1], ring[:, 0]))[0])
    m = len(ring)
    return bool(orient(ring[(i - 1) % m], ring[i], ring[(i + 1) % m]) > 0)


def _collinear(ring: NDArray[np.float64]) -> bool:
    """Every vertex on the line through the first two (exactly, by :func:`orient`)."""
    a = np.broadcast_to(ring[0], ring.shape)
    b = np.broadcast_to(ring[1], ring.shape)
    return bool((orient(a, b, ring) == 0).all())


def _named(domain: Domain, a: int) -> str:
    """Boundary edge ``a -> nxt[a]`` named in input order, as ``"u-v"`` with v after u."""
    b = int(domain.nxt[a])
    k = int(domain.ring[a])
    s, m = int(domain.starts[k]), domain.sizes[k]
    return f"{a}-{b}" if b == s + (a - s + 1) % m else f"{b}-{a}"


def _edge(start: int, size: int, e: int) -> str:
    return f"{start + e}-{start + (e + 1) % size}"


def _require_distinct(pts: NDArray[np.float64], sizes: tuple[int, ...]) -> None:
    _, first, counts = np.unique(pts, axis=0, return_index=True, return_counts=True)
    if (counts > 1).any():
        row = pts[first[np.flatnonzero(counts > 1)[0]]]
        i, j = np.flatnonzero(np.all(pts == row, axis=1))[:2]
        ring = np.repeat(np.arange(len(sizes)), sizes)
        names = ring_names(sizes)
        raise InvalidPolygonError(
            f"vertex {j} ({names[ring[j]]}) repeats vertex {i} ({names[ring[i]]}); "
            f"rings may not share vertices: remove duplicates"
        )


def _require_apart(domain: Domain, names: list[str]) -> None:
    """No edge of one ring meets an edge of another (they share no vertex)."""
    p, nxt, ring = domain.vertices, domain.nxt, domain.ring
    q = p[nxt]
    lo, hi = np.minimum(p, q), np.maximum(p, q)
    n = domain.n
    for start in range(0, n, _BLOCK):
        rows = np.arange(start, min(start + _BLOCK, n))
        near = (lo[rows, None, 0] <= hi[None, :, 0]) & (lo[None, :, 0] <= hi[rows, None, 0])
        near &= (lo[rows, None, 1] <= hi[None, :, 1]) & (lo[None, :, 1] <= hi[rows, None, 1])
        near &= ring[rows, None] < ring[None, :]
        r, f = np.nonzero(near)
        e = rows[r]
        hit = segment_pair_fault(p[e], q[e], p[f], q[f], np.zeros(len(e), dtype=bool))
        if hit is not None:
            m, how = hit
            a, b = int(e[m]), int(f[m])
            raise InvalidPolygonError(
                f"{names[ring[a]]} and {names[ring[b]]} meet: edges {_named(domain, a)} and "
                f"{_named(domain, b)} {how}; rings must be disjoint"
            )


def winding(ring: NDArray[np.float64], at: NDArray[np.float64]) -> NDArray[np.int64]:
    """Winding number of the closed ``ring`` around each row of ``at`` (points off the ring).

    >>> square = np.array([[0., 0.], [2., 0.], [2., 2.], [0., 2.]])
    >>> winding(square, np.array([[1., 1.], [3., 1.]])).tolist()
    [1, 0]
    """
    shape = (len(at), len(ring), 2)
    a = np.broadcast_to(ring[None, :, :], shape)
    b = np.broadcast_to(following(ring)[None, :, :], shape)
    q = np.broadcast_to(at[:, None, :], shape)
    side = orient(a, b, q)
    up = (a[..., 1] <= q[..., 1]) & (b[..., 1] > q[..., 1]) & (side > 0)
    down = (a[..., 1] > q[..., 1]) & (b[..., 1] <= q[..., 1]) & (side < 0)
    return (up.sum(axis=1) - down.sum(axis=1)).astype(np.int64)


def _require_nested(domain: Domain, names: list[str]) -> None:
    """Each hole inside the exterior and outside every other hole.

    Rings do not meet, so one vertex of a ring tells on which side of another
    ring the whole ring lies.
    """
    p, starts, sizes = domain.vertices, domain.starts, domain.sizes
    rings = [p[s : s + m] for s, m in zip(starts, sizes)]
    firsts = p[starts]
    if domain.holes == 0:
        return
    outside = winding(rings[0], firsts[1:]) == 0
    if outside.any():
        k = int(np.flatnonzero(outside)[0]) + 1
        raise InvalidPolygonError(
            f"{names[k]} lies outside the exterior ring; every hole must lie inside it"
        )
    for k in range(1, len(rings)):
        inside = winding(rings[k], firsts[1:]) != 0
        inside[k - 1] = False
        if inside.any():
            j = int(np.flatnonzero(inside)[0]) + 1
            raise InvalidPolygonError(
                f"{names[j]} lies inside {names[k]}; holes may not nest (give the inner "
                f"ring as a separate polygon)"
            )
