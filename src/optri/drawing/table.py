"""Print the n x n table the way the paper's Table 1 does, or plainly.

The paper (Section 3, Table 1) keeps optimal sub-polygon weights above the
diagonal and, below it, the candidate split vertices of each chord ("2,3,4")
or the adjacent pair ("(2,1)") for a polygon side, with 1-based vertex labels.
Its upper part uses matrix-chain indices: cell (r, c) holds the weight of
sub-polygon v_r .. v_{c+1}, so the last column is unused ("X"), while its
lower part uses vertex labels directly: cell (r, c) is chord v_c v_r. The two
halves are therefore *not* transposes of each other (cell (1, 4) = 35 pairs with
cell (5, 1) = "2,3,4"); ``style="paper"`` reproduces that layout faithfully,
``style="vertex"`` gives the consistent one (cell (i, j) and (j, i) describe
the same chord). ``base`` numbers the labels: 1 as in the paper, 0 as optri's
API (``Triangulation.diagonals`` and ``triangles``, ``optri.trace``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..errors import OptriError

if TYPE_CHECKING:  # pragma: no cover
    from ..result import Triangulation

__all__ = ["format_table", "table_cells"]


def table_cells(
    tri: Triangulation, style: str = "paper", base: int = 1
) -> tuple[list[list[str]], list[tuple[int, int]]]:
    """Cell texts of the table and the cells to highlight (the optimal chords).

    In ``"paper"`` style the optimal split in each candidate list carries a
    ``*``; in ``"vertex"`` style the lower cells hold the split vertex. Vertex
    numbers in the texts start at ``base`` (1: the paper's labels, 0: the API's).
    The highlighted cells are 0-based (row, column) positions either way.
    """
    if base not in (0, 1):
        raise OptriError(f"base must be 0 or 1, got {base!r}")
    if tri.table is None:
        raise OptriError(
            "this result kept no table; solve with method='memo' or 'table' (or keep_table=True)"
        )
    t = tri.table
    n = t.shape[0]
    chords = {(int(a), int(b)) for a, b in _internal_diagonals(tri)} | {(0, n - 1)}
    if style == "vertex":
        cells = [
            [
                _num(t[r, c]) if r <= c else (_split(t[r, c], base) if c < r - 1 else "-")
                for c in range(n)
            ]
            for r in range(n)
        ]
        marks: list[tuple[int, int]] = [(i, j) for i, j in chords] + [(j, i) for i, j in chords]
        return cells, marks
    if style != "paper":
        raise OptriError(f"unknown table style {style!r}; use 'paper' or 'vertex'")
    cells = [["" for _ in range(n)] for _ in range(n)]
    marks = []
    for r in range(n):  # 0-based row/col of the printed table
        for c in range(n):
            if r == c:
                cells[r][c] = "0"
            elif r < c:
                # matrix-chain indices: printed (r+1, c+1) -> sub-polygon v_r .. v_{c+1}
                cells[r][c] = "X" if c == n - 1 else _num(t[r, c + 1])
                if (r, c + 1) in chords:
                    marks.append((r, c))
            elif r == c + 1:
                cells[r][c] = f"({r + base},{c + base})"
            else:
                best = int(t[r, c])
                cells[r][c] = ",".join(
                    f"{k + base}*" if k == best else str(k + base) for k in range(c + 1, r)
                )
                if (c, r) in chords:
                    marks.append((r, c))
    return cells, marks


def format_table(tri: Triangulation, style: str = "paper", base: int | None = None) -> str:
    """The table as aligned text.

    ``base`` numbers rows, columns and the vertices in the cells: 1 (the paper's
    labels; the default for ``style="paper"``) or 0 (the API's; the default for
    ``style="vertex"``). ``optri solve --table`` prints 0-based, like the
    diagonals and triangles above it, and 1-based with ``--one-based``.

    Examples
    --------
    >>> import optri
    >>> t = optri.triangulate([5, 1, 5, 1, 5], weight="product", method="memo")
    >>> print(optri.format_table(t))
        1      2      3      4      5
    1   0      25     10     35     X
    2 (2,1)    0      5      10     X
    3   2*   (3,2)    0      25     X
    4  2*,3    3*   (4,3)    0      X
    5 2*,3,4  3,4*    4*   (5,4)    0
    >>> print(optri.format_table(t, base=0).splitlines()[-1])
    4 1*,2,3  2,3*    3*   (4,3)    0
    """
    if base is None:
        base = 1 if style == "paper" else 0
    cells, _ = table_cells(tri, style, base)
    n = len(cells)
    labels = [str(i + base) for i in range(n)]
    width = max(max(len(s) for row in cells for s in row), max(len(s) for s in labels))
    head = " " * len(labels[-1]) + " " + " ".join(s.center(width) for s in labels)
    lines = [head.rstrip()]
    for lab, row in zip(labels, cells):
        lines.append(
            (lab.ljust(len(labels[-1])) + " " + " ".join(s.center(width) for s in row)).rstrip()
        )
    return "\n".join(lines)


def _split(v: float, base: int = 0) -> str:
    # a chord without a usable split (unreachable in a simple polygon) has none to show
    return str(int(v) + base) if v >= 0 else "–"


def _num(v: float) -> str:
    if not np.isfinite(v):
        return "inf"
    return str(int(v)) if float(v).is_integer() and abs(v) < 1e15 else f"{v:.6g}"


def _internal_diagonals(tri: Triangulation) -> list[tuple[int, int]]:
    order = tri.order if tri.order is not None else np.arange(tri.n)
    inverse = np.empty_like(order)
    inverse[order] = np.arange(len(order))
    out = []
    for a, b in tri.diagonals.tolist():
        i, j = sorted((int(inverse[a]), int(inverse[b])))
        out.append((i, j))
    return out
