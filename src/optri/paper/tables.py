"""Tables 2 and 3 of the paper, recomputed by running optri's own code."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import Any, cast

from ..enumeration.builder import regular_polygon
from ..enumeration.counting import catalan
from ..enumeration.hurtado_noy import hn_operation_counts
from ..enumeration.listing import enumerate_triangulations
from ..solve import triangulate
from . import published

__all__ = [
    "GEOMETRIC_PENTAGON",
    "Table2Row",
    "Table3Row",
    "markdown_table",
    "table2",
    "table3",
    "table3_row",
]

#: An irregular convex pentagon for a geometric (perimeter-weight) Table 2.
GEOMETRIC_PENTAGON = ((0.0, 0.0), (4.0, 0.0), (5.0, 3.0), (2.0, 5.0), (-1.0, 3.0))


@dataclass
class Table2Row:
    """One triangulation of a pentagon: 1-based diagonals, weight, optimal or not."""

    index: int
    diagonals: tuple[tuple[int, int], ...]
    weight: float
    optimal: bool


def table2(vertices: Any, weight: str) -> list[Table2Row]:
    """All triangulations of a pentagon in Hurtado–Noy order, the optima marked.

    Examples
    --------
    >>> rows = table2(published.PENTAGON_VALUES, "product")
    >>> [(r.diagonals, r.weight, r.optimal) for r in rows][:2]
    [(((1, 3), (1, 4)), 75.0, False), (((1, 3), (3, 5)), 175.0, False)]
    """
    tris = list(enumerate_triangulations(vertices, weight=weight))
    weights = [cast(float, t.weight) for t in tris]  # a scalar objective
    best = min(weights)
    return [
        Table2Row(
            i + 1,
            tuple((a + 1, b + 1) for a, b in t.diagonals.tolist()),
            w,
            bool(abs(w - best) <= 1e-9 * max(1.0, abs(best))),
        )
        for i, (t, w) in enumerate(zip(tris, weights))
    ]


@dataclass
class Table3Row:
    """Measured operation counts at one n beside the paper's formulas and print."""

    n: int
    triangulations: int
    hn_operations: int
    hn_weight_evaluations: int
    hn_scratch_evaluations: int
    sm_weight_evaluations: int
    mm_weight_evaluations: int
    mm_cells: int
    mm_lookups: int

    @property
    def eq5(self) -> int:
        """Eq. 5 at n."""
        return published.eq5(self.n)

    @property
    def eq5_shifted(self) -> int | None:
        """Eq. 5 at n - 2: what the paper prints in its HN column."""
        return published.eq5(self.n - 2) if self.n >= 5 else None

    @property
    def eq6(self) -> int:
        """Eq. 6 at n (= C(n, 3))."""
        return published.eq6(self.n)

    @property
    def eq7(self) -> int:
        """Eq. 7 at n (= number of table cells)."""
        return published.eq7(self.n)

    @property
    def printed(self) -> tuple[Any, ...] | None:
        """The paper's Table 3 row (n = 7..14), or None."""
        return published.TABLE3.get(self.n)


def table3_row(n: int) -> Table3Row:
    """Instrument the three methods on a convex n-gon and collect their counts."""
    poly = regular_polygon(n)
    hn = hn_operation_counts(n)
    sm = triangulate(poly, "perimeter", method="table").stats
    mm = triangulate(poly, "perimeter", method="memo").stats
    return Table3Row(
        n=n,
        triangulations=catalan(n - 2),
        hn_operations=hn.operations,
        hn_weight_evaluations=hn.weight_evaluations,
        hn_scratch_evaluations=hn.scratch_evaluations,
        sm_weight_evaluations=sm["weight_evaluations"],
        mm_weight_evaluations=mm["weight_evaluations"],
        mm_cells=mm["cells"],
        mm_lookups=mm["lookups"],
    )


def table3(ns: Iterable[int], progress: Callable[[], None] | None = None) -> list[Table3Row]:
    """:func:`table3_row` for each n, calling ``progress()`` after each."""
    rows = []
    for n in ns:
        rows.append(table3_row(n))
        if progress is not None:
            progress()
    return rows


def markdown_table(headers: Sequence[str], rows: Iterable[Sequence[Any]]) -> str:
    """A GitHub-flavoured markdown table; floats to 4 significant digits.

    >>> print(markdown_table(["n", "x"], [[5, 0.5]]))
    | n | x |
    |---:|---:|
    | 5 | 0.5 |
    """
    out = ["| " + " | ".join(headers) + " |", "|" + "|".join("---:" for _ in headers) + "|"]
    for row in rows:
        out.append("| " + " | ".join(_cell(v) for v in row) + " |")
    return "\n".join(out)


def _cell(v: Any) -> str:
    if v is None:
        return "–"
    if isinstance(v, float):
        return f"{v:.4g}"
    return str(v)
