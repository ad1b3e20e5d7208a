"""optri: optimal triangulation of polygons by dynamic programming.

>>> import optri
>>> optri.triangulate([[0, 0], [2, 0], [3, 2], [1, 3], [-1, 2]]).n
5
"""

from __future__ import annotations

from .chain import ChainOrder, matrix_chain
from .errors import (
    EngineUnavailableError,
    InvalidPolygonError,
    OptriError,
    TableTooLargeError,
    WeightError,
)
from .geometry import Polygon, as_polygon
from .holes import fill_polyline
from .mesh import fill_holes
from .papertable import format_table
from .result import Triangulation
from .solve import triangulate
from .weights import WEIGHTS, Weight, custom_weight

__version__ = "0.1.0"

__all__ = [
    "WEIGHTS",
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
    "custom_weight",
    "fill_holes",
    "fill_polyline",
    "format_table",
    "matrix_chain",
    "triangulate",
]
