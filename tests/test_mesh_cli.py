"""``optri fill`` on the bundled mesh with two holes."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
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


def test_pinched_mesh_is_filled(tmp_path):
    src = tmp_path / "bow.obj"
    src.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv -1 0 0\nv 0 -1 0\nf 1 2 3\nf 1 4 5\n")
    out = tmp_path / "o.obj"
    res = CliRunner().invoke(main, ["fill", str(src), "-o", str(out), "--quiet"])
    assert res.exit_code == 0, res.output
    assert "2 of 2 holes filled" in res.output and "split at pinched vertex 0" in res.output


def _write_obj(path, vertices, faces):
    # full precision: the file itself must not merge or lose any vertex
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in np.asarray(vertices, dtype=float).tolist()]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in np.asarray(faces).tolist()]
    path.write_text("\n".join(lines) + "\n")


@pytest.mark.parametrize("scale", [1e-9, 1e-8, 1e-3, 1.0, 1e12])
@pytest.mark.parametrize("suffix", [".obj", ".stl"])
def test_any_scale_fills_the_same_holes(tmp_path, scale, suffix):
    base = trimesh.load(EXAMPLE, force="mesh", process=False)
    src = tmp_path / f"scaled{suffix}"
    if suffix == ".obj":
        _write_obj(src, base.vertices * scale, base.faces)
    else:  # binary STL: float32 corners, one copy per face; loading merges them back
        trimesh.Trimesh(base.vertices * scale, base.faces, process=False).export(src)
    out = tmp_path / f"out{suffix}"
    res = CliRunner().invoke(main, ["fill", str(src), "-o", str(out), "--quiet", "--json"])
    assert res.exit_code == 0, res.output
    report = json.loads(res.stdout)
    assert [h["edges"] for h in report["holes"]] == [16, 12]
    assert [h["status"] for h in report["holes"]] == ["filled", "filled"]
    assert report["faces_after"] == 292 and report["watertight"]


@pytest.mark.parametrize("name", ["junk.obj", "junk.stl", "junk.off", "junk.ply"])
def test_corrupt_mesh_files_one_line_exit_2(tmp_path, name):
    src = tmp_path / name
    src.write_bytes(bytes(np.random.default_rng(1).integers(0, 256, 3000, dtype=np.uint8)))
    res = CliRunner().invoke(main, ["fill", str(src), "-o", str(tmp_path / "o.obj")])
    assert res.exit_code == 2
    assert len(res.stderr.strip().splitlines()) == 1 and res.stderr.startswith("optri: error:")
    assert "charset" not in res.stderr and "Traceback" not in res.output
    assert not (tmp_path / "o.obj").exists()


def test_mesh_with_no_hole_but_not_closed_exit_2(tmp_path):
    # three triangles on one edge: not closed, yet no edge with a single face
    v = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1]]
    f = [[0, 1, 2], [1, 0, 3], [0, 1, 4], [0, 2, 1], [0, 3, 1], [1, 0, 4]]
    src = tmp_path / "fan.obj"
    _write_obj(src, v, f)
    out = tmp_path / "o.obj"
    res = CliRunner().invoke(main, ["fill", str(src), "-o", str(out)])
    assert res.exit_code == 2 and "no hole to fill" in res.stderr
    assert not out.exists()


def test_every_hole_failing_exit_2_nothing_written(tmp_path):
    v = [
        [0, 0, 0],
        [1, 0, 0.6],
        [1, 1, 0],
        [0, 1, 0.6],
        [0.5, 0.5, 1.5],
        [0.5, 0.5, -2],
        [0.9, 0.1, -2.5],
    ]
    f = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4], [0, 2, 5], [2, 0, 6], [0, 5, 6], [2, 6, 5]]
    f += [[1, 3, 6], [3, 1, 5]]  # both diagonals of the square hole are mesh edges
    src = tmp_path / "stuck.obj"
    _write_obj(src, v, f)
    out = tmp_path / "o.obj"
    res = CliRunner().invoke(main, ["fill", str(src), "-o", str(out)])
    assert res.exit_code == 2, res.output
    assert "holes could be filled" in res.stderr and "edge-manifold" in res.stderr
    assert not out.exists()


def test_strict_exits_1_when_a_hole_is_left_open(tmp_path):
    out = tmp_path / "o.obj"
    args = ["fill", str(EXAMPLE), "-o", str(out), "--quiet", "--max-hole-edges", "12"]
    assert CliRunner().invoke(main, args).exit_code == 0
    res = CliRunner().invoke(main, [*args, "--strict"])
    assert res.exit_code == 1 and out.exists()


def test_merge_tolerance_is_relative_to_the_mesh(tmp_path):
    base = trimesh.load(EXAMPLE, force="mesh", process=False)
    v, f = np.asarray(base.vertices) * 1e-6, np.asarray(base.faces)
    # the first 100 faces get their own copies of their vertices, 1e-12 of the size away
    n = len(v)
    used = np.unique(f[:100])
    copy = {int(x): n + i for i, x in enumerate(used)}
    v2 = np.vstack([v, v[used] * (1 + 1e-12)])
    f2 = f.copy()
    f2[:100] = np.vectorize(copy.get)(f[:100])
    src = tmp_path / "seam.obj"
    _write_obj(src, v2, f2)
    plain = CliRunner().invoke(
        main, ["fill", str(src), "-o", str(tmp_path / "a.obj"), "--json", "-q"]
    )
    merged = CliRunner().invoke(
        main,
        [
            "fill",
            str(src),
            "-o",
            str(tmp_path / "b.obj"),
            "--json",
            "-q",
            "--merge-tolerance",
            "1e-9",
        ],
    )
    assert plain.exit_code == 0 and merged.exit_code == 0
    seam = [h["edges"] for h in json.loads(plain.stdout)["holes"]]
    assert seam != [16, 12]  # unmerged, the seam joins the holes
    report = json.loads(merged.stdout)
    assert 0 < report["merged_vertices"] <= len(used)  # copies along the seam
    assert [h["edges"] for h in report["holes"]] == [16, 12]


def _cpu_seconds(pid):
    """CPU seconds a child has used (Linux's /proc), or None where that cannot be read."""
    import os

    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return None
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def test_ctrl_c_during_a_search_exits_130(tmp_path):
    import os
    import signal
    import subprocess
    import sys
    import time

    # open tubes: two round holes of 450 edges each per tube, a long exact search
    sections, tubes = 450, 12
    ang = np.linspace(0, 2 * np.pi, sections, endpoint=False)
    ring = np.column_stack((np.cos(ang), np.sin(ang), np.zeros(sections)))
    v, f = [], []
    for t in range(tubes):
        base = t * 2 * sections
        v += (ring + [3 * t, 0, 0]).tolist() + (ring + [3 * t, 0, 1]).tolist()
        for s in range(sections):
            a, b = base + s, base + (s + 1) % sections
            f += [[a, b, b + sections], [a, b + sections, a + sections]]
    src = tmp_path / "tubes.obj"
    _write_obj(src, v, f)
    from optri import fill_polyline

    fill_polyline(ring[::45] + [0, 0, 0.1] * np.arange(10)[:, None], method="exact")  # compiled
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    cmd = [sys.executable, "-m", "optri", "fill", str(src), "-o", str(tmp_path / "o.obj"), "-q"]
    cmd += ["--method", "exact"]
    proc = subprocess.Popen(
        cmd,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),  # not ignored
    )
    # Ctrl-C once the search runs: after 4 s of the child's CPU time (its imports and the
    # mesh take under 2 s), not after a fixed wall time, which a busy machine can spend in
    # imports (trimesh's optional imports catch BaseException, KeyboardInterrupt included)
    start = time.monotonic()
    while time.monotonic() - start < 90:
        cpu = _cpu_seconds(proc.pid)
        if (cpu if cpu is not None else time.monotonic() - start - 4.0) >= 4.0:
            break
        time.sleep(0.2)
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, (out, err)
    assert err.strip().splitlines()[-1] == "optri: interrupted"
    assert "Traceback" not in err and "SystemError" not in err
    assert not (tmp_path / "o.obj").exists()
