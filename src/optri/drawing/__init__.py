"""Drawing results: matplotlib figures, the paper's table as text, SVG for notebooks.

matplotlib is imported inside the functions that draw, so importing this
package costs nothing.
"""

from __future__ import annotations

from .figures import new_axes, plot_table, plot_triangulation, save_figure
from .svg import triangulation_svg
from .table import format_table, table_cells

__all__ = [
    "format_table",
    "new_axes",
    "plot_table",
    "plot_triangulation",
    "save_figure",
    "table_cells",
    "triangulation_svg",
]
