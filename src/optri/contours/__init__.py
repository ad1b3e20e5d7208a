"""Contour stacks to closed surfaces: optimal tilings between slices, branching, caps.

:func:`tile_contours` joins two closed contours by the band of least total
(or largest) triangle weight, over every first span (Fuchs, Kedem and Uselton
1977); :func:`contours_to_mesh` turns a stack of slices into one closed,
oriented surface, tiling matched contours, merging branches through a bridged
contour at an intermediate level and capping the ends with optri's optimal
polygon triangulation.
"""

from __future__ import annotations

from .mesh import ContourMesh, contours_to_mesh
from .slices import contours_overlap
from .tiling import CONTOUR_WEIGHTS, ContourTiling, tile_contours

__all__ = [
    "CONTOUR_WEIGHTS",
    "ContourMesh",
    "ContourTiling",
    "contours_overlap",
    "contours_to_mesh",
    "tile_contours",
]
