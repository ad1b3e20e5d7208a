"""Filling 3-D holes: optimal patches of closed polylines and of the holes of meshes.

:func:`fill_polyline` triangulates one closed 3-D polyline (Liepa's objective
searched exactly, by Liepa's recurrence, or over 3-D Delaunay faces; any
triangle weight through the normal engines); :func:`fill_holes` finds every
boundary loop of a triangle mesh and fills it, refined (:func:`refine_patch`) and
faired (:func:`fair_region`) when asked. :func:`fill_polylines` fills an outer loop
and islands inside it as one surface; :func:`fill_holes` finds such islands itself.
"""

from __future__ import annotations

from .boundary import boundary_loops
from .fair import fair_region
from .islands import fill_polylines
from .liepa import liepa_objective
from .mesh import HoleRecord, fill_holes
from .polyline import METHODS, fill_polyline
from .refine import refine_patch

__all__ = [
    "METHODS",
    "HoleRecord",
    "boundary_loops",
    "fair_region",
    "fill_holes",
    "fill_polyline",
    "fill_polylines",
    "liepa_objective",
    "refine_patch",
]
