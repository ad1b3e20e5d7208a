"""The paper's Figures 2 and 3 as drawings: the cell scheme and the recursion tree."""

from __future__ import annotations

from typing import Any

from ..drawing.figures import new_axes
from ..errors import OptriError
from .board import value_text
from .tree import Node, layout, recursion_tree

__all__ = ["cell_scheme", "plot_cell_scheme", "plot_recursion_tree"]

_FILL = {
    "upper": "#fff4d6",
    "lower": "#e3efff",
    "diagonal": "#eeeeee",
    "unused": "#f4f4f4",
    "optimum": "#ffd08a",
    "dots": "#ffffff",
}


def cell_scheme(n: int | None = None) -> list[list[tuple[str, str]]]:
    """The labels of Figure 2: ``(text, part)`` per cell, rows and columns 1 ... n.

    Without ``n``, the general scheme (rows and columns 1, 2, 3, ..., n-2, n-1,
    n); with ``n``, the labels of that table. ``part`` is ``"upper"``
    (``w[i, j]``), ``"lower"`` (``|v_i v_j|``), ``"diagonal"``, ``"unused"``
    (column n, X), ``"optimum"`` (``Opt w``) or ``"dots"``.

    >>> [text for text, _ in cell_scheme(4)[0]]
    ['0', 'w[1,2]', 'Opt w', 'X']
    >>> [text for text, _ in cell_scheme(4)[3]]
    ['|v4v1|', '|v4v2|', '|v4v3|', '0']
    """
    if n is not None and n < 3:
        raise OptriError(f"a polygon has at least 3 vertices, got n = {n}")
    if n is None:
        names: list[str | None] = ["1", "2", "3", None, "n-2", "n-1", "n"]
        last = "n"
    else:
        names = [str(i) for i in range(1, n + 1)]
        last = str(n)
    rows = []
    for r, a in enumerate(names):
        row = []
        for c, b in enumerate(names):
            if a is None or b is None:
                row.append(("⋱" if r == c else "⋮" if a is None else "⋯", "dots"))
            elif r == c:
                row.append(("0", "diagonal"))
            elif b == last:
                row.append(("X", "unused"))
            elif r < c:
                optimum = r == 0 and c == len(names) - 2
                row.append(("Opt w", "optimum") if optimum else (f"w[{a},{b}]", "upper"))
            else:
                row.append((f"|v{a}v{b}|", "lower"))
        rows.append(row)
    return rows


def plot_cell_scheme(n: int | None = None, ax: Any = None) -> Any:
    """Draw Figure 2, the labelling of the n x n table's cells; returns the Axes.

    Above the diagonal ``w[i, j]``, the optimal weight of the sub-polygon
    v_i ... v_{j+1} (the paper's matrix-chain indices), ``Opt w = w[1, n-1]``
    the optimum; below it ``|v_i v_j|``, the chord whose candidate splits the
    cell lists; column n unused (X).
    """
    cells = cell_scheme(n)
    size = len(cells)
    ax = new_axes(ax, figsize=(1.2 + 1.05 * size, 1.0 + 0.62 * size))
    from matplotlib.patches import Rectangle

    head = ["1", "2", "3", "⋯", "n-2", "n-1", "n"] if n is None else [str(i + 1) for i in range(n)]
    for r, row in enumerate(cells):
        for c, (text, part) in enumerate(row):
            ax.add_patch(Rectangle((c, r), 1, 1, facecolor=_FILL[part], edgecolor="#999999"))
            ax.text(c + 0.5, r + 0.5, text, ha="center", va="center", fontsize=9)
        ax.text(-0.3, r + 0.5, head[r].replace("⋯", "⋮"), ha="center", va="center", weight="bold")
        ax.text(r + 0.5, -0.3, head[r], ha="center", va="center", weight="bold")
    ax.text(-0.3, -0.3, "i \\ j", ha="center", va="center", fontsize=8, style="italic")
    ax.set_xlim(-0.8, size + 0.05)
    ax.set_ylim(size + 0.05, -0.8)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title(
        "Figure 2: labelling of the table's cells: w[i, j] (weights) above the diagonal,\n"
        "|v_i v_j| (chords, with their candidate splits) below, Opt w the optimum, X unused",
        fontsize=9,
    )
    return ax


def plot_recursion_tree(source: Any, ax: Any = None, *, title: str | None = None) -> Any:
    """Draw Figure 3, the recursion tree of a memo (or naive) trace; returns the Axes.

    ``source`` is a :class:`~optri.teaching.Trace` or the root
    :class:`~optri.teaching.tree.Node`. Nodes carry the matrix-chain label of
    their chord as in the paper's Figure 3 (chord (i, j) is the product
    A_{i+1} ... A_j, written ``i+1..j``) and the value returned; calls answered
    from the table are grey pruned leaves, sides (single matrices) dotted.
    """
    root = source if isinstance(source, Node) else recursion_tree(source.events)
    pos = layout(root)
    width = max(x for x, _ in pos.values()) + 1
    depth = max(d for _, d in pos.values()) + 1
    ax = new_axes(ax, figsize=(max(6.0, 0.62 * width), 1.1 + 1.05 * depth))
    nodes = list(root.walk())
    for node in nodes:
        x, d = pos[id(node)]
        for child in node.children:
            cx, cd = pos[id(child)]
            ax.plot([x, cx], [d, cd], color="#777777", lw=0.8, zorder=1)
    style = {
        "computed": {"fc": "white", "ec": "black", "ls": "-"},
        "hit": {"fc": "#c8c8c8", "ec": "#555555", "ls": "-"},
        "side": {"fc": "#f7f7f7", "ec": "#999999", "ls": ":"},
    }
    for node in nodes:
        x, d = pos[id(node)]
        label = f"{node.i + 1}..{node.j}"
        if node.status != "side":
            label += f"\n{value_text(node.value)}"
        s = style[node.status]
        ax.text(
            x,
            d,
            label,
            ha="center",
            va="center",
            fontsize=7,
            zorder=2,
            bbox={"boxstyle": "round,pad=0.25", "fc": s["fc"], "ec": s["ec"], "ls": s["ls"]},
        )
    hits = sum(n.status == "hit" for n in nodes)
    sides = sum(n.status == "side" for n in nodes)
    ax.set_xlim(-0.7, width - 0.3)
    ax.set_ylim(depth - 0.4, -0.6)
    ax.axis("off")
    if title is None and hits:
        title = (
            f"Figure 3: recursion tree with memoization, {len(nodes)} calls: {hits} answered "
            f"from the table (grey, pruned), {sides} sides (dotted); i..j = A_i ... A_j"
        )
    elif title is None:
        title = (
            f"The recursion without memoization: {len(nodes)} calls, every sub-polygon "
            f"computed again, {sides} sides (dotted); i..j = A_i ... A_j"
        )
    ax.set_title(title, fontsize=9)
    return ax
