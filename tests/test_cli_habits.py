"""CLI habits: one flag scheme, stdin, pipes, one-line errors, sniffed CSVs, --json."""

import io
import json
import math
import os
import signal
import subprocess
import sys
import time

import click
import pytest
from click.testing import CliRunner

import optri
from cli_run import checkout_env, run_optri
from optri import config
from optri.cli import main
from optri.cli.app import summary
from optri.cli.progress import COMPILE_NOTICE, compile_notice, progress_bar
from optri.engines.progress import announce_compile

OCTAGON = optri.data.path("octagon.csv")
SPHERE = optri.data.path("sphere_two_holes.obj")
FOOTPRINTS = optri.data.path("footprints.ndjson")
SQUARE = [(0, 0), (2, 0), (2, 2), (0, 2)]
#: Commands that report something a script may want to parse.
REPORTING = {"batch", "bench", "best", "chain", "count", "data", "enumerate", "explore", "fill",
             "paper", "solve"}  # fmt: skip


def _commands():
    ctx = click.Context(main)
    return {name: main.get_command(ctx, name) for name in main.list_commands(ctx)}


def _options(command):
    return [p for p in command.params if isinstance(p, click.Option)]


# --- the flag scheme ---------------------------------------------------------------------


def test_each_short_flag_has_one_meaning_across_commands():
    meanings: dict[str, set[str]] = {}
    for command in _commands().values():
        for opt in _options(command):
            longs = [o for o in opt.opts + opt.secondary_opts if o.startswith("--")]
            for short in (o for o in opt.opts if not o.startswith("--")):
                meanings.setdefault(short, set()).add(longs[0] if longs else opt.name)
    clashes = {flag: sorted(m) for flag, m in meanings.items() if len(m) > 1}
    assert not clashes, clashes
    expected = {"-o": "--output", "-O": "--objective", "-w": "--weight", "-m": "--method",
                "-k": "--k", "-n": "--limit", "-j": "--workers", "-q": "--quiet"}  # fmt: skip
    for flag, long in expected.items():
        assert meanings.get(flag) == {long}, (flag, meanings.get(flag))


def test_every_output_path_is_dash_o_and_every_objective_dash_capital_o():
    writers = set()
    for name, command in _commands().items():
        for opt in _options(command):
            if opt.name == "output":
                assert opt.opts[:2] == ["--output", "-o"], (name, opt.opts)
                writers.add(name)
            if opt.name == "objective":
                assert "-O" in opt.opts and "-o" not in opt.opts, (name, opt.opts)
    assert {"batch", "data", "explore", "fill", "paper"} <= writers


def test_every_reporting_command_has_json():
    commands = _commands()
    assert REPORTING <= set(commands)
    for name in REPORTING:
        assert "--json" in [o for p in _options(commands[name]) for o in p.opts], name


def test_help_lists_whole_summaries():
    res = CliRunner().invoke(main, ["--help"], terminal_width=80)
    text = " ".join(res.output.split())
    for name, command in _commands().items():
        assert summary(command) in text, name
    assert "Reproduce Selimi et al. (2019): Tables 2-4, Figures 1-7, notes on the paper." in text


def test_deprecated_out_still_works_with_a_warning(tmp_path):
    out = tmp_path / "o.ndjson"
    res = CliRunner().invoke(main, ["batch", str(FOOTPRINTS), "--out", str(out), "-j", "1"])
    assert res.exit_code == 0, res.output
    assert "--out is deprecated; use -o/--output" in res.stderr
    assert len(out.read_text().splitlines()) == 31


# --- one-line errors ---------------------------------------------------------------------

BAD_CALLS = [
    (["solve", "--no-such-flag", str(OCTAGON)], "No such option"),
    (["solve"], "Missing argument"),
    (["solve", str(OCTAGON), "-m", "quantum"], "'quantum' is not one of"),
    (["enumerate", "30", "--limit", "-1"], "-1 is not in the range"),
    (["enumerate", "6", "-o", "max"], "No such option '-o'"),
    (["best", "8", "-k", "0"], "0 is not in the range"),
    (["solve", str(OCTAGON), "--plot", "out.xyz"], "unknown picture format 'xyz'"),
    (["solve", str(OCTAGON), "--plot", "."], "is a directory"),
    (["solve", str(OCTAGON), "--plot", os.devnull], "is not a regular file"),
    (["solve", "no-such-file.csv"], "No such file"),
    (["solve", str(OCTAGON), "--columns", "x"], "two or three column"),
    (["solve", str(OCTAGON), "--columns", "lon,lat"], "no column 'lon'"),
    (["fill", str(SPHERE)], "Missing option '-o'"),
    (["batch", str(FOOTPRINTS)], "Missing option '-o'"),
    (["explore", str(OCTAGON), "-o", os.devnull], "is not a regular file"),
    (["data", "-o", str(OCTAGON)], "is not a directory"),
    (["count", "nope"], "cannot read nope"),
]


@pytest.mark.parametrize("args,words", BAD_CALLS, ids=[" ".join(a[:2]) for a, _ in BAD_CALLS])
def test_errors_are_one_line_and_exit_2(args, words):
    res = run_optri(*args)
    assert res.returncode == 2, (res.stdout, res.stderr)
    assert res.stderr.startswith("optri: error: ") and res.stderr.count("\n") == 1, res.stderr
    assert words in res.stderr and "Traceback" not in res.stderr


@pytest.mark.parametrize(
    "content,words",
    [
        (b"\x7fELF\x02\x01\x01\x00\x00\x00" * 30, "a binary file"),
        ("x,y\n0,0\n1,0\n0,1\nZürich,1\n".encode("latin-1"), "not UTF-8 text (byte 0xfc"),
        (b"", "no vertices found"),
        (b"x,y\n0,0\n1,zz\n0,1\n", ":3: not a number 'zz' in column 2 (y)"),
        (b"a,b\nc,d\n", "needs two numeric columns"),
    ],
    ids=["binary", "latin-1", "empty", "bad-number", "text-only"],
)
def test_unreadable_files_are_clean_errors(tmp_path, content, words):
    path = tmp_path / "poly.csv"
    path.write_bytes(content)
    for args in (["solve", path], ["count", path], ["solve", "-"]):
        res = subprocess.run(
            [sys.executable, "-m", "optri", *map(str, args)],
            input=content if args[-1] == "-" else None,
            capture_output=True,
            env=checkout_env(),
        )
        err = res.stderr.decode()
        assert res.returncode == 2 and err.count("\n") == 1, err
        assert err.startswith("optri: error: ") and words in err, err


def test_unexpected_exceptions_are_one_line_too(monkeypatch):
    import optri.cli.solve_cmd as solve_cmd

    def boom(*args, **kwargs):
        raise RuntimeError("a bug")

    monkeypatch.setattr(solve_cmd, "triangulate", boom)
    res = CliRunner().invoke(main, ["solve", str(OCTAGON)])
    assert res.exit_code == 2 and res.stderr.count("\n") == 1
    assert res.stderr.startswith("optri: error: unexpected RuntimeError: a bug")


def test_table_above_the_bound_is_refused_before_solving(monkeypatch):
    import optri.cli.solve_cmd as solve_cmd

    monkeypatch.setattr(solve_cmd, "triangulate", lambda *a, **k: pytest.fail("solved"))
    monkeypatch.setattr(config, "CLI_TABLE_MAX_N", 6)
    res = CliRunner().invoke(main, ["solve", str(OCTAGON), "--table"])
    assert res.exit_code == 2 and res.stderr.count("\n") == 1
    assert "--table prints tables up to n = 6 (this polygon has n = 8" in res.stderr
    assert "keep_table=True" in res.stderr


# --- stdin, pipes and signals ------------------------------------------------------------


def test_dash_reads_stdin_through_a_real_pipe():
    text = OCTAGON.read_text()
    from_file = json.loads(run_optri("solve", OCTAGON, "--json").stdout)
    piped = run_optri("solve", "-", "--json", input=text)
    assert piped.returncode == 0, piped.stderr
    assert json.loads(piped.stdout)["triangles"] == from_file["triangles"]
    assert run_optri("count", "-", input=text).stdout.strip() == "132"  # Catalan(6)
    best = run_optri("best", "-", "-k", "2", input=text).stdout.splitlines()
    assert best == run_optri("best", OCTAGON, "-k", "2").stdout.splitlines() and len(best) == 2


def test_dash_reads_a_mesh_and_a_layer_from_stdin(tmp_path):
    args = ("--json", "-q", "--max-hole-edges", "12")
    filed = run_optri("fill", SPHERE, "-o", tmp_path / "a.ply", *args)
    piped = run_optri("fill", "-", "-o", tmp_path / "b.ply", *args, input=SPHERE.read_text())
    assert piped.returncode == 0, piped.stderr
    a, b = json.loads(filed.stdout), json.loads(piped.stdout)
    assert a["faces_after"] == b["faces_after"] > a["faces_before"]
    res = run_optri(
        "batch", "-", "-o", tmp_path / "o.ndjson", "-j", "1", "--json",
        input=FOOTPRINTS.read_text(),
    )  # fmt: skip
    assert res.returncode == 0, res.stderr
    assert json.loads(res.stdout)["total"] == 31
    assert len((tmp_path / "o.ndjson").read_text().splitlines()) == 31


def test_a_closed_pipe_ends_quietly():
    # enumerate 14 prints 208,012 lines: far more than a pipe holds, so optri meets EPIPE
    cmd = [sys.executable, "-m", "optri", "enumerate", "14"]
    producer = subprocess.Popen(
        cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=checkout_env()
    )
    head = subprocess.run(["head", "-1"], stdin=producer.stdout, capture_output=True, text=True)
    producer.stdout.close()
    err = producer.stderr.read().decode()
    assert producer.wait(timeout=120) == 0, err
    assert err == "" and head.stdout.startswith("     1  ")


_SLOW_WRITE = """
import sys, time
from optri.cli import main
import optri.cli.solve_cmd as solve_cmd
from optri.io.atomic import atomic_write

def slow_save(ax, path):
    with atomic_write(path, "wb") as fh:
        fh.write(b"half a picture")
        print("ready", file=sys.stderr, flush=True)
        time.sleep(60)

solve_cmd.save_figure = slow_save
main(sys.argv[1:], prog_name="optri")
"""


@pytest.mark.parametrize("sig,code,word", [(signal.SIGTERM, 143, "terminated"),
                                           (signal.SIGHUP, 129, "hung up"),
                                           (signal.SIGINT, 130, "interrupted")])  # fmt: skip
def test_signals_end_cleanly_and_leave_no_temporary_file(tmp_path, sig, code, word):
    out = tmp_path / "o.png"
    proc = subprocess.Popen(
        [sys.executable, "-c", _SLOW_WRITE, "solve", str(OCTAGON), "--plot", str(out), "-q"],
        stderr=subprocess.PIPE, stdout=subprocess.PIPE, text=True, env=checkout_env(),
        # a test run started as a background job of a shell without job control has
        # SIGINT ignored, and so would the child: Python then installs no Ctrl-C handler
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )  # fmt: skip
    assert proc.stderr.readline().strip() == "ready"
    assert any(p.name.endswith(".tmp") for p in tmp_path.iterdir())  # mid-write
    proc.send_signal(sig)
    rest = proc.stderr.read()
    assert proc.wait(timeout=60) == code
    assert rest == f"optri: {word}\n"
    assert list(tmp_path.iterdir()) == []


# --- files: BOM, sniffed CSVs ------------------------------------------------------------


def test_a_byte_order_mark_keeps_the_first_vertex(tmp_path):
    path = tmp_path / "bom.csv"
    path.write_bytes(b"\xef\xbb\xbf" + b"0,0\n2,0\n2,2\n0,2\n")
    assert optri.io.read_polygon(path).tolist() == [list(map(float, p)) for p in SQUARE]
    res = run_optri("solve", path, "--json")
    assert json.loads(res.stdout)["n"] == 4


LAYOUTS = {
    "plain": "0,0\n2,0\n2,2\n0,2\n",
    "header": "x,y\n0,0\n2,0\n2,2\n0,2\n",
    "semicolon": "x;y\n0;0\n2;0\n2;2\n0;2\n",
    "tab": "0\t0\n2\t0\n2\t2\n0\t2\n",
    "spaces": "  0   0\n2 0\n 2  2\n0 2\n",
    "text column": 'lon,lat,name\n0,0,a\n2,0,"b, c"\n2,2,d\n0,2,e\n',
    "id first": "id,x,y\n10,0,0\n11,2,0\n12,2,2\n13,0,2\n",
    "lat,lon named": "name;lat;lon\na;0;0\nb;0;2\nc;2;2\nd;2;0\n",
    "comments, crlf": "# a square\r\nx,y\r\n0,0\r\n2,0\r\n\r\n2,2\r\n0,2\r\n",
}


@pytest.mark.parametrize("layout", LAYOUTS)
def test_csv_layouts_are_sniffed(tmp_path, layout):
    path = tmp_path / "poly.csv"
    path.write_text(LAYOUTS[layout], newline="")
    assert optri.io.read_polygon(path).tolist() == [list(map(float, p)) for p in SQUARE]


def test_columns_name_the_coordinates(tmp_path):
    path = tmp_path / "poly.csv"
    path.write_text("a,b,c,d\n9,0,0,7\n9,2,0,7\n9,2,2,7\n9,0,2,7\n")
    want = [list(map(float, p)) for p in SQUARE]
    assert optri.io.read_polygon(path, ["b", "c"]).tolist() == want
    assert optri.io.read_polygon(path, ["2", "3"]).tolist() == want
    res = run_optri("solve", path, "--columns", "b,c", "--json")
    assert json.loads(res.stdout)["n"] == 4


# --- numbers, progress, compile notice ---------------------------------------------------


def test_huge_counts_are_printed_in_full():
    res = run_optri("count", "10000")
    assert res.returncode == 0, res.stderr
    digits = res.stdout.strip()
    m = 9998  # the 10000-gon has Catalan(9998) triangulations
    old = sys.get_int_max_str_digits()
    sys.set_int_max_str_digits(0)
    try:
        assert int(digits) == math.comb(2 * m, m) // (m + 1) and len(digits) > 4300
    finally:
        sys.set_int_max_str_digits(old)
    as_json = run_optri("count", "10000", "--json").stdout
    assert f'"count": {digits},' in as_json and f'"digits": {len(digits)}' in as_json


def test_best_json_has_real_seconds_and_stats():
    res = run_optri("best", "9", "-k", "3", "--json")
    rows = [json.loads(line) for line in res.stdout.splitlines()]
    assert [r["rank"] for r in rows] == [1, 2, 3]
    assert all(r["seconds"] > 0 and r["stats"] == {"k": 3, "found": 3} for r in rows)


def test_the_bar_appears_after_the_delay_only(monkeypatch):
    from rich.console import Console

    def run(delay, work):
        monkeypatch.setattr(config, "CLI_PROGRESS_DELAY", delay)
        sink = io.StringIO()
        with progress_bar("working", console=Console(file=sink, force_terminal=True)) as cb:
            cb(1, 10)
            time.sleep(work)
        return sink.getvalue()

    assert "working" in run(0.05, 0.5)  # a long run: the bar was drawn
    assert run(60, 0.0) == ""  # a short run: nothing at all
    with progress_bar("x", console=Console(file=io.StringIO(), force_terminal=False)) as cb:
        assert cb is None  # not a terminal: no bar


def test_the_compile_notice_is_printed_once_per_run():
    @click.command()
    def fake():
        with compile_notice():
            announce_compile()
            announce_compile()

    res = CliRunner().invoke(fake)
    assert res.stderr == COMPILE_NOTICE + "\n"
    with compile_notice(enabled=False):
        announce_compile()  # nobody listening: nothing printed, nothing raised


def test_a_user_numba_weight_is_announced_and_a_built_in_one_is_not(tmp_path):
    pytest.importorskip("numba")
    code = (
        "import click, numba, numpy as np, optri\n"
        "from optri.cli.progress import compile_notice\n"
        "@numba.njit\n"
        "def w(v, i, k, j):\n"
        "    return abs(v[i, 0] - v[j, 0])\n"
        "t = np.linspace(0, 2 * np.pi, 130, endpoint=False)\n"
        "P = np.column_stack([np.cos(t), np.sin(t)])\n"
        "@click.command()\n"
        "def run():\n"
        "    with compile_notice():\n"
        "        optri.triangulate(P, 'area', method='fast')\n"
        "        optri.triangulate(P, optri.custom_weight(w), method='fast')\n"
        "run([])\n"
    )
    env = checkout_env(NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env,
                         timeout=300)
    assert res.returncode == 0 and res.stderr == COMPILE_NOTICE + "\n", res.stderr


def test_solve_announces_a_compile_during_its_run(monkeypatch):
    import optri.cli.solve_cmd as solve_cmd

    real = solve_cmd.triangulate

    def compiling(*args, **kwargs):
        announce_compile()  # what numba's compile event does on a cache miss
        return real(*args, **kwargs)

    monkeypatch.setattr(solve_cmd, "triangulate", compiling)
    res = CliRunner().invoke(main, ["solve", str(OCTAGON)])
    assert res.exit_code == 0 and res.stderr == COMPILE_NOTICE + "\n"
    assert CliRunner().invoke(main, ["solve", str(OCTAGON), "-q"]).stderr == ""
