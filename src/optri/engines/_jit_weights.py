"""The built-in weights of :mod:`optri.weights`, compiled: the very same functions.

numba compiles :data:`optri.weights.FORMULAS` wherever a kernel calls them, so
the compiled and the Python engines evaluate one definition. Vertex data
arrive as a 2-D float64 array in internal order; 1-D vertex values are passed
as an ``(n, 1)`` column.
"""

from __future__ import annotations

from numba.extending import register_jitable

from ..weights import (
    FORMULAS,
    OUT_OF_LINE,
    edge_weight,
    edge_weight_row,
    side_length,
    triangle_weight,
)

__all__ = ["edge_weight", "edge_weight_row", "triangle_weight"]

# Straight-line helpers are inlined into their callers (numba IR), as the hand-written
# kernels were: 1.5-2x faster on the generic path than calls. side_length is left to
# LLVM's inliner: its branches would trip numba's IR-inlining checks.
for _formula in FORMULAS:
    out_of_line = _formula in (side_length, triangle_weight) or _formula in OUT_OF_LINE
    inline = "never" if out_of_line else "always"
    register_jitable(inline=inline)(_formula)
