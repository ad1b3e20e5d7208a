"""Table 4 and Figures 5–7: square matrix vs memoization, timed on this machine.

(A) filling the table: the engine's own time (``Triangulation.seconds``) for
``method="table"`` (the square-matrix method) and ``method="memo"`` (the
paper's memoization). (B) total: solving plus drawing the optimal
triangulation with matplotlib (Agg) and rendering it to an in-memory PNG.
Each figure is the median of ``repeats`` runs on the same convex polygon.
"""

from __future__ import annotations

import io
import statistics
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass

import numpy as np

from ..drawing.figures import new_axes, plot_triangulation
from ..enumeration.counting import catalan
from ..solve import triangulate

__all__ = ["TimingRow", "convex_polygon", "time_methods", "timing_table"]

METHODS = {"square": "table", "memo": "memo"}


@dataclass
class TimingRow:
    """Median seconds at one n; ratios are square-matrix / memoization."""

    n: int
    square_a: float
    square_b: float
    memo_a: float
    memo_b: float
    repeats: int
    #: Lowest and highest square/memo ratio of (B) over the alternating run pairs.
    ratio_b_range: tuple[float, float] | None = None

    @property
    def triangulations(self) -> int:
        """C(n - 2), the paper's T column."""
        return catalan(self.n - 2)

    @property
    def ratio_a(self) -> float:
        """R(A) = MwtS(A) / MwtM(A)."""
        return self.square_a / self.memo_a

    @property
    def ratio_b(self) -> float:
        """R(B) = MwtS(B) / MwtM(B)."""
        return self.square_b / self.memo_b

    @property
    def b_is_noise(self) -> bool | None:
        """Whether R(B) is noise: the run pairs disagree on which method is faster.

        Each pair runs both methods back to back; when some pairs find the square
        matrix faster and others memoization (their ratios span 1), the median
        ratio says nothing about the methods. None with fewer than two pairs.

        >>> TimingRow(9, 1e-4, 0.10, 5e-5, 0.09, 5, (0.93, 1.2)).b_is_noise
        True
        """
        if self.ratio_b_range is None or self.repeats < 2:
            return None
        low, high = self.ratio_b_range
        return low <= 1.0 <= high


def convex_polygon(n: int, seed: int = 0) -> np.ndarray:
    """A random convex polygon: n points at sorted random angles on an ellipse."""
    rng = np.random.default_rng(seed + n)
    ang = np.sort(rng.uniform(0.0, 2 * np.pi, n))
    ang += np.linspace(0.0, 1e-3, n)  # keeps angles distinct (a strictly convex polygon)
    return np.column_stack((3.0 * np.cos(ang), 2.0 * np.sin(ang)))


def _run(vertices: np.ndarray, method: str) -> tuple[float, float]:
    """(A, B) seconds of one solve-and-draw."""
    import matplotlib.pyplot as plt

    start = time.perf_counter()
    tri = triangulate(vertices, "perimeter", method=method)
    ax = plot_triangulation(tri, labels=tri.n <= 60)
    buf = io.BytesIO()
    ax.figure.savefig(buf, format="png", dpi=80)
    plt.close(ax.figure)
    return tri.seconds, time.perf_counter() - start


#: Extra solve-only runs for (A) at small n, where one run takes microseconds.
A_REPEATS_SMALL = 31


def time_methods(n: int, repeats: int = 5) -> TimingRow:
    """Median (A) and (B) of both methods at n; runs alternate to share drift.

    (B) takes ``repeats`` solve-and-draw runs; (A) adds solve-only runs up to
    ``A_REPEATS_SMALL`` for n <= 30.
    """
    new_axes(None)  # select the Agg backend once (headless)
    import matplotlib.pyplot as plt

    plt.close("all")
    poly = convex_polygon(n)
    runs: dict[str, list[tuple[float, float | None]]] = {k: [] for k in METHODS}
    for _ in range(repeats):
        for key, method in METHODS.items():
            runs[key].append(_run(poly, method))
    for _ in range(max(0, (A_REPEATS_SMALL if n <= 30 else 0) - repeats)):
        for key, method in METHODS.items():
            runs[key].append((triangulate(poly, "perimeter", method=method).seconds, None))
    med = {
        k: (statistics.median(a for a, _ in v), statistics.median(b for _, b in v if b is not None))
        for k, v in runs.items()
    }
    pairs = [
        s / m
        for (_, s), (_, m) in zip(runs["square"][:repeats], runs["memo"][:repeats])
        if s is not None and m
    ]
    spread = (min(pairs), max(pairs)) if pairs else None
    return TimingRow(n, *med["square"], *med["memo"], repeats, spread)


def timing_table(
    ns: Iterable[int],
    repeats: Callable[[int], int] | int = 5,
    progress: Callable[[], None] | None = None,
) -> list[TimingRow]:
    """:func:`time_methods` for each n (``repeats`` may depend on n)."""
    rows = []
    for n in ns:
        r = repeats(n) if callable(repeats) else repeats
        rows.append(time_methods(n, r))
        if progress is not None:
            progress()
    return rows
