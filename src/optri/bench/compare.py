"""Benchmark the compiled engine against the C and pure-Python yardsticks.

For each n: a random convex polygon from the yardsticks' ``gen.py``, solved
by ``ref_mwt.c`` (built here with ``gcc -O3 -march=native -ffast-math``), by
``naive_memo.py`` (small n only) and by ``method="fast"`` in a fresh process
(so its peak memory is its own), all on the same CSV file, weight perimeter.
Used by ``benchmarks/bench_fast.py`` and ``optri bench``; ``python -m optri.bench``
runs the fresh-process worker.
"""

from __future__ import annotations

import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path

from ..io.files import read_polygon
from ..solve import triangulate

__all__ = ["BenchRow", "find_yardsticks", "format_rows", "run_benchmark", "worker"]

#: Where the yardsticks live, tried in turn: ``shared/bench`` beside the repository
#: root, then beside the current directory (``$OPTRI_BENCH_DIR`` comes first).
_BENCH_DIRS = (
    str(Path(__file__).resolve().parents[4] / "shared" / "bench"),
    str(Path.cwd().parent / "shared" / "bench"),
)


@dataclass
class BenchRow:
    """One size: seconds of each solver, ratios, peak memory of the optri process.

    ``optri_s`` is the engine's solve (``Triangulation.seconds``), ``wall_s`` the
    whole ``triangulate`` call (validation, result checks' set-up included).
    """

    n: int
    optri_s: float
    wall_s: float
    c_s: float | None
    naive_s: float | None
    peak_mb: float
    table_mb: float
    agrees: bool | None

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
        return {**asdict(self), "c_ratio": self.c_ratio, "naive_ratio": self.naive_ratio}


def find_yardsticks() -> Path | None:
    """The folder holding ``ref_mwt.c``, ``gen.py`` and ``naive_memo.py``, or None."""
    env = os.environ.get("OPTRI_BENCH_DIR")
    for d in ([env] if env else []) + list(_BENCH_DIRS):
        p = Path(d)
        if (p / "gen.py").is_file() and (p / "ref_mwt.c").is_file():
            return p.resolve()
    return None


def run_benchmark(
    sizes: Sequence[int],
    naive_max: int = 500,
    repeats: int = 3,
    seed: int = 1,
    dtype: str = "float64",
    log: Callable[[str], None] | None = None,
) -> list[BenchRow]:
    """Time every solver on the same polygon for each n in ``sizes``."""
    bench = find_yardsticks()
    if bench is None:
        raise FileNotFoundError("yardsticks not found (set OPTRI_BENCH_DIR to ../shared/bench)")
    rows = []
    with tempfile.TemporaryDirectory(prefix="optri-bench-") as tmp:
        ref = _build_c(bench, Path(tmp))
        for n in sizes:
            csv = Path(tmp) / f"poly{n}.csv"
            out = subprocess.run(
                [sys.executable, str(bench / "gen.py"), str(n), str(seed)],
                check=True,
                capture_output=True,
                text=True,
            ).stdout
            csv.write_text(out)
            c = _run_yardstick([str(ref), str(csv)]) if ref else None
            naive = None
            if n <= naive_max:
                naive = _run_yardstick([sys.executable, str(bench / "naive_memo.py"), str(csv)])
            mine = _run_worker(csv, repeats if n <= 2000 else 1, dtype)
            ref_w = c[0] if c else None
            agrees = None if ref_w is None else abs(mine["weight"] - ref_w) <= 1e-9 * abs(ref_w)
            row = BenchRow(
                n,
                mine["seconds"],
                mine["wall"],
                c[1] if c else None,
                naive[1] if naive else None,
                mine["peak_mb"],
                mine["peak_mb"] - mine["base_mb"],
                agrees,
            )
            rows.append(row)
            if log is not None:
                log(format_rows([row], header=len(rows) == 1))
    return rows


def format_rows(rows: Sequence[BenchRow], header: bool = True) -> str:
    """Rows as an aligned text table."""
    lines = []
    if header:
        lines.append(
            f"{'n':>6} {'optri s':>9} {'wall s':>8} {'C s':>9} {'optri/C':>8} {'naive s':>9} "
            f"{'naive/optri':>11} {'peak MB':>8} {'+table MB':>9} {'same opt':>8}"
        )

    def f(v: float | None, fmt: str) -> str:
        return "-" if v is None else format(v, fmt)

    for r in rows:
        lines.append(
            f"{r.n:>6} {r.optri_s:>9.4f} {r.wall_s:>8.4f} {f(r.c_s, '.4f'):>9} "
            f"{f(r.c_ratio, '.3f'):>8} "
            f"{f(r.naive_s, '.3f'):>9} {f(r.naive_ratio, '.0f'):>11} {r.peak_mb:>8.1f} "
            f"{r.table_mb:>9.1f} {f(r.agrees, ''):>8}"
        )
    return "\n".join(lines)


def _build_c(bench: Path, tmp: Path) -> Path | None:
    gcc = shutil.which("gcc") or shutil.which("cc")
    if gcc is None:
        return None
    exe = tmp / "ref_mwt"
    cmd = [gcc, "-O3", "-march=native", "-ffast-math", "-o", str(exe), str(bench / "ref_mwt.c")]
    subprocess.run([*cmd, "-lm"], check=True, capture_output=True)
    return exe


def _run_yardstick(cmd: list[str]) -> tuple[float, float]:
    """(weight, seconds) printed as ``n weight seconds``."""
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout.split()
    return float(out[1]), float(out[2])


def _run_worker(csv: Path, repeats: int, dtype: str) -> dict[str, float]:
    cmd = [sys.executable, "-m", "optri.bench", str(csv), str(repeats), dtype]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def _peak_mb() -> float:
    """Peak resident memory of this process so far (ru_maxrss counts KiB on Linux)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024 / 1e6


def worker(csv: str, repeats: int, dtype: str) -> dict[str, float]:
    """Solve ``csv`` with method="fast" ``repeats`` times in this fresh process."""
    pts = read_polygon(csv)
    triangulate(pts[:40], method="fast", dtype=dtype)  # load the cached kernels
    base = _peak_mb()  # Python, numpy, numba and the kernels: everything but the table
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
    return {"seconds": best, "wall": wall, "weight": weight, "base_mb": base, "peak_mb": peak}
