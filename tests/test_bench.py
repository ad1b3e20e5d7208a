"""``optri bench`` and its own yardsticks: the C reference, the peak run, the Python recursion.

No timing assertions: the benchmark runs on tiny n and the tests check what it
reports (rows, agreement with the C reference, the message without a compiler)
and that every yardstick computes the same optimum as optri.
"""

from __future__ import annotations

import math
import os
import shutil
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import optri
from optri.bench import BenchRow, convex_polygon
from optri.bench.compare import Solver, machine
from optri.bench.compiled import (
    YARDSTICKS,
    build,
    measure_peak,
    measure_transfer,
    run_reference,
)
from optri.bench.naive import min_perimeter
from optri.cli import main

needs_gcc = pytest.mark.skipif(shutil.which("gcc") is None, reason="gcc not installed")


def _polygons() -> list[np.ndarray]:
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    t = np.arange(12) * 2 * np.pi / 12  # regular: many ties
    regular = np.column_stack((np.cos(t), np.sin(t)))
    return [square, regular, convex_polygon(3, 5), convex_polygon(37, 2), convex_polygon(150, 3)]


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory):
    if shutil.which("gcc") is None:
        pytest.skip("gcc not installed")
    out = build(tmp_path_factory.mktemp("yardsticks"))
    assert out.note is None and out.ref is not None and out.peak is not None, out.note
    assert out.probe is not None
    return out


def _write(path: Path, pts: np.ndarray) -> Path:
    path.write_text("x,y\n" + "".join(f"{x!r},{y!r}\n" for x, y in pts.tolist()))
    return path


@pytest.mark.parametrize("k", range(5))
def test_c_reference_equals_optri(built, tmp_path: Path, k: int) -> None:
    pts = _polygons()[k]
    weight, seconds = run_reference(built.ref, _write(tmp_path / "p.csv", pts))
    mine = optri.triangulate(pts, weight="perimeter", method="table").weight
    assert math.isclose(weight, mine, rel_tol=1e-12) and seconds >= 0


def test_c_reference_refuses_a_bad_file(built, tmp_path: Path) -> None:
    (tmp_path / "two.csv").write_text("0,0\n1,0\n")
    import subprocess

    done = subprocess.run([str(built.ref), str(tmp_path / "two.csv")], capture_output=True)
    assert done.returncode == 2 and b"usage" in done.stderr


def test_peak_run_reports_a_rate(built) -> None:
    rate = measure_peak(built.peak, 0.05)
    assert rate is not None and rate > 0


def _kernel_lines(peak: Path) -> tuple[int, list[str]]:
    import subprocess

    done = subprocess.run([str(peak), "0.02", "1"], capture_output=True, text=True)
    return done.returncode, done.stderr.splitlines()


def test_every_peak_kernel_computes_the_plain_product(built) -> None:
    """Each kernel's product was checked against the plain loop before it was timed."""
    code, lines = _kernel_lines(built.peak)
    assert code == 0 and lines
    for line in lines:
        name, rate = line.split()
        assert float(rate) > 0, line


@needs_gcc
def test_peak_leaves_out_kernels_with_a_wrong_product(tmp_path: Path) -> None:
    """A block that skips the minimum is caught by the check, and no rate is reported."""
    src = tmp_path / "src"
    src.mkdir()
    shutil.copy(YARDSTICKS / "ref_mwt.c", src)
    text = (YARDSTICKS / "minplus_peak.c").read_text()
    good = "acc[r][q] = MIN(acc[r][q], ADD(ar, bk[q]));"
    assert text.count(good) == 1  # the one block every kernel is made of
    (src / "minplus_peak.c").write_text(text.replace(good, "acc[r][q] = ADD(ar, bk[q]);"))
    broken = build(tmp_path / "out", source=src)
    assert broken.peak is not None, broken.note
    code, lines = _kernel_lines(broken.peak)
    assert code == 1 and lines[-1] == "minplus_peak: no kernel computed the product right"
    assert lines[:-1] and all(line.endswith(": wrong product, left out") for line in lines[:-1])
    assert measure_peak(broken.peak, 0.02) is None  # the report leaves the peak out


@pytest.mark.parametrize("k", range(4))
def test_naive_recursion_equals_optri(k: int) -> None:
    pts = _polygons()[k]
    mine = optri.triangulate(pts, weight="perimeter", method="memo").weight
    assert math.isclose(min_perimeter([tuple(p) for p in pts.tolist()]), mine, rel_tol=1e-12)


def test_sources_ship_in_the_package() -> None:
    want = ["crosscore.c", "minplus_peak.c", "ref_mwt.c"]
    assert sorted(p.name for p in YARDSTICKS.glob("*.c")) == want


def _cpus() -> list[int]:
    return sorted(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else []


two_cpus = pytest.mark.skipif(len(_cpus()) < 2, reason="the cross-core probe needs two CPUs")


@two_cpus
def test_transfer_probe_reports_two_rates(built) -> None:
    """crosscore: GB/s read across two CPUs and on one, the reader on another CPU."""
    import subprocess

    out = subprocess.run([str(built.probe), "1", "2"], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    cross, local, writer, reader = out.stdout.split()
    assert float(cross) > 0 and float(local) > 0
    cpus = _cpus()
    assert (int(writer), int(reader)) == (cpus[0], cpus[1])  # pinned to the first two
    rate = measure_transfer(built.probe)
    assert rate is not None and rate > 0


@pytest.mark.skipif(not _cpus(), reason="no CPU affinity to narrow on this system")
def test_transfer_probe_needs_two_cpus(built) -> None:
    """On one CPU the probe says why and exits 1, and the report leaves the column empty."""
    import subprocess

    one = {_cpus()[0]}
    out = subprocess.run(
        [str(built.probe)],
        capture_output=True,
        text=True,
        preexec_fn=lambda: os.sched_setaffinity(0, one),
    )
    assert out.returncode == 1 and out.stdout == ""
    assert out.stderr.strip() == "crosscore: this process may run on one CPU only"
    bad = subprocess.run([str(built.probe), "0"], capture_output=True, text=True)
    assert bad.returncode == 2 and "usage" in bad.stderr


@pytest.mark.skipif(not _cpus(), reason="no CPU affinity to narrow on this system")
def test_rewrite_probe_prints_two_costs_and_refuses(built) -> None:
    """``crosscore rewrite``: ns a line for stores after the other CPU read, and alone.

    It backs docs/performance-log.md's account of the slow periods (and ``claim_at``'s).
    """
    import subprocess

    bad = subprocess.run([str(built.probe), "rewrite", "0"], capture_output=True, text=True)
    assert bad.returncode == 2 and "usage" in bad.stderr
    one = {_cpus()[0]}
    alone = subprocess.run(
        [str(built.probe), "rewrite", "4"],
        capture_output=True,
        text=True,
        preexec_fn=lambda: os.sched_setaffinity(0, one),
    )
    assert alone.returncode == 1 and alone.stdout == ""
    assert alone.stderr.strip() == "crosscore: this process may run on one CPU only"
    if len(_cpus()) >= 2:
        out = subprocess.run([str(built.probe), "rewrite", "4"], capture_output=True, text=True)
        assert out.returncode == 0, out.stderr
        shared, own = map(float, out.stdout.split())
        assert shared > 0 and own > 0


def test_a_shared_folder_without_the_probe_builds_without_it(built, tmp_path: Path) -> None:
    other = tmp_path / "other"
    other.mkdir()
    for name in ("ref_mwt.c", "minplus_peak.c"):
        shutil.copy(YARDSTICKS / name, other / name)
    got = build(tmp_path / "out", other)
    assert got.note is None and got.peak is not None and got.probe is None


@pytest.mark.parametrize(
    ("n", "transfer", "best", "spell"),
    [
        (1000, 28.0, 78.0, True),
        (4000, 46.0, 78.0, True),  # just under 0.6 of the best
        (1000, 47.0, 78.0, False),  # just over
        (1000, 78.0, 78.0, False),
        (500, 28.0, 78.0, False),  # one thread below FAST_PARALLEL_MIN_N: spells do not matter
        (1000, None, 78.0, False),  # no probe
        (1000, 28.0, None, False),
    ],
)
def test_spell_note(n: int, transfer: float | None, best: float | None, spell: bool) -> None:
    from optri.bench.compare import spell_note

    row = BenchRow(n, 0.006, 0.006, None, None, 5e10, 1, 1, None, 0, transfer_gbs=transfer)
    note = spell_note(row, best)
    assert (note is not None) == spell
    if note:
        assert note.startswith(f"n = {n}: measured while this machine was slow")
        assert f"{transfer:.0f} GB/s" in note


def test_fraction_of_peak_and_ratios() -> None:
    row = BenchRow(1000, 0.5, 0.6, 2.0, 10.0, 1e9, 200.0, 8.0, True, 1.0)
    assert row.fraction == pytest.approx(1000**3 / 6 / 0.5 / 1e9)
    assert row.c_ratio == 0.25 and row.naive_ratio == 20.0
    assert BenchRow(10, 0.5, 0.6, None, None, None, 1, 1, None, 0).fraction is None


def test_worker_times_warm_calls(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Each window's timed calls come after its warm-up's untimed ones, on the same polygon."""
    from optri.bench import compare

    csv = _write(tmp_path / "p.csv", convex_polygon(60, 4))
    sizes: list[int] = []
    solve = compare.triangulate

    def counted(pts, **kw):  # type: ignore[no-untyped-def]
        sizes.append(len(pts))
        return solve(pts, **kw)

    monkeypatch.setattr(compare, "triangulate", counted)
    cold = compare.Solver(str(csv), "float64", warmup=0)
    got = cold.window(0.0, 2)
    assert cold.warm_calls == 0 and sizes == [40, 60, 60]  # kernels, then the timed calls
    assert len(got["times"]) == len(got["walls"]) == 2
    assert all(0 < t <= w for t, w in zip(got["times"], got["walls"]))
    sizes.clear()
    warm = compare.Solver(str(csv), "float64", warmup=0.05)
    assert warm.warm_calls == 0 and sizes == [40]  # the kernels only
    warm.window(0.0, 2)
    first = warm.warm_calls
    assert first >= 1 and sizes == [40] + [60] * (first + 2)
    warm.window(0.0, 1)  # the next window warms up again
    assert warm.warm_calls > first and len(sizes) == 1 + warm.warm_calls + 3
    assert warm.summary()["weight"] == cold.summary()["weight"] > 0


def test_solver_window_lasts_its_seconds(tmp_path: Path) -> None:
    """A window runs calls until its seconds are over, however many calls were asked for."""
    import time

    solver = Solver(str(_write(tmp_path / "p.csv", convex_polygon(30))), "float64")
    start = time.perf_counter()
    got = solver.window(0.05, 1)
    assert time.perf_counter() - start >= 0.05 and len(got["times"]) > 1


def test_serve_answers_each_window(tmp_path: Path) -> None:
    """The worker's protocol: ready, one JSON line per window, then the summary."""
    import io
    import json

    from optri.bench.compare import serve

    csv = _write(tmp_path / "p.csv", convex_polygon(25, 3))
    out = io.StringIO()
    serve([str(csv), "float64", "0"], io.StringIO("0 2\n0 1\n"), out)
    lines = [json.loads(line) for line in out.getvalue().splitlines()]
    assert lines[0] == {"ready": True}
    assert [len(w["times"]) for w in lines[1:3]] == [2, 1]
    want = optri.triangulate(convex_polygon(25, 3), weight="perimeter", method="table").weight
    assert math.isclose(lines[3]["weight"], want, rel_tol=1e-12)
    assert lines[3]["peak_mb"] >= lines[3]["base_mb"] > 0 and len(lines) == 4


def test_peak_runs_and_solves_take_turns(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Each window of solves follows a peak run as long as one of its kernels; bests count."""
    from optri.bench import compare

    events: list[tuple[str, float]] = []
    rates = iter([3e9, 5e9, 4e9, 2e9, 2.5e9, 1e9])
    windows = iter([[0.9, 0.4, 0.8, 0.7], [0.5], [0.6, 0.3]])

    def peak(exe: Path, seconds: float, runs: int = 3) -> float:
        events.append((exe.name, seconds))
        assert runs == 1
        return next(rates)

    class Fake:
        def __init__(self, csv: Path, dtype: str, warmup: float) -> None:
            self.result = {"weight": 1.0, "peak_mb": 9.0, "base_mb": 1.0}

        def __enter__(self):  # type: ignore[no-untyped-def]
            return self

        def __exit__(self, *exc: object) -> None:
            events.append(("end", 0.0))

        def window(self, seconds: float, calls: int) -> dict[str, list[float]]:
            events.append((f"solve {calls}", seconds))
            times = next(windows)
            return {"times": times, "walls": [t + 1 for t in times]}

    transfers = iter([70.0, 80.0, 30.0])

    def probe(exe: Path) -> float:
        events.append((exe.name, 0.0))
        return next(transfers)

    monkeypatch.setattr(compare, "measure_peak", peak)
    monkeypatch.setattr(compare, "measure_transfer", probe)
    monkeypatch.setattr(compare, "_Worker", Fake)
    ours = compare.Built(None, tmp_path / "ours", probe=tmp_path / "probe")
    theirs = compare.Built(None, tmp_path / "theirs")
    plan = compare._Plan(repeats=4, dtype="float64", peak_seconds=0.75, warmup=0, rounds=3)
    row = compare._one_size(10, tmp_path / "p.csv", ours, theirs, 0, plan)
    turn = [("ours", 0.25), ("theirs", 0.25), ("solve 2", 0.25), ("probe", 0.0)]
    assert events == [*turn, *turn, *turn, ("end", 0.0)]
    assert row.optri_s == 0.3 and row.wall_s == 1.3 and row.calls == 7
    assert row.first_s == 0.4  # the first window's first three calls
    assert row.peak == 4e9 and row.shared_peak == 5e9  # runs alternate: ours, theirs
    assert row.table_mb == 8.0 and row.c_s is None and row.agrees is None
    # the probe right after the window of the best solve (the third), and the best probe
    assert row.transfer_gbs == 30.0 and row.transfer_max_gbs == 80.0


def test_a_failing_solver_process_is_a_clear_error(tmp_path: Path) -> None:
    from optri.bench.compare import _Worker
    from optri.errors import EngineUnavailableError

    (tmp_path / "bad.csv").write_text("0,0\n1,0\n")  # two vertices: not a polygon
    with pytest.raises(EngineUnavailableError, match="solver process failed: .*"):
        _Worker(tmp_path / "bad.csv", "float64", 0)


def _rows(output: str) -> dict[int, list[str]]:
    return {
        int(line.split()[0]): line.split()
        for line in output.splitlines()
        if line[:6].strip().isdigit()
    }


@needs_gcc
def test_bench_cli_tiny_sizes() -> None:
    args = ["bench", "40", "130", "--naive-max", "40", "--repeats", "1", "--peak-seconds", "0.05"]
    args += ["--warmup", "0.01"]
    out = CliRunner().invoke(main, args)
    assert out.exit_code == 0, out.output
    assert "optri bench:" not in out.output  # every yardstick built
    # the report names its machine first: CPU model and count, optri's register block
    first = out.output.splitlines()[0]
    assert first == machine() and f"{os.cpu_count()} CPUs" in first and "x 16 cells" in first
    rows = _rows(out.output)
    assert sorted(rows) == [40, 130]
    for n, row in rows.items():
        assert row[-1] == "True"  # same optimum as the C reference
        assert row[2].endswith("%") and float(row[3]) >= 0  # fraction of peak, C seconds
        assert (row[5] == "-") == (n > 40)  # the Python recursion on small n only


def test_bench_cli_without_a_compiler(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.setenv("PATH", str(tmp_path))  # no gcc, no cc
    monkeypatch.delenv("CC", raising=False)
    out = CliRunner().invoke(main, ["bench", "40", "--repeats", "1", "--naive-max", "40"])
    assert out.exit_code == 0, out.output
    notes = [line for line in out.output.splitlines() if line.startswith("optri bench:")]
    assert len(notes) == 1 and "no C compiler" in notes[0]
    row = _rows(out.output)[40]
    assert row[2] == row[3] == row[4] == row[-1] == "-"  # no peak, no C, no agreement
    assert float(row[5]) >= 0  # the Python recursion still ran


@needs_gcc
def test_bench_json_and_shared_cross_check(tmp_path: Path) -> None:
    import json

    shared = tmp_path / "other"
    shared.mkdir()
    for name in ("ref_mwt.c", "minplus_peak.c"):
        shutil.copy(YARDSTICKS / name, shared / name)
    args = ["bench", "50", "--repeats", "1", "--peak-seconds", "0.05", "--json"]
    out = CliRunner().invoke(main, [*args, "--shared", str(shared)])
    assert out.exit_code == 0, out.output
    (row,) = json.loads(out.stdout.strip().splitlines()[-1])
    assert row["agrees"] is True and row["shared_c_s"] >= 0 and row["shared_peak"] > 0
    assert row["fraction"] == pytest.approx(50**3 / 6 / row["optri_s"] / row["peak"])


def test_bench_cli_rounds(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    """--rounds windows of solves, each at least ceil(--repeats / --rounds) solves long."""
    import json

    monkeypatch.setenv("PATH", str(tmp_path))  # no compiler: no peak runs between windows
    monkeypatch.delenv("CC", raising=False)
    args = ["bench", "40", "--naive-max", "0", "--repeats", "4", "--rounds", "2"]
    out = CliRunner().invoke(main, [*args, "--peak-seconds", "1e-6", "--warmup", "0", "--json"])
    assert out.exit_code == 0, out.output
    (row,) = json.loads(out.stdout.strip().splitlines()[-1])
    assert row["calls"] == 4 and row["peak"] is None  # 2 solves in each of 2 windows


@pytest.mark.parametrize("bad", ["0", "-1", "x"])
def test_bench_cli_refuses_bad_peak_seconds(bad: str) -> None:
    out = CliRunner().invoke(main, ["bench", "40", "--peak-seconds", bad])
    assert out.exit_code == 2 and "--peak-seconds" in out.output


@pytest.mark.parametrize(
    ("kwargs", "says"),
    [
        ({"peak_seconds": 0}, "peak_seconds must be a positive number of seconds, got 0"),
        ({"peak_seconds": None}, "peak_seconds must be a positive number of seconds"),
        ({"warmup": -0.5}, "warmup must be 0 or a positive number of seconds, got -0.5"),
        ({"rounds": 0}, "rounds must be at least 1, got 0"),
        ({"repeats": 0}, "repeats must be at least 1, got 0"),
        ({"naive_max": -1}, "naive_max must be at least 0, got -1"),
        ({"sizes": [40, 2]}, "each size must be at least 3, got 2"),
        ({"dtype": "float16"}, "unknown dtype 'float16'"),
    ],
)
def test_run_benchmark_refuses_bad_parameters_before_any_work(
    monkeypatch: pytest.MonkeyPatch, kwargs: dict[str, object], says: str
) -> None:
    """A peak of 0 s used to leave the fraction of peak empty without a word; now refused."""
    from optri.bench import compare
    from optri.errors import InvalidParameterError

    def no_build(*_args: object, **_kwargs: object) -> None:
        raise AssertionError("built the yardsticks before checking the parameters")

    monkeypatch.setattr(compare, "build", no_build)
    given = {"sizes": [40], **kwargs}
    with pytest.raises(InvalidParameterError, match=says.replace("(", r"\(")):
        compare.run_benchmark(**given)  # type: ignore[arg-type]


def test_bench_fast_script_refuses_bad_rounds() -> None:
    """``benchmarks/bench_fast.py --rounds 0`` says why and exits 2 (it used to clamp to 1)."""
    import subprocess
    import sys

    script = Path(__file__).resolve().parents[1] / "benchmarks" / "bench_fast.py"
    done = subprocess.run(
        [sys.executable, str(script), "40", "--rounds", "0"], capture_output=True, text=True
    )
    assert done.returncode == 2, done.stderr
    assert "rounds must be at least 1, got 0" in done.stderr and "Traceback" not in done.stderr


def test_bench_cli_refuses_negative_naive_max() -> None:
    out = CliRunner().invoke(main, ["bench", "40", "--naive-max", "-1"])
    assert out.exit_code == 2 and "--naive-max" in out.output


def test_a_spell_before_the_usual_rate_is_noted_after_the_last_size(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A run that starts in a spell notes its rows once a later size shows the usual rate."""
    from optri.bench import compare

    rates = {1000: 34.0, 2000: 31.0, 4000: 78.0, 8000: 29.0}

    def one_size(n, *_args):  # type: ignore[no-untyped-def]
        x = rates[n]
        return BenchRow(n, 0.006, 0.006, None, None, 5e10, 1, 1, None, 0, None, None, 3, None, x, x)

    monkeypatch.setattr(compare, "build", lambda *_a, **_k: compare.Built(None, None, None, None))
    monkeypatch.setattr(compare, "_one_size", one_size)
    lines: list[str] = []
    compare.run_benchmark(list(rates), naive_max=0, log=lines.append)
    notes = [line for line in lines if "measured while this machine was slow" in line]
    # 8000 as it comes (78 seen before it); 1000 and 2000 after the last size, in order
    assert [note.split(":")[0] for note in notes] == ["n = 8000", "n = 1000", "n = 2000"]
    assert lines[-2:] == notes[1:] and all("78 GB/s at best" in note for note in notes)
