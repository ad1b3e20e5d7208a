"""The k best triangulations by weight: a k-best dynamic program.

Each cell (i, j) keeps its k cheapest sub-triangulations, as (cost, split,
rank in (i, split), rank in (split, j)). Both "sum" and "max" (and their
lexicographic pairs) are monotone in each half's cost, so the candidates of a
split k form a sorted grid over the two halves' sorted lists, and the k best of
all splits come out of one heap seeded with each split's best pair and grown
lazily: popping (a, b) pushes (a + 1, b) and (a, b + 1).
"""

from __future__ import annotations

import heapq
import math
from typing import Any

from .. import config
from ..engines.memory import require_memory
from ..engines.recurrence import chords_by_length, split_points, walk
from ..errors import InvalidPolygonError, NoTriangulationError, WeightError, check_count
from ..objective import ObjectiveLike, as_objective
from ..result import Triangulation
from ..solve import build_problem, solve_problem
from ..weights import resolve_weights
from .builder import PolygonOrN, TriangulationBuilder, as_enumerable, usable_chords
from .counting import count_triangulations
from .listing import index_triangulations

__all__ = ["best_triangulations", "kbest_bytes"]

Entry = tuple[Any, int, int, int]  # (cost, split, rank left, rank right)


def best_triangulations(
    vertices: PolygonOrN,
    weight: Any = "perimeter",
    k: int = 10,
    objective: ObjectiveLike = "sum",
) -> list[Triangulation]:
    """The ``k`` cheapest triangulations, cheapest first (fewer if there are fewer).

    Parameters
    ----------
    vertices : array_like or int
        The polygon (or n for the regular n-gon).
    weight : str or callable
    k : int
        How many to return (>= 1).
    objective : {"sum", "max"} or pair

    Returns
    -------
    list of Triangulation
        Costs non-decreasing; ``method == "kbest"``. The first has the optimal
        cost (ties may be broken differently from :func:`optri.triangulate`).

    Notes
    -----
    For "sum", "max" and "sum"-led lexicographic pairs (monotone objectives):
    O(n^3 + n^2 k log(n + k)) time and O(n^2 k) space: each of the O(n^2)
    cells scans its O(n) splits once and pops k entries from a heap.
    A "max"-led lexicographic pair is not monotone, so it falls back to a heap
    over the full enumeration (exact; at most ``config.KBEST_ENUMERATION_LIMIT``
    triangulations). Weights equal up to
    rounding may come in either order.

    Examples
    --------
    >>> best = best_triangulations([5, 1, 5, 1, 5], "product", k=3)
    >>> [t.weight for t in best]
    [35.0, 35.0, 75.0]
    """
    k = check_count(k, "k")
    obj = as_objective(objective)
    if weight is None:
        raise WeightError("best_triangulations needs a weight to rank triangulations by")
    resolve_weights(weight, len(obj.components))
    polygon = as_enumerable(vertices)
    build = TriangulationBuilder(polygon, weight, objective, "kbest")
    if k == 1:  # the plain DP: O(n^2) memory, any engine
        problem = build_problem(polygon, weight, obj)
        _, solution = solve_problem(problem)
        return [build(solution.triangles.tolist())]
    if not _monotone(obj.components):
        return _by_enumeration(polygon, build, k)
    combine, neutral = obj.combine, obj.neutral
    n = polygon.n
    require_memory(
        kbest_bytes(n, k, polygon.convex or polygon.is_values),
        f"the k-best tables for n = {n}, k = {k}",
        "ask for fewer (k = 1 is the plain DP) or use a smaller polygon",
    )
    ok = usable_chords(polygon)
    best: dict[tuple[int, int], list[Entry]] = {
        (i, i + 1): [(neutral, -1, 0, 0)] for i in range(n - 1)
    }
    for i, j in chords_by_length(n, ok):
        best[(i, j)] = _cell(i, j, k, best, ok, combine, build.triangle_weight)
    top = best.get((0, n - 1), [])
    if not top:
        raise InvalidPolygonError("the polygon has no triangulation with its allowed chords")
    _require_finite(top[0][0])
    out = []
    for rank, entry in enumerate(top):
        tris = _expand(best, 0, n - 1, rank)
        out.append(build(tris, obj.finalize(entry[0])))
    return out


def _require_finite(cost: Any) -> None:
    """The cheapest cost must be finite: an infinite one means the weights overflow."""
    values = cost if isinstance(cost, tuple) else (cost,)
    if not all(v == -math.inf or math.isfinite(v) for v in values):
        raise NoTriangulationError(
            f"the cheapest cost {cost} is not a finite number: the weights are infinite or "
            f"overflow float64 (coordinates near 1e308); scale the coordinates down"
        )


def kbest_bytes(n: int, k: int, convex: bool = True) -> int:
    """Peak bytes of the k-best tables: up to k entries for each of the n^2 / 2 chords.

    A chord spanning ``L`` sides keeps at most ``min(k, Catalan(L - 1))`` entries, each
    a 4-tuple with its cost (about 110 bytes), in a list in a dict (about 160 bytes a
    chord); a simple polygon adds its chord mask as an array and as nested lists.

    >>> kbest_bytes(1000, 10) // 10**6
    625
    """
    total, entries, cat = 0, 1, 1  # cat = Catalan(length - 1), capped at k
    for length in range(2, n):
        cat = min(k, cat * 2 * (2 * length - 3) // length) if cat < k else k
        entries = cat
        total += (n - length) * (160 + 110 * entries)
    return total + (0 if convex else 9 * n * n)


def _monotone(components: tuple[str, ...]) -> bool:
    """True when combine preserves order in each half's cost (per-cell k best suffice).

    "sum" and "max" are; a lexicographic pair is when its first component is
    "sum". With "max" first it is not: (1, 100) < (2, 5), yet with a triangle
    (3, 0) they give (3, 100) > (3, 5), so a cell's k best can miss the answer.
    """
    return len(components) == 1 or components[0] == "sum"


def _by_enumeration(polygon, build, k):  # type: ignore[no-untyped-def]
    """Exact k best of a non-monotone objective: every triangulation, kept in a heap."""
    total = count_triangulations(polygon)
    if total > config.KBEST_ENUMERATION_LIMIT:
        raise WeightError(
            f"k-best for a lexicographic objective led by 'max' enumerates all {total} "
            f"triangulations, above the limit {config.KBEST_ENUMERATION_LIMIT}; use a 'sum'-led "
            "objective or fewer vertices"
        )
    scored = (
        (build.cost(t), i, [list(x) for x in t])
        for i, t in enumerate(index_triangulations(polygon))
    )
    return [build(tris, cost) for cost, _, tris in heapq.nsmallest(k, scored)]


def _cell(i, j, k, best, ok, combine, w):  # type: ignore[no-untyped-def]
    """The k best entries of chord (i, j) by lazy merging of its splits."""
    heap = []
    for s in split_points(i, j, ok):
        left, right = best.get((i, s)), best.get((s, j))
        if not left or not right:
            continue
        ws = w(i, s, j)
        heap.append((combine(left[0][0], right[0][0], ws), s, 0, 0, ws))
    heapq.heapify(heap)
    out: list[Entry] = []
    seen = set()
    while heap and len(out) < k:
        cost, s, a, b, ws = heapq.heappop(heap)
        out.append((cost, s, a, b))
        left, right = best[(i, s)], best[(s, j)]
        for a2, b2 in ((a + 1, b), (a, b + 1)):
            if a2 < len(left) and b2 < len(right) and (s, a2, b2) not in seen:
                seen.add((s, a2, b2))
                heapq.heappush(heap, (combine(left[a2][0], right[b2][0], ws), s, a2, b2, ws))
    return out


def _expand(best, i: int, j: int, rank: int) -> list[list[int]]:  # type: ignore[no-untyped-def]
    """Triangles of the rank-th best sub-triangulation of (i, j)."""

    def expand(state):  # type: ignore[no-untyped-def]
        a, b, r = state
        _, s, ra, rb = best[(a, b)][r]
        children = [c for c in ((a, s, ra), (s, b, rb)) if c[1] - c[0] >= 2]
        return (a, s, b), children

    return [list(t) for t in walk((i, j, rank), expand, j - i - 1)]
