"""numba's recurrence on one n x n table, for the numba kernels not in the compiled core.

The compiled engine's generic path runs in the compiled core
(``optri._core.generic``); ``best_split`` and ``trace`` here serve the
many-polygon kernel (:mod:`optri.simple._many_kernels`), and the min-plus
fill's trace and split table the numba min-plus path.

Table layout: ``T[i, j]`` (``i < j``) holds the cost of chord ``(i, j)`` and
``T[j, i]`` the same value, so for a cell ``(i, j)`` both operands of every
split, ``cost(i, k)`` = ``T[i, k]`` and ``cost(k, j)`` = ``T[j, k]``, are read
along contiguous rows ``T[i]`` and ``T[j]``.
"""

from __future__ import annotations

import numpy as np
from numba import prange, types
from numba.extending import overload

from ..objective import lex_better
from ..weights import WeightCode
from ._jit_weights import triangle_weight
from ._minplus import minplus_split, minplus_tiles, mirror_table, subtract_edges, tile_flags
from .compiled import kernel

__all__ = [
    "NO_GATE",
    "best_split",
    "minplus_split",
    "minplus_tiles",
    "mirror_table",
    "split_table",
    "subtract_edges",
    "tile_flags",
    "trace",
]

NO_GATE = -2  # codes[2] when the problem has no gate


# --- generic path (any compiled weight, sum / max / lexicographic) -------------------
#
# Arguments travel in three packed tuples (built by optri.simple._many_kernels):
#   tables = (T1, T2)            cost tables of components 1 and 2 (T2 read only if lex)
#   weigh  = (pts, codes, gate, verts, order, wfn1, wfn2, wfng)
#            built-in weights by code (codes = [w1, w2, gate weight or NO_GATE]) on
#            pts; a user's numba weights wfn* on the input vertices ``verts``
#            (indices mapped back through ``order``); the gate's threshold gate[0]
#   rule   = (is_max, lex, nan)  combine of each component (max or sum), whether the
#            objective is a lexicographic pair, and the flag a NaN weight sets


def _user_weight(wfn, verts, a, b, c):  # type: ignore[no-untyped-def]
    """A user's numba weight ``wfn(verts, a, b, c)``; NaN where there is none."""


@overload(_user_weight, inline="always")
def _user_weight_impl(wfn, verts, a, b, c):  # type: ignore[no-untyped-def]
    # chosen while typing: a None ``wfn`` (every built-in weight) compiles to a constant
    if isinstance(wfn, types.NoneType):
        return lambda wfn, verts, a, b, c: np.nan
    return lambda wfn, verts, a, b, c: float(wfn(verts, a, b, c))


@kernel(inline="always")
def _weight(code, pts, i, k, j, wfn, verts, order):
    if code == WeightCode.CUSTOM:
        return _user_weight(wfn, verts, order[i], order[k], order[j])
    return triangle_weight(code, pts, i, k, j)


@kernel(inline="always")
def _combine(is_max, a, b, w):
    if is_max:
        return max(a, max(b, w))
    return a + b + w


@kernel(inline="always")
def _gated_first(weigh, i, k, j):
    """Weight of component 1; +inf when a gate is set and the gate weight exceeds it."""
    pts, codes, gate, verts, order = weigh[0], weigh[1], weigh[2], weigh[3], weigh[4]
    w1 = _weight(codes[0], pts, i, k, j, weigh[5], verts, order)
    if codes[2] != NO_GATE:  # a triangle above the gate's threshold is forbidden
        if _weight(codes[2], pts, i, k, j, weigh[7], verts, order) > gate[0]:
            w1 = np.inf
    return w1


# ties of a lexicographic objective: optri.objective's rule, compiled from its source
_lex_better = kernel(inline="always")(lex_better)


@kernel(inline="always")
def best_split(tables, weigh, rule, i, j):
    """The recurrence for one cell: ``(cost1, cost2, k)``, ties to the smallest k.

    ``cost(i, j) = best_k combine(cost(i, k), cost(k, j), w(i, k, j))``, compared
    on component 1, then (``lex``) component 2, component-1 values within
    ``optri.objective.LEX_TIE_RTOL`` counting as equal. A NaN weight sets ``nan[0]``.
    With ``codes[2] != NO_GATE``, a triangle whose weight ``codes[2]`` exceeds
    ``gate[0]`` gets weight +inf (second phase of a max-led lexicographic objective).
    """
    T1, T2 = tables
    is_max, lex, nan = rule
    pts, codes, verts, order = weigh[0], weigh[1], weigh[3], weigh[4]
    b1, b2, arg = np.inf, np.inf, -1
    r1i, r1j = T1[i, i + 1 : j], T1[j, i + 1 : j]
    if lex:
        r2i, r2j = T2[i, i + 1 : j], T2[j, i + 1 : j]
    else:
        r2i, r2j = r1i, r1j
    for kk in range(r1i.shape[0]):
        k = i + 1 + kk
        if r1i[kk] == np.inf or r1j[kk] == np.inf:
            continue  # a half with no triangulation (not a diagonal): skip its weight
        w1 = _gated_first(weigh, i, k, j)
        if w1 != w1:
            nan[0] = 1
            continue
        v1 = _combine(is_max[0], r1i[kk], r1j[kk], w1)
        if not lex:
            if v1 < b1:
                b1, arg = v1, k
            continue
        w2 = _weight(codes[1], pts, i, k, j, weigh[6], verts, order)
        if w2 != w2:
            nan[0] = 1
            continue
        v2 = _combine(is_max[1], r2i[kk], r2j[kk], w2)
        if _lex_better(v1, v2, b1, b2):
            b1, b2, arg = v1, v2, k
    return b1, b2, arg


# --- reconstruction and the exported table ---------------------------------------------


@kernel()
def trace(tables, weigh, rule):
    """Optimal triangles from chord (0, n-1) down.

    Re-scans only the O(n) cells on the optimal path. Returns ``(triangles,
    bad)``; ``bad = (i, j)`` of a chord with no finite split, else ``(-1, -1)``.
    The walk is bounded: at most n - 2 triangles, each with i < k < j.
    ``weigh`` and ``rule`` None: the min-plus table (``minplus_split``), a
    version of its own in which the generic branch is pruned; the call is also
    cheaper to dispatch (10 against 28 us right after a fill at n = 1000,
    whose tables push the interpreter's data out of the caches).
    """
    n = tables[0].shape[0]
    tris = np.empty((max(n - 2, 0), 3), dtype=np.int64)
    stack = np.empty((n, 2), dtype=np.int64)
    top, m = 1, 0
    stack[0, 0], stack[0, 1] = 0, n - 1
    while top > 0:
        top -= 1
        i, j = stack[top, 0], stack[top, 1]
        if j - i < 2:
            continue
        # the branch written out here: behind a helper of both (inlined or not), the walk
        # took 97-113 us instead of 11-13 us at n = 1000 (min-plus), in every form tried
        if weigh is None:
            k = minplus_split(tables[0], i, j, False)
        else:
            k = best_split(tables, weigh, rule, i, j)[2]
        if k <= i or k >= j or m >= n - 2:
            return tris[:m], (i, j)
        tris[m, 0], tris[m, 1], tris[m, 2] = i, k, j
        m += 1
        stack[top, 0], stack[top, 1] = k, j
        stack[top + 1, 0], stack[top + 1, 1] = i, k
        top += 2
    return tris[:m], (-1, -1)


@kernel(parallel=True)
def split_table(tables, weigh, rule):
    """Optimal split of every chord (O(n^3): only for an exported table).

    ``weigh`` and ``rule`` None: the min-plus table, whose lower half must
    hold its upper half (``mirror_table``).
    """
    n = tables[0].shape[0]
    out = np.full((n, n), -1, dtype=np.int32)
    for i in prange(n):
        for j in range(i + 2, n):
            if weigh is None:
                out[i, j] = minplus_split(tables[0], i, j, True)
            else:
                out[i, j] = best_split(tables, weigh, rule, i, j)[2]
    return out
