"""The table as a trace leaves it after some steps, and how its cells read.

:class:`Board` replays events one at a time (the animation's frames); the
explorer page does the same in JavaScript from the same events. Labels follow
the paper: vertices v_1 ... v_n (1-based) and its matrix-chain cell names, so
chord (i, j) of a trace (0-based vertices, the sub-polygon v_{i+1} ... v_{j+1})
is the paper's ``w[i+1, j]``, printed in the upper cell (i+1, j) and listed
with its candidate splits in the lower cell (j+1, i+1); a side (i, i+1) is the
diagonal cell ``w[i+1, i+1] = 0``, the product of one matrix.
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass, field
from typing import Any

__all__ = ["Board", "cell_name", "describe", "lower_cell", "upper_cell", "value_text"]


def value_text(v: Any) -> str:
    """A cost as the table prints it: integers plainly, 6 significant digits otherwise.

    >>> value_text(35.0), value_text(2.0 / 3), value_text(math.inf), value_text((1.0, 2.5))
    ('35', '0.666667', '∞', '(1, 2.5)')
    """
    if v is None:
        return ""
    if isinstance(v, tuple):
        return "(" + ", ".join(value_text(x) for x in v) + ")"
    v = float(v)
    if math.isinf(v):
        return "∞" if v > 0 else "−∞"  # -inf: the neutral cost of a side under "max"
    return str(int(v)) if v.is_integer() and abs(v) < 1e15 else f"{v:.6g}"


def cell_name(i: int, j: int) -> str:
    """The paper's name of chord (i, j): ``w[i+1, j]`` (matrix chain A_{i+1} ... A_j).

    >>> cell_name(0, 4), cell_name(1, 2)
    ('w[1,4]', 'w[2,2]')
    """
    return f"w[{i + 1},{j}]"


def describe(event: Any) -> str:
    """One line saying what an event does, in the paper's labels.

    >>> describe(("candidate", 0, 4, 1, 35.0))
    'candidate w[1,4] (v1…v5): split at v2, triangle v1 v2 v5, gives 35'
    """
    kind, i, j, k, value = event
    name = cell_name(i, j)
    if j - i == 1:
        what = {"call": "call", "side": "look-up", "store": "store"}.get(kind, kind)
        return f"{what} {name}: the side v{i + 1} v{j + 1}, no triangle (0)"
    sub = f"{name} (v{i + 1}…v{j + 1})"
    if kind == "call":
        return f"call {sub}"
    if kind == "hit":
        return f"look-up {sub} = {value_text(value)}: answered from the table, no recursion"
    if kind == "candidate":
        return (
            f"candidate {sub}: split at v{k + 1}, triangle v{i + 1} v{k + 1} v{j + 1}, "
            f"gives {value_text(value)}"
        )
    best = "none" if k is None else f"v{k + 1}"
    return f"store {sub} = {value_text(value)}, optimal split {best}"


def upper_cell(i: int, j: int) -> tuple[int, int]:
    """Printed (row, column), 0-based, of chord (i, j)'s weight: the paper's w[i+1, j]."""
    return i, j - 1


def lower_cell(i: int, j: int) -> tuple[int, int]:
    """Printed (row, column), 0-based, of chord (i, j)'s candidate splits."""
    return j, i


@dataclass
class Board:
    """Cells filled, candidates tried and counters after the events applied so far.

    Examples
    --------
    >>> from optri.teaching import trace
    >>> t = trace([5, 1, 5, 1, 5], "product")
    >>> b = Board(t.n)
    >>> for e in t.events:
    ...     b.apply(e)
    >>> b.values[(0, 4)], b.splits[(0, 4)], b.tried[(0, 4)]
    (35, 1, {1: 35, 2: 175, 3: 35})
    """

    n: int
    values: dict[tuple[int, int], Any] = field(default_factory=dict)
    splits: dict[tuple[int, int], int | None] = field(default_factory=dict)
    tried: dict[tuple[int, int], dict[int, Any]] = field(default_factory=dict)
    counts: Counter[str] = field(default_factory=Counter)
    last: Any = None

    def apply(self, event: Any) -> None:
        """Apply one event (kind, i, j, k, value)."""
        kind, i, j, k, value = event
        self.counts[kind] += 1
        self.last = event
        if kind == "candidate":
            self.tried.setdefault((i, j), {})[k] = value
        elif kind == "store":
            self.values[(i, j)], self.splits[(i, j)] = value, k

    def lower_text(self, i: int, j: int) -> str:
        """The lower cell of chord (i, j): candidate splits tried, the best starred."""
        tried = self.tried.get((i, j), {})
        best = self.splits.get((i, j))
        if best is None and tried:
            best = min(tried, key=lambda k: (tried[k], k))
        return ",".join(f"{k + 1}*" if k == best else str(k + 1) for k in sorted(tried))

    def cell_texts(self) -> list[list[str]]:
        """The printed n x n table now: the paper's layout, 1-based labels."""
        n = self.n
        cells = [["" for _ in range(n)] for _ in range(n)]
        for r in range(n):
            cells[r][r] = "0"
            cells[r][n - 1] = cells[r][n - 1] or ("X" if r < n - 1 else "0")
            if r + 1 < n:
                cells[r + 1][r] = f"({r + 2},{r + 1})"
        for (i, j), v in self.values.items():
            r, c = upper_cell(i, j)
            cells[r][c] = value_text(v)
        for i, j in set(self.tried) | set(self.values):
            r, c = lower_cell(i, j)
            cells[r][c] = self.lower_text(i, j)
        return cells
