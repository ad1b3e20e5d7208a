"""Benchmark ``method="fast"`` against the yardsticks, all in one run.

For each n: a random convex polygon (sorted random angles on an ellipse, written
to a CSV with every digit, so each solver reads the same doubles), solved by
the C reference ``yardsticks/ref_mwt.c``, by the plain-Python recursion
:mod:`optri.bench.naive` (small n only) and by ``method="fast"`` in a fresh
process (so its peak memory is its own). The peak microbenchmark
``yardsticks/minplus_peak.c`` and optri's solves take turns: ``rounds`` windows
each, a peak run then a window of solves as long as each of the peak's kernels
ran, so that both are sampled across the same seconds of the machine. The
fraction of peak is ``(n³/6 candidates / optri's best seconds) / the best peak
rate``. After each window, ``yardsticks/crosscore.c`` measures how fast one CPU
reads what another has just written: where that is slow beside a size's best
solves, the report says the row was measured while the machine was slow to pass
data between CPUs, which slows optri's threads (they read each other's tiles) and
not the peak's (they share nothing). Used by ``optri bench`` and
``benchmarks/bench_fast.py``; ``python -m optri.bench`` runs the fresh-process worker
(:func:`serve`).
"""

from __future__ import annotations

import json
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import IO, Any

import numpy as np

from .. import config
from ..errors import EngineUnavailableError, check_choice, check_count, check_seconds
from ..io.files import read_polygon
from ..solve import triangulate
from .compiled import Built, build, measure_peak, measure_transfer, run_reference

__all__ = [
    "BenchRow",
    "Solver",
    "convex_polygon",
    "format_rows",
    "machine",
    "run_benchmark",
    "serve",
    "spell_note",
]

#: A size's best solves count as measured in a slow period of the machine where one CPU
#: read another's writes at less than this fraction of the run's best rate
#: (``crosscore.c``); virtual machines show such periods at a third of the usual rate.
SPELL_TRANSFER = 0.6


@dataclass
class BenchRow:
    """One size: seconds of each solver, the peak rate, memory, agreement, load.

    ``optri_s`` is the engine's best solve (``Triangulation.seconds``), ``wall_s``
    the best whole ``triangulate`` call, of ``calls`` timed calls; ``peak`` the
    best min-plus candidates per second of the peak runs between them; ``first_s``
    the best of the first window's first three calls (what a benchmark that
    times three calls in one place would report); ``agrees`` whether optri's
    weight equals the C reference's (relative difference at most 1e-9; None
    without the C one). ``transfer_gbs`` is the GB/s at which one CPU read
    what another had just written, measured right after the window of the best
    solve, ``transfer_max_gbs`` the best of the size's windows (None without
    ``crosscore.c``'s program, or on one CPU).
    """

    n: int
    optri_s: float
    wall_s: float
    c_s: float | None
    naive_s: float | None
    peak: float | None
    peak_mb: float
    table_mb: float
    agrees: bool | None
    load: float
    shared_c_s: float | None = None
    shared_peak: float | None = None
    calls: int = 0
    first_s: float | None = None
    transfer_gbs: float | None = None
    transfer_max_gbs: float | None = None

    @property
    def fraction(self) -> float | None:
        """Fraction of peak: ``n³/6 / optri_s / peak``."""
        return self.n**3 / 6 / self.optri_s / self.peak if self.peak else None

    @property
    def c_ratio(self) -> float | None:
        """Ratio optri time / C time (below 1: optri is faster)."""
        return self.optri_s / self.c_s if self.c_s else None

    @property
    def naive_ratio(self) -> float | None:
        """Ratio naive Python time / optri time (how many times faster optri is)."""
        return self.naive_s / self.optri_s if self.naive_s else None

    def to_dict(self) -> dict[str, object]:
        """Plain dict including the ratios."""
        extra = {"fraction": self.fraction, "c_ratio": self.c_ratio}
        return {**asdict(self), **extra, "naive_ratio": self.naive_ratio}


def convex_polygon(n: int, seed: int = 1) -> np.ndarray:
    """``n`` vertices at sorted random angles on a 1000 × 600 ellipse (convex).

    >>> convex_polygon(4).shape
    (4, 2)
    """
    angles = np.sort(np.random.default_rng(seed).uniform(0.0, 2 * np.pi, n))
    return np.column_stack((1000 * np.cos(angles), 600 * np.sin(angles)))


def run_benchmark(
    sizes: Sequence[int],
    naive_max: int = 500,
    repeats: int = 3,
    seed: int = 1,
    dtype: str = "float64",
    log: Callable[[str], None] | None = None,
    shared: str | os.PathLike[str] | None = None,
    peak_seconds: float = 1.0,
    cc: str | None = None,
    warmup: float = 0.25,
    rounds: int = 3,
) -> list[BenchRow]:
    """Time every solver on the same polygon for each n in ``sizes``.

    The peak runs and optri's solves alternate, ``rounds`` times: a peak run of
    ``peak_seconds / rounds`` seconds a kernel (and the shared one's, with
    ``shared``), then optri's calls for as many seconds, at least
    ``ceil(repeats / rounds)`` of them. optri's seconds are its best call, the
    peak the best run of its fastest kernel: both the best the machine gave
    over the same stretch of time, sampled alike. On a virtual machine a
    two-thread solve can run at half its speed or less for seconds at a time
    while a one-thread solve does not slow down (``benchmarks/bench_spells.py``),
    so solves timed in one place could all fall in such a slow period while
    peak runs spread over many seconds miss it. The calls come after ``warmup``
    seconds of untimed ones in each window (see :class:`Solver`).

    ``shared``: a folder with another ``ref_mwt.c`` and ``minplus_peak.c`` (such
    as ``../shared/bench``) to build and run as well, as a cross-check. ``cc``:
    the C compiler (default: found on the ``PATH``).

    Raises :class:`~optri.errors.InvalidParameterError` before any work where a
    size is below 3, ``repeats`` or ``rounds`` below 1, ``naive_max`` or
    ``warmup`` negative, ``peak_seconds`` not positive (the peak programme
    would not run, and the fraction of peak would be left out without a word)
    or ``dtype`` neither ``"float64"`` nor ``"float32"``.

    Examples
    --------
    >>> rows = run_benchmark([40], naive_max=0, repeats=1, peak_seconds=0.03, warmup=0)
    >>> rows[0].n, rows[0].calls >= 3, rows[0].agrees in (True, None)
    (40, True, True)
    """
    say = log or (lambda _line: None)
    sizes = [check_count(n, "each size", minimum=3) for n in sizes]
    naive_max = check_count(naive_max, "naive_max", minimum=0)
    plan = _Plan(
        check_count(repeats, "repeats"),
        check_choice(dtype, "dtype", ("float64", "float32")),
        check_seconds(peak_seconds, "peak_seconds", allow_none=False),
        check_seconds(warmup, "warmup", allow_none=False, allow_zero=True),
        check_count(rounds, "rounds"),
    )
    rows = []
    with tempfile.TemporaryDirectory(prefix="optri-bench-") as tmp:
        ours = build(Path(tmp) / "ours", cc=cc)
        if ours.note:
            say(f"optri bench: {ours.note}")
        theirs = None
        if shared is not None:
            theirs = build(Path(tmp) / "shared", Path(shared), cc=cc)
            if theirs.note:
                say(f"optri bench: --shared: {theirs.note}")
        say(machine())
        say(
            f"load average {_load():.2f} (fraction of peak is noisy on a busy machine: "
            "compare figures from one run)"
        )
        say(
            f"optri s: the best solve of {plan.rounds} windows of {plan.window:.2g} s, "
            f"each right after a peak run of {plan.window:.2g} s a kernel"
        )
        noted: set[int] = set()
        for n in sizes:
            csv = Path(tmp) / f"poly{n}.csv"
            csv.write_text("".join(f"{x!r},{y!r}\n" for x, y in convex_polygon(n, seed).tolist()))
            rows.append(_one_size(n, csv, ours, theirs, naive_max, plan))
            say(format_rows(rows[-1:], header=len(rows) == 1))
            note = spell_note(rows[-1], _best_transfer(rows))
            if note:
                noted.add(len(rows) - 1)
                say(note)
        # a row measured in a slow period before the run had seen the machine's usual rate
        best_gbs = _best_transfer(rows)
        for k, row in enumerate(rows):
            note = None if k in noted else spell_note(row, best_gbs)
            if note:
                say(note)
    return rows


def _best_transfer(rows: Sequence[BenchRow]) -> float | None:
    """The best cross-core rate of ``rows``' windows; None without the probe."""
    seen = [r.transfer_max_gbs for r in rows if r.transfer_max_gbs is not None]
    return max(seen, default=None)


def spell_note(row: BenchRow, best_gbs: float | None) -> str | None:
    """One line when ``row``'s best solves were measured in a slow period of the machine.

    A slow period: one CPU read another's writes at less than :data:`SPELL_TRANSFER`
    of ``best_gbs`` (the run's best) right after the window of the size's best
    solve, at a size the engine solves on more than one thread. Its two threads
    read each other's finished tiles and slow down; the peak's threads share
    nothing and do not, so the fraction of peak reads low for the machine's
    sake, not the engine's (``docs/fast-engine.md``). None otherwise.

    >>> row = BenchRow(1000, 0.006, 0.006, None, None, 5e10, 1, 1, None, 0, transfer_gbs=28)
    >>> spell_note(row, 78.0).startswith("n = 1000: measured while this machine was slow")
    True
    >>> spell_note(row, 40.0) is None
    True
    """
    if row.transfer_gbs is None or best_gbs is None or row.n < config.FAST_PARALLEL_MIN_N:
        return None
    if row.transfer_gbs >= SPELL_TRANSFER * best_gbs:
        return None
    return (
        f"n = {row.n}: measured while this machine was slow to pass data between CPUs: one "
        f"CPU read another's writes at {row.transfer_gbs:.0f} GB/s beside the best solves, "
        f"{best_gbs:.0f} GB/s at best in this run; optri's threads, which read each other's "
        "tiles, slow down then and the peak does not, so the fraction of peak reads low "
        "(docs/fast-engine.md)"
    )


@dataclass(frozen=True)
class _Plan:
    """How one size is timed: :func:`run_benchmark`'s arguments of that name."""

    repeats: int
    dtype: str
    peak_seconds: float
    warmup: float
    rounds: int

    @property
    def window(self) -> float:
        """Seconds of each peak run (a kernel) and of each window of solves."""
        return self.peak_seconds / self.rounds

    @property
    def calls(self) -> int:
        """Timed solves a window at least: ``ceil(repeats / rounds)``."""
        return -(-self.repeats // self.rounds)


def _one_size(
    n: int, csv: Path, ours: Built, theirs: Built | None, naive_max: int, plan: _Plan
) -> BenchRow:
    c = run_reference(ours.ref, csv) if ours.ref else None
    shared_c = run_reference(theirs.ref, csv) if theirs and theirs.ref else None
    naive = None
    if n <= naive_max:
        naive = _seconds([sys.executable, "-m", "optri.bench.naive", str(csv)])
    peaks: list[float | None] = []
    shared_peaks: list[float | None] = []
    times: list[float] = []
    walls: list[float] = []
    bests: list[float] = []  # each window's best solve
    transfers: list[float | None] = []  # the probe right after each window
    with _Worker(csv, plan.dtype, plan.warmup) as mine:
        for _ in range(plan.rounds):
            if ours.peak:
                peaks.append(measure_peak(ours.peak, plan.window, runs=1))
            if theirs and theirs.peak:
                shared_peaks.append(measure_peak(theirs.peak, plan.window, runs=1))
            got = mine.window(plan.window, plan.calls)
            times += got["times"]
            walls += got["walls"]
            bests.append(min(got["times"]))
            if ours.probe:
                transfers.append(measure_transfer(ours.probe))
    done = mine.result
    agrees = None if c is None else abs(done["weight"] - c[0]) <= 1e-9 * abs(c[0])
    return BenchRow(
        n,
        min(times),
        min(walls),
        c[1] if c else None,
        naive[1] if naive else None,
        _best(peaks),
        done["peak_mb"],
        done["peak_mb"] - done["base_mb"],
        agrees,
        _load(),
        shared_c[1] if shared_c else None,
        _best(shared_peaks),
        len(times),
        min(times[:3]),
        transfers[bests.index(min(bests))] if transfers else None,
        max((t for t in transfers if t is not None), default=None),
    )


def _best(rates: list[float | None]) -> float | None:
    """The highest rate; None when there was none or a run failed (a broken build)."""
    if not rates or any(r is None for r in rates):
        return None
    return max(r for r in rates if r is not None)


def format_rows(rows: Sequence[BenchRow], header: bool = True) -> str:
    """Rows as an aligned text table (shared columns only when measured)."""
    shared = any(r.shared_c_s is not None or r.shared_peak is not None for r in rows)
    lines = []
    if header:
        lines.append(
            f"{'n':>6} {'optri s':>9} {'of peak':>7} {'C s':>9} {'optri/C':>7} {'naive s':>8} "
            f"{'naive/optri':>11} {'peak MB':>8} {'+table MB':>9} {'load':>5} {'calls':>5} "
            f"{'xfer':>5} {'same':>5}"
            + (f" {'shared C s':>10} {'of shared peak':>14}" if shared else "")
        )

    def f(v: float | bool | None, fmt: str) -> str:
        return "-" if v is None else format(v, fmt)

    for r in rows:
        frac2 = r.n**3 / 6 / r.optri_s / r.shared_peak if r.shared_peak else None
        lines.append(
            f"{r.n:>6} {r.optri_s:>9.4f} {f(r.fraction, '.1%'):>7} {f(r.c_s, '.4f'):>9} "
            f"{f(r.c_ratio, '.3f'):>7} {f(r.naive_s, '.3f'):>8} {f(r.naive_ratio, '.0f'):>11} "
            f"{r.peak_mb:>8.1f} {r.table_mb:>9.1f} {r.load:>5.2f} {r.calls:>5} "
            f"{f(r.transfer_gbs, '.0f'):>5} {f(r.agrees, ''):>5}"
            + (f" {f(r.shared_c_s, '.4f'):>10} {f(frac2, '.1%'):>14}" if shared else "")
        )
    return "\n".join(lines)


def machine() -> str:
    """One line naming this machine: CPU model, CPU count, optri's register block on it.

    >>> "CPUs" in machine()
    True
    """
    model = platform.processor() or platform.machine() or "unknown CPU"
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            names = [line.split(":", 1)[1].strip() for line in f if line.startswith("model name")]
        model = names[0] if names else model
    except OSError:  # not Linux
        pass
    try:
        from ..engines.core import minplus
    except ImportError:  # pragma: no cover - a checkout whose core is not built
        return f"{model}, {os.cpu_count()} CPUs"
    return (
        f"{model}, {os.cpu_count()} CPUs; optri's register block: {describe_plan(minplus.plan())}"
    )


def describe_plan(plan: dict[str, object]) -> str:
    """The min-plus plan's register block in words (``optri._core.minplus.plan()``).

    >>> describe_plan({"rows": 4, "cols": 16, "vector_width": 32, "min_float64": "float",
    ...                "isa": "avx2", "level": "avx2"})
    '4 x 16 cells in 32-byte vectors, float minimum (avx2 kernels, SIMD level avx2)'
    """
    width = plan["vector_width"]
    vectors = f"{width}-byte vectors" if width else "plain C++"
    return (
        f"{plan['rows']} x {plan['cols']} cells in {vectors}, {plan['min_float64']} minimum "
        f"({plan['isa']} kernels, SIMD level {plan['level']})"
    )


def _load() -> float:
    """One-minute load average (0 where the system has none)."""
    try:
        return os.getloadavg()[0]
    except OSError:  # pragma: no cover - platforms without getloadavg
        return 0.0


def _seconds(cmd: list[str]) -> tuple[float, float]:
    """(weight, seconds) printed as ``n weight seconds``."""
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout.split()
    return float(out[1]), float(out[2])


class _Worker:
    """The parent's side of :func:`serve`: one fresh process, asked for windows of solves."""

    def __init__(self, csv: Path, dtype: str, warmup: float) -> None:
        cmd = [sys.executable, "-m", "optri.bench", str(csv), dtype, str(warmup)]
        # stderr to a file: a pipe nobody reads while the windows run could fill and stall
        self.errors = tempfile.TemporaryFile("w+")
        self.proc = subprocess.Popen(
            cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=self.errors, text=True
        )
        self.result: dict[str, float] = {}
        try:
            self._read()  # ready: the kernels loaded
        except BaseException:
            self._close(failed=True)
            raise

    def window(self, seconds: float, calls: int) -> dict[str, list[float]]:
        assert self.proc.stdin is not None
        self.proc.stdin.write(f"{seconds!r} {calls}\n")
        self.proc.stdin.flush()
        return self._read()

    def _read(self) -> dict[str, Any]:
        assert self.proc.stdout is not None
        line = self.proc.stdout.readline()
        if not line:
            self.proc.wait()
            self.errors.seek(0)
            why = (self.errors.read().strip().splitlines() or ["no output"])[-1]
            raise EngineUnavailableError(f"the benchmark's solver process failed: {why}")
        out: dict[str, Any] = json.loads(line)
        return out

    def __enter__(self) -> _Worker:
        return self

    def __exit__(self, *exc: object) -> None:
        self._close(failed=exc[0] is not None)

    def _close(self, failed: bool) -> None:
        """End the process: after its summary (into ``result``), or killed on a failure."""
        assert self.proc.stdin is not None
        try:
            self.proc.stdin.close()  # end of the windows: the process reports its memory
            if not failed:
                self.result = self._read()
        finally:
            if failed and self.proc.poll() is None:
                self.proc.kill()
            self.proc.wait()
            if self.proc.stdout is not None:
                self.proc.stdout.close()
            self.errors.close()


def _peak_mb() -> float:
    """Peak resident memory of this process so far (ru_maxrss counts KiB on Linux)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024 / 1e6


class Solver:
    """Solves one polygon with method="fast" in this fresh process, in timed windows.

    Each window starts with untimed calls on the same polygon, for ``warmup``
    seconds (at least one call when ``warmup > 0``). A process's first calls pay for fresh
    memory (the C library maps the first table, then grows its heap for the
    second), two to three times a warm call's time, so the best of a few cold
    calls is not a warm call. Tables of 32 MiB or more (n >= 2048 in float64)
    are mapped by optri itself, and the last one is kept for the next call
    (``optri.engines.memory.release_table``), so from the second call on those
    skip the first touch too; but only for a second, and a peak run between two
    windows takes longer, so each window needs a warm-up of its own
    (docs/performance-log.md).

    Examples
    --------
    >>> import os, tempfile
    >>> csv = os.path.join(tempfile.mkdtemp(), "p.csv")
    >>> np.savetxt(csv, convex_polygon(50), fmt="%.17g", delimiter=",")
    >>> got = Solver(csv, "float64", warmup=0).window(0.0, 2)
    >>> len(got["times"])
    2
    """

    def __init__(self, csv: str, dtype: str, warmup: float = 0.0) -> None:
        self.pts = read_polygon(csv)
        self.dtype = dtype
        self.warmup = warmup
        triangulate(self.pts[:40], method="fast", dtype=dtype)  # load the cached kernels
        self.base_mb = _peak_mb()  # Python, numpy, numba, the kernels: all but the table
        self.warm_calls = 0
        self.weight = float("nan")

    def window(self, seconds: float, calls: int) -> dict[str, list[float]]:
        """Timed calls for ``seconds``, at least ``calls``, after the warm-up's untimed ones.

        Returns each timed call's solve seconds (``times``) and whole-call seconds
        (``walls``).
        """
        start = time.perf_counter()
        warm = 0
        while self.warmup > 0 and (warm == 0 or time.perf_counter() - start < self.warmup):
            triangulate(self.pts, method="fast", dtype=self.dtype)
            warm += 1
        self.warm_calls += warm
        times: list[float] = []
        walls: list[float] = []
        start = time.perf_counter()
        while len(times) < calls or time.perf_counter() - start < seconds:
            began = time.perf_counter()
            tri = triangulate(self.pts, method="fast", dtype=self.dtype)
            walls.append(time.perf_counter() - began)
            times.append(tri.seconds)
            self.weight = float(tri.weight)  # type: ignore[arg-type]  # scalar objective
            del tri
        return {"times": times, "walls": walls}

    def summary(self) -> dict[str, float]:
        """The optimum, memory before the first table and at the end, the warm-up's calls."""
        return {
            "weight": self.weight,
            "base_mb": self.base_mb,
            "peak_mb": _peak_mb(),
            "warm_calls": self.warm_calls,
        }


def serve(argv: Sequence[str], commands: IO[str], out: IO[str]) -> None:
    """The fresh-process worker: ``argv`` = CSV DTYPE WARMUP; one JSON line per reply.

    A line ``{"ready": true}`` once the kernels are loaded;
    then for each command line ``SECONDS CALLS`` the window's seconds
    (:meth:`Solver.window`); at the end of the commands, :meth:`Solver.summary`.
    """
    solver = Solver(argv[0], argv[1], float(argv[2]))

    def reply(obj: object) -> None:
        out.write(json.dumps(obj) + "\n")
        out.flush()

    reply({"ready": True})
    for line in commands:
        seconds, calls = line.split()
        reply(solver.window(float(seconds), int(calls)))
    reply(solver.summary())
