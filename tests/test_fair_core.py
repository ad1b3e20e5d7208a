"""The compiled fairing solve against its numpy/scipy reference: the same positions to
rounding on analytic and random patches, each continuity, one and two passes; the same
failures; an order with little fill."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import optri
from optri.errors import InvalidPolygonError
from optri.holes.fair import fair_vertices, laplacian, reference_fair_vertices

trimesh = pytest.importorskip("trimesh")
sparse = pytest.importorskip("scipy.sparse")
linalg = pytest.importorskip("scipy.sparse.linalg")

TOL = 1e-9  # of the patch's extent


def _grid(k: int):
    g = np.stack(np.meshgrid(np.arange(k, dtype=float), np.arange(k, dtype=float)), -1)
    faces = []
    for r in range(k - 1):
        for c in range(k - 1):
            a = r * k + c
            faces += [[a, a + 1, a + k + 1], [a, a + k + 1, a + k]]
    return g.reshape(-1, 2), np.array(faces, dtype=np.int64)


def _agree(v, f, free, continuity, passes):
    got = fair_vertices(v, f, free, continuity, passes=passes)
    want = reference_fair_vertices(v, f, free, continuity, passes=passes)
    assert got.ok and want.ok
    extent = np.ptp(want.vertices[free], axis=0).max()
    assert np.abs(got.vertices - want.vertices).max() <= TOL * extent
    others = np.setdiff1d(np.arange(len(v)), free)
    assert np.array_equal(got.vertices[others], v[others])  # the rest untouched, bit for bit
    return got


def _sphere_patch():
    s = trimesh.creation.icosphere(subdivisions=3)
    keep = s.vertices[s.faces].mean(axis=1)[:, 2] < 0.5
    v, f = np.asarray(s.vertices), np.asarray(s.faces)[keep]
    (v1, f1), _ = optri.fill_holes((v, f), refine=True)
    return v1, f1, np.arange(len(v), len(v1))


def _paraboloid_patch():
    g, faces = _grid(17)
    g = (g - 8) / 8
    v = np.column_stack([g, g[:, 0] ** 2 + 0.5 * g[:, 1] ** 2])
    cen = v[faces].mean(axis=1)
    (v1, f1), recs = optri.fill_holes(
        (v, faces[np.hypot(cen[:, 0], cen[:, 1]) > 0.6]), refine=True, max_hole_edges=80
    )
    return v1, f1, np.arange(len(v), len(v1))


@pytest.mark.parametrize("passes", [1, 2])
@pytest.mark.parametrize("continuity", [0, 1, 2])
@pytest.mark.parametrize("surface", [_sphere_patch, _paraboloid_patch])
def test_the_core_solves_refined_patches_as_the_reference(surface, continuity, passes):
    v, f, free = surface()
    assert len(free) > 20
    _agree(v, f, free, continuity, passes)


@settings(max_examples=40, deadline=None)
@given(
    k=st.integers(5, 10),
    seed=st.integers(0, 2**32 - 1),
    continuity=st.sampled_from([0, 1, 2]),
    passes=st.integers(1, 2),
)
def test_the_core_solves_random_patches_as_the_reference(k, seed, continuity, passes):
    rng = np.random.default_rng(seed)
    g, f = _grid(k)
    g = g + rng.uniform(-0.2, 0.2, g.shape)  # obtuse corners too
    v = np.column_stack([g, rng.normal(0, 0.3, len(g))])
    inner = np.flatnonzero((g.min(axis=1) > 0.5) & (g.max(axis=1) < k - 1.5))
    free = inner[rng.random(len(inner)) < 0.7]
    if len(free) == 0:
        free = inner[:1]
    f = f[rng.permutation(len(f))]  # faces in any order
    _agree(v, f, free, continuity, passes)


def test_a_vertex_without_area_fails_alike():
    g, f = _grid(5)
    v = np.vstack([np.column_stack([g, np.zeros(len(g))]), [[9.0, 9.0, 9.0]]])
    free = np.array([12, 25])  # 25 is on no face
    got = fair_vertices(v, f, free, 1)
    want = reference_fair_vertices(v, f, free, 1)
    assert not got.ok and got.reason == want.reason == "a vertex to fair has no area around it"
    assert np.array_equal(got.vertices, v)


def test_a_non_finite_neighbourhood_fails_and_keeps_the_input():
    g, f = _grid(6)
    v = np.column_stack([g, np.zeros(len(g))])
    # two rings from the free vertex: in its right-hand side from L^2 on (a non-finite
    # solution), in its system from L^3 on (a non-finite pivot)
    v[0, 2] = np.nan
    for k in (1, 2):
        got = fair_vertices(v, f, np.array([14]), k)
        want = reference_fair_vertices(v, f, np.array([14]), k)
        assert not got.ok and not want.ok
        assert got.reason.split(" (")[0] == want.reason.split(" (")[0]  # detail aside
        assert np.array_equal(got.vertices, v, equal_nan=True)
    assert fair_vertices(v, f, np.array([14]), 0).ok  # out of L's reach
    v[8, 2] = np.nan  # a neighbour: the free vertex's own area is not finite
    got = fair_vertices(v, f, np.array([14]), 0)
    assert not got.ok and got.reason == reference_fair_vertices(v, f, np.array([14]), 0).reason


def test_faces_naming_missing_vertices_are_refused():
    g, f = _grid(4)
    v = np.column_stack([g, np.zeros(len(g))])
    for bad in (len(v), -1):
        f2 = f.copy()
        f2[0, 0] = bad
        for solve in (fair_vertices, reference_fair_vertices):
            with pytest.raises(InvalidPolygonError, match="does not exist"):
                solve(v, f2, np.array([5]), 1)


@pytest.mark.parametrize("continuity", [1, 2])
def test_the_order_keeps_the_fill_near_minimum_degree(continuity):
    # a 30 x 30 patch: the nested-dissection order's factor is at most 1.5 times
    # SuperLU's under multiple minimum degree (a row-by-row order's is over twice)
    from optri._core import fair as core

    g, f = _grid(32)
    v = np.column_stack([g, 0.1 * np.sin(g[:, 0]) * np.cos(g[:, 1])])
    free = np.flatnonzero((g.min(axis=1) > 0) & (g.max(axis=1) < 31))
    C, A = laplacian(v, f)
    inv = np.diag(1.0 / A)
    op = C.toarray()
    for _ in range(continuity):
        op = C.toarray() @ inv @ op
    lhs = sparse.csc_matrix(op[np.ix_(free, free)])
    lu = linalg.splu(
        lhs, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True}
    )
    ours = core.fill(v, f, free, continuity)
    assert ours <= 1.5 * (lu.L.nnz - len(free))
