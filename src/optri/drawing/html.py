"""HTML for notebooks: the paper's table beside the drawing (``_repr_html_``)."""

from __future__ import annotations

from html import escape
from typing import TYPE_CHECKING

from .. import config
from .svg import triangulation_svg
from .table import table_cells

if TYPE_CHECKING:  # pragma: no cover
    from ..result import Triangulation

__all__ = ["table_html", "triangulation_html"]

_CELL = "border:1px solid #ccc;padding:2px 6px;text-align:center;white-space:nowrap"
_COLOURS = {"upper": "#fff4d6", "lower": "#e3efff", "diagonal": "#eeeeee", "mark": "#ffd08a"}


def table_html(tri: Triangulation) -> str:
    """The paper's n x n table (:func:`optri.format_table` layout) as an HTML table.

    Weights above the diagonal, candidate splits below with the optimal one
    starred, the optimal triangulation's chords highlighted; no sentinel
    values (an unset cell is empty, an unreachable one shows ``inf``).

    >>> import optri
    >>> html = table_html(optri.triangulate([5, 1, 5, 1, 5], "product", method="memo"))
    >>> html.count("<tr>"), ">35<" in html, "-1" in html
    (6, True, False)
    """
    cells, marks = table_cells(tri, style="paper")
    marked = set(marks)
    n = len(cells)
    head = "".join(f'<th style="{_CELL}">{c + 1}</th>' for c in range(n))
    rows = [f'<tr><th style="{_CELL}"></th>{head}</tr>']
    for r, row in enumerate(cells):
        tds = []
        for c, text in enumerate(row):
            part = "diagonal" if r == c else "upper" if r < c else "lower"
            colour = _COLOURS["mark" if (r, c) in marked else part]
            tds.append(f'<td style="{_CELL};background:{colour}">{escape(text)}</td>')
        rows.append(f'<tr><th style="{_CELL}">{r + 1}</th>{"".join(tds)}</tr>')
    return '<table style="border-collapse:collapse;font-size:12px">' + "".join(rows) + "</table>"


def triangulation_html(tri: Triangulation) -> str:
    """The drawing (SVG) with the paper's table beside it and a one-line summary.

    The table is left out, with a note saying why, when the result kept none
    (compiled engines) or n exceeds :data:`optri.config.HTML_TABLE_MAX_N`.
    """
    w = tri.weight
    wtxt = ", ".join(f"{v:.6g}" for v in w) if isinstance(w, tuple) else f"{w:.6g}"
    summary = (
        f"n = {tri.n} &middot; {escape(str(tri.weight_name))} {escape(str(tri.objective))} "
        f"= <b>{wtxt}</b> &middot; method {escape(tri.method)}"
    )
    if tri.table is None:
        right = (
            "<p>No table kept (compiled engine); solve with <code>method='memo'</code> or "
            "<code>keep_table=True</code> to see the paper's n&times;n table.</p>"
        )
    elif tri.n > config.HTML_TABLE_MAX_N:
        right = (
            f"<p>The n&times;n table is shown up to n = {config.HTML_TABLE_MAX_N} "
            "(<code>optri.config.HTML_TABLE_MAX_N</code>); print it with "
            "<code>optri.format_table</code>.</p>"
        )
    else:
        right = (
            table_html(tri)
            + '<p style="font-size:11px;color:#555">weights above the diagonal, candidate '
            "splits below (optimal starred), as in the paper's Table 1; 1-based labels</p>"
        )
    svg = triangulation_svg(tri.vertices, tri.triangles, size=260)
    return (
        '<div style="display:flex;gap:18px;align-items:flex-start;font-family:sans-serif">'
        f"<div>{svg}</div><div><div>{summary}</div>{right}</div></div>"
    )
