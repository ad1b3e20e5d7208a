"""All triangulations of a polygon: enumerate, count, sample uniformly, the k best.

Convex polygons are enumerated along the Hurtado–Noy tree; simple polygons
over their valid-diagonal mask. Counting and sampling follow the same
recurrence as the optimum (:mod:`optri.engines.recurrence`) over other
semirings; the k best keep k entries per cell.
"""

from __future__ import annotations

from .builder import regular_polygon
from .counting import catalan, count_triangulations
from .hurtado_noy import hn_index_triangulations, hn_operation_counts
from .kbest import best_triangulations
from .listing import enumerate_triangulations, index_triangulations
from .sampling import random_triangulation

__all__ = [
    "best_triangulations",
    "catalan",
    "count_triangulations",
    "enumerate_triangulations",
    "hn_index_triangulations",
    "hn_operation_counts",
    "index_triangulations",
    "random_triangulation",
    "regular_polygon",
]
