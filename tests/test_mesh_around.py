"""Per-hole work on the faces near the hole: the same mesh as on the whole mesh.

``fill_holes`` gives its refinement, fairing and crossing checks only the faces
around each hole (:class:`optri.holes.around.Around`). The oracle: the same fill with
those queries returning every face, which is the whole mesh each step saw before.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import optri
from optri.holes import around
from optri.holes.around import Around

trimesh = pytest.importorskip("trimesh")
pytest.importorskip("scipy")


def _everything(self, *args):
    return None  # every face, as for the first holes


def _holed_sphere(subdivisions: int, holes: int, seed: int):
    """An icosphere with the stars of ``holes`` vertices removed, some of them touching."""
    s = trimesh.creation.icosphere(subdivisions=subdivisions)
    v, f = np.asarray(s.vertices), np.asarray(s.faces)
    rng = np.random.default_rng(seed)
    keep = np.ones(len(f), dtype=bool)
    for p in rng.choice(len(v), size=holes, replace=False):
        keep[(f == p).any(axis=1)] = False
    return v, f[keep]


def _fill_both(monkeypatch, mesh, **kw):
    with monkeypatch.context() as m:
        m.setattr(around, "WHOLE_MESH_HOLES", 0)  # every hole sees the faces near it only
        local = optri.fill_holes(mesh, **kw)
    with monkeypatch.context() as m:
        m.setattr(Around, "rings", _everything)
        m.setattr(Around, "boxed", _everything)
        whole = optri.fill_holes(mesh, **kw)
    return local, whole


def _same(a, b):
    (va, fa), ra = a
    (vb, fb), rb = b
    assert np.array_equal(va, vb) and np.array_equal(fa, fb)
    strip = [{k: x for k, x in vars(r).items() if k != "seconds"} for r in ra]
    assert strip == [{k: x for k, x in vars(r).items() if k != "seconds"} for r in rb]


@pytest.mark.parametrize(
    "kw",
    [{}, {"refine": True}, {"refine": True, "fair": 0}, {"refine": True, "fair": 1},
     {"refine": True, "fair": 2, "density": 3.0}],  # fmt: skip
)
def test_local_steps_give_the_whole_mesh_result(monkeypatch, kw):
    # 30 vertex stars cut from 642 vertices: holes merge, touch at a vertex, sit apart
    mesh = _holed_sphere(3, 30, seed=5)
    local, whole = _fill_both(monkeypatch, mesh, **kw)
    _same(local, whole)
    (v, f), records = local
    added = sum(r.vertices_added for r in records)
    assert added > 0 or not kw.get("refine")
    assert len(records) > 10 and all(r.status == "filled" for r in records)
    # closed again: every directed edge once, each new vertex appended and used
    e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    assert len(np.unique(e, axis=0)) == len(e) == 3 * len(f)
    n = len(mesh[0])
    assert len(v) == n + added and np.isin(np.arange(n, len(v)), f).all()


def test_local_steps_give_the_whole_mesh_result_with_islands(monkeypatch):
    # a disc with an annular hole and a smaller disc left inside it: a hole with an island
    g = np.stack(np.meshgrid(np.linspace(-1, 1, 17), np.linspace(-1, 1, 17)), -1).reshape(-1, 2)
    faces = []
    for r in range(16):
        for c in range(16):
            a = r * 17 + c
            faces += [[a, a + 1, a + 18], [a, a + 18, a + 17]]
    f = np.array(faces)
    v = np.column_stack([g, 0.2 * g[:, 0] ** 2])
    radius = np.linalg.norm(v[f].mean(axis=1)[:, :2], axis=1)
    mesh = (v, f[(radius < 0.25) | (radius > 0.6)])
    local, whole = _fill_both(monkeypatch, mesh, refine=True, fair=1)
    _same(local, whole)
    assert any(r.islands for r in local[1])


def _brute_rings(faces, seeds, sweeps):
    reached, found = set(seeds.tolist()), set()
    for _ in range(sweeps):
        new = {t for t, face in enumerate(faces.tolist()) if reached & set(face)}
        found |= new
        reached |= {v for t in new for v in faces[t].tolist()}
    return sorted(found)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 10**6), st.integers(1, 4), st.integers(0, 3))
def test_rings_and_boxes_match_a_scan_of_every_face(seed, sweeps, patches):
    rng = np.random.default_rng(seed)
    v, f = _holed_sphere(1, 3, seed)
    a = Around(v, f, whole_holes=0)
    all_faces = [f]
    for _ in range(patches):  # a fan over a new vertex on a random face's corners
        corners = f[rng.integers(len(f))]
        new = v[corners].mean(axis=0, keepdims=True) * 1.1
        k = a.size
        fan = np.array([[corners[0], corners[1], k], [corners[1], corners[2], k]])
        a.add(new, fan)
        all_faces.append(fan)
    every = np.concatenate(all_faces)
    pos = np.concatenate([v, a.new_vertices()])
    seeds = rng.choice(a.size, size=2, replace=False)
    assert a.rings(seeds, sweeps).tolist() == _brute_rings(every, seeds, sweeps)
    lo = rng.uniform(-1.2, 0.8, 3)
    hi = lo + rng.uniform(0, 0.6, 3)
    boxes = pos[every]
    meet = np.all((boxes.min(axis=1) <= hi) & (boxes.max(axis=1) >= lo), axis=1)
    got = a.boxed(lo, hi)
    assert set(np.flatnonzero(meet).tolist()) <= set(got.tolist())
    # the slack is a millionth of the extent: nothing farther comes back
    far = 1e-5 * 2
    near = np.all((boxes.min(axis=1) <= hi + far) & (boxes.max(axis=1) >= lo - far), axis=1)
    assert set(got.tolist()) <= set(np.flatnonzero(near).tolist())
    assert np.array_equal(a.faces_of(np.arange(len(every))), every)


def test_a_box_query_finds_a_wide_face_far_from_its_low_corner():
    # a strip of 40 small faces and one face a hundred times longer lying over it
    x = np.arange(41.0)
    v = np.concatenate([np.column_stack([x, np.zeros(41), np.zeros(41)]),
                        np.column_stack([x, np.ones(41), np.zeros(41)]),
                        [[0.0, 0.5, 1.0], [40.0, 0.5, 1.0], [20.0, 2.0, 1.0]]])  # fmt: skip
    small = [[i, i + 1, 41 + i] for i in range(40)]
    f = np.array([*small, [82, 83, 84]])
    a = Around(v, f, whole_holes=0)
    assert a.boxed(np.array([35.0, 0.4, 0.9]), np.array([36.0, 0.6, 1.1])).tolist() == [40]
    got = a.boxed(np.array([35.2, 0.1, -0.1]), np.array([35.4, 0.6, 1.1])).tolist()
    assert got == [35, 40]


def test_local_numbers_keep_the_global_order_and_place_pending_vertices():
    v = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])
    a = Around(v, np.array([[0, 1, 2], [1, 3, 2]]))
    pos, faces, patch, ids = a.local(np.array([1]), np.array([[3, 1, 4]]), np.array([[2.0, 2, 0]]))
    assert ids.tolist() == [1, 2, 3, 4]
    assert faces.tolist() == [[0, 2, 1], [2, 0, 3]] and patch.tolist() == [[2, 0, 3]]
    assert pos.tolist() == [[1, 0, 0], [0, 1, 0], [1, 1, 0], [2, 2, 0]]
