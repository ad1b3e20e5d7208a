"""The compiled candidate sets of polygons with holes against two oracles.

``optri._core.domains`` computes the valid diagonals, their turns, the candidate
triangles, their sides and signs, the forced diagonals and the blocks' links.
Each is held to the readable numpy implementation of the same definitions
(``domain_candidates_oracle``, array for array, order included) on random and
adversarial polygons with holes, and the sets to the brute-force oracle of
``domain_polys`` (its own validity tests in exact rational arithmetic).
"""

from __future__ import annotations

import numpy as np
import pytest

shapely = pytest.importorskip("shapely")

from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

import domain_candidates_oracle as oracle  # noqa: E402
from domain_polys import BruteDomain, small_domains  # noqa: E402
from optri import _core  # noqa: E402
from optri.domains import as_domain, find_candidates, random_domain  # noqa: E402
from optri.domains.candidates import side_signs, valid_diagonals  # noqa: E402
from optri.domains.reduce import blocks, forced_diagonals, prune  # noqa: E402
from optri.domains.weighing import DomainWeight  # noqa: E402
from optri.predicates import orient  # noqa: E402
from optri.weights import get_weight  # noqa: E402

SETTINGS = settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.filter_too_much]
)


def _same_as_oracle(d):
    got = find_candidates(d)
    edges, tris, sides, signs, turns = oracle.find_candidates(d)
    assert np.array_equal(got.edges, edges)
    assert np.array_equal(got.triangles, tris)
    assert np.array_equal(got.sides, sides)
    assert np.array_equal(got.signs, signs)
    assert np.array_equal(got.turns, turns)
    assert got.n_boundary == d.n
    assert got.edges.dtype == np.int64 and got.triangles.dtype == np.int64
    assert got.signs.dtype == np.int8 and got.turns.dtype == np.int8
    return got


@SETTINGS
@given(small_domains(n_max=16, holes=(1, 3)))
def test_small_domains_match_both_oracles(dom):
    ext, holes = dom
    d = as_domain(ext, holes)
    got = _same_as_oracle(d)
    brute = BruteDomain(ext, holes)
    assert sorted(map(tuple, got.triangles.tolist())) == brute.triangles()
    ok = {
        (a, b)
        for a in range(d.n)
        for b in range(a + 1, d.n)
        if not d.is_side(a, b) and brute._segment_ok(a, b)
    }
    assert set(map(tuple, valid_diagonals(d).tolist())) == ok


@pytest.mark.parametrize(
    "n, h, seed", [(20, 1, 0), (40, 2, 1), (60, 3, 2), (90, 3, 3), (80, 10, 4), (100, 1, 5)]
)
def test_random_domains_match_the_oracle(n, h, seed):
    _same_as_oracle(as_domain(*random_domain(n, h, seed=seed, depth=0.7)))


def _grid_domain():
    """Collinear runs everywhere: exterior sides split by vertices, holes on shared lines."""
    ext = [[x, 0] for x in range(0, 9, 2)] + [[8, y] for y in range(2, 9, 2)]
    ext += [[x, 8] for x in range(6, -1, -2)] + [[0, y] for y in range(6, 0, -2)]
    holes = [
        # collinear runs of its own; its corner (2, 2) on the line y = x with (0, 0), (8, 8)
        [[2, 2], [3, 2], [4, 2], [4, 3], [3, 3], [2, 3]],
        [[5, 5], [6, 5], [6, 6], [5, 6]],  # corners (5, 5), (6, 6) on y = x too
        [[2, 5], [3, 6], [2, 6]],  # (2, 5), (2, 6) on x = 2 with hole 1's (2, 2), (2, 3)
    ]
    return as_domain(np.array(ext, float), [np.array(r, float) for r in holes])


def _near_collinear_domain():
    """Hole vertices off chords' lines by one unit in the last place, on both sides."""
    ext = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]])
    tiny = np.nextafter(5.0, 6.0) - 5.0
    hole1 = np.array([[5.0, 5.0 + tiny], [6.0, 6.0], [6.0, 5.0 + 3 * tiny]])[::-1]
    hole2 = np.array([[2.0, 2.0 - tiny], [3.0, 2.0], [3.0, 3.0 - tiny], [2.0, 3.0]])[::-1]
    return as_domain(ext, [hole1, hole2])


def _rings(d):
    """The domain's rings as given (exterior, holes)."""
    p = d.vertices
    return p[: d.sizes[0]], [p[a : a + m] for a, m in zip(d.starts[1:], d.sizes[1:])]


def _scaled(d, s):
    ext, holes = _rings(d)
    return as_domain(ext * s, [h * s for h in holes])


@pytest.mark.parametrize("scale", [1.0, 1e-300, 2.0**-1060, 1e300, 3.0])
@pytest.mark.parametrize("make", [_grid_domain, _near_collinear_domain])
def test_adversarial_domains_match_the_oracle(make, scale):
    # collinear vertices (exact zeros), signs a float filter cannot decide, subnormal and
    # huge coordinates: the exact predicate decides them all, so both sides agree
    d = _scaled(make(), scale)
    got = _same_as_oracle(d)
    assert len(got.triangles) > 0


def test_grid_domain_matches_brute_force():
    d = _grid_domain()
    brute = BruteDomain(*_rings(d))
    got = find_candidates(d)
    assert sorted(map(tuple, got.triangles.tolist())) == brute.triangles()
    # the side 0-1 runs along (0,0)-(2,0)-(4,0): chord 0-2 would pass through vertex 1
    assert [0, 2] not in valid_diagonals(d).tolist()


@SETTINGS
@given(small_domains(n_max=14, holes=(1, 2), grid=True))
def test_integer_domains_match_the_oracle(dom):
    _same_as_oracle(as_domain(*dom))


def test_side_signs_are_exact_orientations():
    d = _near_collinear_domain()
    seg = np.array([[0, 2], [4, 5], [7, 9], [1, 3]], dtype=np.int64)
    got = side_signs(d.vertices, seg)
    p = d.vertices
    for r, (a, b) in enumerate(seg.tolist()):
        want = orient(np.broadcast_to(p[a], p.shape), np.broadcast_to(p[b], p.shape), p)
        assert got[r].tolist() == want.tolist()
    assert side_signs(d.vertices, np.zeros((0, 2), dtype=np.int64)).shape == (0, d.n)


@pytest.mark.parametrize("n, h, seed", [(30, 1, 0), (60, 3, 1), (120, 2, 2), (60, 10, 3)])
def test_forced_diagonals_and_blocks_match_the_oracle(n, h, seed):
    d = as_domain(*random_domain(n, h, seed=seed))
    cand = find_candidates(d)
    values = DomainWeight(d, get_weight("perimeter")).on(cand)
    for keep in (np.ones(len(values), dtype=bool), values <= np.quantile(values, 0.6)):
        kept = prune(cand, keep)
        if kept is None:
            continue
        alive = np.unique(cand.sides[kept].ravel())
        alive = alive[alive >= cand.n_boundary] - cand.n_boundary
        want = oracle.forced_rows(cand.turns, cand.edges[cand.n_boundary :], alive.tolist())
        forced = forced_diagonals(cand, kept)
        assert np.flatnonzero(forced).tolist() == [r + cand.n_boundary for r in want]
        fixed = ~cand.is_diagonal | forced
        tris = np.flatnonzero(kept)
        key = (2 * cand.sides[tris] + (fixed[cand.sides[tris]] & (cand.signs[tris] > 0))).ravel()
        roots = oracle.link_roots(key, 3)
        assert np.array_equal(_core.domains.link(key.astype(np.int64), 3), roots)
        got = blocks(cand, kept, fixed)
        want_blocks = [tris[roots == r].tolist() for r in np.unique(roots)]
        assert [b.triangles.tolist() for b in got] == want_blocks


def test_link_joins_items_sharing_a_key():
    key = np.array([5, 1, 9, 9, 2, 3, 3, 7, 8], dtype=np.int64)  # items 0-1-2 chained via 9 and 3
    roots = _core.domains.link(key, 3)
    assert roots[0] == roots[1] == roots[2]
    key = np.array([1, 2, 3, 4, 5, 6], dtype=np.int64)
    assert _core.domains.link(key, 3).tolist() == [0, 1]


@pytest.mark.parametrize("name", ["diagonal", "perimeter", "area", "max_angle"])
def test_weights_on_candidates_are_the_per_triangle_floats(name):
    d = as_domain(*random_domain(80, 3, seed=7))
    cand = find_candidates(d)
    w = DomainWeight(d, get_weight(name))
    fast = w.on(cand)
    slow = w.many(cand.triangles)
    assert fast.tobytes() == slow.tobytes()  # bit for bit
    tri = cand.triangles[len(cand.triangles) // 2]
    assert fast[len(cand.triangles) // 2] == w(*tri.tolist())


def test_core_refuses_bad_arrays_with_value_errors():
    d = _grid_domain()
    pts, nxt = d.vertices, d.nxt
    with pytest.raises(ValueError, match="differ in length"):
        _core.domains.diagonals(pts, nxt[:-1])
    bad = nxt.copy()
    bad[0] = d.n
    with pytest.raises(ValueError, match="out of range"):
        _core.domains.diagonals(pts, bad)
    with pytest.raises(ValueError, match="out of range"):
        _core.domains.candidates(pts, nxt, np.array([-1], dtype=np.int64))
    with pytest.raises(ValueError, match="out of range"):
        _core.domains.side_signs(pts, np.array([[0, d.n]], dtype=np.int64))
    with pytest.raises(ValueError, match="multiple"):
        _core.domains.link(np.arange(4, dtype=np.int64), 3)
    cand = find_candidates(d)
    with pytest.raises(ValueError, match="out of range"):
        _core.domains.forced(cand.turns, cand.edges[d.n :], np.array([10**6], dtype=np.int64))
    with pytest.raises(TypeError):  # not (N, 2): nanobind names the expected signature
        _core.domains.diagonals(np.zeros((d.n, 3)), nxt)


@given(st.integers(0, 2**32 - 1), st.integers(1, 4))
@settings(max_examples=25, deadline=None)
def test_threads_do_not_change_the_sets(seed, h):
    # 300 vertices: the compiled loops run on threads; the order must not depend on them
    d = as_domain(*random_domain(300, h, seed=seed, depth=0.6))
    got = find_candidates(d)
    diag, turns = _core.domains.diagonals(np.ascontiguousarray(d.vertices), d.nxt)
    assert np.array_equal(got.edges[d.n :], diag) and np.array_equal(got.turns, turns)
    t = got.triangles
    assert (np.diff(t[:, 0]) >= 0).all() and (t[:, 0] < t[:, 1:].min(axis=1)).all()
    keys = (t[:, 0] * d.n + t[:, 1]) * d.n + t[:, 2]
    assert (np.diff(keys) > 0).all()
