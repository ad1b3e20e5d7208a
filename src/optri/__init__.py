"""optri: optimal triangulation of polygons by dynamic programming.

>>> import optri
>>> optri.triangulate([[0, 0], [2, 0], [3, 2], [1, 3], [-1, 2]]).n
5
"""

from __future__ import annotations

from . import data
from ._version import __version__
from .batch import BatchSummary, batch, triangulate_many
from .chain import ChainOrder, matrix_chain
from .contours import ContourMesh, ContourTiling, contours_to_mesh, tile_contours
from .drawing import format_table
from .enumeration import (
    best_triangulations,
    count_triangulations,
    enumerate_triangulations,
    random_triangulation,
)
from .errors import (
    EngineUnavailableError,
    InvalidParameterError,
    InvalidPolygonError,
    MissingDependencyError,
    NoTriangulationError,
    OptriError,
    ParameterTypeError,
    TableTooLargeError,
    WeightError,
)
from .holes import fair_region, fill_holes, fill_polyline, fill_polylines
from .polygon import Polygon, as_polygon, require_simple
from .result import Triangulation
from .simple import valid_diagonals
from .solve import triangulate
from .teaching import Trace, trace
from .weights import WEIGHTS, Weight, custom_weight

__all__ = [
    "WEIGHTS",
    "BatchSummary",
    "ChainOrder",
    "ContourMesh",
    "ContourTiling",
    "EngineUnavailableError",
    "InvalidParameterError",
    "InvalidPolygonError",
    "MissingDependencyError",
    "NoTriangulationError",
    "OptriError",
    "ParameterTypeError",
    "Polygon",
    "TableTooLargeError",
    "Trace",
    "Triangulation",
    "Weight",
    "WeightError",
    "__version__",
    "as_polygon",
    "batch",
    "best_triangulations",
    "contours_to_mesh",
    "count_triangulations",
    "custom_weight",
    "data",
    "enumerate_triangulations",
    "fair_region",
    "fill_holes",
    "fill_polyline",
    "fill_polylines",
    "format_table",
    "matrix_chain",
    "random_triangulation",
    "require_simple",
    "tile_contours",
    "trace",
    "triangulate",
    "triangulate_many",
    "valid_diagonals",
]
