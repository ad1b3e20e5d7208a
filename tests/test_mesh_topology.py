"""The core's whole-mesh passes (``optri._core.topology``) against numpy oracles.

Each oracle is the plain numpy statement of what the pass returns (sorts and unique
calls over every row); the meshes are random index soups, so repeated, degenerate and
non-manifold faces, isolated vertices, signed zeros and exact duplicates all occur.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from optri._core import topology

from optri import fill_holes
from optri.holes.boundary import edge_keys
from optri.meshdata import weld


def oracle_weld_first(points: np.ndarray) -> np.ndarray:
    _, first, inverse = np.unique(points, axis=0, return_index=True, return_inverse=True)
    return first[inverse.reshape(-1)].astype(np.int64)


def oracle_single_edges(faces: np.ndarray, nv: int) -> np.ndarray:
    key = edge_keys(faces, nv)
    _, inverse, counts = np.unique(key, return_inverse=True, return_counts=True)
    return np.flatnonzero(counts[inverse] == 1)


def oracle_components(faces: np.ndarray, nv: int) -> np.ndarray:
    label = np.arange(nv)
    for _ in range(nv):  # relax every edge until no label drops: the least id reachable
        for a, b in ((0, 1), (1, 2), (0, 2)):
            low = np.minimum(label[faces[:, a]], label[faces[:, b]])
            np.minimum.at(label, faces[:, a], low)
            np.minimum.at(label, faces[:, b], low)
    return label


def oracle_edges_among(faces: np.ndarray, nv: int, flag: np.ndarray) -> np.ndarray:
    key = edge_keys(faces, nv)
    a, b = np.divmod(key, nv)
    return np.unique(key[flag[a] & flag[b]])


@st.composite
def soups(draw):
    nv = draw(st.integers(1, 30))
    m = draw(st.integers(1, 50))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    faces = rng.integers(0, nv, (m, 3)).astype(np.int64)
    points = rng.integers(-2, 3, (nv, 3)).astype(np.float64)
    points[rng.random((nv, 3)) < 0.3] = -0.0
    flag = rng.random(nv) < 0.6
    return faces, points, flag, nv


@settings(max_examples=200, deadline=None)
@given(soups())
def test_passes_equal_their_oracles(soup):
    faces, points, flag, nv = soup
    np.testing.assert_array_equal(topology.weld_first(points), oracle_weld_first(points))
    np.testing.assert_array_equal(topology.single_edges(faces, nv), oracle_single_edges(faces, nv))
    np.testing.assert_array_equal(topology.components(faces, nv), oracle_components(faces, nv))
    np.testing.assert_array_equal(
        topology.edges_among(faces, nv, flag), oracle_edges_among(faces, nv, flag)
    )


def test_signed_zeros_are_one_position():
    points = np.array([[0.0, 1, 2], [-0.0, 1, 2], [0.0, 1, -2], [0.0, -0.0, 2]])
    assert topology.weld_first(points).tolist() == [0, 0, 2, 3]


def test_weld_keeps_faces_without_shared_positions():
    v = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])
    f = np.array([[0, 1, 2], [1, 3, 2]])
    assert weld(v, f) is f
    v[3] = v[0]
    assert weld(v, f).tolist() == [[0, 1, 2], [1, 0, 2]]


def test_components_of_two_pieces_and_a_loose_vertex():
    f = np.array([[4, 2, 3], [3, 2, 6], [0, 5, 1]])
    assert topology.components(f, 8).tolist() == [0, 0, 2, 2, 2, 0, 2, 7]


@pytest.mark.parametrize(
    "call",
    [
        lambda: topology.single_edges(np.array([[0, 1, 5]]), 3),
        lambda: topology.components(np.array([[0, -1, 2]]), 3),
        lambda: topology.edges_among(np.array([[0, 1, 2]]), 3, np.ones(2, dtype=bool)),
        lambda: topology.weld_first(np.zeros((3, 2))),
    ],
)
def test_bad_shapes_and_indices_are_value_errors(call):
    with pytest.raises(ValueError):
        call()


@pytest.mark.filterwarnings("ignore::optri.errors.HoleSkippedWarning")
@pytest.mark.parametrize("fair", [None, 1])
def test_fill_holes_reports_the_crossings_left(fair):
    # a flat grid with a round hole and a closed tetrahedron piercing it: every patch
    # crosses the tetrahedron; a faired fill counts its final crossings in the fairing
    # check, an unfaired one afterwards, and the record equals a fresh count either way
    from optri.holes.intersect import intersecting_pairs

    g = np.arange(-4.0, 5.0)
    x, y = np.meshgrid(g, g, indexing="ij")
    v = np.column_stack([x.ravel(), y.ravel(), np.zeros(81)])
    quads = [
        (i * 9 + j, (i + 1) * 9 + j, (i + 1) * 9 + j + 1, i * 9 + j + 1)
        for i in range(8)
        for j in range(8)
    ]
    f = np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))])
    f = f[np.linalg.norm(v[f].mean(axis=1)[:, :2], axis=1) > 2.3]
    tip = len(v)
    v = np.concatenate([v, [[0, 0, 1.0], [0.6, 0, -1], [-0.5, 0.5, -1], [-0.4, -0.5, -1]]])
    a, b, c, d = tip, tip + 1, tip + 2, tip + 3
    f = np.concatenate([f, [[a, b, c], [a, c, d], [a, d, b], [b, d, c]]])
    (v2, f2), records = fill_holes((v, f), max_hole_edges=20, refine=True, fair=fair)
    rec = next(r for r in records if r.status == "filled")
    assert rec.vertices_added > 0 and rec.faired == (fair is not None)
    new = f2[len(f) :]
    assert rec.self_intersections == len(intersecting_pairs(v2, f2, new)) > 0
