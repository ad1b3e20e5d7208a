"""Polygons with holes proven optimal: this checkout against an older revision, same run.

The older revision is checked out into a temporary directory (``git worktree
add``) and run in a subprocess with ``PYTHONPATH=<tmp>/src``; this checkout runs
in another subprocess with its own ``src``. Both solve the same polygons
(``optri.domains.random_domain``, written once to a file both read) with
``method="auto"`` and no time limit, after a warm-up (imports, compiled kernels,
HiGHS). Rounds alternate old and new so both see the same machine; each
polygon's time is the median over rounds. Both must prove the same optimum
with the same triangles.

    PYTHONPATH=src python benchmarks/bench_domains_core.py [--rev 8cfecf8] [--n 400]
        [--holes 3] [--seeds 0 1 2] [--rounds 3] [--weight diagonal] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from optri.domains import random_domain

ROOT = Path(__file__).resolve().parents[1]

#: What each subprocess runs: warm up, then solve every polygon once, print JSON.
CHILD = r"""
import json, sys, time
import numpy as np
import optri
from optri.domains import random_domain

data = np.load(sys.argv[1])
weight = sys.argv[2]
optri.triangulate(random_domain(30, 1, seed=1), weight=weight)
optri.triangulate(random_domain(60, 2, seed=2), weight=weight)
rows = []
for key in sorted(k for k in data.files if not k.endswith("_sizes")):
    sizes = data[key + "_sizes"].tolist()
    pts = data[key]
    rings, at = [], 0
    for m in sizes:
        rings.append(pts[at : at + m])
        at += m
    start = time.perf_counter()
    t = optri.triangulate((rings[0], rings[1:]), weight=weight, time_limit=None)
    seconds = time.perf_counter() - start
    tris = sorted(map(tuple, t.triangles.tolist()))
    rows.append(dict(key=key, seconds=seconds, weight=float(t.weight), proven=t.optimality,
                     triangles=hash(tuple(tris)), stats=dict(t.stats)))
print(json.dumps(dict(source=optri.__file__, rows=rows)))
"""


def _solve_all(src: Path, polys: Path, weight: str) -> list[dict]:
    env = dict(os.environ, PYTHONPATH=str(src))
    out = subprocess.run(
        [sys.executable, "-c", CHILD, str(polys), weight],
        env=env,
        capture_output=True,
        text=True,
        cwd=str(src.parent),
    )
    if out.returncode:
        sys.exit(f"the run with {src} failed:\n{out.stderr}")
    got = json.loads(out.stdout.strip().splitlines()[-1])
    assert Path(got["source"]).resolve().is_relative_to(src.resolve()), got["source"]
    return got["rows"]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rev", default="8cfecf8", help="the older revision (default 8cfecf8)")
    ap.add_argument("--n", type=int, default=400, help="vertices in all")
    ap.add_argument("--holes", type=int, default=3)
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--weight", default="diagonal", help="a sum weight (default: MWT)")
    ap.add_argument("--json", help="write the rows to this file")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        old = Path(tmp) / "old"
        subprocess.run(
            ["git", "-C", str(ROOT), "worktree", "add", "--detach", "-q", str(old), args.rev],
            check=True,
        )
        try:
            arrays = {}
            for s in args.seeds:
                ext, hs = random_domain(args.n, args.holes, seed=s)
                arrays[f"poly{s:04d}"] = np.concatenate([ext, *hs])
                arrays[f"poly{s:04d}_sizes"] = np.array([len(ext), *map(len, hs)])
            polys = Path(tmp) / "polys.npz"
            np.savez(polys, **arrays)
            runs: dict[str, list[list[dict]]] = {"old": [], "new": []}
            for r in range(args.rounds):
                for name, src in (("old", old / "src"), ("new", ROOT / "src")):
                    runs[name].append(_solve_all(src, polys, args.weight))
                    print(f"round {r + 1}: {name} done", flush=True)
        finally:
            subprocess.run(
                ["git", "-C", str(ROOT), "worktree", "remove", "--force", str(old)], check=True
            )
    rows = []
    for m, seed in enumerate(args.seeds):
        o = [run[m] for run in runs["old"]]
        w = [run[m] for run in runs["new"]]
        assert o[0]["proven"] == w[0]["proven"] == "proven", (o[0]["proven"], w[0]["proven"])
        assert o[0]["weight"] == w[0]["weight"], "the optimum changed"
        assert o[0]["triangles"] == w[0]["triangles"], "the triangles changed"
        old_s = statistics.median(x["seconds"] for x in o)
        new_s = statistics.median(x["seconds"] for x in w)
        rows.append(dict(seed=seed, old=old_s, new=new_s, ratio=old_s / new_s,
                         candidates=w[0]["stats"].get("candidate_triangles")))  # fmt: skip
        print(
            f"h={args.holes} N={args.n} seed {seed}: old {old_s:7.3f} s  new {new_s:7.3f} s  "
            f"x{old_s / new_s:5.2f}  T={rows[-1]['candidates']}",
            flush=True,
        )
    old_total = sum(r["old"] for r in rows)
    new_total = sum(r["new"] for r in rows)
    print(f"all: old {old_total:.3f} s  new {new_total:.3f} s  x{old_total / new_total:.2f}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(dict(args=vars(args), rows=rows), fh, indent=1)


if __name__ == "__main__":
    main()
