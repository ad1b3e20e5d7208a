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
    # one numbering: the table counts from 0 like the diagonals and triangles above it
    assert "vertices numbered from 0" in lines
    assert "diagonals: 1-3 1-4" in lines and "triangles: (0,1,4) (1,3,4) (1,2,3)" in lines
    assert next(ln for ln in lines if ln.startswith("   ")).split() == ["0", "1", "2", "3", "4"]
    row0 = next(ln for ln in lines if ln.startswith("0 "))
    assert row0.split() == ["0", "0", "25", "10", "35", "X"]
    # the optimal chords (1, 3) and (1, 4) are the starred splits 1* below the diagonal
    assert lines[-1].split() == ["4", "1*,2,3", "2,3*", "3*", "(4,3)", "0"]
    # --one-based: the paper's labels, in the table and in the lines above it alike
    r = run("solve", str(f), "-w", "product", "-m", "memo", "--table", "--one-based")
    lines = r.stdout.splitlines()
    assert "diagonals: 2-4 2-5" in lines and "triangles: (1,2,5) (2,4,5) (2,3,4)" in lines
    row1 = next(ln for ln in lines if ln.startswith("1 "))
    assert row1.split() == ["1", "0", "25", "10", "35", "X"]
    assert lines[-1].split() == ["5", "2*,3,4", "3,4*", "4*", "(5,4)", "0"]  # Table 1


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
