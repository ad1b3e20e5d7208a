"""What a triangulation of a domain may use: valid diagonals and candidate triangles.

A *valid diagonal* joins two vertices through the domain's interior: it starts
into the domain at both ends (in-cone test at each end, against the two
boundary edges there), crosses no boundary edge and passes through no vertex.
A *candidate triangle* has three sides that are boundary edges (run in the
boundary's direction, so the triangle lies on the domain's side) or valid
diagonals, positive area, and no hole inside it. Every triangulation of the
domain is a set of candidate triangles, and every candidate triangle lies in
some triangulation. All signs come from :mod:`optri.predicates`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..predicates import on_open_segment, orient
from .domain import Domain

__all__ = [
    "Candidates",
    "diagonals_and_turns",
    "find_candidates",
    "in_wedge",
    "side_signs",
    "valid_diagonals",
]

#: Elements per block of the chord-against-vertex tests (memory ~ 100 bytes each).
_CELLS = 1 << 20
#: Boundary edges on each side of a chord's ends that screen it before the full test.
_NEAR = 4


@dataclass(frozen=True)
class Candidates:
    """The candidate triangles of a domain and the edges they are made of.

    Attributes
    ----------
    edges : ndarray of int64, shape (E, 2)
        Sorted vertex pairs ``(a, b)``, ``a < b``: the N boundary edges first
        (edge ``v`` joins ``v`` and ``nxt[v]``), then the valid diagonals.
    n_boundary : int
        Number of boundary edges (the domain's vertex count).
    triangles : ndarray of int64, shape (T, 3)
        Candidate triangles, counter-clockwise.
    sides : ndarray of int64, shape (T, 3)
        Edge ids of sides ``(t0, t1)``, ``(t1, t2)``, ``(t2, t0)``.
    signs : ndarray of int8, shape (T, 3)
        +1 where the side runs from its smaller vertex to its larger one, else -1:
        which side of the edge the triangle lies on.
    turns : ndarray of int8, shape (E - N, N)
        ``orient(a, b, v)`` of every vertex ``v`` against each diagonal ``(a, b)``
        (row ``e - N`` for edge ``e``): crossing tests become look-ups.
    """

    edges: NDArray[np.int64]
    n_boundary: int
    triangles: NDArray[np.int64]
    sides: NDArray[np.int64]
    signs: NDArray[np.int8]
    turns: NDArray[np.int8]

    @property
    def is_diagonal(self) -> NDArray[np.bool_]:
        """Per edge: True for a diagonal, False for a boundary edge."""
        return np.arange(len(self.edges)) >= self.n_boundary


def in_wedge(domain: Domain, i: NDArray[np.int64], j: NDArray[np.int64]) -> NDArray[np.bool_]:
    """Whether the segment from vertex ``i`` towards vertex ``j`` starts into the domain.

    The domain's angle at ``i`` lies between the boundary edges ``prv[i] -> i``
    and ``i -> nxt[i]`` (on their left); the direction towards ``j`` must lie
    strictly inside it.
    """
    p = domain.vertices
    prev, apex, nxt, target = p[domain.prv[i]], p[i], p[domain.nxt[i]], p[j]
    left_of_next = orient(apex, nxt, target) > 0
    left_of_prev = orient(prev, apex, target) > 0
    convex = orient(prev, apex, nxt) > 0
    return np.where(convex, left_of_next & left_of_prev, left_of_next | left_of_prev)


def valid_diagonals(domain: Domain) -> NDArray[np.int64]:
    """The valid diagonals of ``domain`` as sorted pairs ``(a, b)``, ``a < b``; (D, 2).

    See :func:`diagonals_and_turns`.

    Examples
    --------
    >>> from optri.domains import as_domain
    >>> d = as_domain([[0, 0], [3, 0], [3, 3], [0, 3]], [[[1, 1], [2, 1], [2, 2], [1, 2]]])
    >>> valid_diagonals(d).tolist()   # each corner sees three hole corners
    [[0, 4], [0, 5], [0, 7], [1, 4], [1, 5], [1, 6], [2, 5], [2, 6], [2, 7], [3, 4], [3, 6], [3, 7]]
    """
    return diagonals_and_turns(domain)[0]


def diagonals_and_turns(domain: Domain) -> tuple[NDArray[np.int64], NDArray[np.int8]]:
    """The valid diagonals of ``domain``, and every vertex's side of each; (D, 2), (D, N).

    Notes
    -----
    O(N^2) in-cone tests, then each surviving chord against every vertex and
    boundary edge: O(N^3) time in numpy blocks, O(N) memory per chord. Most
    chords that are not diagonals cross a boundary edge near one of their ends,
    so those few edges screen them out first.
    """
    n = domain.n
    i, j = np.triu_indices(n, 1)
    keep = ~domain.is_side(i, j)
    i, j = i[keep], j[keep]
    ok = in_wedge(domain, i, j)
    i, j = i[ok], j[ok]
    ok = in_wedge(domain, j, i)
    i, j = i[ok], j[ok]
    k = np.arange(n)
    edge_sides = side_signs(domain.vertices, np.column_stack((k, domain.nxt)))
    # most chords that are not diagonals leave the domain close to an end: screen those first
    keep = ~_crossed_near_ends(domain, i, j, edge_sides)
    i, j = i[keep], j[keep]
    pairs, turns = [], []
    step = max(1, _CELLS // n)
    for lo in range(0, len(i), step):
        ci, cj = i[lo : lo + step], j[lo : lo + step]
        blocked, sv = _crossed(domain, ci, cj, k, edge_sides, through=True)
        pairs.append(np.column_stack((ci[~blocked], cj[~blocked])))
        turns.append(sv[~blocked])
    if not pairs:
        return np.zeros((0, 2), dtype=np.int64), np.zeros((0, n), dtype=np.int8)
    return np.concatenate(pairs).astype(np.int64), np.concatenate(turns)


def side_signs(
    points: NDArray[np.float64], seg: NDArray[np.int64], at: NDArray[np.int64] | None = None
) -> NDArray[np.int8]:
    """``orient(a, b, p)`` of points ``p`` (all, or those ``at``) against segments ``(a, b)``.

    Returns an ``(S, P)`` int8 array.
    """
    targets = points if at is None else points[at]
    out = np.empty((len(seg), len(targets)), dtype=np.int8)
    step = max(1, _CELLS // max(len(targets), 1))
    for lo in range(0, len(seg), step):
        s = seg[lo : lo + step]
        shape = (len(s), len(targets), 2)
        a = np.broadcast_to(points[s[:, 0]][:, None, :], shape)
        b = np.broadcast_to(points[s[:, 1]][:, None, :], shape)
        out[lo : lo + step] = orient(a, b, np.broadcast_to(targets[None, :, :], shape))
    return out


def _crossed_near_ends(
    domain: Domain, i: NDArray[np.int64], j: NDArray[np.int64], edge_sides: NDArray[np.int8]
) -> NDArray[np.bool_]:
    """Chords ``(i, j)`` crossed properly by one of the ``_NEAR`` boundary edges around an end."""
    p, nxt, prv = domain.vertices, domain.nxt, domain.prv
    out = np.zeros(len(i), dtype=bool)
    step = max(1, _CELLS // (8 * _NEAR))
    for lo in range(0, len(i), step):
        ci, cj = i[lo : lo + step], j[lo : lo + step]
        for base in (ci, cj):
            walk = [base]
            for _ in range(_NEAR):
                walk.insert(0, prv[walk[0]])
            for _ in range(_NEAR + 1):
                walk.append(nxt[walk[-1]])
            ring = np.stack(walk, axis=1)  # (C, 2 NEAR + 2) consecutive boundary vertices
            shape = (*ring.shape, 2)
            a = np.broadcast_to(p[ci][:, None, :], shape)
            b = np.broadcast_to(p[cj][:, None, :], shape)
            side = orient(a, b, p[ring])
            starts = ring[:, :-1]
            apart = edge_sides[starts, ci[:, None]] * edge_sides[starts, cj[:, None]] < 0
            hit = (side[:, :-1] * side[:, 1:] < 0) & apart
            out[lo : lo + step] |= hit.any(axis=1)
    return out


def _crossed(
    domain: Domain,
    i: NDArray[np.int64],
    j: NDArray[np.int64],
    edges: NDArray[np.int64],
    edge_sides: NDArray[np.int8],
    through: bool = False,
) -> tuple[NDArray[np.bool_], NDArray[np.int8]]:
    """Chords ``(i, j)`` crossed properly by a boundary edge ``e -> nxt[e]`` of ``edges``.

    ``edge_sides[e, v]``: the side of edge ``e`` vertex ``v`` is on. With
    ``through`` (``edges`` all of them), a vertex on the open chord blocks it too.
    Also returns the chords' sides of the edges' ends.
    """
    p, nxt = domain.vertices, domain.nxt
    ends = np.unique(np.concatenate((edges, nxt[edges])))
    col = np.full(domain.n, -1, dtype=np.int64)
    col[ends] = np.arange(len(ends))
    sv = side_signs(p, np.column_stack((i, j)), ends)  # (C, ends): chord sides
    ends_apart = (edge_sides[edges][:, i] * edge_sides[edges][:, j]).T < 0
    blocked = ((sv[:, col[edges]] * sv[:, col[nxt[edges]]] < 0) & ends_apart).any(axis=1)
    if through:
        r, v = np.nonzero(sv == 0)  # collinear: on the open chord, or beyond it
        v = ends[v]
        on = on_open_segment(p[i[r]], p[j[r]], p[v])
        blocked[r[on]] = True
    return blocked, sv


def find_candidates(domain: Domain, diagonals: NDArray[np.int64] | None = None) -> Candidates:
    """Every candidate triangle of ``domain`` with its sides' edge ids.

    Examples
    --------
    >>> from optri.domains import as_domain
    >>> d = as_domain([[0, 0], [3, 0], [3, 3], [0, 3]], [[[1, 1], [2, 1], [2, 2], [1, 2]]])
    >>> c = find_candidates(d)
    >>> len(c.edges), len(c.triangles)      # 8 boundary edges + 12 diagonals
    (20, 16)
    """
    if diagonals is None:
        diagonals, turns = diagonals_and_turns(domain)
    else:
        turns = side_signs(domain.vertices, diagonals)
    n = domain.n
    k = np.arange(n)
    boundary = np.sort(np.column_stack((k, domain.nxt)), axis=1)
    edges = np.concatenate((boundary, diagonals)).astype(np.int64)
    usable = np.zeros((n, n), dtype=bool)
    usable[edges[:, 0], edges[:, 1]] = True
    usable |= usable.T
    tris = _oriented_triples(domain, usable)
    tris = tris[_empty(domain, tris)]
    tris = tris[np.lexsort((tris[:, 2], tris[:, 1], tris[:, 0]))]
    sides, signs = _side_ids(edges, n, tris)
    return Candidates(edges, n, tris, sides, signs, turns)


def _oriented_triples(domain: Domain, usable: NDArray[np.bool_]) -> NDArray[np.int64]:
    """Triples of pairwise usable vertices, made counter-clockwise, boundary sides inward."""
    n = domain.n
    found = []
    for a in range(n - 2):
        nb = np.flatnonzero(usable[a, a + 1 :]) + a + 1
        if len(nb) < 2:
            continue
        bi, ci = np.nonzero(np.triu(usable[np.ix_(nb, nb)], 1))
        if len(bi):
            found.append(np.column_stack((np.full(len(bi), a), nb[bi], nb[ci])))
    if not found:
        return np.zeros((0, 3), dtype=np.int64)
    t = np.concatenate(found).astype(np.int64)
    p = domain.vertices
    turn = orient(p[t[:, 0]], p[t[:, 1]], p[t[:, 2]])
    t = t[turn != 0]
    cw = turn[turn != 0] < 0
    t[cw] = t[cw][:, [0, 2, 1]]
    ok = np.ones(len(t), dtype=bool)
    for x, y in ((0, 1), (1, 2), (2, 0)):
        a, b = t[:, x], t[:, y]
        ok &= ~domain.is_side(a, b) | (domain.nxt[a] == b)  # a boundary side runs forward
    return t[ok]


def _empty(domain: Domain, tris: NDArray[np.int64]) -> NDArray[np.bool_]:
    """No hole inside each triangle (whose sides are usable).

    Sides cross no boundary and pass through no vertex, so a hole is either
    wholly outside the triangle or inside it but for corners; then every
    vertex of it that is not a corner lies strictly inside. Testing four
    vertices of each hole (not all corners) decides it.
    """
    if domain.holes == 0 or len(tris) == 0:
        return np.ones(len(tris), dtype=bool)
    reps = np.concatenate(
        [s + np.arange(min(4, m)) for s, m in zip(domain.starts[1:], domain.sizes[1:])]
    )
    p = domain.vertices
    ok = np.ones(len(tris), dtype=bool)
    step = max(1, _CELLS // len(reps))
    for lo in range(0, len(tris), step):
        t = tris[lo : lo + step]
        shape = (len(t), len(reps), 2)
        a, b, c = (np.broadcast_to(p[t[:, m]][:, None, :], shape) for m in range(3))
        r = np.broadcast_to(p[reps][None, :, :], shape)
        inside = (orient(a, b, r) > 0) & (orient(b, c, r) > 0) & (orient(c, a, r) > 0)
        ok[lo : lo + step] = ~inside.any(axis=1)
    return ok


def _side_ids(
    edges: NDArray[np.int64], n: int, tris: NDArray[np.int64]
) -> tuple[NDArray[np.int64], NDArray[np.int8]]:
    keys = edges[:, 0] * n + edges[:, 1]
    order = np.argsort(keys)
    sides = np.empty(tris.shape, dtype=np.int64)
    signs = np.empty(tris.shape, dtype=np.int8)
    for m, (x, y) in enumerate(((0, 1), (1, 2), (2, 0))):
        a, b = tris[:, x], tris[:, y]
        lo, hi = np.minimum(a, b), np.maximum(a, b)
        pos = np.searchsorted(keys, lo * n + hi, sorter=order)
        sides[:, m] = order[pos]
        signs[:, m] = np.where(a < b, 1, -1)
    return sides, signs
