"""fill_holes on trimesh meshes: watertight round trips, winding, reports, bad meshes."""

from __future__ import annotations

import numpy as np
import pytest

from optri import config, fill_holes
from optri.errors import HoleSkippedWarning, InvalidPolygonError, WeightError
from optri.holes import boundary_loops

trimesh = pytest.importorskip("trimesh")


def _holed_sphere(subdivisions=3):
    sphere = trimesh.creation.icosphere(subdivisions=subdivisions)
    c = sphere.triangles_center
    cut = (c[:, 2] > 0.85) | (np.linalg.norm(c - [1, 0, 0], axis=1) < 0.45)
    cut |= np.linalg.norm(c - [0, -1, 0], axis=1) < 0.25
    return sphere, trimesh.Trimesh(sphere.vertices, sphere.faces[~cut], process=False)


@pytest.mark.parametrize(
    "weight, method",
    [("liepa", "auto"), ("liepa", "liepa"), ("liepa", "delaunay"), ("area", "exact")],
)
def test_filled_sphere_is_watertight(weight, method):
    sphere, holed = _holed_sphere()
    loops = boundary_loops(holed.faces)
    assert len(loops) == 3 and not holed.is_watertight
    filled, records = fill_holes(holed, weight=weight, method=method)
    assert [r.status for r in records] == ["filled"] * 3
    assert len(filled.faces) == len(holed.faces) + sum(r.edges - 2 for r in records)
    assert filled.is_watertight and filled.is_winding_consistent
    assert filled.volume > 0  # outward, like the sphere's own faces
    assert filled.volume == pytest.approx(sphere.volume, rel=0.05)
    assert np.array_equal(filled.faces[: len(holed.faces)], holed.faces)
    for rec in records:
        assert rec.faces_added == rec.edges - 2 and rec.seconds >= 0
        if method == "auto":  # exact search up to the limit, Liepa's recurrence above it
            expected = "exact" if rec.edges <= config.HOLES_EXACT_MAX_N else "liepa"
        else:
            expected = method
        assert rec.method.split("->")[0] == expected  # "delaunay->exact" after a fallback


def test_new_faces_run_against_their_neighbours():
    _, holed = _holed_sphere(2)
    filled, _ = fill_holes(holed)
    old = {(a, b) for f in holed.faces.tolist() for a, b in zip(f, f[1:] + f[:1])}
    new = [
        (a, b) for f in filled.faces[len(holed.faces) :].tolist() for a, b in zip(f, f[1:] + f[:1])
    ]
    assert not old & set(new)  # no directed edge twice: consistent orientation
    for loop, _third in boundary_loops(holed.faces):
        for a, b in zip(loop.tolist(), np.roll(loop, -1).tolist()):
            assert (b, a) in old and (a, b) in new


def test_arrays_in_arrays_out_and_exact_liepa_patch():
    _, holed = _holed_sphere(2)
    (v, f), records = fill_holes((holed.vertices, holed.faces), method="exact")
    assert isinstance(f, np.ndarray) and f.shape[1] == 3
    assert trimesh.Trimesh(v, f, process=False).is_watertight
    assert all(isinstance(r.weight, tuple) for r in records)


def test_skipped_holes_are_reported_and_warned():
    _, holed = _holed_sphere()
    sizes = sorted(len(loop) for loop, _ in boundary_loops(holed.faces))
    limit = sizes[0]
    with pytest.warns(HoleSkippedWarning, match="max_hole_edges"):
        filled, records = fill_holes(holed, max_hole_edges=limit)
    skipped = [r for r in records if r.status == "skipped"]
    assert len(skipped) == sum(s > limit for s in sizes) > 0
    assert all("max_hole_edges" in r.reason and r.faces_added == 0 for r in skipped)
    assert len(filled.faces) == len(holed.faces) + sum(r.faces_added for r in records)
    first = records[0].to_dict()
    assert first["status"] == ("skipped" if first["edges"] > limit else "filled")
    assert first["faces_added"] == (0 if first["status"] == "skipped" else first["edges"] - 2)


def test_closed_mesh_has_no_holes():
    sphere = trimesh.creation.icosphere(subdivisions=1)
    filled, records = fill_holes(sphere)
    assert records == [] and len(filled.faces) == len(sphere.faces)


def test_pinched_bowtie_fills_both_loops():
    # two triangles touching at one vertex: vertex 0 has four boundary edges
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0]], dtype=float)
    f = np.array([[0, 1, 2], [0, 3, 4]])
    (_, f2), records = fill_holes((v, f))
    assert [r.status for r in records] == ["filled", "filled"]
    assert [r.pinched for r in records] == [[0], [0]]
    assert sorted(map(sorted, f2[2:].tolist())) == [[0, 1, 2], [0, 3, 4]]


@pytest.mark.parametrize(
    "mesh, match",
    [
        ((np.zeros((3, 3)), np.array([[0, 1, 5]])), "does not exist"),
        ((np.zeros((3, 2)), np.array([[0, 1, 2]])), "vertices"),
        ((np.zeros((3, 3)), np.zeros((0, 3), dtype=int)), "no faces"),
        ("not a mesh", "expected a trimesh"),
    ],
)
def test_bad_meshes(mesh, match):
    with pytest.raises(InvalidPolygonError, match=match):
        fill_holes(mesh)


def test_unknown_weight_or_method_fails_before_filling():
    _, holed = _holed_sphere(1)
    with pytest.raises(WeightError, match="unknown weight"):
        fill_holes(holed, weight="no_such_weight")
    with pytest.raises(InvalidPolygonError, match="unknown method"):
        fill_holes(holed, method="fastest")


def test_hole_that_cannot_be_filled_is_reported_not_fatal(monkeypatch):
    # exact search with no memory to spare: each hole fails alone, with a warning
    import optri

    _, holed = _holed_sphere(2)
    monkeypatch.setattr(optri.config, "MEMORY_LIMIT_BYTES", 1000)
    with pytest.warns(HoleSkippedWarning, match="needs"):
        filled, records = fill_holes(holed, method="exact")
    assert records and all(r.status == "failed" and "MB" in r.reason for r in records)
    assert len(filled.faces) == len(holed.faces)
    monkeypatch.setattr(optri.config, "MEMORY_LIMIT_BYTES", None)
    _, records = fill_holes(holed, method="auto")
    assert all(r.status == "filled" for r in records)


def test_callable_weight_fills_holes():
    _, holed = _holed_sphere(2)
    calls = []

    def w(vertices, i, k, j):
        calls.append(1)
        return float(np.linalg.norm(np.cross(vertices[k] - vertices[i], vertices[j] - vertices[i])))

    filled, records = fill_holes(holed, weight=w)
    assert filled.is_watertight and calls
    assert all(r.status == "filled" for r in records)


def test_filling_holes_never_imports_numba():
    # the hole searches are the compiled core's: no JIT, no compile wait on a first call
    import subprocess
    import sys

    code = (
        "import sys, numpy as np, optri\n"
        "from optri.io.meshes import read_mesh\n"
        "m = read_mesh(optri.data.path('sphere_two_holes.obj'))\n"
        "for method in optri.holes.METHODS:\n"
        "    (v, f), recs = optri.fill_holes((m.vertices, m.faces), method=method)\n"
        "    assert [r.status for r in recs] == ['filled', 'filled'], recs\n"
        "a = np.arange(60) / 9.6\n"
        "ring = np.column_stack((np.cos(a), np.sin(a), 0.3 * np.sin(3 * a)))\n"
        "for method in optri.holes.METHODS:\n"
        "    optri.fill_polyline(ring, 'liepa', method, 1.4 * ring)\n"
        "print('numba' in sys.modules)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "False"
