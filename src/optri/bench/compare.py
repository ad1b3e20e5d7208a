"""Benchmark ``method="fast"`` against the yardsticks, all in one run.

For each n: a random convex polygon (sorted random angles on an ellipse, written
to a CSV with every digit, so each solver reads the same doubles), solved by
the C reference ``yardsticks/ref_mwt.c``, by the plain-Python recursion
:mod:`optri.bench.naive` (small n only) and by ``method="fast"`` in a fresh
process (so its peak memory is its own); the peak microbenchmark
``yardsticks/minplus_peak.c`` runs just before optri, and the fraction of peak
is ``(n³/6 candidates / optri's seconds) / peak candidates per second``.
Used by ``optri bench`` and ``benchmarks/bench_fast.py``; ``python -m
optri.bench`` runs the fresh-process worker.
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

import numpy as np

from ..io.files import read_polygon
from ..solve import triangulate
from .compiled import Built, build, measure_peak, run_reference

__all__ = ["BenchRow", "convex_polygon", "format_rows", "machine", "run_benchmark", "worker"]


@dataclass
class BenchRow:
    """One size: seconds of each solver, the peak rate, memory, agreement, load.

    ``optri_s`` is the engine's solve (``Triangulation.seconds``), ``wall_s`` the
    whole ``triangulate`` call; ``peak`` the min-plus candidates per second
    measured just before; ``agrees`` whether optri's weight equals the C
    reference's (relative difference at most 1e-9; None without the C one).
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
) -> list[BenchRow]:
    """Time every solver on the same polygon for each n in ``sizes``.

    optri's seconds are the best of ``repeats`` calls after ``warmup`` seconds
    of untimed ones (see :func:`worker`), as the peak is a rate of a steady run.

    ``shared``: a folder with another ``ref_mwt.c`` and ``minplus_peak.c`` (such
    as ``../shared/bench``) to build and run as well, as a cross-check. ``cc``:
    the C compiler (default: found on the ``PATH``).
    """
    say = log or (lambda _line: None)
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
        for n in sizes:
            csv = Path(tmp) / f"poly{n}.csv"
            csv.write_text("".join(f"{x!r},{y!r}\n" for x, y in convex_polygon(n, seed).tolist()))
            rows.append(
                _one_size(n, csv, ours, theirs, naive_max, repeats, dtype, peak_seconds, warmup)
            )
            say(format_rows(rows[-1:], header=len(rows) == 1))
    return rows


def _one_size(
    n: int,
    csv: Path,
    ours: Built,
    theirs: Built | None,
    naive_max: int,
    repeats: int,
    dtype: str,
    peak_seconds: float,
    warmup: float,
) -> BenchRow:
    c = run_reference(ours.ref, csv) if ours.ref else None
    shared_c = run_reference(theirs.ref, csv) if theirs and theirs.ref else None
    naive = None
    if n <= naive_max:
        naive = _seconds([sys.executable, "-m", "optri.bench.naive", str(csv)])
    peak = measure_peak(ours.peak, peak_seconds) if ours.peak else None
    shared_peak = measure_peak(theirs.peak, peak_seconds) if theirs and theirs.peak else None
    mine = _run_worker(csv, repeats, dtype, warmup)
    agrees = None if c is None else abs(mine["weight"] - c[0]) <= 1e-9 * abs(c[0])
    return BenchRow(
        n,
        mine["seconds"],
        mine["wall"],
        c[1] if c else None,
        naive[1] if naive else None,
        peak,
        mine["peak_mb"],
        mine["peak_mb"] - mine["base_mb"],
        agrees,
        _load(),
        shared_c[1] if shared_c else None,
        shared_peak,
    )


def format_rows(rows: Sequence[BenchRow], header: bool = True) -> str:
    """Rows as an aligned text table (shared columns only when measured)."""
    shared = any(r.shared_c_s is not None or r.shared_peak is not None for r in rows)
    lines = []
    if header:
        lines.append(
            f"{'n':>6} {'optri s':>9} {'of peak':>7} {'C s':>9} {'optri/C':>7} {'naive s':>8} "
            f"{'naive/optri':>11} {'peak MB':>8} {'+table MB':>9} {'load':>5} {'same':>5}"
            + (f" {'shared C s':>10} {'of shared peak':>14}" if shared else "")
        )

    def f(v: float | bool | None, fmt: str) -> str:
        return "-" if v is None else format(v, fmt)

    for r in rows:
        frac2 = r.n**3 / 6 / r.optri_s / r.shared_peak if r.shared_peak else None
        lines.append(
            f"{r.n:>6} {r.optri_s:>9.4f} {f(r.fraction, '.1%'):>7} {f(r.c_s, '.4f'):>9} "
            f"{f(r.c_ratio, '.3f'):>7} {f(r.naive_s, '.3f'):>8} {f(r.naive_ratio, '.0f'):>11} "
            f"{r.peak_mb:>8.1f} {r.table_mb:>9.1f} {r.load:>5.2f} {f(r.agrees, ''):>5}"
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
        from ..engines._llvm import describe_plan  # imports numba
    except ImportError:  # pragma: no cover - numba is a core dependency
        return f"{model}, {os.cpu_count()} CPUs"
    return f"{model}, {os.cpu_count()} CPUs; optri's register block: {describe_plan()}"


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


def _run_worker(csv: Path, repeats: int, dtype: str, warmup: float) -> dict[str, float]:
    cmd = [sys.executable, "-m", "optri.bench", str(csv), str(repeats), dtype, str(warmup)]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def _peak_mb() -> float:
    """Peak resident memory of this process so far (ru_maxrss counts KiB on Linux)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024 / 1e6


def worker(csv: str, repeats: int, dtype: str, warmup: float = 0.0) -> dict[str, float]:
    """Solve ``csv`` with method="fast" ``repeats`` times in this fresh process; the best.

    Untimed calls on the same polygon come first, for ``warmup`` seconds (at
    least one call when ``warmup > 0``). A process's first calls pay for fresh
    memory: on the Xeon of ``docs/fast-engine.md`` the first two at n = 1000
    took 10-17 ms against 4.6-4.9 ms for every later one (the C library maps
    the first table, then grows its heap for the second), so the best of three
    cold calls was one warm call. Tables of 32 MiB or more (n >= 2048 in
    float64) are mapped by optri itself, and the last one is kept for the next
    call (``optri.engines.memory.release_table``), so from the second call on
    those skip the first touch too.
    """
    pts = read_polygon(csv)
    triangulate(pts[:40], method="fast", dtype=dtype)  # load the cached kernels
    base = _peak_mb()  # Python, numpy, numba and the kernels: everything but the table
    warm_calls = 0
    start = time.perf_counter()
    while warmup > 0 and (warm_calls == 0 or time.perf_counter() - start < warmup):
        triangulate(pts, method="fast", dtype=dtype)
        warm_calls += 1
    best = wall = float("inf")
    weight = float("nan")
    for _ in range(repeats):
        start = time.perf_counter()
        tri = triangulate(pts, method="fast", dtype=dtype)
        wall = min(wall, time.perf_counter() - start)
        best = min(best, tri.seconds)
        weight = float(tri.weight)  # type: ignore[arg-type]  # scalar objective
        del tri
    peak = _peak_mb()
    return {
        "seconds": best,
        "wall": wall,
        "weight": weight,
        "base_mb": base,
        "peak_mb": peak,
        "warm_calls": warm_calls,
    }
