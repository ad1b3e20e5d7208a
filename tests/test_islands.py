"""Holes with islands: ``fill_polylines`` against brute force, invariants, ``fill_holes``."""

from __future__ import annotations

import functools
import itertools
import json
import math
from fractions import Fraction

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st

from optri import fill_holes, fill_polylines
from optri.cli import main
from optri.errors import InvalidPolygonError, NoTriangulationError
from optri.holes import islands
from optri.holes.boundary import edge_summary
from optri.holes.candidates import delaunay_faces
from optri.holes.islands import island_groups

# --- the oracle: every surface, enumerated -------------------------------------------------


@functools.cache
def surfaces(sizes: tuple[int, ...]) -> list[list[tuple[int, int, int]]]:
    """Every triangulated surface of genus 0 bounded by loops of these sizes.

    Loop ``l`` runs over its point numbers in increasing order (patch order); each
    surface is a set of oriented triangles with every loop side once in its loop's
    direction, every other edge once each way, no vertex but the loops', connected,
    every vertex link one path, and ``V + 2k - 2`` triangles (Euler, k islands).
    Triangles are found by growing a front from its smallest open directed edge, so
    each surface comes out once.
    """
    loops, start = [], 0
    for n in sizes:
        loops.append(list(range(start, start + n)))
        start += n
    V, k = start, len(sizes) - 1
    F = V + 2 * k - 2
    sides = {(a, b) for lp in loops for a, b in zip(lp, lp[1:] + lp[:1])}
    rev = {(b, a) for a, b in sides}
    used: set[tuple[int, int]] = set()
    tris: list[tuple[int, int, int]] = []
    out = []

    def grow(front: frozenset[tuple[int, int]]) -> None:
        if not front:
            if len(tris) == F:
                out.append(list(tris))
            return
        if len(tris) >= F:
            return
        u, v = min(front)
        for w in range(V):
            if w in (u, v):
                continue
            new = [(v, w), (w, u)]
            if any(e in used or e in rev for e in new):
                continue
            rest = set(front) - {(u, v)}
            ok = True
            for e in new:
                if e in rest:
                    rest.discard(e)
                elif e in sides or (e[1], e[0]) in used or (e[1], e[0]) in sides:
                    ok = False
                    break
                else:
                    rest.add((e[1], e[0]))
            if not ok:
                continue
            used.update([(u, v), *new])
            tris.append((u, v, w))
            grow(frozenset(rest))
            tris.pop()
            used.difference_update([(u, v), *new])

    grow(frozenset(sides))
    return [s for s in out if is_surface(s, V)]


def is_surface(tris: list[tuple[int, int, int]], V: int) -> bool:
    """Connected, and the link of every vertex is one path."""
    links: dict[int, list[tuple[int, int]]] = {v: [] for v in range(V)}
    graph: dict[int, set[int]] = {v: set() for v in range(V)}
    for a, b, c in tris:
        links[a].append((b, c))
        links[b].append((c, a))
        links[c].append((a, b))
        graph[a] |= {b, c}
        graph[b] |= {a, c}
        graph[c] |= {a, b}
    for edges in links.values():
        nodes = {x for e in edges for x in e}
        if not edges or len(nodes) - len(edges) != 1:
            return False
        g: dict[int, set[int]] = {x: set() for x in nodes}
        for x, y in edges:
            g[x].add(y)
            g[y].add(x)
        if _reach(g, next(iter(nodes))) != nodes:
            return False
    return _reach(graph, 0) == set(range(V))


def _reach(g: dict[int, set[int]], start: int) -> set[int]:
    seen, stack = set(), [start]
    while stack:
        x = stack.pop()
        if x not in seen:
            seen.add(x)
            stack.extend(g[x])
    return seen


def liepa_value(P, tris, third=None, sides=()):
    """(largest 1 - cos dihedral, area) of an oriented surface, numpy; mesh thirds optional."""
    S = np.array(tris)
    a, b, c = P[S[:, 0]], P[S[:, 1]], P[S[:, 2]]
    n = np.cross(b - a, c - a)
    area = 0.5 * np.linalg.norm(n, axis=1)
    unit = n / np.linalg.norm(n, axis=1)[:, None]
    owner = {}
    for t, (x, y, z) in enumerate(S.tolist()):
        for e in ((x, y), (y, z), (z, x)):
            owner[e] = t
    worst = 0.0
    for (x, y), t in owner.items():
        if (y, x) in owner:
            worst = max(worst, 1 - float(unit[t] @ unit[owner[(y, x)]]))
    for (x, y), tp in zip(sides, [] if third is None else third):
        m = np.cross(P[x] - P[y], tp - P[y])
        worst = max(worst, 1 - float(unit[owner[(x, y)]] @ (m / np.linalg.norm(m))))
    return min(worst, 2.0), float(area.sum())


def ring(n, r, centre=(0.0, 0.0), z=None, phase=0.0, reverse=False):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False) + phase
    zs = np.zeros(n) if z is None else z
    pts = np.column_stack((centre[0] + r * np.cos(t), centre[1] + r * np.sin(t), zs))
    return pts[::-1] if reverse else pts


def config(rng, sizes, bumpy=0.4):
    """Outer loop counter-clockwise, islands inside running clockwise (patch order)."""
    loops = [ring(sizes[0], 3.0, z=rng.normal(0, bumpy, sizes[0]), phase=rng.uniform(0, 1))]
    for i, n in enumerate(sizes[1:]):
        centre = (
            (0.0, 0.0) if len(sizes) == 2 else (1.3 * math.cos(2.5 * i), 1.3 * math.sin(2.5 * i))
        )
        loops.append(ring(n, 0.6, centre, rng.normal(0, bumpy, n), rng.uniform(0, 1), reverse=True))
    return loops


def sum_weight(P, tris, kind):
    total = 0.0
    for a, b, c in tris:
        if kind == "area":
            total += 0.5 * float(np.linalg.norm(np.cross(P[b] - P[a], P[c] - P[a])))
        else:
            total += sum(float(np.linalg.norm(P[x] - P[y])) for x, y in ((a, b), (b, c), (c, a)))
    return total


# --- exact = brute force ----------------------------------------------------------------


def table_weight(table):
    def w(i, k, j):
        return table[frozenset((i, k, j))]

    return w


@pytest.mark.parametrize("sizes", [(3, 3), (4, 3), (5, 3)])
def test_exact_equals_brute_force_on_arbitrary_triangle_weights(sizes):
    # a random weight per vertex triple: any surface the search missed would show
    rng = np.random.default_rng(sum(sizes))
    V = sum(sizes)
    found = surfaces(sizes)
    assert len(found) == {(3, 3): 21, (4, 3): 132, (5, 3): 645}[sizes]
    for _ in range(4):
        table = {
            frozenset(t): float(rng.integers(1, 1000)) for t in itertools.combinations(range(V), 3)
        }

        w = table_weight(table)

        best = min(sum(w(*t) for t in s) for s in found)
        res = fill_polylines(config(rng, sizes), weight=w, method="exact", orient=False)
        assert res.weight == best and res.optimality == "proven" and res.gap == 0.0
        assert sorted(map(tuple, res.triangles.tolist())) in [sorted(s) for s in found] or (
            is_surface([tuple(t) for t in res.triangles.tolist()], V)
        )


@pytest.mark.parametrize("sizes", [(4, 3), (5, 3)])
@pytest.mark.parametrize("kind", ["area", "perimeter"])
def test_exact_equals_brute_force_on_sum_weights(sizes, kind):
    rng = np.random.default_rng(7)
    for _ in range(3):
        loops = config(rng, sizes)
        P = np.concatenate(loops)
        best = min(sum_weight(P, s, kind) for s in surfaces(sizes))
        res = fill_polylines(loops, weight=kind, method="exact", orient=False)
        assert res.weight == pytest.approx(best, rel=1e-12)
        assert sum_weight(P, res.triangles.tolist(), kind) == pytest.approx(best, rel=1e-12)


@pytest.mark.parametrize("sizes", [(4, 3), (5, 3)])
@pytest.mark.parametrize("with_third", [False, True])
def test_exact_equals_brute_force_on_liepa(sizes, with_third):
    rng = np.random.default_rng(11 + with_third)
    for _ in range(3):
        loops = config(rng, sizes, bumpy=0.8)
        P = np.concatenate(loops)
        third, sides = None, ()
        if with_third:  # mesh triangles around the outer loop; none around the island
            third = [loops[0].mean(axis=0) + rng.normal(0, 1.5, (sizes[0], 3)), loops[1]]
            n0 = sizes[0]
            sides = [(i, (i + 1) % n0) for i in range(n0)]
        best = min(liepa_value(P, s, third and third[0], sides) for s in surfaces(sizes))
        res = fill_polylines(loops, method="exact", orient=False, third_points=third)
        key = 1 - math.cos(res.weight[0])
        assert key == pytest.approx(best[0], rel=1e-9, abs=1e-12)
        assert res.weight[1] == pytest.approx(best[1], rel=1e-9)
        again = liepa_value(P, res.triangles.tolist(), third and third[0], sides)
        assert again[0] == pytest.approx(best[0], rel=1e-9, abs=1e-12)


# --- invariants ---------------------------------------------------------------------------


def check_surface(res, sizes):
    """One connected genus-0 surface: loops used once each way round, manifold edges."""
    tris = [tuple(t) for t in res.triangles.tolist()]
    V, k = sum(sizes), len(sizes) - 1
    assert len(tris) == V + 2 * k - 2  # Euler: a sphere with k + 1 holes
    assert all(len(set(t)) == 3 for t in tris)
    directed = [(a, b) for t in tris for a, b in zip(t, t[1:] + t[:1])]
    assert len(set(directed)) == len(directed)  # each edge at most once each way
    undirected: dict[frozenset[int], int] = {}
    for e in directed:
        undirected[frozenset(e)] = undirected.get(frozenset(e), 0) + 1
    start, sides = 0, set()
    for n in sizes:
        lp = list(range(start, start + n))
        start += n
        for a, b in zip(lp, lp[1:] + lp[:1]):
            sides.add(frozenset((a, b)))
            # the outer loop as given; islands (given clockwise, patch order) likewise
            assert (a, b) in directed
    for e, count in undirected.items():
        assert count == (1 if e in sides else 2), (sorted(e), count)
    assert is_surface(tris, V)


@settings(max_examples=15, deadline=None)
@given(
    st.integers(3, 8),
    st.lists(st.integers(3, 5), min_size=1, max_size=2),
    st.sampled_from(["liepa", "area"]),
    st.sampled_from(["auto", "liepa", "delaunay"]),
    st.integers(0, 2**32 - 1),
)
def test_every_result_is_one_manifold_surface(n0, islands, weight, method, seed):
    rng = np.random.default_rng(seed)
    sizes = (n0, *islands)
    loops = config(rng, sizes)
    res = fill_polylines(loops, weight=weight, method=method, orient=False)
    check_surface(res, sizes)
    assert res.optimality in ("proven", "heuristic")
    if res.optimality == "heuristic":
        assert res.gap == math.inf or res.gap >= 0
    if res.optimality == "heuristic" and len(sizes) == 2 and sum(sizes) <= 12:
        exact = fill_polylines(loops, weight=weight, method="exact", orient=False)
        assert exact.optimality == "proven"
        assert exact.weight <= res.weight  # lexicographic for liepa


def test_two_islands_exact_no_worse_than_heuristic_and_proven():
    rng = np.random.default_rng(5)
    loops = config(rng, (5, 3, 3))
    exact = fill_polylines(loops, method="exact", orient=False)
    heuristic = fill_polylines(loops, method="liepa", orient=False)
    check_surface(exact, (5, 3, 3))
    check_surface(heuristic, (5, 3, 3))
    assert exact.optimality == "proven" and heuristic.optimality == "heuristic"
    assert exact.weight <= heuristic.weight and len(exact.stats["bridges"]) == 2


def exactly_collinear(P, tri):
    """Exact (rational) collinearity of three points with float coordinates."""
    a, b, c = ([Fraction(float(x)) for x in P[v]] for v in tri)
    u = [b[i] - a[i] for i in range(3)]
    v = [c[i] - a[i] for i in range(3)]
    cross = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
    return all(x == 0 for x in cross)


@pytest.mark.parametrize("kind", ["area", "perimeter"])
def test_fewest_zero_area_triangles_first_then_the_objective(kind):
    # a straight run 0-1-2 on the outer loop: its ear is a zero-area triangle that the
    # objective alone may take (it adds no area); the search minimises the count first
    rng = np.random.default_rng(0)
    S = surfaces((5, 3))
    took_fewer = 0
    for _ in range(8):
        z = rng.integers(-2, 3, 2).astype(float)
        outer = np.array([[0, 0, 0], [2, 0, 0], [4, 0, 0], [4, 4, z[0]], [0, 4, z[1]]], float)
        top = float(rng.integers(-1, 2))
        island = np.array([[2.0, 2.5, top], [2.5, 1.0, 0.5], [1.5, 1.0, 0.5]])
        P = np.concatenate((outer, island))
        keyed = [(sum(exactly_collinear(P, t) for t in s), sum_weight(P, s, kind)) for s in S]
        count, best = min(keyed)
        res = fill_polylines([outer, island], weight=kind, method="exact", orient=False)
        got = sum(exactly_collinear(P, t) for t in res.triangles.tolist())
        assert got == count == res.stats["degenerate"] == 0
        assert res.weight == pytest.approx(best, rel=1e-12) and res.optimality == "proven"
        assert res.stats["degenerate_unavoidable"] is False
        plain = min(keyed, key=lambda k: k[1])
        took_fewer += plain[0] > 0  # the objective alone had a zero-area optimum
    assert took_fewer > 0 or kind == "perimeter"  # perimeter never prefers them here


def test_fewest_zero_area_triangles_with_a_user_weight():
    # the straight run's ear costs nothing: most weight tables' plain optimum takes it
    outer = np.array([[0, 0, 0], [2, 0, 0], [4, 0, 0], [4, 4, 1.0], [0, 4, -1.0]], float)
    island = np.array([[2.0, 2.5, 1.0], [2.5, 1.0, 0.5], [1.5, 1.0, 0.5]])
    P = np.concatenate((outer, island))
    rng = np.random.default_rng(4)
    for _ in range(6):
        triples = itertools.combinations(range(8), 3)
        table = {frozenset(t): float(rng.integers(1, 1000)) for t in triples}
        table[frozenset((0, 1, 2))] = 0.0
        w = table_weight(table)
        keyed = [
            (sum(exactly_collinear(P, t) for t in s), sum(w(*t) for t in s))
            for s in surfaces((5, 3))
        ]
        res = fill_polylines([outer, island], weight=w, method="exact", orient=False)
        assert (res.stats["degenerate"], res.weight) == min(keyed)
        assert res.optimality == "proven"


def test_unavoidable_zero_area_triangles_are_reported():
    # the pairs forbidden around point 0 leave side (0, 1) only the apex 2, on the
    # straight run: one zero-area triangle is forced, and the search says so
    outer = np.array([[0, 0, 0], [2, 0, 0], [4, 0, 0], [4, 4, 0], [0, 4, 0]], float)
    island = np.array([[2.0, 2.5, 1.0], [2.5, 1.0, 0.5], [1.5, 1.0, 0.5]])
    P = np.concatenate((outer, island))
    forbidden = [(0, 3), (0, 5), (0, 6), (0, 7), (1, 4)]
    banned = {frozenset(e) for e in forbidden}
    allowed = [
        s
        for s in surfaces((5, 3))
        if not any(frozenset(e) in banned for t in s for e in itertools.combinations(t, 2))
    ]
    keyed = [(sum(exactly_collinear(P, t) for t in s), sum_weight(P, s, "area")) for s in allowed]
    count, best = min(keyed)
    assert count == 1
    res = fill_polylines(
        [outer, island], weight="area", method="exact", orient=False, forbidden=forbidden
    )
    assert res.stats["degenerate"] == count and res.stats["degenerate_unavoidable"] is True
    assert res.weight == pytest.approx(best, rel=1e-12) and res.optimality == "proven"


@pytest.mark.parametrize("sizes", [(24, 8, 8), (40, 12)])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_delaunay_searches_the_tetrahedralization_faces(sizes, seed):
    # Zou, Ju and Carr's candidates: faces of the loops' 3-D Delaunay tetrahedralization
    loops = config(np.random.default_rng(seed), sizes, bumpy=0.3)
    faces = {tuple(f) for f in delaunay_faces(np.concatenate(loops)).tolist()}
    res = fill_polylines(loops, method="delaunay", orient=False)
    check_surface(res, sizes)
    assert res.method == "delaunay" and res.optimality == "heuristic"
    assert all(tuple(sorted(t)) in faces for t in res.triangles.tolist())
    assert set(res.stats["candidates"]) == {"delaunay"}  # never widened here


def test_merged_candidates_are_every_copy_of_every_face():
    # a bridge vertex appears twice in the merged polygon: each Delaunay face of the
    # loops' points is a candidate with every choice of copies, and nothing else is
    loops = config(np.random.default_rng(4), (9, 4, 3))
    V = np.concatenate(loops)
    ids = [np.arange(0, 9), np.arange(9, 13), np.arange(13, 16)]
    m = islands._merge(islands._heuristic_config(V, ids, 0, set()), V, {}, set(), set())
    got = islands._Search(V, None, "liepa", "sum").merged_faces(m)
    copies = np.bincount(m.orig, minlength=len(V))
    faces = delaunay_faces(V)
    assert len(got) == int(np.prod(copies[faces], axis=1).sum()) and copies.max() == 2
    assert {tuple(sorted(t)) for t in m.orig[got].tolist()} == {tuple(f) for f in faces.tolist()}


def test_auto_beyond_exact_keeps_the_better_heuristic():
    better = []
    for seed in range(3):
        loops = config(np.random.default_rng(seed), (120, 30, 20), bumpy=0.3)
        got = {
            m: fill_polylines(loops, method=m, orient=False) for m in ("auto", "liepa", "delaunay")
        }
        check_surface(got["auto"], (120, 30, 20))
        assert got["auto"].weight == min(got["liepa"].weight, got["delaunay"].weight)
        better.append(got["delaunay"].weight < got["liepa"].weight)
    assert any(better)  # the tetrahedralization's candidates find a better surface here


def test_islands_given_either_way_round():
    rng = np.random.default_rng(3)
    loops = config(rng, (6, 4))
    as_patch = fill_polylines(loops, weight="area", orient=False)
    same_way = [loops[0], loops[1][::-1]]  # both counter-clockwise: reversed inside
    turned = fill_polylines(same_way, weight="area")
    assert turned.weight == pytest.approx(as_patch.weight)
    check_surface(as_patch, (6, 4))
    # point j of the reversed island is point 9 - j of the other numbering
    remap = np.array([0, 1, 2, 3, 4, 5, 9, 8, 7, 6])
    mapped = {frozenset(t) for t in remap[turned.triangles].tolist()}
    assert mapped == {frozenset(t) for t in as_patch.triangles.tolist()}


def test_forbidden_pairs_are_avoided():
    rng = np.random.default_rng(9)
    loops = config(rng, (5, 3))
    free = fill_polylines(loops, weight="area", method="exact", orient=False)
    bridge = free.stats["bridges"][0]
    res = fill_polylines(loops, weight="area", method="exact", orient=False, forbidden=[bridge])
    edges = {frozenset(e) for t in res.triangles.tolist() for e in itertools.combinations(t, 2)}
    assert frozenset(bridge) not in edges and res.weight >= free.weight
    check_surface(res, (5, 3))
    every = [[a, b] for a in range(5) for b in range(5, 8)]
    with pytest.raises(NoTriangulationError):
        fill_polylines(loops, weight="area", orient=False, forbidden=every)


def test_a_stopped_search_reports_its_bound_and_gap():
    rng = np.random.default_rng(2)
    loops = config(rng, (6, 4), bumpy=1.0)
    full = fill_polylines(loops, method="exact", orient=False)
    assert full.stats["searches"] > full.stats["configurations"]  # it had to branch
    cut = fill_polylines(
        loops, method="exact", orient=False, max_nodes=full.stats["configurations"] + 1
    )
    if cut.optimality == "heuristic":
        assert cut.bound <= full.weight <= cut.weight and 0 <= cut.gap < math.inf
    else:
        assert cut.weight == full.weight


def test_one_loop_is_fill_polyline():
    square = [[0, 0, 0], [1, 0, 0], [1, 1, 0.2], [0, 1, 0]]
    res = fill_polylines([square], weight="area")
    assert res.optimality == "proven" and len(res.triangles) == 2


@pytest.mark.parametrize(
    "loops, kwargs, match",
    [
        ([], {}, "non-empty"),
        ([ring(4, 2), ring(3, 2)], {}, "share a point"),
        ([ring(4, 2), ring(3, 1)], {"method": "greedy"}, "unknown method"),
        ([ring(4, 2), ring(3, 1)], {"third_points": [ring(4, 2)]}, "one"),
        ([ring(4, 2), ring(3, 1)], {"forbidden": [[0, 1]]}, "loop side"),
        ([ring(4, 2), ring(3, 1)], {"forbidden": [[0, 9]]}, "different vertices"),
    ],
)
def test_bad_input(loops, kwargs, match):
    with pytest.raises(InvalidPolygonError, match=match):
        fill_polylines(loops, **kwargs)


# --- fill_holes -------------------------------------------------------------------------


def capped_sphere():
    """An icosphere with a cap removed, a small patch at its top kept as an island."""
    trimesh = pytest.importorskip("trimesh")
    sphere = trimesh.creation.icosphere(subdivisions=3)
    z = sphere.triangles_center[:, 2]
    return sphere.vertices, sphere.faces[(z < 0.6) | (z > 0.93)]


def components(faces, nv):
    """Connected pieces of the vertices the faces use (scipy's graph components)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    a = faces[:, [0, 1, 2]].ravel()
    b = faces[:, [1, 2, 0]].ravel()
    _, label = connected_components(coo_matrix((np.ones(len(a)), (a, b)), shape=(nv, nv)))
    return len(np.unique(label[np.unique(faces)]))


@pytest.mark.parametrize("kwargs", [{}, {"weight": "area"}, {"refine": True, "fair": 1}])
def test_fill_holes_joins_hole_and_island(kwargs):
    v, f = capped_sphere()
    assert components(f, len(v)) == 2
    (v2, f2), records = fill_holes((v, f), **kwargs)
    assert len(records) == 1  # the island has no record of its own
    rec = records[0]
    assert rec.status == "filled" and len(rec.islands) == 1 and rec.edges == 56
    assert edge_summary(f2) == {"boundary": 0, "nonmanifold": 0, "degenerate_faces": 0}
    assert components(f2, len(v2)) == 1
    if not kwargs.get("refine"):
        assert rec.faces_added == rec.edges + 2 * len(rec.islands) - 2 == len(f2) - len(f)
    else:
        assert rec.vertices_added == len(v2) - len(v) > 0 and rec.faired
    # wound consistently with the mesh around both loops: no directed edge twice
    directed = [(a, b) for t in f2.tolist() for a, b in zip(t, t[1:] + t[:1])]
    assert len(set(directed)) == len(directed)
    assert "island" in rec.detail()


def test_fill_holes_without_islands_caps_each_loop():
    v, f = capped_sphere()
    (v2, f2), records = fill_holes((v, f), islands=False)
    assert len(records) == 2 and not any(r.islands for r in records)
    assert components(f2, len(v2)) == 2


def annulus_and_disk(shift=0.0):
    """A flat annulus (12-gon rims, radii 1 and 3) and a small disk inside it, all facing +z."""
    inner, outer = ring(12, 1.0), ring(12, 3.0)
    disk = ring(5, 0.3) + [0, 0, shift]
    v = np.concatenate([inner, outer, disk, [[0, 0, shift]]])
    f = [[i, 12 + i, (i + 1) % 12] for i in range(12)]
    f += [[(i + 1) % 12, 12 + i, 12 + (i + 1) % 12] for i in range(12)]
    f += [[24 + i, 24 + (i + 1) % 5, 29] for i in range(5)]
    return v, np.array(f)


def test_flat_hole_with_island_and_far_disk():
    from optri.holes import boundary_loops

    v, f = annulus_and_disk()
    loops = [lp for lp, _ in boundary_loops(f)]
    assert island_groups(v, f, loops) == {0: [2]}  # the inner rim holds the disk
    (_, f2), records = fill_holes((v, f), weight="area")
    assert [len(r.islands) for r in records] == [1, 0]  # the outer rim: a cap of its own
    hole = records[0]
    assert hole.edges == 12 + 5 and hole.faces_added == 17 and hole.optimality == "proven"
    # the least area of a surface spanning the ring between the rim and the disk: its area
    ring_area = 0.5 * 12 * math.sin(2 * math.pi / 12) - 0.5 * 5 * 0.09 * math.sin(2 * math.pi / 5)
    assert hole.weight == pytest.approx(ring_area, rel=1e-12)
    assert edge_summary(f2) == {"boundary": 0, "nonmanifold": 0, "degenerate_faces": 0}
    # the same disk lifted 1.5 above the hole (radius 1) is no island
    v_far, f_far = annulus_and_disk(shift=1.5)
    assert island_groups(v_far, f_far, [lp for lp, _ in boundary_loops(f_far)]) == {}


def test_cli_fills_islands_and_no_islands_turns_it_off(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    v, f = capped_sphere()
    src = tmp_path / "capped.obj"
    trimesh.Trimesh(v, f, process=False).export(src)
    reports = {}
    for flag in ([], ["--no-islands"]):
        out = tmp_path / f"out{len(flag)}.obj"
        res = CliRunner().invoke(main, ["fill", str(src), "-o", str(out), "--json", *flag])
        assert res.exit_code == 0, res.output
        reports[bool(flag)] = json.loads(res.stdout)
    assert [len(h["islands"]) for h in reports[False]["holes"]] == [1]
    assert [len(h["islands"]) for h in reports[True]["holes"]] == [0, 0]
    assert reports[False]["watertight"] and reports[True]["watertight"]
