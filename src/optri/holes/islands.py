"""Several closed 3-D polylines filled as one surface: ``fill_polylines``.

A hole with islands is bounded by an outer loop and loops inside it (the borders of
other pieces of the mesh). Its patch is one connected surface, a sphere with one hole
per loop, with no vertex but the loops' own (Zou, Ju and Carr 2013 search the same
space of surfaces). Such a surface always has an edge joining two different loops
(it is connected and every vertex is on a loop); cutting it along a tree of such
*bridges*, one per island, leaves a disk whose border is one merged polygon: the
loops spliced together, each bridge's two ends appearing twice. Conversely a
triangulation of that polygon glues back into a valid surface exactly when

* no edge joins two copies of one vertex (the triangle would repeat a vertex),
* no chord lands on a loop side or a bridge (that edge would get a third face),
* no two chords land on the same pair of vertices (a doubled edge: two copies of
  the same vertex with a common neighbour, whose glued link is no longer a path).

The first two are chords forbidden outright. The third couples two chords, which a
polygon DP cannot express, so the exact search is a branch and bound: every bridge
configuration (tree of loops, bridge vertices, and where a bridge enters a vertex
that already has one) is solved as a polygon with the single-chord rules (a lower
bound), and a solution that doubles an edge is split into two subproblems, one
forbidding each chord. For Liepa's objective the dihedral across a bridge couples
the triangles on its two copies; the polygon search counts it once the apex on one
copy is fixed (the other copy then sees that triangle as its "mesh triangle"), so an
unfixed bridge gives a lower bound and is branched on its apex when it matters.
Best-first order makes the first subproblem solved without conflict optimal.

Beyond the sizes the exhaustive search allows, bridges are chosen as the closest
vertex pairs (a minimum spanning tree of the loops) and the merged polygon is filled
by Liepa's recurrence over every triangle and by the search over Zou, Ju and Carr's
candidates, the faces of the 3-D Delaunay tetrahedralization of the loops' points
(each copy of a bridge vertex standing for its point; widened as
:func:`optri.holes.candidates.candidate_sets` says when they hold no patch); the
better surface is kept and labelled ``"heuristic"``.
"""

from __future__ import annotations

import heapq
import itertools
import math
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..engines import jit
from ..errors import InvalidPolygonError, NoTriangulationError
from ..objective import Cost, ObjectiveLike
from ..result import Triangulation
from ..solve import solve_problem
from ..weights import positional_arity
from .candidates import delaunay_faces
from .liepa import angle_of_key, as_points3d, liepa_keys, power_of_two_scale
from .modes import Hole, degenerate_count, fill_all, fill_delaunay, problem_of, recompute_of
from .polyline import fill_polyline

__all__ = ["ISLAND_METHODS", "fill_polylines", "group_chords", "island_groups"]

#: Accepted ``method`` values of :func:`fill_polylines`.
ISLAND_METHODS = ("auto", "exact", "liepa", "delaunay")
#: ``method="auto"`` searches exactly up to this many merged-polygon vertices ...
EXACT_MAX_N = 40
#: ... and this many bridge configurations.
EXACT_MAX_CONFIGS = 400
#: Polygon searches the exact branch and bound runs at most (then it stops with a gap).
MAX_NODES = 20000
#: Closest pairs tried per bridge by the heuristic.
HEURISTIC_TRIES = 3

Ints = NDArray[np.int64]
Floats = NDArray[np.float64]


# --- input ----------------------------------------------------------------------------


def _loops_input(
    loops: Sequence[ArrayLike], third_points: Sequence[ArrayLike] | None
) -> tuple[Floats, list[Ints], Floats | None]:
    """(all points, each loop's point ids, thirds per point-id side or None), checked."""
    if isinstance(loops, np.ndarray) or len(loops) == 0:
        raise InvalidPolygonError("loops must be a non-empty list of (n, 3) polylines")
    pts = [as_points3d(lp) for lp in loops]
    sizes = [len(p) for p in pts]
    V = np.ascontiguousarray(np.concatenate(pts))
    if len(np.unique(V, axis=0)) < len(V):
        raise InvalidPolygonError("two loops share a point: loops must be disjoint")
    starts = np.cumsum([0, *sizes])
    ids = [np.arange(starts[i], starts[i + 1], dtype=np.int64) for i in range(len(pts))]
    T = None
    if third_points is not None:
        if len(third_points) != len(pts):
            raise InvalidPolygonError(
                f"third_points must give one (n, 3) array per loop ({len(pts)} loops), "
                f"got {len(third_points)}"
            )
        rows = []
        for p, t in zip(pts, third_points):
            arr = np.asarray(t, dtype=np.float64)
            if arr.shape != p.shape or not np.isfinite(arr).all():
                raise InvalidPolygonError(
                    f"third_points must be finite, one 3-D point per loop side, shape "
                    f"{p.shape}; got {arr.shape}"
                )
            rows.append(arr)
        T = np.concatenate(rows)
    return V, ids, T


def _plane_basis(points: Floats) -> Floats:
    """(2, 3) orthonormal basis of the best-fit plane (the normal: least variance)."""
    centred = power_of_two_scale(points)[0]
    centred = centred - centred.mean(axis=0)
    return np.linalg.svd(centred, full_matrices=False)[2][:2]  # type: ignore[no-any-return]


def _signed_area(xy: Floats) -> float:
    x, y = xy[:, 0], xy[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def _oriented(V: Floats, ids: list[Ints]) -> list[Ints]:
    """Islands turned to run opposite the outer loop in the outer loop's plane."""
    basis = _plane_basis(V[ids[0]])
    outer = _signed_area(V[ids[0]] @ basis.T)
    out = [ids[0]]
    for lp in ids[1:]:
        same = (_signed_area(V[lp] @ basis.T) > 0) == (outer > 0)
        out.append(np.roll(lp[::-1], 1) if same else lp)
    return out


def _forbidden_keys(forbidden: ArrayLike | None, nv: int, side_keys: set[int]) -> set[int]:
    if forbidden is None:
        return set()
    pairs = np.asarray(forbidden)
    if pairs.size == 0:
        return set()
    if pairs.ndim != 2 or pairs.shape[1] != 2 or not np.issubdtype(pairs.dtype, np.integer):
        raise InvalidPolygonError(
            f"forbidden must be an (m, 2) array of vertex index pairs, got shape {pairs.shape}"
        )
    a, b = pairs[:, 0].astype(np.int64), pairs[:, 1].astype(np.int64)
    if min(a.min(), b.min()) < 0 or max(a.max(), b.max()) >= nv or (a == b).any():
        raise InvalidPolygonError(
            f"forbidden pairs must join two different vertices of 0..{nv - 1}"
        )
    keys = set((np.minimum(a, b) * nv + np.maximum(a, b)).tolist())
    if keys & side_keys:
        raise InvalidPolygonError("a loop side cannot be forbidden: every patch uses it")
    return keys


# --- bridge configurations --------------------------------------------------------------


def _trees(k: int) -> Iterator[tuple[int, ...]]:
    """Parent of each island 1..k in every spanning tree of loops 0..k rooted at 0."""
    for parents in itertools.product(range(k + 1), repeat=k):
        if all(_reaches_root(i, parents) for i in range(1, k + 1)):
            yield parents


def _reaches_root(i: int, parents: tuple[int, ...]) -> bool:
    seen = set()
    while i != 0:
        if i in seen or parents[i - 1] == i:
            return False
        seen.add(i)
        i = parents[i - 1]
    return True


def _bfs(parents: tuple[int, ...]) -> list[int]:
    order, at = [], [0]
    while at:
        nxt = [i for p in at for i in range(1, len(parents) + 1) if parents[i - 1] == p]
        order += nxt
        at = nxt
    return order


def _splice(cycle: list[int], t: int, child: Ints, c: int) -> list[int]:
    """``cycle`` with loop ``child`` (started at its position ``c``) bridged in at ``t``.

    ``p = cycle[t]``: the merged polygon runs p, child from c around to c, c again,
    p again, then on, so the bridge (p, child[c]) is crossed once each way.
    """
    rot = np.roll(child, -c).tolist()
    return cycle[: t + 1] + rot + [rot[0], cycle[t]] + cycle[t + 1 :]


def _configs(ids: list[Ints]) -> Iterator[list[int]]:
    """Every merged polygon: each tree of loops, bridge pair and entry point at a vertex."""
    k = len(ids) - 1
    for parents in _trees(k):
        yield from _grow(ids[0].tolist(), _bfs(parents), parents, ids)


def _grow(cycle: list[int], order: list[int], parents: tuple[int, ...], ids: list[Ints]):  # type: ignore[no-untyped-def]
    if not order:
        yield cycle
        return
    child, rest = order[0], order[1:]
    parent = set(ids[parents[child - 1]].tolist())
    for t, p in enumerate(cycle):
        if p in parent:
            for c in range(len(ids[child])):
                yield from _grow(_splice(cycle, t, ids[child], c), rest, parents, ids)


def _config_count(ids: list[Ints], limit: int) -> int:
    """Bridge configurations, counted up to ``limit + 1``."""
    count = 0
    for _ in _configs(ids):
        count += 1
        if count > limit:
            break
    return count


def _heuristic_config(V: Floats, ids: list[Ints], rank: int, forbid: set[int]) -> list[int]:
    """One merged polygon: a minimum spanning tree of the loops (Prim's order).

    Each bridge is the ``rank``-th closest vertex pair of its two loops.
    """
    cycle = ids[0].tolist()
    inside = [0]
    left = list(range(1, len(ids)))
    while left:
        best: tuple[float, int, int, int, int] | None = None
        for i in left:
            for j in inside:
                d = np.linalg.norm(V[ids[j]][:, None, :] - V[ids[i]][None, :, :], axis=2)
                a, b = np.meshgrid(ids[j], ids[i], indexing="ij")
                keys = np.minimum(a, b) * len(V) + np.maximum(a, b)
                d[np.isin(keys, np.fromiter(forbid, np.int64))] = np.inf  # no forbidden bridge
                flat = np.argsort(d, axis=None, kind="stable")
                pick = int(flat[min(rank, len(flat) - 1)])
                pj, ci = divmod(pick, len(ids[i]))
                cand = (float(d.flat[pick]), i, j, pj, ci)
                if best is None or cand[0] < best[0]:
                    best = cand
        assert best is not None
        _, i, _, pj, ci = best
        p = int(ids[best[2]][pj])
        cycle = _splice(cycle, cycle.index(p), ids[i], ci)
        inside.append(i)
        left.remove(i)
    return cycle


# --- one merged polygon -------------------------------------------------------------------


@dataclass
class _Merged:
    """A merged polygon: ``orig[q]`` the point id at position q; its bridges' sides."""

    orig: Ints
    bridges: list[tuple[int, int]]  # (s1, s2): merged sides (p, c) and (c', p')
    allowed: NDArray[np.bool_]
    thirds: Floats  # (N, 3): the third point of each merged side
    P: Floats


def _merge(
    cycle: list[int],
    V: Floats,
    side_third: dict[tuple[int, int], Floats],
    loop_keys: set[int],
    forbid_keys: set[int],
) -> _Merged | None:
    orig = np.asarray(cycle, dtype=np.int64)
    N, nv = len(orig), len(V)
    nxt = np.roll(orig, -1)
    skeys = np.minimum(orig, nxt) * nv + np.maximum(orig, nxt)
    first: dict[int, int] = {}
    bridges = []
    for s, key in enumerate(skeys.tolist()):
        if key in loop_keys:
            continue
        if key in first:
            bridges.append((first[key], s))
        else:
            first[key] = s
    if any(int(skeys[s1]) in forbid_keys for s1, _ in bridges):
        return None  # a bridge along a forbidden pair
    lo = np.minimum.outer(orig, orig)
    hi = np.maximum.outer(orig, orig)
    pair = lo * nv + hi
    banned = np.isin(pair, np.fromiter(loop_keys | set(skeys.tolist()) | forbid_keys, np.int64))
    allowed = ~(banned | (lo == hi))
    q = np.arange(N)
    allowed[q, (q + 1) % N] = allowed[(q + 1) % N, q] = True
    thirds = np.empty((N, 3))
    for s in range(N):
        a, b = int(orig[s]), int(nxt[s])
        t = side_third.get((a, b))
        thirds[s] = V[a] if t is None else t  # V[a]: a zero-area mesh triangle counts 0
    return _Merged(orig, bridges, allowed, thirds, np.ascontiguousarray(V[orig]))


def _side_triangle_apex(tris: Ints, s: int, N: int) -> int:
    a, b = s, (s + 1) % N
    rows = np.flatnonzero((tris == a).any(axis=1) & (tris == b).any(axis=1))
    t = tris[rows[0]]
    return int(t[(t != a) & (t != b)][0])


def _force_apex(allowed: NDArray[np.bool_], s: int, x: int, N: int) -> None:
    """Clear chords so that the triangle on merged side (s, s+1) has apex x."""
    p, p1 = s, (s + 1) % N
    z = (p1 + 1) % N
    while z != x:  # chords (p, z), z strictly between p+1 and x
        allowed[p, z] = allowed[z, p] = False
        z = (z + 1) % N
    z = (x + 1) % N
    while z != p:  # chords (p+1, z), z strictly between x and p
        allowed[p1, z] = allowed[z, p1] = False
        z = (z + 1) % N


def _doubled(orig: Ints, tris: Ints, nv: int) -> tuple[tuple[int, int], tuple[int, int]] | None:
    """Two chords of a merged triangulation that land on the same vertex pair, if any."""
    e = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [0, 2]]])
    e = np.unique(np.sort(e, axis=1), axis=0)
    a, b = orig[e[:, 0]], orig[e[:, 1]]
    keys = np.minimum(a, b) * nv + np.maximum(a, b)
    order = np.argsort(keys, kind="stable")
    ks = keys[order]
    same = np.flatnonzero(ks[1:] == ks[:-1])
    N = len(orig)
    for i in same.tolist():
        c1, c2 = e[order[i]], e[order[i + 1]]
        if all(abs(int(c[0]) - int(c[1])) not in (1, N - 1) for c in (c1, c2)):
            return (int(c1[0]), int(c1[1])), (int(c2[0]), int(c2[1]))
    return None


@dataclass(order=True)
class _Node:
    bound: Any
    seq: int
    merged: _Merged = field(compare=False)
    allowed: NDArray[np.bool_] = field(compare=False)
    thirds: Floats = field(compare=False)
    forced: frozenset[int] = field(compare=False)  # bridge numbers whose apex is fixed
    tris: Ints = field(compare=False)


class _Search:
    """Solves merged polygons and values their glued surfaces."""

    def __init__(self, V: Floats, T: Floats | None, weight: Any, objective: ObjectiveLike) -> None:
        self.V, self.weight, self.objective = V, weight, objective
        self.liepa = isinstance(weight, str) and weight == "liepa"
        stack = V if T is None else np.vstack((V, T))
        self.exponent = power_of_two_scale(stack)[1]
        self.solves = 0
        self._again: dict[int, Callable[[Ints], Cost]] = {}
        self._faces: Ints | None = None  # Delaunay faces of the loops' points, once
        self.candidates: dict[str, int] = {}  # candidate sets that held the patches

    def hole(self, m: _Merged, allowed: NDArray[np.bool_], thirds: Floats) -> Hole:
        N = len(m.orig)
        if self.liepa:
            Q = np.ascontiguousarray(np.ldexp(np.vstack((m.P, thirds)), -self.exponent))
        else:
            Q = np.ascontiguousarray(np.ldexp(m.P, -self.exponent))
        weight = self._weight_of(m)
        return Hole(
            m.P, Q, self.exponent, N, self.liepa, weight, self.objective, self.liepa, allowed
        )

    def _weight_of(self, m: _Merged) -> Any:
        """The weight over merged positions: a user callable gets the loops' point numbers."""
        func = self.weight
        if not callable(func):
            return func
        orig, V = m.orig.tolist(), self.V
        if positional_arity(getattr(func, "py_func", func)) >= 4:
            return lambda _v, i, k, j: func(V, orig[i], orig[k], orig[j])
        return lambda i, k, j: func(orig[i], orig[k], orig[j])

    def solve(
        self, m: _Merged, allowed: NDArray[np.bool_], thirds: Floats, mode: str
    ) -> Ints | None:
        """The best triangulation of merged polygon ``m`` with these chords (None: none)."""
        self.solves += 1
        hole = self.hole(m, allowed, thirds)
        if mode == "delaunay":
            sub: dict[str, Any] = {}
            found = fill_delaunay(hole, sub, self.merged_faces(m))[0]
            name = str(sub.get("candidates"))
            self.candidates[name] = self.candidates.get(name, 0) + 1
            return found
        if self.liepa:
            return fill_all(hole, mode, {})[0]
        # triangle weights: the compiled engine at every size (many small searches)
        problem = problem_of(hole, allowed)
        engine = (
            "fast" if jit.unavailable() is None and jit.unsupported(problem) is None else "auto"
        )
        try:
            tris: Ints = solve_problem(problem, engine)[1].triangles
        except NoTriangulationError:
            return None
        if degenerate_count(hole.P, tris):  # the least (zero-area count, objective) instead
            return fill_all(hole, mode, {})[0]
        return tris

    def merged_faces(self, m: _Merged) -> Ints:
        """The loops' Delaunay faces on merged positions: every choice of copies."""
        if self._faces is None:
            self._faces = delaunay_faces(self.V)
        copies: list[list[int]] = [[] for _ in range(len(self.V))]
        for q, p in enumerate(m.orig.tolist()):
            copies[p].append(q)
        rows = [
            t
            for a, b, c in self._faces.tolist()
            for t in itertools.product(copies[a], copies[b], copies[c])
        ]
        if not rows:
            return np.zeros((0, 3), dtype=np.int64)
        return np.unique(np.sort(np.array(rows, dtype=np.int64), axis=1), axis=0)

    def value(self, m: _Merged, tris: Ints, thirds: Floats) -> Any:
        """The polygon search's own value of ``tris``.

        Liepa: the key, not the angle. Triangle weights: the pair (zero-area triangles,
        objective), so that the search minimises the count first, as every fill does.
        """
        hole = self.hole(m, m.allowed, thirds)
        if self.liepa:
            return liepa_keys(hole.Q, hole.n, True, tris)
        again = self._again.get(id(m))
        if again is None:
            again = self._again[id(m)] = recompute_of(hole)
        return (degenerate_count(hole.P, tris), again(tris))

    def glued_thirds(self, m: _Merged, tris: Ints) -> Floats:
        """Third points that make the search's value the glued surface's value."""
        thirds = m.thirds.copy()
        N = len(m.orig)
        for s1, s2 in m.bridges:
            thirds[s2] = m.P[_side_triangle_apex(tris, s1, N)]
        return thirds


# --- the entry point ------------------------------------------------------------------------


def fill_polylines(
    loops: Sequence[ArrayLike],
    weight: str | Callable[..., float] = "liepa",
    method: str = "auto",
    third_points: Sequence[ArrayLike] | None = None,
    *,
    objective: ObjectiveLike = "sum",
    forbidden: ArrayLike | None = None,
    orient: bool = True,
    max_nodes: int = MAX_NODES,
) -> Triangulation:
    """Optimal patch of several closed 3-D polylines: an outer loop and islands inside it.

    The patch is one connected surface bounded by all the loops, with no vertex but
    theirs: every loop side in exactly one triangle, every other edge in exactly two,
    no vertex repeated in a triangle (a sphere with one hole per loop).

    Parameters
    ----------
    loops : sequence of array_like, each (n_i, 3) or (n_i, 2)
        The outer loop first, then the islands. Points are numbered in this order
        (loop 0's first, then loop 1's...): the triangles index that concatenation.
    weight : str or callable
        ``"liepa"`` (largest dihedral angle, then area) or a triangle weight, as in
        :func:`optri.fill_polyline`; dihedrals across the patch's own edges between
        loops count too.
    method : {"auto", "exact", "liepa", "delaunay"}
        ``"exact"``: the optimum over every such surface (a branch and bound over
        bridge configurations; see the module documentation); stops after
        ``max_nodes`` polygon searches with the best surface found, its proven bound
        and gap. ``"liepa"``: bridges along the closest vertex pairs and one polygon
        search (Liepa's recurrence for ``"liepa"``, the exact DP for triangle
        weights): a heuristic. ``"delaunay"``: the same bridges, the search
        restricted to the faces of the loops' 3-D Delaunay tetrahedralization
        (Zou, Ju and Carr's candidates, widened when they hold no patch): a
        heuristic. ``"auto"``: ``"exact"`` up to ``EXACT_MAX_N`` merged vertices
        (the loops' plus two per island) and ``EXACT_MAX_CONFIGS`` bridge
        configurations, else the better of ``"liepa"`` and ``"delaunay"`` (also
        what ``"exact"`` falls back on when ``max_nodes`` ends it before any surface).
    third_points : sequence of array_like, optional
        Per loop, ``third_points[l][s]``: the third vertex of the mesh triangle on
        side ``(s, s + 1)`` of loop ``l`` (only ``"liepa"`` uses them).
    objective : {"sum", "max"} or pair
        How triangle weights combine (ignored by ``"liepa"``).
    forbidden : array_like of shape (m, 2), optional
        Pairs of point numbers no patch edge may join (edges a mesh already has).
    orient : bool
        Traverse each island opposite to the outer loop in the outer loop's
        best-fit plane, reversing the ones given the same way (default). With
        False the loops are taken as given, each in its patch order (as
        :func:`optri.holes.boundary_loops` returns them).
    max_nodes : int
        Polygon searches the exact branch and bound may run.

    Returns
    -------
    Triangulation
        ``vertices`` (all loops' points, concatenated), ``triangles`` (n + 2k - 2
        for n points and k islands, wound in the outer loop's order), ``weight``,
        ``optimality`` (``"proven"`` or ``"heuristic"``), ``bound`` and ``gap``
        (proven lower bound and relative gap; ``-inf`` and ``inf`` when unknown),
        ``stats``: ``loops`` (sizes), ``bridges`` (point pairs the surface was cut
        along), ``configurations`` and ``searches`` (polygon searches run),
        ``candidates`` (the Delaunay searches: how many found their patch in
        each candidate set, ``"all"`` for none), ``degenerate`` (zero-area
        triangles) and ``degenerate_unavoidable``
        (triangle weights, ``"proven"``: no surface has fewer). For triangle
        weights the search minimises the zero-area count first, then the
        objective, as :func:`optri.fill_polyline` does.

    Raises
    ------
    InvalidPolygonError
        Bad loops (as :func:`optri.fill_polyline`), loops sharing a point, bad
        ``third_points`` or ``forbidden``, unknown method.
    NoTriangulationError
        Every surface uses a forbidden pair.

    Notes
    -----
    With one loop this is :func:`optri.fill_polyline`. ``"proven"`` means optimal over
    all surfaces of this kind for the objective as evaluated (floating point).

    References
    ----------
    .. [1] M. Zou, T. Ju, N. Carr, "An algorithm for triangulating multiple 3D
       polygons", Computer Graphics Forum 32(5) (SGP 2013).

    Examples
    --------
    >>> from optri import fill_polylines
    >>> outer = [[0, 0, 0], [4, 0, 0], [4, 4, 0], [0, 4, 0]]
    >>> island = [[1, 1, 0], [3, 1, 0], [2, 3, 0]]
    >>> t = fill_polylines([outer, island], weight="area")
    >>> len(t.triangles), round(t.weight, 9), t.optimality
    (7, 14.0, 'proven')
    """
    V, ids, T = _loops_input(loops, third_points)
    if method not in ISLAND_METHODS:
        raise InvalidPolygonError(
            f"unknown method {method!r}; choose one of: {', '.join(ISLAND_METHODS)}"
        )
    if len(ids) == 1:
        return _one_loop(V, T, weight, method, objective, forbidden)
    start = time.perf_counter()
    if orient:
        ids = _oriented(V, ids)
    nv = len(V)
    side_third: dict[tuple[int, int], Floats] = {}
    loop_keys: set[int] = set()
    for lp in ids:
        nxt = np.roll(lp, -1)
        loop_keys |= set((np.minimum(lp, nxt) * nv + np.maximum(lp, nxt)).tolist())
    if T is not None:
        # T is aligned with the loops as given: row a is side (a, the point after a)
        after = np.concatenate([np.roll(np.arange(nv)[lp.min() : lp.max() + 1], -1) for lp in ids])
        for lp in ids:
            for a, b in zip(lp.tolist(), np.roll(lp, -1).tolist()):
                side_third[(a, b)] = T[a] if after[a] == b else T[b]  # T[b]: a reversed island
    forbid = _forbidden_keys(forbidden, nv, loop_keys)
    search = _Search(V, T, weight, objective)
    N = nv + 2 * (len(ids) - 1)
    exact = method == "exact" or (
        method == "auto"
        and N <= EXACT_MAX_N
        and _config_count(ids, EXACT_MAX_CONFIGS) <= EXACT_MAX_CONFIGS
    )
    stats: dict[str, Any] = {"loops": [len(lp) for lp in ids]}
    merge = lambda cycle: _merge(cycle, V, side_third, loop_keys, forbid)  # noqa: E731
    found = None
    if exact:
        merged = (m for m in map(merge, _configs(ids)) if m is not None)
        found = _branch_and_bound(search, merged, max_nodes, stats)
    if found is None:
        tries = [merge(_heuristic_config(V, ids, r, forbid)) for r in range(HEURISTIC_TRIES)]
        usable = [m for m in tries if m is not None]
        modes = ("liepa", "delaunay") if method in ("auto", "exact") else (method,)
        for mode in modes:  # the better surface of the two searches
            other = _heuristic(search, usable, mode)
            if other is not None and (found is None or other.value < found.value):
                found = other
        stats["configurations"] = len(tries)
    if found is None:
        raise NoTriangulationError(
            "every patch of these loops uses a forbidden pair (an edge the mesh already has)"
        )
    stats["searches"] = search.solves
    if search.candidates:
        stats["candidates"] = search.candidates
    return _result(search, V, found, stats, time.perf_counter() - start)


def _one_loop(
    V: Floats, T: Floats | None, weight: Any, method: str, objective: ObjectiveLike, forbidden: Any
) -> Triangulation:
    tri = fill_polyline(V, weight, method, T, objective=objective, forbidden=forbidden)
    proven = tri.method == "exact"
    tri.optimality = "proven" if proven else "heuristic"
    tri.bound = tri.weight if proven else -math.inf
    tri.gap = 0.0 if proven else math.inf
    tri.stats["loops"] = [len(V)]  # type: ignore[assignment]
    tri.stats["bridges"] = []  # type: ignore[assignment]
    return tri


@dataclass
class _Found:
    """The chosen surface: merged polygon, its triangles, value, bound, how it was found."""

    merged: _Merged
    tris: Ints
    value: Any  # Cost: a float or a tuple, compared with <
    method: str
    proven: bool
    bound: Cost | None = None  # a proven lower bound when not proven (None: unknown)


def _branch_and_bound(
    search: _Search, merged: Iterator[_Merged], max_nodes: int, stats: dict[str, Any]
) -> _Found | None:
    """Best-first search over bridge configurations (module documentation)."""
    heap: list[_Node] = []
    seq = itertools.count()

    def push(
        m: _Merged, allowed: NDArray[np.bool_], thirds: Floats, forced: frozenset[int]
    ) -> None:
        tris = search.solve(m, allowed, thirds, "exact")
        if tris is not None:
            value = search.value(m, tris, thirds)
            heapq.heappush(heap, _Node(value, next(seq), m, allowed, thirds, forced, tris))

    configs = 0
    for m in merged:
        if search.solves >= max_nodes:  # configurations left unsolved: no bound
            stats["configurations"] = configs
            some = _best_of(search, heap)
            return None if some is None else _Found(*some, "exact", False)
        configs += 1
        push(m, m.allowed, m.thirds, frozenset())
    stats["configurations"] = configs
    best: _Found | None = None
    while heap:
        node = heapq.heappop(heap)
        if best is not None and not node.bound < best.value:
            best.proven = True  # every surface left is worth at least node.bound
            return best
        m = node.merged
        dup = _doubled(m.orig, node.tris, len(search.V))
        if dup is None:
            true = search.value(m, node.tris, search.glued_thirds(m, node.tris))
            if best is None or true < best.value:
                best = _Found(m, node.tris, true, "exact", False)
            if not node.bound < true:
                best.proven = True
                return best
            # Liepa: a bridge's dihedral raised the value; fix the apex on one copy
            b = next(i for i in range(len(m.bridges)) if i not in node.forced)
            s1, s2 = m.bridges[b]
            N = len(m.orig)
            for x in range(N):
                if x in (s1, (s1 + 1) % N):
                    continue
                allowed = node.allowed.copy()
                _force_apex(allowed, s1, x, N)
                thirds = node.thirds.copy()
                thirds[s2] = m.P[x]
                push(m, allowed, thirds, node.forced | {b})
        else:
            for i, j in dup:
                allowed = node.allowed.copy()
                allowed[i, j] = allowed[j, i] = False
                push(m, allowed, node.thirds, node.forced)
        if search.solves >= max_nodes and heap:
            if best is not None:
                best.bound = heap[0].bound
            return best
    if best is not None:
        best.proven = True
    return best


def _best_of(search: _Search, heap: list[_Node]) -> tuple[_Merged, Ints, Any] | None:
    """The best glued surface among the nodes' solutions that double no edge."""
    best: tuple[_Merged, Ints, Any] | None = None
    for node in heap:
        m = node.merged
        if _doubled(m.orig, node.tris, len(search.V)) is None:
            value = search.value(m, node.tris, search.glued_thirds(m, node.tris))
            if best is None or value < best[2]:
                best = (m, node.tris, value)
    return best


def _heuristic(search: _Search, candidates: list[_Merged], mode: str) -> _Found | None:
    """The best of one polygon search per candidate, doubled edges repaired by forbidding."""
    best: _Found | None = None
    for m in candidates:
        allowed = m.allowed.copy()
        tris = search.solve(m, allowed, m.thirds, mode)
        for _ in range(4 * len(m.orig)):
            if tris is None:
                break
            dup = _doubled(m.orig, tris, len(search.V))
            if dup is None:
                break
            (i, j), (u, v) = dup
            allowed[i, j] = allowed[j, i] = False
            again = search.solve(m, allowed, m.thirds, mode)
            if again is None:  # keep that chord, drop the other
                allowed[i, j] = allowed[j, i] = True
                allowed[u, v] = allowed[v, u] = False
                again = search.solve(m, allowed, m.thirds, mode)
            tris = again
        if tris is None or _doubled(m.orig, tris, len(search.V)) is not None:
            continue
        value = search.value(m, tris, search.glued_thirds(m, tris))
        if best is None or value < best.value:
            best = _Found(m, tris, value, mode, False)
    return best


def _public(search: _Search, value: Cost) -> Cost:
    """A search value as reported (Liepa's key as the angle, the area unscaled).

    For triangle weights the zero-area count is dropped: the objective alone.
    """
    if search.liepa:
        key, area = value  # type: ignore[misc]
        return (angle_of_key(key), math.ldexp(area, 2 * search.exponent))
    return value[1]  # type: ignore[index,no-any-return]


def _gap(value: Cost, bound: Cost) -> float:
    """Relative gap of the first component where value and bound differ."""
    xs = value if isinstance(value, tuple) else (value,)
    ys = bound if isinstance(bound, tuple) else (bound,)
    for x, y in zip(xs, ys):
        if x != y:
            if not math.isfinite(y):
                return math.inf
            return max(0.0, x - y) / max(abs(x), 1e-300)
    return 0.0


def _result(
    search: _Search, V: Floats, found: _Found, stats: dict[str, Any], seconds: float
) -> Triangulation:
    m, tris = found.merged, found.tris
    N = len(m.orig)
    out = m.orig[tris]
    out = out[np.lexsort((out[:, 2], out[:, 1], out[:, 0]))].astype(np.int64)
    weight = _public(search, found.value)
    stats["bridges"] = [sorted((int(m.orig[s]), int(m.orig[(s + 1) % N]))) for s, _ in m.bridges]
    hole = search.hole(m, m.allowed, m.thirds)
    stats["degenerate"] = degenerate_count(hole.Q, tris)
    name: Any
    obj_name: Any
    if search.liepa:
        name, obj_name = ("liepa_dihedral", "area"), ("max", "sum")
    else:
        problem = problem_of(hole, None)
        names = tuple(w.name for w in problem.weights)
        name = names[0] if len(names) == 1 else names
        obj_name = problem.objective.name
    bound: Cost
    stats["degenerate_unavoidable"] = (
        not search.liepa and found.proven and stats["degenerate"] > 0
    )  # the count is minimised first and the search proved it
    if found.proven:
        bound, gap = weight, 0.0
    elif found.bound is None or (
        not search.liepa and found.bound[0] < found.value[0]  # type: ignore[index]
    ):  # a surface with fewer zero-area triangles may exist: its objective is unbounded
        bound, gap = -math.inf, math.inf
    else:
        bound = _public(search, found.bound)
        gap = _gap(weight, bound)
    return Triangulation(
        vertices=V,
        triangles=out,
        weight=weight,
        method=found.method,
        weight_name=name,
        objective=obj_name,
        orientation=None,
        order=np.arange(len(V), dtype=np.int64),
        stats=stats,
        seconds=seconds,
        optimality="proven" if found.proven else "heuristic",
        bound=bound,
        gap=gap,
    )


# --- islands of a mesh's holes -----------------------------------------------------------


def island_groups(vertices: Floats, faces: Ints, loops: Sequence[Ints]) -> dict[int, list[int]]:
    """Islands of each hole: ``{hole loop number: [island loop numbers]}``.

    Loop ``j`` is an island of hole loop ``h`` when it borders another connected
    piece of the mesh and, in the best-fit plane of ``h``'s points (the plane of
    least variance), every point of ``j`` has a non-zero winding number in ``h``'s
    projection, ``j`` runs the other way round (its patch faces the same side), it
    encloses less area, and no point of ``j`` is farther from that plane than the
    largest distance of ``h``'s points from their centroid. An island inside several
    holes belongs to the smallest; a loop that is an island has no islands itself.

    Examples
    --------
    >>> import numpy as np
    >>> ring = [[np.cos(t), np.sin(t), 0.0] for t in np.linspace(0, 6.28, 8, endpoint=False)]
    >>> v = np.array(ring + [[3 * x, 3 * y, 0.0] for x, y, _ in ring]
    ...              + [[0.1, 0, 0], [0, 0.1, 0], [-0.1, 0, 0]])
    >>> f = [[i, 8 + i, (i + 1) % 8] for i in range(8)]
    >>> f += [[(i + 1) % 8, 8 + i, 8 + (i + 1) % 8] for i in range(8)]
    >>> f += [[16, 17, 18]]                                     # an annulus and a disk
    >>> from optri.holes import boundary_loops
    >>> loops = [lp for lp, _ in boundary_loops(np.array(f))]
    >>> island_groups(v, np.array(f), loops)
    {0: [2]}
    """
    loops = [np.asarray(lp, dtype=np.int64) for lp in loops]
    if len(loops) < 2:
        return {}
    label = _components(faces, len(vertices))
    comp = [int(label[lp[0]]) for lp in loops]
    if len(set(comp)) < 2:
        return {}
    shapes = [_shape(vertices[lp]) for lp in loops]
    owner: dict[int, tuple[float, int]] = {}
    for h, (c_h, basis, normal, area, radius) in enumerate(shapes):
        if area == 0.0:
            continue
        flat = (vertices[loops[h]] - c_h) @ basis.T
        for j, lp in enumerate(loops):
            if comp[j] == comp[h] or abs(shapes[j][3]) >= abs(area):
                continue
            pts = vertices[lp] - c_h
            if np.linalg.norm(shapes[j][0] - c_h) > 2 * radius:
                continue  # a cheap first test: too far to be inside
            if np.abs(pts @ normal).max() > radius:
                continue
            xy = pts @ basis.T
            if (_signed_area(xy) > 0) == (area > 0):
                continue
            if not (_winding(xy, flat) != 0).all():
                continue
            if j not in owner or abs(area) < owner[j][0]:
                owner[j] = (abs(area), h)
    groups: dict[int, list[int]] = {}
    for j, (_, h) in sorted(owner.items()):
        if h not in owner:
            groups.setdefault(h, []).append(j)
    return groups


def _components(faces: Ints, nv: int) -> Ints:
    """Connected-component label of every vertex (through the faces' edges)."""
    parent = np.arange(nv)
    f = np.asarray(faces, dtype=np.int64)
    a = np.concatenate([f[:, 0], f[:, 1]])
    b = np.concatenate([f[:, 1], f[:, 2]])
    while True:  # label propagation: every vertex takes the smallest label around it
        low = np.minimum(parent[a], parent[b])
        new = parent.copy()
        np.minimum.at(new, a, low)
        np.minimum.at(new, b, low)
        new = new[new]
        if np.array_equal(new, parent):
            return parent
        parent = new


def _shape(points: Floats) -> tuple[Floats, Floats, Floats, float, float]:
    """(centroid, plane basis, normal, signed area in that basis, radius) of a loop."""
    centre = points.mean(axis=0)
    if len(points) < 3:
        return centre, np.eye(3)[:2], np.eye(3)[2], 0.0, 0.0
    basis = _plane_basis(points)
    normal = np.cross(basis[0], basis[1])
    xy = (points - centre) @ basis.T
    radius = float(np.linalg.norm(points - centre, axis=1).max())
    return centre, basis, normal, _signed_area(xy), radius


def _winding(points: Floats, polygon: Floats) -> Ints:
    """Winding number of each 2-D point in a closed polygon (points on it: either)."""
    a = polygon[None, :, :]
    b = np.roll(polygon, -1, axis=0)[None, :, :]
    p = points[:, None, :]
    left = (b[..., 0] - a[..., 0]) * (p[..., 1] - a[..., 1]) - (p[..., 0] - a[..., 0]) * (
        b[..., 1] - a[..., 1]
    )
    up = (a[..., 1] <= p[..., 1]) & (b[..., 1] > p[..., 1]) & (left > 0)
    down = (a[..., 1] > p[..., 1]) & (b[..., 1] <= p[..., 1]) & (left < 0)
    return (up.sum(axis=1) - down.sum(axis=1)).astype(np.int64)  # type: ignore[no-any-return]


def group_chords(keys: Ints, nv: int, members: Sequence[Ints]) -> Ints:
    """Pairs of positions in the concatenated ``members`` that an edge key joins.

    ``keys``: undirected edge keys ``min * nv + max`` of the mesh (and patches so
    far); loop sides are left out (every patch uses them).

    >>> group_chords(np.array([0 * 9 + 2, 3 * 9 + 4, 4 * 9 + 5]), 9,
    ...              [np.array([0, 1, 2, 3]), np.array([4, 5, 6])]).tolist()
    [[0, 2], [3, 4]]
    """
    ring = np.concatenate(members)
    pos = {int(v): i for i, v in enumerate(ring.tolist())}
    sides = set()
    for lp in members:
        nxt = np.roll(lp, -1)
        sides |= set((np.minimum(lp, nxt) * nv + np.maximum(lp, nxt)).tolist())
    a, b = np.divmod(np.asarray(keys, dtype=np.int64), nv)
    pairs = [
        (pos[x], pos[y])
        for k, x, y in zip(keys.tolist(), a.tolist(), b.tolist())
        if x in pos and y in pos and k not in sides
    ]
    return np.array(pairs, dtype=np.int64).reshape(-1, 2)
