"""The cost of exact predicates: valid-diagonal mask and simplicity check, before vs after.

The baseline is the package as it was at a git revision (default ``a6bb9bd``, the
last commit with the tolerance-based orientation test), exported with ``git archive``
into a temporary folder; both versions run in child processes, alternately, on the
same polygons, each with its own numba cache (compiled once, not timed). Prints the
best time of each and the ratio after / before.

    python benchmarks/bench_exact.py [--base REV] [--n 2000] [--rounds 5] [--repeat 3]

Polygons: a random star (float coordinates: the filter decides every turn), the
circle with one reflex vertex (1.7 M diagonals) and an integer-grid star (many exactly
collinear triples: the exact stage runs often).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

CHILD = r"""
import json, sys, time
import numpy as np
from optri.polygon import as_polygon, require_simple
from optri.simple.mask import valid_diagonals_compiled

n, repeat = int(sys.argv[1]), int(sys.argv[2])
rng = np.random.default_rng(0)
ang = np.sort(rng.uniform(0, 2 * np.pi, n))
star = np.column_stack((np.cos(ang), np.sin(ang))) * rng.uniform(0.3, 1.0, n)[:, None]
a = np.linspace(0, 2 * np.pi, n, endpoint=False)
notch = np.column_stack((np.cos(a), np.sin(a)))
notch[0] *= 0.5
k = np.arange(n)
r = np.where(k % 2 == 0, 4000.0, 3000.0 + (k % 7))
grid = np.round(np.column_stack((r * np.cos(2 * np.pi * k / n), r * np.sin(2 * np.pi * k / n))))
out = {}
for name, pts in (("star", star), ("notch", notch), ("grid star", grid)):
    poly = as_polygon(pts)
    valid_diagonals_compiled(poly.data)  # compile or load the kernels
    best_mask = best_simple = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        m = valid_diagonals_compiled(poly.data)
        best_mask = min(best_mask, time.perf_counter() - t0)
        t0 = time.perf_counter()
        require_simple(poly)
        best_simple = min(best_simple, time.perf_counter() - t0)
    out[name] = (best_mask, best_simple, int(m.sum()))
print(json.dumps(out))
"""


def export(rev: str, dest: Path) -> Path:
    """``src/`` of revision ``rev`` under ``dest`` (git archive)."""
    archive = subprocess.run(
        ["git", "-C", str(ROOT), "archive", rev, "src"], check=True, capture_output=True
    ).stdout
    subprocess.run(["tar", "-x", "-C", str(dest)], input=archive, check=True)
    return dest / "src"


def run_child(code: str, src: Path, cache: Path, *args: object) -> dict:
    """Run ``code`` with ``src`` first on the path and its own numba cache; its JSON line."""
    env = dict(os.environ, PYTHONPATH=str(src), NUMBA_CACHE_DIR=str(cache))
    proc = subprocess.run(
        [sys.executable, "-c", code, *map(str, args)],
        env=env, check=True, capture_output=True, text=True,
    )  # fmt: skip
    return json.loads(proc.stdout.strip().splitlines()[-1])


def run(src: Path, cache: Path, n: int, repeat: int) -> dict:
    return run_child(CHILD, src, cache, n, repeat)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--base", default="a6bb9bd", help="git revision of the baseline")
    ap.add_argument("--n", type=int, default=2000)
    ap.add_argument("--rounds", type=int, default=5, help="alternating child runs per version")
    ap.add_argument("--repeat", type=int, default=3, help="timed calls per child run")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        base_src = export(args.base, Path(tmp))
        versions = {"before": base_src, "after": ROOT / "src"}
        best: dict[str, dict[str, list[float]]] = {v: {} for v in versions}
        masks: dict[str, dict[str, int]] = {v: {} for v in versions}
        for _ in range(args.rounds):
            for v, src in versions.items():
                res = run(src, Path(tmp) / f"cache-{v}", args.n, args.repeat)
                for name, (t_mask, t_simple, count) in res.items():
                    old = best[v].get(name, [float("inf")] * 2)
                    best[v][name] = [min(old[0], t_mask), min(old[1], t_simple)]
                    masks[v][name] = count
    print(f"n = {args.n}, best of {args.rounds} x {args.repeat}; before = {args.base}")
    print(f"{'polygon':<10} {'mask before':>12} {'mask after':>11} {'ratio':>6}   "
          f"{'simple before':>13} {'simple after':>12} {'ratio':>6}  same mask")  # fmt: skip
    for name in best["after"]:
        (mb, sb), (ma, sa) = best["before"][name], best["after"][name]
        same = masks["before"][name] == masks["after"][name]
        print(f"{name:<10} {mb * 1e3:>10.1f}ms {ma * 1e3:>9.1f}ms {ma / mb:>6.2f}   "
              f"{sb * 1e3:>11.1f}ms {sa * 1e3:>10.1f}ms {sa / sb:>6.2f}  {same}")  # fmt: skip


if __name__ == "__main__":
    main()
