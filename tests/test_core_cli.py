import json
from pathlib import Path

import optri
from cli_run import SRC, run_optri, run_python

ROOT = Path(__file__).resolve().parents[1]
run = run_optri


def test_subprocesses_run_this_checkout():
    r = run_python("-c", "import optri; print(optri.__file__)")
    assert Path(r.stdout.strip()).resolve() == SRC / "optri" / "__init__.py", r.stderr


def test_version_and_help():
    r = run("--version")
    assert r.returncode == 0 and optri.__version__ in r.stdout
    for cmd in (["--help"], ["solve", "--help"], ["chain", "--help"]):
        assert run(*cmd).returncode == 0


def test_solve_json_keys_and_values(tmp_path):
    r = run(
        "solve",
        str(ROOT / "examples" / "octagon.csv"),
        "--json",
        "--method",
        "memo",
        "--plot",
        str(tmp_path / "o.png"),
    )
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert {"n", "weight", "triangles", "diagonals", "method", "seconds"} <= set(out)
    ref = optri.triangulate(str(ROOT / "examples" / "octagon.csv"), method="brute")
    assert abs(out["weight"] - ref.weight) < 1e-9
    assert len(out["triangles"]) == 6 and len(out["diagonals"]) == 5
    assert (tmp_path / "o.png").read_bytes()[:4] == b"\x89PNG"


def test_solve_table_prints_paper_layout(tmp_path):
    f = tmp_path / "p.csv"
    f.write_text("p\n5\n1\n5\n1\n5\n")
    r = run("solve", str(f), "--weight", "product", "--method", "memo", "--table")
    assert r.returncode == 0, r.stderr
    assert "optimal weight: 35" in r.stdout
    lines = r.stdout.splitlines()
    row1 = next(ln for ln in lines if ln.startswith("1 "))
    assert row1.split() == ["1", "0", "25", "10", "35", "X"]
    assert "2*,3,4" in r.stdout


def test_json_file_input_and_chain(tmp_path):
    f = tmp_path / "p.json"
    f.write_text(json.dumps([[0, 0], [1, 0], [1, 1], [0, 1]]))
    assert json.loads(run("solve", str(f), "--json").stdout)["n"] == 4
    r = run("chain", "30", "35", "15", "5", "10", "20", "25")
    assert "15125" in r.stdout and "((A1(A2A3))((A4A5)A6))" in r.stdout


def test_import_is_light():
    code = (
        "import sys, optri; bad = [m for m in ('matplotlib', 'numba', 'trimesh', 'click', "
        "'rich', 'shapely', 'dask') if m in sys.modules]; print(bad)"
    )
    r = run_python("-c", code)
    assert r.stdout.strip() == "[]", r.stdout + r.stderr
