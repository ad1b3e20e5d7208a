"""Drawing results: matplotlib figures, the paper's table as text, SVG and HTML for notebooks.

matplotlib is imported inside the functions that draw, so importing this
package costs nothing.
"""

from __future__ import annotations

from .figures import new_axes, plot_table, plot_triangulation, save_figure
from .html import table_html, triangulation_html
from .svg import drawing_points, triangulation_svg
from .table import format_table, table_cells

__all__ = [
    "drawing_points",
    "format_table",
    "new_axes",
    "plot_table",
    "plot_triangulation",
    "save_figure",
    "table_cells",
    "table_html",
    "triangulation_html",
    "triangulation_svg",
]
