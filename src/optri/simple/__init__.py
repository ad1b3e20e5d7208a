"""Simple (possibly concave) polygons: the valid-diagonal mask the DP runs over.

A triangulation of a simple polygon uses only its internal diagonals;
restricting the recurrence's chords to them (Klincsek 1980) gives the exact
optimum with every engine. :func:`allowed_chords` decides which chords exist;
:func:`valid_diagonals` computes the mask (the compiled core's mask kernels,
``optri._core.simple``).
"""

from __future__ import annotations

from .mask import allowed_chords, valid_diagonals, zero_area_triangles

__all__ = ["allowed_chords", "valid_diagonals", "zero_area_triangles"]
