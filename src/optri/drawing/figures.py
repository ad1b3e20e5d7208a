"""Matplotlib drawings of triangulations and of the paper's table.

matplotlib is imported inside the functions, so ``import optri`` stays light.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .._optional import import_optional
from ..io.atomic import atomic_write
from .svg import drawing_points
from .table import table_cells

if TYPE_CHECKING:  # pragma: no cover
    from ..result import Triangulation

__all__ = ["new_axes", "plot_table", "plot_triangulation", "save_figure"]


def new_axes(ax: Any = None, figsize: tuple[float, float] = (6, 6)) -> Any:
    """``ax``, or the Axes of a new figure (Agg backend unless one is set up)."""
    if ax is not None:
        return ax
    import_optional("matplotlib")
    import matplotlib

    if matplotlib.get_backend().lower() not in ("agg", "module://matplotlib_inline.backend_inline"):
        matplotlib.use("Agg")  # headless by default; callers may pass their own ax
    import matplotlib.pyplot as plt

    _, ax = plt.subplots(figsize=figsize)
    return ax


def plot_triangulation(
    tri: Triangulation, ax: Any = None, *, labels: bool = True, title: str | None = None
) -> Any:
    """Draw polygon sides, optimal diagonals and vertex labels; return the Axes.

    3-D input is drawn from its first two coordinates; value input on a circle.
    """
    ax = new_axes(ax)
    pts = drawing_points(tri.vertices)
    n = tri.n
    tris = tri.triangles
    ax.tripcolor(
        pts[:, 0],
        pts[:, 1],
        tris,
        facecolors=np.arange(len(tris)) % 7,
        cmap="Pastel1",
        alpha=0.55,
        edgecolors="none",
    )
    for a, b in tri.diagonals.tolist():
        ax.plot(pts[[a, b], 0], pts[[a, b], 1], color="tab:blue", lw=1.2)
    ring = np.vstack([pts, pts[:1]])
    ax.plot(ring[:, 0], ring[:, 1], color="black", lw=1.8)
    ax.scatter(pts[:, 0], pts[:, 1], s=12, color="black", zorder=3)
    if labels and n <= 60:
        centre = pts.mean(axis=0)
        span = float(np.ptp(pts, axis=0).max()) or 1.0
        for idx, (x, y) in enumerate(pts.tolist()):
            dx, dy = np.array([x, y]) - centre
            norm = float(np.hypot(dx, dy)) or 1.0
            ax.annotate(
                str(idx),
                (x + 0.04 * span * dx / norm, y + 0.04 * span * dy / norm),
                ha="center",
                va="center",
                fontsize=8,
            )
    w = tri.weight
    wtxt = ", ".join(f"{v:.6g}" for v in w) if isinstance(w, tuple) else f"{w:.6g}"
    ax.set_title(
        title or f"optimal triangulation, n = {n}, {tri.weight_name} {tri.objective} = {wtxt}"
    )
    ax.set_aspect("equal")
    ax.axis("off")
    return ax


def plot_table(tri: Triangulation, ax: Any = None, *, style: str = "paper") -> Any:
    """Draw the paper's Table 1 layout for ``tri`` (see :func:`optri.format_table`)."""
    cells, marks = table_cells(tri, style=style)
    rows = len(cells)
    width = max(len(text) for row in cells for text in row)
    ax = new_axes(ax, figsize=(1.0 + rows * max(0.9, 0.12 * width), 0.9 + 0.42 * rows))
    colours = [
        ["#fff4d6" if r < c else "#e3efff" if r > c else "#eeeeee" for c in range(rows)]
        for r in range(rows)
    ]
    for r, c in marks:
        colours[r][c] = "#ffd08a"
    table = ax.table(
        cellText=cells,
        cellColours=colours,
        loc="center",
        cellLoc="center",
        rowLabels=[str(i + 1) for i in range(rows)],
        colLabels=[str(i + 1) for i in range(rows)],
    )
    table.scale(1, 1.6)
    ax.axis("off")
    ax.set_title("optimal triangulation table (weights above, splits below)")
    return ax


def save_figure(ax: Any, path: str) -> None:
    """Save the figure of ``ax`` to ``path`` atomically (PNG by suffix) and close it."""
    fig = ax.figure
    fmt = path.rsplit(".", 1)[-1].lower() if "." in path else "png"
    with atomic_write(path, "wb") as fh:
        fig.savefig(fh, format=fmt, dpi=120, bbox_inches="tight")
    import matplotlib.pyplot as plt

    plt.close(fig)
