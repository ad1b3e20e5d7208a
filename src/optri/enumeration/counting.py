"""Counting triangulations exactly: Catalan numbers, and the recurrence over a chord mask.

For a polygon with a restricted set of usable chords (a simple, non-convex
polygon) the count follows the same recurrence as the optimum, over the
(+, x) semiring instead of (min, +):

    count(i, j) = sum over usable k of count(i, k) * count(k, j),  count(i, i+1) = 1,

which for a convex polygon is the Catalan number C(j - i - 1) (Klincsek 1980).
"""

from __future__ import annotations

import math

import numpy as np

from .. import config
from ..engines.memory import require_memory
from ..engines.recurrence import Rows, chords_by_length, split_points
from ..errors import InvalidParameterError, InvalidPolygonError
from .builder import PolygonOrN, as_enumerable, usable_chords

__all__ = [
    "catalan",
    "count_bytes",
    "count_table",
    "count_triangulations",
    "require_count_memory",
]


def catalan(m: int) -> int:
    """The Catalan number C(m) = binom(2m, m) / (m + 1), exactly.

    >>> [catalan(m) for m in range(8)]
    [1, 1, 2, 5, 14, 42, 132, 429]
    """
    if m < 0:
        raise ValueError(f"catalan({m}) is undefined for negative m")
    return math.comb(2 * m, m) // (m + 1)


def count_triangulations(vertices_or_n: PolygonOrN) -> int:
    """Number of triangulations, as an exact (big) int.

    Parameters
    ----------
    vertices_or_n : int or array_like
        n for the convex n-gon, or the polygon itself.

    Returns
    -------
    int
        C(n - 2) for a convex polygon; for a polygon with restricted chords
        the DP count over the allowed-chord mask (O(n^3) big-int steps).

    Examples
    --------
    >>> count_triangulations(16)
    2674440
    >>> count_triangulations(40) == math.comb(76, 38) // 39
    True
    >>> count_triangulations([[0, 0], [1, 0], [1, 1], [0, 1]])
    2
    """
    if isinstance(vertices_or_n, (int, np.integer)):
        n = int(vertices_or_n)
        if n < 3:
            raise InvalidPolygonError(f"a polygon needs at least 3 vertices, got {n}")
        if n > config.COUNT_MAX_N:
            shown = n if n.bit_length() < 64 else f"2**{n.bit_length() - 1} or more"
            raise InvalidParameterError(
                f"the count for n = {shown} has about 0.6 n digits; counts are computed "
                f"up to n = {config.COUNT_MAX_N} (config.COUNT_MAX_N)"
            )
        return catalan(n - 2)
    polygon = as_enumerable(vertices_or_n)
    if not (polygon.convex or polygon.is_values):
        require_count_memory(polygon.n, "counting the triangulations")
    ok = usable_chords(polygon)
    if ok is None:
        return catalan(polygon.n - 2)
    return count_table(ok)[0][polygon.n - 1]


def count_bytes(n: int) -> int:
    """Peak bytes of :func:`count_table` for ``n`` vertices, with the chord mask it reads.

    The mask as a numpy array and as nested lists (8 bytes a cell), the count rows
    (8 bytes a cell) and one big int per chord: count(i, j) <= Catalan(j - i - 1)
    < 4^(j - i), about 28 + (j - i) / 4 bytes, so about n^3 / 24 bytes in all.

    >>> count_bytes(2000) // 10**6
    464
    """
    cells = n * n
    ints = sum((n - length) * (32 + length // 4) for length in range(2, n))
    return cells + 8 * cells + 8 * cells + ints


def require_count_memory(n: int, what: str) -> None:
    """Refuse (:class:`~optri.errors.TableTooLargeError`) before counting can run out of memory."""
    require_memory(
        count_bytes(n),
        f"{what} of a {n}-vertex simple polygon (exact big-int counts of every chord)",
        "count a smaller polygon, or a convex one (Catalan numbers need no table)",
    )


def count_table(ok: Rows) -> list[list[int]]:
    """``count[i][j]``: triangulations of sub-polygon i..j over the allowed chords.

    ``ok`` is the chord mask as nested rows with the sides set. ``count[i][j]``
    is 0 when chord (i, j) is not allowed; sides count 1. Exact big ints, O(n^3).

    >>> count_table([[True] * 6 for _ in range(6)])[0][5]   # Catalan(4)
    14
    """
    n = len(ok)
    cnt = [[0] * n for _ in range(n)]
    for i in range(n - 1):
        cnt[i][i + 1] = 1
    for i, j in chords_by_length(n, ok):
        row_i = cnt[i]
        cnt[i][j] = sum(row_i[k] * cnt[k][j] for k in split_points(i, j, ok))
    return cnt
