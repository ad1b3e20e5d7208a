"""Textured and attributed meshes: seams are no holes, attributes survive filling and files.

The real mesh is trimesh's ``fuze.obj`` (664 vertices after its texture seams split
502 positions, a material and a JPEG texture; ``tests/data/meshes/README.md``). A
real hole is cut by deleting the faces around a vertex.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st

import optri
from optri.cli import main
from optri.holes.boundary import edge_summary
from optri.io.meshes import read_mesh, write_mesh
from optri.meshdata import weld

trimesh = pytest.importorskip("trimesh")
DATA = Path(__file__).resolve().parent / "data" / "meshes"
FUZE = DATA / "fuze.obj"


def _seam_vertices(mesh) -> np.ndarray:
    """Mask of the vertices that share their position with another vertex."""
    welded = weld(np.asarray(mesh.vertices), np.asarray(mesh.faces))
    rep = np.arange(len(mesh.vertices))
    rep[mesh.faces.ravel()] = welded.ravel()
    count = np.bincount(rep, minlength=len(rep))
    return count[rep] > 1


def _cut(mesh, on_seam: bool):
    """``mesh`` without the faces around one vertex two rings deep, and those faces."""
    seam = _seam_vertices(mesh)
    welded = weld(np.asarray(mesh.vertices), np.asarray(mesh.faces))
    for v in range(len(mesh.vertices)):
        ring = np.unique(welded[(welded == v).any(axis=1)])
        gone = np.flatnonzero(np.isin(welded, ring).any(axis=1))
        if len(gone) < 12 or seam[v] != on_seam:
            continue
        if on_seam or not seam[np.unique(mesh.faces[gone])].any():
            break
    keep = np.setdiff1d(np.arange(len(mesh.faces)), gone)
    cut = trimesh.Trimesh(
        vertices=mesh.vertices,
        faces=mesh.faces[keep],
        visual=trimesh.visual.TextureVisuals(uv=mesh.visual.uv, material=mesh.visual.material),
        vertex_normals=mesh.vertex_normals,
        process=False,
    )
    return cut, gone


@pytest.fixture(scope="module")
def fuze():
    return read_mesh(FUZE)


def test_the_fuze_is_read_with_its_seams_and_texture(fuze):
    assert len(fuze.vertices) == 664 and len(fuze.faces) == 1000  # 502 positions, 664 vt
    assert fuze.visual.uv.shape == (664, 2) and fuze.visual.material.image is not None
    assert "vertex_normals" in fuze._cache.cache
    assert _seam_vertices(fuze).sum() > 100
    assert len(read_mesh(FUZE, attributes=False).vertices) == 502
    assert not hasattr(read_mesh(FUZE, attributes=False).visual, "uv")


def test_seams_are_not_holes(fuze):
    assert edge_summary(fuze.faces)["boundary"] > 0  # unwelded, the seams are open
    filled, records = optri.fill_holes(fuze)
    assert records == [] and len(filled.faces) == len(fuze.faces)
    np.testing.assert_array_equal(filled.visual.uv, fuze.visual.uv)


@pytest.mark.parametrize("on_seam", [False, True])
@pytest.mark.parametrize("refine", [False, True])
def test_a_cut_hole_is_filled_keeping_every_attribute(fuze, on_seam, refine):
    cut, _ = _cut(fuze, on_seam)
    nv = len(cut.vertices)
    uv, normals = cut.visual.uv.copy(), cut.vertex_normals.copy()
    filled, records = optri.fill_holes(cut, refine=refine, fair=1 if refine else None)
    assert len(records) == 1 and records[0].status == "filled"
    assert (records[0].vertices_added > 0) == refine
    np.testing.assert_array_equal(filled.vertices[:nv], cut.vertices)
    np.testing.assert_array_equal(filled.faces[: len(cut.faces)], cut.faces)
    np.testing.assert_array_equal(filled.visual.uv[:nv], uv)
    np.testing.assert_array_equal(filled.vertex_normals[:nv], normals)
    assert filled.visual.material is cut.visual.material
    # closed once welded, and no seam more than before the cut
    welded = weld(filled.vertices, filled.faces)
    assert edge_summary(welded) == {"boundary": 0, "nonmanifold": 0, "degenerate_faces": 0}
    patch = filled.faces[len(cut.faces) :]
    open_edges = _open_edges(filled.faces)
    left = open_edges - _open_edges(fuze.faces) - _open_edges(patch)
    if not on_seam:  # away from seams the patch meets the mesh along every border edge
        assert open_edges == _open_edges(fuze.faces)
    else:  # a patch face at a seam corner takes one of the two copies there
        seam = _seam_vertices(fuze)
        assert all(seam[a] or seam[b] for a, b in left) and len(left) <= 2
    # new vertices: UVs inside the hull of the border's UVs, unit normals
    new = np.arange(nv, len(filled.vertices))
    assert len(new) == records[0].vertices_added
    if refine:
        border = np.unique(patch[patch < nv])
        hull = _hull(uv[border])
        assert (hull.find_simplex(filled.visual.uv[new], tol=1e-12) >= 0).all()
        np.testing.assert_allclose(np.linalg.norm(filled.vertex_normals[new], axis=1), 1.0)


def _open_edges(faces) -> set[tuple[int, int]]:
    """Undirected edges used by one face."""
    e = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    u, c = np.unique(e, axis=0, return_counts=True)
    return {(int(a), int(b)) for a, b in u[c == 1]}


def _hull(points):
    spatial = pytest.importorskip("scipy.spatial")
    return spatial.Delaunay(points)


def test_patch_faces_on_the_border_use_the_copies_of_the_face_across(fuze):
    cut, _ = _cut(fuze, on_seam=True)
    filled, records = optri.fill_holes(cut)
    assert len(records) == 1
    patch = filled.faces[len(cut.faces) :]
    welded = weld(cut.vertices, cut.faces)
    own = {}
    for f, w in zip(cut.faces.tolist(), welded.tolist()):
        for i in range(3):
            own[(w[i], w[(i + 1) % 3])] = (f[i], f[(i + 1) % 3])
    rep = weld(filled.vertices, patch)
    matched = 0
    for f, w in zip(patch.tolist(), rep.tolist()):
        allowed: dict[int, set[int]] = {}
        for i in range(3):
            across = own.get((w[(i + 1) % 3], w[i]))
            if across is not None:  # a border edge: the copies of the face across
                allowed.setdefault(i, set()).add(across[1])
                allowed.setdefault((i + 1) % 3, set()).add(across[0])
                matched += (f[(i + 1) % 3], f[i]) == across
        assert all(f[i] in copies for i, copies in allowed.items())
    # every border edge meets its face with the same two vertex ids, but where an ear
    # of the patch has a seam at its tip (the faces across use different copies there)
    assert records[0].edges - 1 <= matched <= records[0].edges


def test_refined_vertices_are_interpolated_as_they_are_placed(fuze):
    """Without fairing a new vertex is the mean of its parents: so is any attribute."""
    cut, gone = _cut(fuze, on_seam=True)
    cut.vertex_attributes["position"] = np.asarray(cut.vertices).copy()
    cut.vertex_attributes["label"] = np.arange(len(cut.vertices), dtype=np.int32)
    cut.face_attributes["face_id"] = np.arange(len(cut.faces))
    filled, records = optri.fill_holes(cut, refine=True, density=4.0)
    assert records[0].vertices_added > 5
    np.testing.assert_array_equal(filled.vertex_attributes["position"], filled.vertices)
    labels = filled.vertex_attributes["label"]
    assert labels.dtype == np.int32 and len(labels) == len(filled.vertices)
    # new faces take the face attributes of a mesh face on the hole's border
    ids = filled.face_attributes["face_id"]
    np.testing.assert_array_equal(ids[: len(cut.faces)], np.arange(len(cut.faces)))
    loop = set(records[0].vertices)
    welded = weld(cut.vertices, cut.faces)
    for fid in set(ids[len(cut.faces) :].tolist()):
        assert len(loop & set(welded[fid].tolist())) >= 2  # an edge on the border


def test_face_and_vertex_colours_are_kept(fuze):
    cut, _ = _cut(fuze, on_seam=False)
    colours = cut.visual.to_color().vertex_colors  # sampled from the texture
    by_vertex = trimesh.Trimesh(cut.vertices, cut.faces, vertex_colors=colours, process=False)
    filled, rec = optri.fill_holes(by_vertex, refine=True)
    assert rec[0].vertices_added > 0
    out = filled.visual.vertex_colors
    np.testing.assert_array_equal(out[: len(colours)], colours)
    border = np.asarray(rec[0].vertices)
    new = out[len(colours) :]
    assert (new >= colours[border].min(axis=0)).all() and (new <= colours[border].max(axis=0)).all()
    face_colours = np.tile([10, 20, 30, 255], (len(cut.faces), 1)).astype(np.uint8)
    face_colours[::2] = [200, 100, 50, 255]
    by_face = trimesh.Trimesh(cut.vertices, cut.faces, face_colors=face_colours, process=False)
    filled, rec = optri.fill_holes(by_face)
    got = filled.visual.face_colors
    np.testing.assert_array_equal(got[: len(cut.faces)], face_colours)
    assert {tuple(c) for c in got[len(cut.faces) :].tolist()} <= {
        (10, 20, 30, 255),
        (200, 100, 50, 255),
    }


def test_plain_arrays_keep_their_layout(fuze):
    cut, _ = _cut(fuze, on_seam=True)
    (v, f), records = optri.fill_holes((np.asarray(cut.vertices), np.asarray(cut.faces)))
    assert len(records) == 1
    np.testing.assert_array_equal(v, cut.vertices)
    np.testing.assert_array_equal(f[: len(cut.faces)], cut.faces)


def test_near_copies_are_welded_with_merge_rtol():
    grid = trimesh.creation.box().subdivide()
    v = np.asarray(grid.vertices).copy()
    f = np.asarray(grid.faces).copy()
    f = f[1:]  # one hole
    # split every vertex of the first 40 faces into a copy 1e-12 away
    dup = np.unique(f[:40])
    copy_of = {int(x): len(v) + i for i, x in enumerate(dup)}
    v = np.concatenate([v, v[dup] + 1e-12])
    f[:40] = np.vectorize(copy_of.get)(f[:40])
    _, exact = optri.fill_holes((v, f))
    _, near = optri.fill_holes((v, f), merge_rtol=1e-9)
    assert len(exact) > 1 and len(near) == 1 and near[0].edges == 3
    with pytest.raises(optri.InvalidPolygonError, match="merge tolerance"):
        optri.fill_holes((v, f), merge_rtol=-1.0)


@settings(max_examples=25, deadline=None)
@given(st.data())
def test_splitting_vertices_finds_the_same_holes(data):
    """Duplicating vertices arbitrarily (and renumbering) changes no hole."""
    mesh = read_mesh(DATA / "pmp_hole_capsule.off", attributes=False)
    v, f = np.asarray(mesh.vertices), np.asarray(mesh.faces)
    _, base = optri.fill_holes((v, f), method="liepa")
    rng = np.random.default_rng(data.draw(st.integers(0, 2**32 - 1)))
    corners = rng.random(f.shape) < data.draw(st.floats(0.05, 0.9))
    split_f = f.copy()
    split_f[corners] = len(v) + np.arange(corners.sum())
    split_v = np.concatenate([v, v[f[corners]]])
    perm = rng.permutation(len(split_v))
    inv = np.empty_like(perm)
    inv[perm] = np.arange(len(perm))
    (v2, f2), split = optri.fill_holes((split_v[perm], inv[split_f]), method="liepa")

    def holes(records, vertices):
        return sorted(
            (r.edges, r.faces_added, sorted(map(tuple, vertices[r.vertices].tolist())))
            for r in records
        )

    assert holes(split, split_v[perm]) == holes(base, v)
    assert edge_summary(weld(v2, f2))["boundary"] == 0


def test_fill_cli_round_trip_obj_keeps_texture(fuze, tmp_path):
    cut, _ = _cut(fuze, on_seam=False)
    src = tmp_path / "in" / "cut.obj"
    src.parent.mkdir()
    write_mesh(cut, src)
    assert sorted(p.name for p in src.parent.iterdir()) == [
        "cut.mtl",
        "cut.obj",
        "cut_texture.jpeg",
    ]
    before = read_mesh(src)
    out = tmp_path / "out" / "filled mesh.obj"
    out.parent.mkdir()
    res = CliRunner().invoke(
        main, ["fill", str(src), "-o", str(out), "--refine", "--json", "--quiet"]
    )
    assert res.exit_code == 0, res.output
    report = json.loads(res.stdout)
    assert len(report["holes"]) == 1 and report["watertight"] is True
    names = sorted(p.name for p in out.parent.iterdir())
    assert names == ["filled mesh.obj", "filled_mesh.mtl", "filled_mesh_texture.jpeg"]
    after = read_mesh(out)
    nv = len(before.vertices)
    assert len(after.vertices) == nv + report["holes"][0]["vertices_added"] > nv
    np.testing.assert_array_equal(after.visual.uv[:nv], before.visual.uv)
    np.testing.assert_array_equal(after.vertex_normals[:nv], before.vertex_normals)
    assert after.visual.material.image.size == before.visual.material.image.size
    text = out.read_text()
    assert "mtllib filled_mesh.mtl" in text and "\nvt " in text and "\nvn " in text


def test_fill_cli_round_trip_ply_keeps_colours(fuze, tmp_path):
    cut, _ = _cut(fuze, on_seam=True)
    colours = cut.visual.to_color().vertex_colors
    coloured = trimesh.Trimesh(cut.vertices, cut.faces, vertex_colors=colours, process=False)
    src, out = tmp_path / "cut.ply", tmp_path / "filled.ply"
    write_mesh(coloured, src)
    before = read_mesh(src)  # copies of equal colour are merged on reading
    assert before.visual.kind == "vertex" and len(before.vertices) < len(colours)
    res = CliRunner().invoke(main, ["fill", str(src), "-o", str(out), "--refine", "--quiet"])
    assert res.exit_code == 0, res.output
    assert "1 of 1 holes filled" in res.output and "watertight: True" in res.output
    after = read_mesh(out)
    nv = len(before.vertices)
    np.testing.assert_array_equal(after.vertices[:nv], before.vertices)
    np.testing.assert_array_equal(after.visual.vertex_colors[:nv], before.visual.vertex_colors)
    assert len(after.vertices) > nv


def test_material_names_from_the_input_never_choose_where_files_go(tmp_path):
    image = pytest.importorskip("PIL.Image").new("RGB", (4, 4), (255, 0, 0))
    material = trimesh.visual.material.SimpleMaterial(image=image, name="../../escape")
    mesh = trimesh.Trimesh(
        [[0, 0, 0], [1, 0, 0], [0, 1, 0]],
        [[0, 1, 2]],
        visual=trimesh.visual.TextureVisuals(uv=[[0, 0], [1, 0], [0, 1]], material=material),
        process=False,
    )
    out = tmp_path / "a" / "b" / "x;y z.obj"
    out.parent.mkdir(parents=True)
    write_mesh(mesh, out)
    written = sorted(str(p.relative_to(tmp_path)) for p in tmp_path.rglob("*") if p.is_file())
    assert written == ["a/b/x;y z.obj", "a/b/x_y_z.mtl", "a/b/x_y_z_texture.png"]
    assert ".." not in (out.parent / "x_y_z.mtl").read_text()
    np.testing.assert_array_equal(read_mesh(out).visual.uv, mesh.visual.uv)


def test_fill_cli_welds_near_copies_with_merge_tolerance(fuze, tmp_path):
    """Copies a little apart keep their UVs on reading and are welded to find holes."""
    cut, _ = _cut(fuze, on_seam=False)
    v = np.asarray(cut.vertices).copy()
    seam = _seam_vertices(cut)
    v[seam] += 3e-8 * (np.arange(seam.sum()) % 3)[:, None]  # the copies drift apart
    moved = trimesh.Trimesh(v, cut.faces, visual=cut.visual.copy(), process=False)
    src, out = tmp_path / "moved.obj", tmp_path / "filled.obj"
    write_mesh(moved, src)
    args = ["fill", str(src), "-o", str(out), "--json", "--quiet"]
    loose = json.loads(CliRunner().invoke(main, args).stdout)
    res = CliRunner().invoke(main, [*args, "--merge-tolerance", "1e-2"])
    assert res.exit_code == 0, res.output
    report = json.loads(res.stdout)
    assert len(loose["holes"]) > 1 and len(report["holes"]) == 1 and report["watertight"]
    after = read_mesh(out)
    np.testing.assert_array_equal(after.visual.uv[: len(v)], read_mesh(src).visual.uv)


def test_ply_keeps_texture_coordinates_and_normals(fuze, tmp_path):
    cut, _ = _cut(fuze, on_seam=True)
    used = np.unique(cut.faces)  # trimesh's PLY reader drops normals beside unused vertices
    remap = np.zeros(len(cut.vertices), dtype=np.int64)
    remap[used] = np.arange(len(used))
    compact = trimesh.Trimesh(
        cut.vertices[used],
        remap[cut.faces],
        vertex_normals=cut.vertex_normals[used],
        visual=trimesh.visual.TextureVisuals(uv=cut.visual.uv[used]),
        process=False,
    )
    src, out = tmp_path / "cut.ply", tmp_path / "filled.ply"
    write_mesh(compact, src)
    before = read_mesh(src)
    assert "vertex_normals" in before._cache.cache and before.visual.uv is not None
    filled, records = optri.fill_holes(before, refine=True)
    write_mesh(filled, out)
    after = read_mesh(out)
    nv = len(before.vertices)
    assert len(after.vertices) == nv + records[0].vertices_added
    np.testing.assert_array_equal(after.visual.uv[:nv], before.visual.uv)
    np.testing.assert_array_equal(after.vertex_normals[:nv], before.vertex_normals)


def test_a_planted_link_beside_the_output_is_replaced_not_followed(fuze, tmp_path):
    victim = tmp_path / "victim.txt"
    victim.write_text("keep me")
    out = tmp_path / "out" / "m.obj"
    out.parent.mkdir()
    (out.parent / "m.mtl").symlink_to(victim)
    write_mesh(fuze, out)
    assert victim.read_text() == "keep me"
    assert not (out.parent / "m.mtl").is_symlink()
    assert "map_Kd m_texture.jpeg" in (out.parent / "m.mtl").read_text()
