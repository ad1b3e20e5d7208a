"""``optri fill`` on the bundled mesh with two holes."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from optri.cli import main

trimesh = pytest.importorskip("trimesh")
EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "sphere_two_holes.obj"


def test_fill_bundled_mesh(tmp_path):
    out = tmp_path / "filled.ply"
    res = CliRunner().invoke(main, ["fill", str(EXAMPLE), "-o", str(out), "--quiet"])
    assert res.exit_code == 0, res.output
    assert "2 of 2 holes filled" in res.output and "watertight: True" in res.output
    mesh = trimesh.load(out, force="mesh")
    before = trimesh.load(EXAMPLE, force="mesh")
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert len(mesh.faces) == len(before.faces) + 24  # holes of 16 and 12 edges


def test_fill_json_with_limit(tmp_path):
    out = tmp_path / "filled.obj"
    args = ["fill", str(EXAMPLE), "-o", str(out), "--json", "--max-hole-edges", "12"]
    res = CliRunner().invoke(main, [*args, "--method", "liepa", "--weight", "area"])
    assert res.exit_code == 0, res.output
    report = json.loads(res.stdout)
    assert [h["status"] for h in report["holes"]] == ["skipped", "filled"]
    assert report["faces_after"] == report["faces_before"] + 10
    assert "hole 0 left open" in res.stderr
    mesh = trimesh.load(out, force="mesh")
    assert len(mesh.faces) == report["faces_after"] and not mesh.is_watertight  # one hole left


@pytest.mark.parametrize(
    "make, out_name, match",
    [
        (lambda p: p.write_text("not a mesh\n"), "o.obj", "no triangle faces"),
        (None, "o.obj", "no such file"),
        (lambda p: p.write_text(EXAMPLE.read_text()), "o.xyz", "unsupported mesh format"),
    ],
)
def test_bad_input_one_line_exit_2_nothing_written(tmp_path, make, out_name, match):
    src = tmp_path / "in.obj"
    if make is not None:
        make(src)
    out = tmp_path / out_name
    res = CliRunner().invoke(main, ["fill", str(src), "-o", str(out)])
    assert res.exit_code == 2
    assert match in res.stderr and len(res.stderr.strip().splitlines()) == 1
    assert not out.exists() and list(tmp_path.iterdir()) == ([src] if make else [])


def test_non_manifold_mesh_exit_2(tmp_path):
    src = tmp_path / "bow.obj"
    src.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv -1 0 0\nv 0 -1 0\nf 1 2 3\nf 1 4 5\n")
    out = tmp_path / "o.obj"
    res = CliRunner().invoke(main, ["fill", str(src), "-o", str(out)])
    assert res.exit_code == 2 and "non-manifold" in res.stderr
    assert not out.exists()
