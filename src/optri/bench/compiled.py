"""The C yardsticks shipped with optri: found, built with the system's C compiler, run.

``optri/bench/yardsticks/`` holds three C programs written for this project:
``ref_mwt.c``, the textbook O(n³) dynamic programme (one thread, untiled),
``minplus_peak.c``, the machine's min-plus ceiling (register-blocked, cache-resident
64 × 64 tiles, every core), and ``crosscore.c``, how fast one CPU reads what another
has just written (the machine's state, which the peak cannot see). They are compiled
at run time into a scratch folder (``gcc``, else ``cc``, else ``$CC``); without a
compiler the benchmark still runs its Python parts and says once why the C columns
are empty. A folder of other
yardsticks with the same two file names and output formats (``--shared DIR``)
is built the same way, as a cross-check (``crosscore.c`` where it has one).
"""

from __future__ import annotations

import os
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

__all__ = [
    "YARDSTICKS",
    "Built",
    "build",
    "find_compiler",
    "measure_peak",
    "measure_transfer",
    "run_reference",
]

#: The yardsticks' sources, inside the installed package.
YARDSTICKS = Path(__file__).resolve().with_name("yardsticks")
_REF, _PEAK, _PROBE = "ref_mwt.c", "minplus_peak.c", "crosscore.c"
_FLAGS = ["-O3", "-march=native", "-ffast-math"]


@dataclass(frozen=True)
class Built:
    """Paths of the built programs (None when not built) and why not, in one line.

    ``probe`` is ``crosscore.c``'s program, built where the folder has its source.
    """

    ref: Path | None
    peak: Path | None
    note: str | None = None
    probe: Path | None = None


def find_compiler() -> str | None:
    """``gcc``, ``cc`` or ``$CC`` on the ``PATH``, or None."""
    for name in ("gcc", "cc", os.environ.get("CC", "")):
        found = shutil.which(name) if name else None
        if found:
            return found
    return None


def build(out: Path, source: Path = YARDSTICKS, cc: str | None = None) -> Built:
    """Compile ``ref_mwt.c``, ``minplus_peak.c`` (and ``crosscore.c``) of ``source`` into ``out``.

    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     built = build(Path(tmp), cc="/nonexistent/gcc")
    >>> built.ref is None and "compiler" in built.note
    True
    """
    cc = cc or find_compiler()
    if cc is None or not Path(cc).is_file():
        return Built(
            None,
            None,
            "no C compiler (gcc, cc or $CC) found: the C reference and "
            "the peak microbenchmark are skipped; install gcc for optri/C and % of peak",
        )
    out.mkdir(parents=True, exist_ok=True)
    notes: list[str] = []
    ref = _compile(cc, source / _REF, out / "ref_mwt", [*_FLAGS, "-lm"], notes)
    peak = _compile(
        cc, source / _PEAK, out / "minplus_peak", [*_FLAGS, "-pthread", "-fopenmp"], notes
    )
    probe = None
    if (source / _PROBE).is_file():
        probe = _compile(cc, source / _PROBE, out / "crosscore", [*_FLAGS, "-pthread"], notes)
    return Built(ref, peak, "; ".join(notes) or None, probe)


def _compile(cc: str, src: Path, exe: Path, flags: list[str], notes: list[str]) -> Path | None:
    if not src.is_file():
        notes.append(f"{src} is missing")
        return None
    done = subprocess.run(
        [cc, *flags[:3], "-o", str(exe), str(src), *flags[3:]], capture_output=True, text=True
    )
    if done.returncode != 0:
        first = (done.stderr.strip().splitlines() or ["no message"])[0]
        notes.append(f"{src.name} did not compile ({first})")
        return None
    return exe


def run_reference(exe: Path, csv: Path) -> tuple[float, float]:
    """(weight, seconds) of a C reference, which prints ``n weight seconds``."""
    out = subprocess.run([str(exe), str(csv)], check=True, capture_output=True, text=True)
    fields = out.stdout.split()
    return float(fields[1]), float(fields[2])


def measure_peak(exe: Path, seconds: float = 1.0, runs: int = 3) -> float | None:
    """Min-plus candidates per second on every core (the program's second figure).

    The best of ``runs`` runs of ``seconds / runs`` each: other work on the
    machine only ever lowers the rate, so the highest is the best estimate of
    the ceiling. None when the program fails: ours exits with status 1 when
    none of its kernels computes its check product right (a broken compiler),
    and a report then leaves the peak out, as without a compiler.
    """
    rates = []
    for _ in range(max(1, runs)):
        cmd = [str(exe), str(seconds / max(1, runs))]
        out = subprocess.run(cmd, capture_output=True, text=True)
        if out.returncode != 0:
            return None
        rates.append(float(out.stdout.split()[1]))
    return max(rates)


def measure_transfer(exe: Path) -> float | None:
    """GB/s at which one CPU reads 4 MB that another has just written (``crosscore.c``).

    The best of five rounds of a few milliseconds each. None where the program
    cannot measure it: one CPU only (it exits with status 1 and says so).
    """
    out = subprocess.run([str(exe)], capture_output=True, text=True)
    if out.returncode != 0:
        return None
    return float(out.stdout.split()[0])
