"""Matrix-chain multiplication order: the same DP with the product weight."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from .errors import InvalidPolygonError, OptriError
from .solve import triangulate

__all__ = ["ChainOrder", "matrix_chain"]


@dataclass(frozen=True)
class ChainOrder:
    """Optimal parenthesization of a matrix chain.

    Attributes
    ----------
    cost : int
        Fewest scalar multiplications.
    parenthesization : str
        Like ``"((A1(A2A3))((A4A5)A6))"``.
    splits : dict
        ``splits[(i, j)] = k``: product A_{i+1..j} splits after A_k.
    m : ndarray of int, shape (M + 1, M + 1)
        CLRS's cost table, indexed as in the book (1-based; row and column 0
        unused): ``m[i, j]`` is the fewest scalar multiplications for
        A_i ... A_j, i <= j, exact integers (int64, or Python ints in an object
        array when a cost exceeds int64); 0 below the diagonal.
    s : ndarray of int64, shape (M + 1, M + 1)
        CLRS's split table: ``s[i, j] = k`` for i < j, the optimal product
        (A_i ... A_k)(A_{k+1} ... A_j); 0 elsewhere (no matrix is numbered 0).

    Examples
    --------
    >>> c = matrix_chain([10, 30, 5, 60])
    >>> c.cost, c.parenthesization
    (4500, '((A1A2)A3)')
    """

    cost: int
    parenthesization: str
    splits: dict[tuple[int, int], int]
    m: NDArray[Any] = field(default_factory=lambda: np.zeros((0, 0), np.int64), repr=False)
    s: NDArray[np.int64] = field(default_factory=lambda: np.zeros((0, 0), np.int64), repr=False)


def matrix_chain(dims: Sequence[int], method: str = "auto") -> ChainOrder:
    """Cheapest order to multiply matrices A_1 ... A_m, A_i of size d_{i-1} x d_i.

    Solved as the optimal triangulation of a polygon whose vertices carry the
    dimensions d_0..d_m with triangle weight d_i * d_k * d_j (the paper's
    correspondence between triangulations and parenthesizations, Section 3),
    in exact integer arithmetic: int64 where no cost can overflow it, Python
    ints beyond (``method="integer"``, the default's choice).

    Parameters
    ----------
    dims : sequence of int
        m + 1 positive dimensions for m >= 2 matrices.
    method : str
        Engine, as for :func:`optri.triangulate`; float engines (``"fast"``,
        ``"gpu"``) are refused when a cost could exceed 2**53.

    Returns
    -------
    ChainOrder

    Raises
    ------
    InvalidPolygonError
        Fewer than 3 dimensions or a dimension that is not a positive integer.

    References
    ----------
    .. [1] T. H. Cormen, C. E. Leiserson, R. L. Rivest, C. Stein,
       *Introduction to Algorithms*, 3rd ed., MIT Press, 2009, Section 15.2.

    Examples
    --------
    >>> c = matrix_chain([30, 35, 15, 5, 10, 20, 25])
    >>> c.cost, c.parenthesization
    (15125, '((A1(A2A3))((A4A5)A6))')
    >>> int(c.m[2, 5]), int(c.s[1, 6])      # CLRS Figure 15.5
    (7125, 3)
    """
    d = _exact_dims(dims)
    values = np.array(d, dtype=np.int64 if max(d) < 2**63 else object)
    t = triangulate(values, weight="product", method=method, keep_table=True)
    splits = {(int(i), int(j)): int(k) for i, k, j in np.sort(t.triangles, axis=1).tolist()}
    cost = cast(int, t.weight)  # exact: integer values give an int
    assert t.table is not None  # keep_table=True: every engine keeps it
    m, s = _clrs_tables(t.table, d)
    return ChainOrder(int(cost), _parens(splits, 0, len(d) - 1), splits, m, s)


def _exact_dims(dims: Sequence[int]) -> list[int]:
    """The dimensions as Python ints, refusing anything but positive integers."""
    try:
        items = list(dims)
    except TypeError:
        items = None
    if items is None or len(items) < 3:
        raise InvalidPolygonError("a matrix chain needs at least 3 dimensions (2 matrices)")
    out = []
    for v in items:
        ok = isinstance(v, (int, np.integer)) and not isinstance(v, (bool, np.bool_))
        if not ok and isinstance(v, (float, np.floating)) and math.isfinite(v):
            ok = float(v).is_integer()
        if not ok or v <= 0:
            raise InvalidPolygonError(
                f"matrix dimensions must be positive integers, got {list(dims)}"
            )
        out.append(int(v))
    return out


def _clrs_tables(table: NDArray[np.float64], d: list[int]) -> tuple[NDArray[Any], NDArray[Any]]:
    """CLRS's m and s (1-based) from the polygon table: chord (i - 1, j) is A_i ... A_j.

    The splits come from the table's lower half; the costs are recomputed from
    them in exact integers, shortest products first.
    """
    size = len(d) - 1
    s = np.zeros((size + 1, size + 1), dtype=np.int64)
    m = [[0] * (size + 1) for _ in range(size + 1)]
    for length in range(2, size + 1):
        for i in range(1, size - length + 2):
            j = i + length - 1
            k = int(table[j, i - 1])
            s[i, j] = k
            m[i][j] = m[i][k] + m[k + 1][j] + d[i - 1] * d[k] * d[j]
    big = max(max(row) for row in m) >= 2**63
    return np.array(m, dtype=object if big else np.int64), s


def _parens(splits: dict[tuple[int, int], int], i: int, j: int) -> str:
    """The parenthesization the splits describe; bounded: a corrupt table raises.

    >>> _parens({(0, 2): 1}, 0, 2)
    '(A1A2)'
    """
    # chord (i, j) is the product A_{i+1} ... A_j; iterative to allow long chains
    out: list[str] = []
    stack: list[tuple[int, int] | str] = [(i, j)]
    expanded = 0
    while stack:
        item = stack.pop()
        if isinstance(item, str):
            out.append(item)
            continue
        a, b = item
        if b - a == 1:
            out.append(f"A{b}")
            continue
        k = splits.get((a, b), -1)
        expanded += 1
        if not a < k < b or expanded > j - i - 1:
            raise OptriError(
                f"internal error: split {k} of chord ({a}, {b}) is not inside it, or the "
                f"walk exceeds {j - i - 1} products; please report this input"
            )
        stack.extend([")", (k, b), (a, k), "("])
    return "".join(out)
