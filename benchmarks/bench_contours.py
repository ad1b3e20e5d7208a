"""Contour tiling: time per pair against m·n, a 100-slice stack, and the closest-point start.

Three parts, all in one run:

1. ``tile_contours`` on pairs of m = n = 50 ... 1600 vertices: seconds per pair, and
   seconds / (m n log2 n), which stays flat if the divide and conquer is O(m n log n);
   beside it the same pair with the first span fixed at the closest pair of vertices
   (one shortest path, O(m n): the rule of SlicerRT's and MeshLib's stitching), timed
   here as the baseline.
2. ``contours_to_mesh`` on a stack of 100 slices x 200 points (a twisting, swelling
   blob): total seconds, seconds per pair of slices, closed and manifold.
3. Optimal against closest-point start on the same pairs (the stack's 99 and 300
   random pairs of star-shaped contours, offset and rotated): the optimum's cost is
   never higher (counted), how often it is strictly lower, and by how much.

    python benchmarks/bench_contours.py
    python benchmarks/bench_contours.py --sizes 50 100 200 --pairs 100
"""

from __future__ import annotations

import argparse
import math
import statistics
import time

import numpy as np

import optri


def blob(k: int, z: float, twist: float, swell: float, rng: np.random.Generator) -> np.ndarray:
    """A smooth star-shaped contour of k vertices on plane z."""
    t = np.linspace(0, 2 * np.pi, k, endpoint=False) + twist
    r = swell * (1 + 0.25 * np.cos(3 * t + twist) + 0.1 * np.sin(5 * t)) + 0.01 * rng.random(k)
    return np.c_[r * np.cos(t), 0.7 * r * np.sin(t), np.full(k, z)]


def star(k: int, rng: np.random.Generator, z: float) -> np.ndarray:
    """A random star-shaped contour: sorted jittered angles, random radii."""
    t = np.sort(rng.uniform(0, 2 * np.pi, k))
    r = rng.uniform(0.5, 1.5, k)
    off = rng.normal(scale=0.4, size=2)
    return np.c_[off[0] + r * np.cos(t), off[1] + r * np.sin(t), np.full(k, z)]


def best_of(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def part_sizes(sizes: list[int], rng: np.random.Generator) -> None:
    print("1. one pair, m = n, area sum: seconds per pair")
    print(
        f"{'m=n':>6} {'m*n':>9} {'optimal s':>11} {'closest s':>11} {'ratio':>6} "
        f"{'opt/(mn log2 n) ns':>19}"
    )
    for n in sizes:
        a, b = blob(n, 0.0, 0.0, 1.0, rng), blob(n, 1.0, 0.4, 1.1, rng)
        repeat = 5 if n <= 400 else 2
        best = best_of(lambda a=a, b=b: optri.tile_contours(a, b), repeat)
        closest = best_of(lambda a=a, b=b: optri.tile_contours(a, b, start="closest"), repeat)
        per = best / (n * n * math.log2(n)) * 1e9
        print(f"{n:6d} {n * n:9d} {best:11.5f} {closest:11.5f} {best / closest:6.2f} {per:19.2f}")


def part_stack(slices: int, points: int, rng: np.random.Generator) -> list[tuple]:
    stack = [
        blob(points, 3.0 * s, 0.02 * s, 1.0 + 0.4 * math.sin(s / 15), rng) for s in range(slices)
    ]
    optri.contours_to_mesh(stack[:3])  # load the caps' engine once, outside the timing
    t0 = time.perf_counter()
    mesh = optri.contours_to_mesh(stack)
    total = time.perf_counter() - t0
    mesh.check()
    print(
        f"\n2. stack of {slices} slices x {points} points: {total:.3f} s in all, "
        f"{total / (slices - 1) * 1e3:.2f} ms per pair of slices; {len(mesh.faces)} faces, "
        f"closed and manifold, volume {mesh.volume:.6g}"
    )
    return [(stack[s], stack[s + 1]) for s in range(slices - 1)]


def part_closest(pairs: list[tuple], label: str) -> None:
    for weight in ("area", "span", "span_squared"):
        higher = lower = 0
        gains = []
        for a, b in pairs:
            best = optri.tile_contours(a, b, weight).weight
            fixed = optri.tile_contours(a, b, weight, start="closest").weight
            if best > fixed * (1 + 1e-12):
                higher += 1
            if best < fixed * (1 - 1e-12):
                lower += 1
                gains.append((fixed - best) / fixed)
        gain = "no gain"
        if gains:
            gain = (
                f"mean gain where lower {100 * statistics.mean(gains):.3f} %, "
                f"max {100 * max(gains):.3f} %"
            )
        print(
            f"   {label}, {weight:12s}: optimum higher on {higher}, lower on {lower} of "
            f"{len(pairs)}; {gain}"
        )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[50, 100, 200, 400, 800, 1600])
    ap.add_argument("--slices", type=int, default=100)
    ap.add_argument("--points", type=int, default=200)
    ap.add_argument("--pairs", type=int, default=300)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    part_sizes(args.sizes, rng)
    stack_pairs = part_stack(args.slices, args.points, rng)
    print("\n3. optimal start against the closest-point start, same pairs")
    part_closest(stack_pairs, f"stack's {len(stack_pairs)} pairs")
    random_pairs = [
        (star(int(rng.integers(8, 60)), rng, 0.0), star(int(rng.integers(8, 60)), rng, 1.0))
        for _ in range(args.pairs)
    ]
    part_closest(random_pairs, f"{args.pairs} random pairs")


if __name__ == "__main__":
    main()
