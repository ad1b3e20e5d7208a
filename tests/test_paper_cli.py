import json

from click.testing import CliRunner

from optri.cli import main

SQUARE = "0,0\n1,0\n1,1\n0,1\n"


def _run(*args):
    res = CliRunner().invoke(main, list(args))
    return res.exit_code, res.output


def test_count():
    assert _run("count", "40") == (0, "176733862787006701400\n")


def test_count_file(tmp_path):
    f = tmp_path / "sq.csv"
    f.write_text(SQUARE)
    assert _run("count", str(f)) == (0, "2\n")


def test_enumerate_json_lines(tmp_path):
    code, out = _run("enumerate", "6", "--json", "--weight", "perimeter", "--limit", "5")
    assert code == 0
    rows = [json.loads(line) for line in out.splitlines()]
    assert [r["index"] for r in rows] == [1, 2, 3, 4, 5]
    assert all(len(r["diagonals"]) == 3 and r["weight"] > 0 for r in rows)


def test_enumerate_plain_all():
    code, out = _run("enumerate", "7")
    assert code == 0 and len(out.splitlines()) == 42


def test_best(tmp_path):
    f = tmp_path / "sq.csv"
    f.write_text(SQUARE)
    code, out = _run("best", str(f), "--k", "5", "--json")
    assert code == 0
    rows = [json.loads(line) for line in out.splitlines()]
    assert len(rows) == 2 and rows[0]["rank"] == 1 and rows[0]["method"] == "kbest"


def test_enumerate_bad_file_is_one_line_error(tmp_path):
    code, out = _run("enumerate", str(tmp_path / "missing.csv"))
    assert code == 2
    assert out.startswith("optri: error:") and out.count("\n") == 1 and "missing.csv" in out


def test_paper_quick(tmp_path):
    code, out = _run("paper", "-o", str(tmp_path / "p"), "--quick", "--quiet", "--no-figures")
    assert code == 0, out
    report = (tmp_path / "p" / "report.md").read_text()
    assert "## Notes on the paper" in report and "175, 35, 35, 75, 75" in report
