"""The candidate sets of a polygon with holes in plain numpy: the compiled core's oracle.

The definitions of ``optri.domains.candidates`` written out directly, every
sign from :func:`optri.predicates.orient` (exact), with no screening and no
threads: all chords, all boundary edges, all vertices. It returns the very
arrays ``optri.domains.find_candidates`` documents, in the same order, so the
tests compare them with ``np.array_equal``. Not collected (no ``test_`` prefix).
"""

from __future__ import annotations

import numpy as np

from optri.domains import Domain
from optri.predicates import on_open_segment, orient


def _signs(p, seg):
    """``orient(a, b, v)`` of every vertex ``v`` against each segment ``(a, b)``: (S, N)."""
    shape = (len(seg), len(p), 2)
    a = np.broadcast_to(p[seg[:, 0]][:, None, :], shape)
    b = np.broadcast_to(p[seg[:, 1]][:, None, :], shape)
    return orient(a, b, np.broadcast_to(p[None, :, :], shape)).astype(np.int8)


def _in_wedge(d: Domain, i, j):
    """The segment from ``i`` towards ``j`` starts strictly inside the domain's angle at ``i``."""
    p = d.vertices
    prev, apex, nxt, target = p[d.prv[i]], p[i], p[d.nxt[i]], p[j]
    left_of_next = orient(apex, nxt, target) > 0
    left_of_prev = orient(prev, apex, target) > 0
    convex = orient(prev, apex, nxt) > 0
    return np.where(convex, left_of_next & left_of_prev, left_of_next | left_of_prev)


def diagonals_and_turns(d: Domain):
    """Valid diagonals (sorted pairs, ``triu_indices`` order) and their turn rows."""
    n, p, nxt = d.n, d.vertices, d.nxt
    i, j = np.triu_indices(n, 1)
    keep = ~d.is_side(i, j) & _in_wedge(d, i, j) & _in_wedge(d, j, i)
    i, j = i[keep], j[keep]
    if len(i) == 0:
        return np.zeros((0, 2), dtype=np.int64), np.zeros((0, n), dtype=np.int8)
    edge_sides = _signs(p, np.column_stack((np.arange(n), nxt)))  # (edge, vertex)
    chord = _signs(p, np.column_stack((i, j)))  # (chord, vertex)
    # a boundary edge e -> nxt[e] crosses the chord properly: each one's ends on both sides
    ends_apart = chord[:, np.arange(n)] * chord[:, nxt] < 0
    chord_apart = (edge_sides[:, i] * edge_sides[:, j]).T < 0
    crossed = (ends_apart & chord_apart).any(axis=1)
    r, v = np.nonzero(chord == 0)  # collinear: a vertex on the open chord blocks it
    through = np.zeros(len(i), dtype=bool)
    through[r[on_open_segment(p[i[r]], p[j[r]], p[v])]] = True
    ok = ~crossed & ~through
    return np.column_stack((i[ok], j[ok])).astype(np.int64), chord[ok]


def find_candidates(d: Domain):
    """``(edges, triangles, sides, signs, turns)`` as :class:`optri.domains.Candidates` holds."""
    n, p = d.n, d.vertices
    diagonals, turns = diagonals_and_turns(d)
    k = np.arange(n)
    edges = np.concatenate((np.sort(np.column_stack((k, d.nxt)), axis=1), diagonals))
    usable = np.zeros((n, n), dtype=bool)
    usable[edges[:, 0], edges[:, 1]] = True
    usable |= usable.T
    a, b, c = (x.ravel() for x in np.meshgrid(k, k, k, indexing="ij"))
    pick = (a < b) & (b < c)
    a, b, c = a[pick], b[pick], c[pick]
    pick = usable[a, b] & usable[b, c] & usable[a, c]
    t = np.column_stack((a[pick], b[pick], c[pick])).astype(np.int64)
    turn = orient(p[t[:, 0]], p[t[:, 1]], p[t[:, 2]])
    t = t[turn != 0]
    cw = turn[turn != 0] < 0
    t[cw] = t[cw][:, [0, 2, 1]]
    ok = np.ones(len(t), dtype=bool)
    for x, y in ((0, 1), (1, 2), (2, 0)):
        u, v = t[:, x], t[:, y]
        ok &= ~d.is_side(u, v) | (d.nxt[u] == v)  # a boundary side runs forward
    t = t[ok]
    if d.holes:  # four vertices of each hole, none strictly inside
        reps = np.concatenate([s + np.arange(min(4, m)) for s, m in zip(d.starts[1:], d.sizes[1:])])
        shape = (len(t), len(reps), 2)
        corners = [np.broadcast_to(p[t[:, m]][:, None, :], shape) for m in range(3)]
        r = np.broadcast_to(p[reps][None, :, :], shape)
        inside = np.ones(shape[:2], dtype=bool)
        for m in range(3):
            inside &= orient(corners[m], corners[(m + 1) % 3], r) > 0
        t = t[~inside.any(axis=1)]
    t = t[np.lexsort((t[:, 2], t[:, 1], t[:, 0]))]
    index = {pair: e for e, pair in enumerate(map(tuple, edges.tolist()))}
    sides = np.array(
        [
            [index[min(x, y), max(x, y)] for x, y in ((u, v), (v, w), (w, u))]
            for u, v, w in t.tolist()
        ],
        dtype=np.int64,
    ).reshape(-1, 3)
    signs = np.where(t < np.roll(t, -1, axis=1), 1, -1).astype(np.int8)
    return edges.astype(np.int64), t, sides, signs, turns


def forced_rows(turns, ends, rows):
    """Greedy maximal non-crossing subset of ``rows`` (in order), less those any row crosses."""

    def cross(x, y):
        return (
            turns[x, ends[y, 0]] * turns[x, ends[y, 1]] < 0
            and turns[y, ends[x, 0]] * turns[y, ends[x, 1]] < 0
        )

    greedy = []
    for r in rows:
        if not any(cross(r, g) for g in greedy):
            greedy.append(r)
    return [g for g in greedy if not any(cross(g, r) for r in rows)]


def link_roots(key, per):
    """Union-find roots of items (``per`` keys each) joined through equal keys."""
    items = len(key) // per
    parent = list(range(items))

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    order = np.argsort(key, kind="stable")
    e, t = key[order].tolist(), (order // per).tolist()
    for m in range(1, len(e)):
        if e[m] == e[m - 1]:
            ra, rb = find(t[m]), find(t[m - 1])
            if ra != rb:
                parent[ra] = rb
    return np.array([find(x) for x in range(items)], dtype=np.int64)
