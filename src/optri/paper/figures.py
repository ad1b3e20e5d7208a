"""The paper's figures as PNGs: Figures 1/4, 2, 3, 5, 6, 7 and Table 1 as a picture."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from ..drawing.figures import new_axes, plot_table, plot_triangulation, save_figure
from ..solve import triangulate
from ..teaching import plot_cell_scheme, plot_recursion_tree, trace
from . import published
from .timing import TimingRow

__all__ = ["FIGURES", "draw_all"]

#: File name -> what it shows.
FIGURES = {
    "fig1_octagon.png": "Figures 1/4: optimal (perimeter) triangulation of a convex octagon",
    "fig2_cell_scheme.png": "Figure 2: the general scheme of labelling the n x n table's cells",
    "fig3_recursion_tree.png": (
        "Figure 3: recursion tree of the memoized pentagon (memo hits are grey pruned leaves)"
    ),
    "fig3_naive_tree.png": "Figure 3 without memoization: every sub-polygon computed again",
    "fig4_pentagon.png": "Figure 4: optimal triangulation of the Table 1 pentagon (product weight)",
    "table1_pentagon.png": "Table 1: the pentagon's n x n table (weights above, splits below)",
    "fig5_completion_time.png": "Figure 5: matrix completion time (A)",
    "fig6_total_time.png": "Figure 6: total time incl. drawing (B)",
    "fig7_ratio.png": "Figure 7: ratio square matrix / memoization, (A) and (B)",
}


def draw_all(out: Path, rows: Sequence[TimingRow]) -> list[str]:
    """Write every figure into ``out``; return the file names written."""
    octagon = triangulate(list(published.OCTAGON), "perimeter", method="memo")
    save_figure(plot_triangulation(octagon), str(out / "fig1_octagon.png"))
    pentagon = triangulate(list(published.PENTAGON_VALUES), "product", method="memo")
    save_figure(
        plot_triangulation(
            pentagon, title="Table 1 pentagon p = 5,1,5,1,5 (0-based labels): optimum 35"
        ),
        str(out / "fig4_pentagon.png"),
    )
    save_figure(plot_table(pentagon), str(out / "table1_pentagon.png"))
    save_figure(plot_cell_scheme(), str(out / "fig2_cell_scheme.png"))
    values = list(published.PENTAGON_VALUES)
    save_figure(
        plot_recursion_tree(trace(values, "product", method="memo")),
        str(out / "fig3_recursion_tree.png"),
    )
    save_figure(
        plot_recursion_tree(trace(values, "product", method="naive")),
        str(out / "fig3_naive_tree.png"),
    )
    _lines(out / "fig5_completion_time.png", rows, "a", "(A) table filling")
    _lines(out / "fig6_total_time.png", rows, "b", "(B) total incl. drawing")
    _ratio(out / "fig7_ratio.png", rows)
    return list(FIGURES)


def _lines(path: Path, rows: Sequence[TimingRow], which: str, label: str) -> None:
    ax = new_axes(None)
    ax.figure.set_size_inches(7, 4.5)
    ns = [r.n for r in rows]
    for key, name in (("square", "square matrix (method='table')"), ("memo", "memoization")):
        ax.plot(ns, [getattr(r, f"{key}_{which}") for r in rows], marker="o", ms=3, label=name)
    ax.set_xlabel("n (vertices)")
    ax.set_ylabel("seconds (median)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_title(f"{label}, measured on this machine")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    save_figure(ax, str(path))


def _ratio(path: Path, rows: Sequence[TimingRow]) -> None:
    ax = new_axes(None)
    ax.figure.set_size_inches(7, 4.5)
    ns = [r.n for r in rows]
    ax.plot(ns, [r.ratio_a for r in rows], marker="o", ms=3, label="R(A) measured")
    ax.plot(ns, [r.ratio_b for r in rows], marker="s", ms=3, label="R(B) measured")
    pn = sorted(published.TABLE4)
    ax.plot(pn, [published.TABLE4[n][5] for n in pn], "k--", lw=1, label="R(A) paper")
    ax.plot(pn, [published.TABLE4[n][6] for n in pn], "k:", lw=1, label="R(B) paper")
    ax.axhline(1.0, color="grey", lw=0.8)
    ax.set_xscale("log")
    ax.set_xlabel("n (vertices)")
    ax.set_ylabel("square matrix / memoization")
    ax.set_title("Ratio (speedup) of memoization over the square matrix")
    ax.grid(True, alpha=0.3)
    ax.legend()
    save_figure(ax, str(path))
