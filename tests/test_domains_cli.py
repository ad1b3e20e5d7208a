"""``optri solve`` on GeoJSON and WKT files with holes."""

from __future__ import annotations

import json

import pytest
from click.testing import CliRunner

shapely = pytest.importorskip("shapely")
pytest.importorskip("scipy")

import optri  # noqa: E402
from optri.cli import main  # noqa: E402
from optri.domains import random_domain  # noqa: E402

POLY = shapely.Polygon(
    [(0, 0), (8, 0), (8, 6), (0, 6)], [[(1, 1), (3, 1), (2, 3)], [(5, 2), (7, 2), (7, 4), (5, 4)]]
)


@pytest.fixture
def files(tmp_path):
    (tmp_path / "p.wkt").write_text(POLY.wkt)
    (tmp_path / "p.geojson").write_text(json.dumps(shapely.geometry.mapping(POLY)))
    return tmp_path


@pytest.mark.parametrize("name", ["p.wkt", "p.geojson"])
def test_solve_a_file_with_holes(files, name):
    ref = optri.triangulate(POLY, weight="diagonal")
    r = CliRunner().invoke(main, ["solve", str(files / name), "-w", "diagonal", "--json"])
    assert r.exit_code == 0, r.output
    out = json.loads(r.stdout)
    assert out["n"] == 11 and out["rings"] == [4, 3, 4]
    assert len(out["triangles"]) == 11 + 2 * 2 - 2
    assert out["optimality"] == "proven" and out["gap"] == 0.0
    assert out["weight"] == pytest.approx(ref.weight)


def test_solve_prints_optimality_and_takes_a_time_limit(files):
    args = ["solve", str(files / "p.wkt"), "--time-limit", "30", "--method", "ip"]
    r = CliRunner().invoke(main, args)
    assert r.exit_code == 0, r.output
    assert "holes: 2" in r.output and "optimality: proven" in r.output


def test_solve_bridge_is_labelled_heuristic(tmp_path):
    ext, holes = random_domain(40, 3, seed=2)  # no forced diagonal: one block with holes
    (tmp_path / "r.wkt").write_text(shapely.Polygon(ext, holes).wkt)
    args = [
        "solve",
        str(tmp_path / "r.wkt"),
        "-m",
        "bridge",
        "-w",
        "max_angle",
        "--objective",
        "max",
    ]
    r = CliRunner().invoke(main, [*args, "--json"])
    assert r.exit_code == 0, r.output
    out = json.loads(r.output)
    assert out["optimality"] == "heuristic" and out["method"] == "bridge"
    assert out["bound"] <= out["weight"]


def test_bad_input_is_one_error_line(tmp_path):
    bad = shapely.Polygon([(0, 0), (4, 0), (4, 4), (0, 4)], [[(3, 3), (5, 3), (3, 5)]])
    (tmp_path / "bad.wkt").write_text(bad.wkt)
    r = CliRunner().invoke(main, ["solve", str(tmp_path / "bad.wkt")])
    assert r.exit_code == 2
    assert r.output.strip().startswith("optri: error: exterior and hole 1 meet")
    r = CliRunner().invoke(main, ["solve", str(tmp_path / "bad.wkt"), "--table"])
    assert r.exit_code == 2 and "no table" in r.output
