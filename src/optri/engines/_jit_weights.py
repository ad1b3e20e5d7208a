"""The built-in weights of :mod:`optri.weights`, compiled: the very same functions.

numba compiles :data:`optri.weights.FORMULAS` wherever a kernel calls them, so
the compiled and the Python engines evaluate one definition. Vertex data
arrive as a 2-D float64 array in internal order; 1-D vertex values are passed
as an ``(n, 1)`` column.
"""

from __future__ import annotations

from numba.extending import register_jitable

from ..weights import FORMULAS, edge_weight, triangle_weight

__all__ = ["edge_weight", "triangle_weight"]

for _formula in FORMULAS:
    register_jitable(_formula)
