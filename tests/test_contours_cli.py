"""optri contours: every input format to a mesh file; errors as one line, exit 2."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from cli_run import run_optri

RTSS = Path(__file__).parent / "data" / "contours" / "rtss_heart.dcm"


def _circle(r: float, k: int = 12) -> list[list[float]]:
    t = np.linspace(0, 2 * np.pi, k, endpoint=False)
    return np.c_[r * np.cos(t), r * np.sin(t)].round(6).tolist()


def _slices_json(tmp_path: Path) -> Path:
    f = tmp_path / "stack.json"
    f.write_text(
        json.dumps({"slices": [{"z": z, "contours": [_circle(1 + 0.1 * z)]} for z in range(3)]})
    )
    return f


def _volume(path: Path) -> float:
    import trimesh

    mesh = trimesh.load(path)  # merges the STL's repeated corners
    assert mesh.is_watertight and mesh.is_winding_consistent
    return float(mesh.volume)


@pytest.mark.parametrize("suffix", ["ply", "obj", "stl"])
def test_json_to_every_mesh_format(tmp_path, suffix):
    pytest.importorskip("trimesh")
    out = tmp_path / f"out.{suffix}"
    r = run_optri("contours", _slices_json(tmp_path), "-o", out, "--json")
    assert r.returncode == 0, r.stderr
    report = json.loads(r.stdout)
    assert report["faces"] == 2 * 12 * 2 + 2 * 10 and report["slices"] == 3
    assert _volume(out) == pytest.approx(report["volume"], rel=1e-6)


def test_csv_geojson_and_stdin_agree(tmp_path):
    pytest.importorskip("trimesh")
    rows = ["x,y,z,contour"]
    feats = []
    for z in range(3):
        ring = _circle(1 + 0.1 * z)
        rows += [f"{x},{y},{z},c{z}" for x, y in ring]
        feats.append(
            {
                "type": "Feature",
                "properties": {"z": z},
                "geometry": {"type": "Polygon", "coordinates": [ring + ring[:1]]},
            }
        )
    csv, geo = tmp_path / "s.csv", tmp_path / "s.geojson"
    csv.write_text("\n".join(rows) + "\n")
    geo.write_text(json.dumps({"type": "FeatureCollection", "features": feats}))
    volumes = []
    for src in (csv, geo, _slices_json(tmp_path)):
        r = run_optri("contours", src, "-o", tmp_path / "m.ply", "--json")
        assert r.returncode == 0, r.stderr
        volumes.append(json.loads(r.stdout)["volume"])
    r = run_optri("contours", "-", "-o", tmp_path / "m.ply", "--json", input=csv.read_text())
    assert r.returncode == 0, r.stderr
    volumes.append(json.loads(r.stdout)["volume"])
    assert max(volumes) - min(volumes) <= 1e-9 * max(volumes)


def test_rtstruct(tmp_path):
    pytest.importorskip("pydicom")
    pytest.importorskip("trimesh")
    out = tmp_path / "tumor.stl"
    r = run_optri("contours", RTSS, "--roi", "Tumor Bed", "-o", out, "-q")
    assert r.returncode == 0, r.stderr
    assert "18 contours on 18 slices" in r.stdout
    assert _volume(out) > 0


@pytest.mark.parametrize(
    ("content", "name", "args", "match"),
    [
        ("x,y,z,contour\n0,0,0,a\n1,0,0,a\n", "s.csv", (), "at least 3 points"),
        ("x,y,contour\n0,0,a\n", "s.csv", (), "must name x, y, z and contour"),
        (
            '{"slices": [{"z": 0, "contours": [[[0, 0], [1, 1], [1, 0], [0, 1]]]},'
            ' {"z": 1, "contours": [[[0, 0], [1, 0], [0, 1]]]}]}',
            "s.json",
            (),
            "not simple",
        ),
        ("{", "s.json", (), "not valid JSON"),
        ("x", "s.txt", (), "unsupported contour format"),
        (
            '{"slices": [{"z": 0, "contours": [[[0, 0], [1, 0], [0, 1]]]}]}',
            "s.json",
            (),
            "at least two slices",
        ),
        ("x,y,z,contour\n0,0,0,a\n1,0,0,a\n0,1,0,a\n", "s.csv", ("--roi", "x"), "RTSTRUCT"),
    ],
)
def test_errors_are_one_line(tmp_path, content, name, args, match):
    src = tmp_path / name
    src.write_text(content)
    r = run_optri("contours", src, "-o", tmp_path / "o.ply", *args)
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("optri: error:") and match in lines[0]
    assert not (tmp_path / "o.ply").exists()


def test_bad_output_suffix_and_unknown_roi(tmp_path):
    r = run_optri("contours", _slices_json(tmp_path), "-o", tmp_path / "o.vtk")
    assert r.returncode == 2 and "unsupported mesh format" in r.stderr
    pytest.importorskip("pydicom")
    r = run_optri("contours", RTSS, "--roi", "Liver", "-o", tmp_path / "o.ply")
    assert r.returncode == 2 and "no structure 'Liver'" in r.stderr and "Heart" in r.stderr


def test_open_rtstruct_contour_is_refused(tmp_path):
    pydicom = pytest.importorskip("pydicom")
    ds = pydicom.dcmread(RTSS)
    ds.ROIContourSequence[0].ContourSequence[3].ContourGeometricType = "OPEN_PLANAR"
    bad = tmp_path / "open.dcm"
    ds.save_as(bad)
    r = run_optri("contours", bad, "--roi", "Heart", "-o", tmp_path / "o.ply")
    assert r.returncode == 2 and "contour 3 is OPEN_PLANAR" in r.stderr
