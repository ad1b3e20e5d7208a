"""Ties go to the smallest split, and every engine returns the same triangles.

The recurrence tries the splits k of a chord in increasing order and keeps a
later one only when it is strictly better (:meth:`optri.engines.recurrence.
Recurrence.cell`, the compiled ``best_split`` and ``minplus_split``). The
inputs here tie exactly (integer arithmetic, or equal numbers added in the same
order), so a rule that kept the last tie, or any engine that breaks ties its
own way, returns other triangles than the ones written out below.
"""

import numpy as np
import pytest

import optri
from optri.paper.published import PENTAGON_VALUES, TABLE2, TABLE2_MARKED_ROW

ENGINES = ["memo", "table", "brute", "fast"]
SQUARE = [[0, 0], [1, 0], [1, 1], [0, 1]]
# a convex octagon with integer corners: every triangle area is an exact half-integer
OCTAGON = [[1, 0], [2, 0], [3, 1], [3, 2], [2, 3], [1, 3], [0, 2], [0, 1]]


def fan(n):
    """The triangulation that smallest splits give when everything ties: a fan from n - 1."""
    return [(i, i + 1, n - 1) for i in range(n - 2)]


def triangles(t):
    return sorted(map(tuple, t.triangles.tolist()))


def solve(method, vertices, weight, objective):
    if method == "fast":
        pytest.importorskip("numba")
    return optri.triangulate(vertices, weight, objective, method=method)


EXACT_TIES = [
    # every triangle of equal vertex values weighs 8: all 132 triangulations tie
    ("equal values sum", [2] * 8, "product", "sum", fan(8)),
    ("equal values max", [2] * 8, "product", "max", fan(8)),
    ("equal values max-sum", [2] * 8, ("product", "product"), ("max", "sum"), fan(8)),
    ("equal values sum-max", [2] * 8, ("product", "product"), ("sum", "max"), fan(8)),
    # the paper's pentagon: two triangulations cost 35 (Table 2 rows 3 and 4 of 1-based
    # diagonals); the smallest split at chord (0, 4) is k = 1, giving row 3
    ("paper pentagon", list(PENTAGON_VALUES), "product", "sum", [(0, 1, 4), (1, 2, 3), (1, 3, 4)]),
    # every triangulation of a polygon has the same total area, exactly so here
    ("integer octagon area", OCTAGON, "area", "sum", fan(8)),
    # the square's two triangulations: the same two perimeters (resp. one diagonal)
    ("square perimeter", SQUARE, "perimeter", "sum", [(0, 1, 3), (1, 2, 3)]),
    ("square diagonal", SQUARE, "diagonal", "sum", [(0, 1, 3), (1, 2, 3)]),
]


@pytest.mark.parametrize("method", ENGINES)
@pytest.mark.parametrize(
    "vertices, weight, objective, expected",
    [case[1:] for case in EXACT_TIES],
    ids=[case[0] for case in EXACT_TIES],
)
def test_exact_ties_go_to_the_smallest_split(method, vertices, weight, objective, expected):
    t = solve(method, vertices, weight, objective)
    t.check()
    assert triangles(t) == expected


def test_paper_pentagon_tie_is_the_row_table2_marks():
    t = optri.triangulate(list(PENTAGON_VALUES), "product", method="memo")
    marked = next(d for row, d, _ in TABLE2 if row == TABLE2_MARKED_ROW)
    assert sorted((a + 1, b + 1) for a, b in t.diagonals.tolist()) == sorted(marked)
    assert t.weight == 35.0


@pytest.mark.parametrize("n", [6, 8, 10])
@pytest.mark.parametrize("weight", ["max_angle", "min_angle", "aspect_ratio"])
def test_regular_polygon_bottleneck_same_triangles_in_every_dp_engine(n, weight):
    """A regular polygon under "max": congruent triangles, so many equal sub-costs.

    The DP engines evaluate the same weights (one definition) and compare maxima
    exactly, so they must agree triangle for triangle. Brute force is left out
    on purpose: it returns the first optimal triangulation in its enumeration
    order, while the DP engines also solve every sub-polygon optimally, and
    under "max" those can differ (both optimal; see the equal-values cases
    above, where they coincide).
    """
    ang = np.linspace(0, 2 * np.pi, n, endpoint=False)
    poly = np.column_stack((np.cos(ang), np.sin(ang)))
    results = {m: solve(m, poly, weight, "max") for m in ("memo", "table", "fast")}
    first = triangles(results["memo"])
    for method, t in results.items():
        t.check()
        assert triangles(t) == first, method
        assert t.weight == results["memo"].weight, method
