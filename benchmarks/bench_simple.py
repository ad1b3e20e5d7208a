"""Simple polygons: optri's exact optimum against ear clipping and constrained Delaunay.

For random star polygons (n = 16, 40, 100), random 2-opt simple polygons and
comb polygons, triangulate with optri (exact minimum perimeter sum), with
mapbox-earcut and with shapely's constrained Delaunay triangulation, and report
how far above the optimum each heuristic lands (perimeter sum of all
triangles) and the time each took. Then time the valid-diagonal mask and the
simplicity check at n = 2000, and, where the compiled engine exists, the
n = 2000 star polygon against a convex polygon of the same n.

Writes ``simple.csv``, ``simple.md`` and ``simple.png`` to ``--out``
(default ``benchmarks/out``).

    python benchmarks/bench_simple.py [--seeds 5] [--out DIR]
"""

from __future__ import annotations

import argparse
import csv
import statistics
import time
from pathlib import Path

import numpy as np

import optri
from optri import require_simple, valid_diagonals
from optri.errors import EngineUnavailableError
from optri.polygon import as_polygon


def star(n: int, rng: np.random.Generator) -> np.ndarray:
    ang = np.sort(rng.uniform(0, 2 * np.pi, n))
    r = rng.uniform(0.3, 1.0, n)
    return np.column_stack((r * np.cos(ang), r * np.sin(ang)))


def comb(teeth: int, rng: np.random.Generator) -> np.ndarray:
    """A comb: a base bar with ``teeth`` jittered teeth pointing up (4 * teeth + 3 vertices)."""
    top = []
    for t in range(teeth):
        x0 = t * 2.0
        h = 3 + rng.uniform(0, 2)
        top += [(x0 + 1.0, 1.0), (x0 + 1.2, h), (x0 + 1.8, h + rng.uniform(-0.5, 0.5))]
        top += [(x0 + 2.0, 1.0)]
    return np.array([(0.0, 0.0), (teeth * 2.0 + 1, 0.0), *top[::-1], (0.0, 1.0)])[::-1]


def two_opt(n: int, rng: np.random.Generator) -> np.ndarray:
    """Random points joined in random order, untangled by 2-opt moves."""
    pts = rng.uniform(0, 1, (n, 2))
    ring = list(rng.permutation(n))

    def crosses(p, q, r, s):
        def o(a, b, c):
            return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])

        return o(p, q, r) * o(p, q, s) < 0 and o(r, s, p) * o(r, s, q) < 0

    changed = True
    while changed:
        changed = False
        for e in range(n):
            for f in range(e + 2, n - (e == 0)):
                a, b = pts[ring[e]], pts[ring[e + 1]]
                c, d = pts[ring[f]], pts[ring[(f + 1) % n]]
                if crosses(a, b, c, d):
                    ring[e + 1 : f + 1] = ring[e + 1 : f + 1][::-1]
                    changed = True
    return pts[ring]


def perimeter_sum(pts: np.ndarray, tris: np.ndarray) -> float:
    a, b, c = pts[tris[:, 0]], pts[tris[:, 1]], pts[tris[:, 2]]
    return float((np.hypot(*(a - b).T) + np.hypot(*(b - c).T) + np.hypot(*(c - a).T)).sum())


def timed(fn, *args, repeat: int = 3, **kwargs):
    best, out = float("inf"), None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn(*args, **kwargs)
        best = min(best, time.perf_counter() - t0)
    return out, best


def run_earcut(pts: np.ndarray) -> np.ndarray:
    import mapbox_earcut as earcut

    idx = earcut.triangulate_float64(pts, np.array([len(pts)], dtype=np.uint32))
    return np.asarray(idx, dtype=np.int64).reshape(-1, 3)


def check_cover(pts: np.ndarray, tris: np.ndarray) -> None:
    """Sanity: n - 2 triangles whose unsigned areas add up to the polygon's area."""
    a, b, c = pts[tris[:, 0]], pts[tris[:, 1]], pts[tris[:, 2]]
    u, v = b - a, c - a
    areas = 0.5 * np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
    x, y = pts[:, 0], pts[:, 1]
    total = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))
    assert len(tris) == len(pts) - 2 and np.isclose(areas.sum(), total), "bad triangulation"


def run_cdt(pts: np.ndarray) -> float:
    import shapely

    tris = shapely.constrained_delaunay_triangles(shapely.Polygon(pts))
    total = 0.0
    for g in tris.geoms:
        ring = np.asarray(g.exterior.coords)[:3]
        total += perimeter_sum(ring, np.array([[0, 1, 2]]))
    return total


def compare(families, seeds: int) -> list[dict]:
    rows = []
    for family, _n, make in families:
        for seed in range(seeds):
            pts = make(np.random.default_rng(seed))
            tri, t_opt = timed(optri.triangulate, pts, method="auto", repeat=1)
            tri.check()
            opt = float(tri.weight)
            ear_tris, t_ear = timed(run_earcut, pts)
            check_cover(pts, ear_tris)
            cdt, t_cdt = timed(run_cdt, pts)
            for method, w, sec in (
                ("optri", opt, t_opt),
                ("earcut", perimeter_sum(pts, ear_tris), t_ear),
                ("shapely CDT", cdt, t_cdt),
            ):
                rows.append(
                    dict(family=family, n=len(pts), seed=seed, method=method, weight=w,
                         above_pct=100 * (w / opt - 1), seconds=sec, engine=tri.method)
                )  # fmt: skip
    return rows


def summarize(rows: list[dict]) -> list[dict]:
    out = []
    rank = {"optri": 0, "earcut": 1, "shapely CDT": 2}
    keys = sorted(
        {(r["family"], r["n"], r["method"]) for r in rows}, key=lambda k: (k[0], k[1], rank[k[2]])
    )
    for family, n, method in keys:
        sel = [r for r in rows if (r["family"], r["n"], r["method"]) == (family, n, method)]
        out.append(
            dict(family=family, n=n, method=method, runs=len(sel),
                 mean_above_pct=statistics.mean(r["above_pct"] for r in sel),
                 max_above_pct=max(r["above_pct"] for r in sel),
                 median_ms=1000 * statistics.median(r["seconds"] for r in sel))
        )  # fmt: skip
    return out


def big_n(n: int = 2000) -> list[str]:
    lines = []
    pts = star(n, np.random.default_rng(0))
    poly = as_polygon(pts)
    valid_diagonals(poly)  # compile / load the kernel once
    _, t_simple = timed(require_simple, poly)
    mask, t_mask = timed(valid_diagonals, poly)
    lines.append(
        f"n = {n} random star: simplicity check {t_simple * 1000:.0f} ms, valid-diagonal "
        f"mask (the check included) {t_mask * 1000:.0f} ms ({int(mask.sum() - 2 * n) // 2} "
        f"diagonals of {n * (n - 3) // 2} chords)"
    )
    a = np.linspace(0, 2 * np.pi, n, endpoint=False)
    convex = np.column_stack((np.cos(a), np.sin(a)))
    notch = convex.copy()
    notch[0] *= 0.5
    _, t_notch = timed(valid_diagonals, notch)
    lines.append(f"n = {n} circle with one reflex vertex: mask {t_notch * 1000:.0f} ms")
    try:
        _, t_star = timed(optri.triangulate, pts, method="fast", repeat=2)
        _, t_conv = timed(optri.triangulate, convex, method="fast", repeat=2)
    except EngineUnavailableError as exc:
        lines.append(f"compiled engine not available here ({exc}); end-to-end ratio not measured")
    else:
        lines.append(
            f"n = {n} method='fast': star {t_star:.3f} s, convex {t_conv:.3f} s, "
            f"ratio {t_star / t_conv:.2f}"
        )
    return lines


def write_outputs(out: Path, rows, summary, notes) -> None:
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "simple.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    md = ["| polygons | n | method | runs | mean % above optimum | max % | median ms |",
          "|---|---:|---|---:|---:|---:|---:|"]  # fmt: skip
    for s in summary:
        md.append(
            f"| {s['family']} | {s['n']} | {s['method']} | {s['runs']} | "
            f"{s['mean_above_pct']:.2f} | {s['max_above_pct']:.2f} | {s['median_ms']:.2f} |"
        )
    md += ["", *[f"- {line}" for line in notes], ""]
    (out / "simple.md").write_text("\n".join(md))
    plot(out / "simple.png", summary)


def plot(path: Path, summary) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    groups = [(s["family"], s["n"]) for s in summary if s["method"] == "optri"]
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4))
    x = np.arange(len(groups))
    for off, method in ((-0.2, "earcut"), (0.2, "shapely CDT")):
        mean = {
            (s["family"], s["n"]): s["mean_above_pct"] for s in summary if s["method"] == method
        }
        vals = [mean[g] for g in groups]
        ax.bar(x + off, vals, width=0.4, label=method)
    ax.set_xticks(x, [f"{f}\nn={n}" for f, n in groups], fontsize=8)
    ax.set_ylabel("mean % above optimal perimeter sum")
    ax.set_title("Heuristics vs optri's exact optimum")
    ax.legend()
    pts = star(40, np.random.default_rng(0))
    tri = optri.triangulate(pts, method="auto")
    ear = run_earcut(pts)
    for tris, color, label in ((ear, "tab:orange", "earcut"), (tri.triangles, "k", "optri")):
        for t in tris:
            ring = pts[np.append(t, t[0])]
            ax2.plot(ring[:, 0], ring[:, 1], color=color, lw=0.7 if color == "k" else 1.8)
        ax2.plot([], [], color=color, label=label)
    ax2.set_aspect("equal")
    ax2.set_axis_off()
    ax2.legend(loc="upper right", fontsize=8)
    ax2.set_title("star n=40: optimal (black) vs earcut (orange)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--out", default=str(Path(__file__).resolve().parent / "out"))
    ap.add_argument("--big-n", type=int, default=2000)
    args = ap.parse_args()
    families = [
        ("star", 16, lambda r: star(16, r)),
        ("star", 40, lambda r: star(40, r)),
        ("star", 100, lambda r: star(100, r)),
        ("2-opt", 40, lambda r: two_opt(40, r)),
        ("comb", 43, lambda r: comb(10, r)),
    ]
    optri.triangulate(star(8, np.random.default_rng(0)))  # load the compiled mask kernel once
    rows = compare(families, args.seeds)
    summary = summarize(rows)
    notes = big_n(args.big_n)
    write_outputs(Path(args.out), rows, summary, notes)
    print((Path(args.out) / "simple.md").read_text())


if __name__ == "__main__":
    main()
