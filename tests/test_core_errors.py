"""Bad input: a clear optri error from the API, one line and exit 2 from the CLI."""

import errno
import json
import math
import os
import pickle
import signal
import threading

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import optri
from cli_run import run_optri
from exact_oracle import exact_strictly_convex
from optri import config
from optri.engines.interrupts import interruptible, stop_signals_unwind
from optri.errors import Terminated

SQUARE = [[0, 0], [1, 0], [1, 1], [0, 1]]


@pytest.mark.parametrize(
    "vertices, fragment",
    [
        ([[0, 0], [1, 0]], "at least 3"),
        ([], "at least 3"),
        ([[0, 0], [1, np.nan], [1, 1]], "non-finite"),
        ([[0, 0], [1, np.inf], [1, 1]], "non-finite"),
        ([[0, 0], [1, 0], [1, 0], [0, 1]], "repeats"),
        ([[0, 0], [1, 0], [1, 1], [0, 1], [1, 0], [2, 2]], "repeats"),
        # every turn strictly left, but around twice: not convex, so searched for repeats
        ([[0, 0], [1, 0], [1, 1], [0, 1]] * 2, "vertex 4 repeats vertex 0"),
        ([[0, 0], [1, 1], [2, 2]], "collinear"),
        ([[0, 0, 0, 0]], "shape"),
        ([["a", "b"], ["c", "d"], ["e", "f"]], "numbers"),
    ],
)
def test_invalid_polygons(vertices, fragment):
    with pytest.raises(optri.InvalidPolygonError, match=fragment):
        optri.triangulate(vertices)


def test_reflex_or_straight_vertex_is_not_strictly_convex():
    assert optri.as_polygon([[0, 0], [2, 0], [2, 2], [0, 2]]).convex
    assert not optri.as_polygon([[0, 0], [2, 0], [1, 0.2], [2, 2], [0, 2]]).convex
    assert not optri.as_polygon([[0, 0], [1, 0], [2, 0], [2, 2], [0, 2]]).convex


def test_pentagram_is_not_convex():
    ang = np.pi / 2 + 2 * np.pi * np.arange(5) / 5
    star = np.column_stack((np.cos(ang), np.sin(ang)))[[0, 2, 4, 1, 3]]
    assert not optri.as_polygon(star).convex


@settings(max_examples=300, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 4), st.integers(0, 4)), min_size=3, max_size=9))
def test_convexity_matches_an_exact_oracle(pts):
    # as_polygon skips its search for repeated vertices on a strictly convex ring: the
    # flag must be exactly the oracle's (either orientation), so that repeats are found
    try:
        polygon = optri.as_polygon(pts)
    except optri.InvalidPolygonError:
        assume(False)
    ring = polygon.vertices  # closing copies dropped
    assert polygon.convex == exact_strictly_convex(ring)
    assert optri.as_polygon(ring[::-1]).convex == polygon.convex


def test_weight_errors():
    with pytest.raises(optri.WeightError, match="unknown weight"):
        optri.triangulate(SQUARE, "nonsense")
    with pytest.raises(optri.WeightError, match="NaN"):
        optri.triangulate(SQUARE, lambda i, k, j: math.nan, method="memo")
    with pytest.raises(optri.WeightError, match="values"):
        optri.triangulate(SQUARE, "product")
    with pytest.raises(optri.WeightError, match="coordinates"):
        optri.triangulate([1, 2, 3], "perimeter")
    with pytest.raises(optri.WeightError, match="component"):
        optri.triangulate(SQUARE, "perimeter", ("max", "sum"))
    with pytest.raises(optri.WeightError, match="objective"):
        optri.triangulate(SQUARE, "perimeter", "median")


def test_unknown_method():
    with pytest.raises(optri.EngineUnavailableError, match="unknown method"):
        optri.triangulate(SQUARE, method="quantum")


def test_brute_refuses_large_n():
    ang = np.linspace(0, 2 * np.pi, config.BRUTE_MAX_N + 1, endpoint=False)
    with pytest.raises(optri.InvalidPolygonError, match="brute"):
        optri.triangulate(np.column_stack((np.cos(ang), np.sin(ang))), method="brute")


def test_table_too_large_refused_before_allocating(monkeypatch):
    monkeypatch.setattr(config, "MEMORY_LIMIT_BYTES", 10_000)
    ang = np.linspace(0, 2 * np.pi, 100, endpoint=False)
    with pytest.raises(optri.TableTooLargeError, match="MB"):
        optri.triangulate(np.column_stack((np.cos(ang), np.sin(ang))), method="table")


def run_cli(*args, cwd=None):
    return run_optri(*args, cwd=cwd)


@pytest.mark.parametrize(
    "content",
    ["0,0\n1,0\n", "0,0\n1,nan\n1,1\n", "0,0\n1,0\n1,0\n0,1\n", "x,y\n0,0\nfoo,1\n1,1\n"],
)
def test_cli_bad_input_one_line_exit_2(tmp_path, content):
    f = tmp_path / "bad.csv"
    f.write_text(content)
    r = run_cli("solve", str(f))
    assert r.returncode == 2
    assert r.stderr.count("\n") == 1 and r.stderr.startswith("optri: error:")
    assert "Traceback" not in r.stderr


def test_cli_multi_line_library_error_is_one_stderr_line(tmp_path):
    # a file name with a newline: the library's message spans two lines
    missing = tmp_path / "no\nsuch.csv"
    with pytest.raises(optri.InvalidPolygonError) as info:
        optri.io.read_polygon(missing)
    assert "\n" in str(info.value)
    r = run_cli("solve", str(missing))
    assert r.returncode == 2
    assert r.stderr.count("\n") == 1 and r.stderr.startswith("optri: error: cannot read ")
    assert "no such.csv" in r.stderr and "Traceback" not in r.stderr


def test_cli_unwritable_output_is_one_line(tmp_path):
    # --plot inside a regular file: the OSError becomes one line naming the path, exit 2
    from click.testing import CliRunner

    from optri.cli import main

    f = tmp_path / "sq.csv"
    f.write_text("0,0\n1,0\n1,1\n0,1\n")
    res = CliRunner().invoke(main, ["solve", str(f), "--plot", str(f / "x.png")])
    assert res.exit_code == 2, res.output
    assert res.stderr.startswith("optri: error:") and res.stderr.count("\n") == 1
    assert "sq.csv" in res.stderr and "Traceback" not in res.output
    # the system's reason, as an expected failure, not as "unexpected ... a bug in optri"
    assert os.strerror(errno.ENOTDIR) in res.stderr and "bug" not in res.stderr


def test_cli_disk_full_mid_run_is_one_line_naming_the_file(tmp_path, monkeypatch):
    # an OSError raised while a command runs (not caught by an option's check up front)
    from click.testing import CliRunner

    import optri.cli.solve_cmd as solve_cmd
    from optri.cli import main

    out = tmp_path / "plot.png"

    def full(figure, path):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))

    monkeypatch.setattr(solve_cmd, "save_figure", full)
    f = tmp_path / "sq.csv"
    f.write_text("0,0\n1,0\n1,1\n0,1\n")
    res = CliRunner().invoke(main, ["solve", str(f), "--plot", str(out)])
    assert res.exit_code == 2, res.output
    assert res.stderr == f"optri: error: {out}: {os.strerror(errno.ENOSPC)}\n"


def test_cli_missing_file_and_bad_weight(tmp_path):
    r = run_cli("solve", str(tmp_path / "none.csv"))
    assert r.returncode == 2 and "Traceback" not in r.stderr
    f = tmp_path / "sq.csv"
    f.write_text("0,0\n1,0\n1,1\n0,1\n")
    r = run_cli("solve", str(f), "--weight", "nonsense")
    assert r.returncode == 2 and "unknown weight" in r.stderr
    r = run_cli("chain", "3", "0", "4")
    assert r.returncode == 2 and r.stderr.count("\n") == 1


def test_cli_plot_write_failure_leaves_nothing(tmp_path):
    f = tmp_path / "sq.csv"
    f.write_text("0,0\n1,0\n1,1\n0,1\n")
    out = tmp_path / "plot.png"
    out.write_bytes(b"old")
    r = run_cli("solve", str(f), "--weight", "nonsense", "--plot", str(out), "--json")
    assert r.returncode == 2
    assert out.read_bytes() == b"old"
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []
    json.loads(run_cli("solve", str(f), "--json").stdout)


def test_atomic_write_gives_normal_permissions(tmp_path):
    import os
    import stat

    from optri.io import atomic_write

    out = tmp_path / "x.txt"
    with atomic_write(out) as fh:
        fh.write("x")
    mask = os.umask(0)
    os.umask(mask)
    assert stat.S_IMODE(out.stat().st_mode) == 0o666 & ~mask


def test_atomic_write_failure_keeps_old_file(tmp_path):
    from optri.io import atomic_write

    out = tmp_path / "x.txt"
    out.write_text("old")
    with pytest.raises(RuntimeError):
        with atomic_write(out) as fh:
            fh.write("new, half")
            raise RuntimeError("interrupted")
    assert out.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["x.txt"]


def test_atomic_write_interrupted_before_writing_leaves_no_temporary(tmp_path, monkeypatch):
    # an interruption between making the temporary file and writing to it removes it too
    from optri.io import atomic as atomic_mod

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt("signal 15")

    monkeypatch.setattr(atomic_mod.os, "fdopen", interrupted)
    out = tmp_path / "x.txt"
    with pytest.raises(KeyboardInterrupt):
        with atomic_mod.atomic_write(out) as fh:
            fh.write("never")
    assert list(tmp_path.iterdir()) == []


def test_atomic_write_signal_as_the_temporary_comes_into_being_leaves_nothing(
    tmp_path, monkeypatch
):
    # SIGTERM delivered the moment the temporary file exists, to whichever thread the kernel
    # picks: its handler (which raises, as the CLI's does) runs before the file could be
    # handed back, so only a name chosen in advance, inside the guard, finds it again
    real_open = os.open

    def open_then_signal(path, *args, **kwargs):
        fd = real_open(path, *args, **kwargs)
        if ".x.txt." in os.fspath(path):
            os.kill(os.getpid(), signal.SIGTERM)
            for _ in range(1000):  # give the handler its bytecode boundaries
                pass
        return fd

    def terminate(signum, frame):
        raise KeyboardInterrupt("terminated")

    from optri.io import atomic as atomic_mod

    old = signal.signal(signal.SIGTERM, terminate)
    try:
        monkeypatch.setattr(os, "open", open_then_signal)
        out = tmp_path / "x.txt"
        with pytest.raises(KeyboardInterrupt):
            with atomic_mod.atomic_write(out) as fh:
                fh.write("never")
    finally:
        monkeypatch.undo()
        signal.signal(signal.SIGTERM, old)
    assert list(tmp_path.iterdir()) == []


# --- stop signals: SIGTERM and SIGHUP unwind like Ctrl-C, and say which they were --------


def test_a_stop_signal_is_raised_as_terminated_and_the_old_handler_comes_back():
    before = signal.getsignal(signal.SIGTERM)
    with pytest.raises(Terminated) as info:
        with stop_signals_unwind():
            os.kill(os.getpid(), signal.SIGHUP)
            for _ in range(1000):  # give the handler its bytecode boundaries
                pass
    assert (info.value.signum, str(info.value)) == (signal.SIGHUP, "SIGHUP")
    again = pickle.loads(pickle.dumps(info.value))
    assert (type(again), again.signum, str(again)) == (Terminated, signal.SIGHUP, "SIGHUP")
    assert isinstance(info.value, KeyboardInterrupt)  # what catches Ctrl-C catches it too
    assert signal.getsignal(signal.SIGTERM) is before


def test_stop_signals_are_left_alone_outside_the_main_thread():
    seen = []

    def worker():
        with stop_signals_unwind():
            seen.append(signal.getsignal(signal.SIGTERM))

    before = signal.getsignal(signal.SIGTERM)
    t = threading.Thread(target=worker)
    t.start()
    t.join()
    assert seen == [before]  # signal.signal would raise ValueError there


def test_interruptible_keeps_a_stop_signal_what_it_is():
    # a SIGTERM noticed as a compiled kernel returned: still Terminated (the CLI exits 143)
    with pytest.raises(Terminated) as info:
        with interruptible():
            try:
                raise Terminated(signal.SIGTERM)
            except KeyboardInterrupt as exc:
                raise SystemError("returned a result with an exception set") from exc
    assert info.value.signum == signal.SIGTERM
