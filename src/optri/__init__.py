"""optri: optimal triangulation of polygons by dynamic programming.

>>> import optri
>>> optri.triangulate([[0, 0], [2, 0], [3, 2], [1, 3], [-1, 2]]).n
5
"""

from __future__ import annotations

from .batch import BatchSummary, batch
from .chain import ChainOrder, matrix_chain
from .enumerate import count_triangulations, enumerate_triangulations, random_triangulation
from .errors import (
    EngineUnavailableError,
    InvalidPolygonError,
    OptriError,
    TableTooLargeError,
    WeightError,
)
from .geometry import Polygon, as_polygon
from .holes import fill_polyline
from .kbest import best_triangulations
from .mesh import fill_holes
from .papertable import format_table
from .result import Triangulation
from .simple import require_simple, valid_diagonals
from .solve import triangulate
from .weights import WEIGHTS, Weight, custom_weight

__version__ = "0.1.0"

__all__ = [
    "WEIGHTS",
    "BatchSummary",
    "ChainOrder",
    "EngineUnavailableError",
    "InvalidPolygonError",
    "OptriError",
    "Polygon",
    "TableTooLargeError",
    "Triangulation",
    "Weight",
    "WeightError",
    "__version__",
    "as_polygon",
    "best_triangulations",
    "count_triangulations",
    "batch",
    "custom_weight",
    "enumerate_triangulations",
    "fill_holes",
    "fill_polyline",
    "format_table",
    "matrix_chain",
    "random_triangulation",
    "require_simple",
    "triangulate",
    "valid_diagonals",
]
