"""The 3-D hole searches before and after a change: same patches bit for bit, and their times.

The baseline is the package at a git revision (default ``8cfecf8``, the last one
whose hole searches were numba kernels), checked out with ``git worktree add`` into
a temporary folder. Both versions run the same script in child processes
(``PYTHONPATH=<version>/src``) on the same inputs:

* random closed 3-D polylines (Gaussian points, wavy rings with and without third
  points and forbidden chords, lattice rectangles with collinear runs, so zero-area
  triangles and exact area ties occur), ``n = 3..150`` for ``exact`` and ``auto``,
  up to 400 for ``liepa`` and ``delaunay``; a few with the ``area`` weight;
* every mesh in ``tests/data/meshes`` and the bundled ``sphere_two_holes.obj``,
  filled by ``fill_holes`` in every mode.

Every patch's triangles, objective value (floats compared as hex), mode, candidate
set and degenerate count must be equal; the script exits 1 and names the first
differences otherwise. Then it times, in both versions (warm: the baseline's numba
kernels compiled or loaded by an untimed call first): the exact search of a
400-edge hole, ``fill_holes`` on the bundled sphere, and the first ``fill_holes``
call in a fresh process (the baseline with an empty numba cache).

    python benchmarks/check_port_holes.py [--base REV] [--new DIR] [--quick] [--no-time]
                                          [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

CHILD = r"""
import json, sys, time, warnings
from pathlib import Path
import numpy as np
import optri
from optri import fill_holes, fill_polyline
from optri.io.meshes import read_mesh

root, quick = Path(sys.argv[1]), sys.argv[2] == "quick"
warnings.simplefilter("ignore")


def ring(n, rng, wave=0.3):
    a = np.sort(rng.uniform(0, 2 * np.pi, n)) if n > 3 else np.array([0.0, 2.0, 4.0])
    return np.column_stack((np.cos(a), np.sin(a), wave * np.sin(3 * a) + 0.05 * rng.normal(size=n)))


def lattice(n, rng):
    # the boundary of a w x h lattice rectangle, a few points lifted: collinear runs
    w = max(1, n // 4)
    h = max(1, (n - 2 * w) // 2)
    pts = [(x, 0) for x in range(w)] + [(w, y) for y in range(h)]
    pts += [(w - x, h) for x in range(w)] + [(0, h - y) for y in range(h)]
    P = np.array([(x, y, 0.0) for x, y in pts], dtype=float)
    lift = rng.choice(len(P), size=max(1, len(P) // 6), replace=False)
    P[lift, 2] = rng.integers(1, 3, size=len(lift))
    return P


def polyline(kind, n, seed):
    rng = np.random.default_rng([seed, n, len(kind)])
    third = forbidden = None
    if kind == "noise":
        P = rng.normal(size=(n, 3))
    elif kind == "lattice":
        P = lattice(n, rng)
    else:
        P = ring(n, rng)
    if kind in ("ring3", "ring3f", "lattice"):
        nxt = np.roll(P, -1, axis=0)
        mid = 0.5 * (P + nxt)
        out = mid * np.array([1.3, 1.3, 1.0]) + np.array([0.0, 0.0, -0.2])
        third = out + 0.05 * rng.normal(size=P.shape)
    if kind == "ring3f" and len(P) > 5:
        m = len(P)
        pairs = []
        for _ in range(max(1, m // 8)):
            a, b = sorted(rng.choice(m, size=2, replace=False).tolist())
            if 1 < b - a < m - 1:
                pairs.append((a, b))
        forbidden = np.array(pairs, dtype=np.int64).reshape(-1, 2) if pairs else None
    return P, third, forbidden


def record(fn):
    try:
        t = fn()
    except Exception as exc:  # the same error, the same message
        return {"error": type(exc).__name__, "message": str(exc)}
    w = t.weight if isinstance(t.weight, tuple) else (t.weight,)
    return {
        "triangles": t.triangles.tolist(),
        "weight": [float(x).hex() for x in w],
        "method": t.method,
        "degenerate": int(t.stats.get("degenerate", -1)),
        "candidates": str(t.stats.get("candidates", "")),
    }


def cases():
    for n in range(3, 151):
        yield "exact", "noise", n, "liepa"
        if n % 3 == 0 or n < 20:
            yield "exact", "ring3f", n, "liepa"
            yield "auto", "ring3", n, "liepa"
        if n % 3 == 1 and n >= 8:
            yield "exact", "lattice", n, "liepa"
    for n in list(range(3, 60)) + list(range(60, 401, 7)):
        yield "liepa", "noise" if n % 2 else "ring3f", n, "liepa"
        if n % 4 == 0:
            yield "liepa", "lattice", n, "liepa"
        yield "delaunay", "ring3" if n % 2 else "noise", n, "liepa"
    for n in (4, 7, 12, 25, 40):
        for mode in ("exact", "delaunay"):
            yield mode, "lattice", n, "area"


out = {"polylines": {}, "meshes": {}, "times": {}}
todo = list(cases())
if quick:
    todo = todo[::9]
for mode, kind, n, weight in todo:
    P, third, forbidden = polyline(kind, n, 0)
    key = f"{mode}/{kind}/{n}/{weight}"
    out["polylines"][key] = record(
        lambda: fill_polyline(P, weight, mode, third, forbidden=forbidden)
    )

folder = root / "tests/data/meshes"
meshes = sorted(p for p in folder.iterdir() if p.suffix in (".obj", ".off", ".ply"))
meshes.append(root / "src/optri/data/sphere_two_holes.obj")
for path in meshes:
    mesh = read_mesh(path)
    v, f = np.asarray(mesh.vertices), np.asarray(mesh.faces)
    for mode in ("auto", "exact", "liepa", "delaunay"):
        if quick and mode != "auto":
            continue
        try:
            (_, faces), records = fill_holes((v, f), method=mode)
            res = {"faces": faces.tolist(), "records": [
                {k: (list(map(float.hex, r.weight)) if isinstance(r.weight, tuple) else r.weight)
                 if k == "weight" else val for k, val in r.to_dict().items() if k != "seconds"}
                for r in records]}
        except Exception as exc:
            res = {"error": type(exc).__name__, "message": str(exc)}
        out["meshes"][f"{path.name}/{mode}"] = res

if sys.argv[3] == "time":
    def best(fn, repeat):
        fn()  # warm: compiles or loads the baseline's kernels
        times = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            fn()
            times.append(time.perf_counter() - t0)
        return min(times)

    P, third, _ = polyline("ring3", 400, 1)
    out["times"]["exact n=400 (s)"] = best(lambda: fill_polyline(P, "liepa", "exact", third), 3)
    out["times"]["liepa n=400 (s)"] = best(lambda: fill_polyline(P, "liepa", "liepa", third), 5)
    sphere = read_mesh(root / "src/optri/data/sphere_two_holes.obj")
    v, f = np.asarray(sphere.vertices), np.asarray(sphere.faces)
    out["times"]["fill_holes sphere (s)"] = best(lambda: fill_holes((v, f)), 10)
print(json.dumps(out))
"""

FIRST = r"""
import sys, time
t0 = time.perf_counter()
import numpy as np
from optri import fill_holes
from optri.io.meshes import read_mesh
mesh = read_mesh(sys.argv[1])
v, f = np.asarray(mesh.vertices), np.asarray(mesh.faces)
t1 = time.perf_counter()
fill_holes((v, f))
t2 = time.perf_counter()
print(t2 - t1, t2 - t0, "numba" in sys.modules)
"""


def run_child(src: Path, cache: Path, quick: bool, timed: bool) -> dict:
    env = dict(os.environ, PYTHONPATH=str(src / "src"), NUMBA_CACHE_DIR=str(cache))
    env.pop("NUMBA_DISABLE_JIT", None)
    args = [sys.executable, "-c", CHILD, str(ROOT), "quick" if quick else "full"]
    args.append("time" if timed else "no")
    proc = subprocess.run(args, env=env, capture_output=True, text=True, check=False)
    if proc.returncode != 0:
        raise SystemExit(f"child failed for {src}:\n{proc.stderr[-4000:]}")
    return json.loads(proc.stdout)


def first_call(src: Path, cache: Path) -> tuple[float, float, bool]:
    """(seconds of the first fill_holes call, of the whole script, numba imported)."""
    env = dict(os.environ, PYTHONPATH=str(src / "src"), NUMBA_CACHE_DIR=str(cache))
    sphere = ROOT / "src/optri/data/sphere_two_holes.obj"
    proc = subprocess.run(
        [sys.executable, "-c", FIRST, str(sphere)], env=env, capture_output=True, text=True
    )
    if proc.returncode != 0:
        raise SystemExit(f"first call failed for {src}:\n{proc.stderr[-4000:]}")
    call, script, numba = proc.stdout.split()
    return float(call), float(script), numba == "True"


def differences(old: dict, new: dict) -> list[str]:
    out = []
    for part in ("polylines", "meshes"):
        for key in sorted(set(old[part]) | set(new[part])):
            if old[part].get(key) != new[part].get(key):
                a, b = old[part].get(key), new[part].get(key)
                fields = sorted(k for k in set(a or {}) | set(b or {})
                                if (a or {}).get(k) != (b or {}).get(k))  # fmt: skip
                out.append(f"{part} {key}: differs in {', '.join(fields) or 'presence'}")
    return out


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--base", default="8cfecf8", help="baseline git revision (8cfecf8)")
    p.add_argument("--quick", action="store_true", help="every 9th polyline, meshes in auto only")
    p.add_argument("--no-time", action="store_true", help="compare only, time nothing")
    p.add_argument("--json", help="also write the results to this file")
    p.add_argument("--new", default=str(ROOT), help="the checkout to compare (this one)")
    args = p.parse_args()
    new_root = Path(args.new).resolve()
    with tempfile.TemporaryDirectory(prefix="optri-holes-port-") as tmp:
        base = Path(tmp) / "base"
        subprocess.run(
            ["git", "-C", str(ROOT), "worktree", "add", "--detach", "-q", str(base), args.base],
            check=True,
        )
        try:
            warm = Path(tmp) / "numba-cache"
            t0 = time.perf_counter()
            old = run_child(base, warm, args.quick, not args.no_time)
            t1 = time.perf_counter()
            new = run_child(new_root, warm, args.quick, not args.no_time)
            t2 = time.perf_counter()
            firsts = {}
            if not args.no_time:
                firsts["old"] = first_call(base, Path(tmp) / "numba-empty")
                firsts["new"] = first_call(new_root, Path(tmp) / "numba-empty-2")
        finally:
            subprocess.run(
                ["git", "-C", str(ROOT), "worktree", "remove", "--force", str(base)], check=False
            )
    diff = differences(old, new)
    n_poly, n_mesh = len(new["polylines"]), len(new["meshes"])
    print(f"compared {n_poly} polylines and {n_mesh} mesh fills: {len(diff)} differ")
    print(f"whole run: baseline {t1 - t0:.1f} s, this checkout {t2 - t1:.1f} s")
    for line in diff[:30]:
        print("  " + line)
    rows = {}
    for name in new["times"]:
        a, b = old["times"][name], new["times"][name]
        rows[name] = (a, b)
        print(f"{name:<24} baseline {a:9.4f}  now {b:9.4f}  ratio now/baseline {b / a:6.3f}")
    for who, (call, script, numba) in firsts.items():
        print(f"first fill_holes, fresh process ({who}): call {call:.2f} s, whole script "
              f"{script:.2f} s, numba imported: {numba}")  # fmt: skip
    if args.json:
        Path(args.json).write_text(
            json.dumps({"differences": diff, "times": rows, "first_call": firsts}, indent=1)
        )
    return 1 if diff else 0


if __name__ == "__main__":
    raise SystemExit(main())
