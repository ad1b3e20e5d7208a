"""Each built-in weight against values worked out by hand, in the Python and compiled paths."""

import math

import pytest

import optri
from optri.weights import WeightCode, triangle_weight

RIGHT = [[0, 0], [3, 0], [0, 4]]  # the 3-4-5 right triangle
EQUILATERAL = [[0, 0], [2, 0], [1, math.sqrt(3)]]
FLAT = [[0, 0], [1, 0], [2, 0]]  # degenerate: as a weight only, never a polygon

CASES = [
    ("perimeter", RIGHT, 12.0),
    ("area", RIGHT, 6.0),
    ("max_angle", RIGHT, math.pi / 2),
    ("min_angle", RIGHT, -math.asin(0.6)),  # minus the angle opposite the side of 3
    ("aspect_ratio", RIGHT, 1.25),  # R / (2 r) = 2.5 / (2 * 1)
    ("aspect_ratio", EQUILATERAL, 1.0),
    ("max_angle", EQUILATERAL, math.pi / 3),
    ("min_angle", EQUILATERAL, -math.pi / 3),
    ("area", [[0, 0, 0], [1, 0, 0], [0, 1, 1]], math.sqrt(2) / 2),  # a tilted 3-D triangle
    ("product", [2, 3, 4], 24.0),
]


@pytest.mark.parametrize("method", ["memo", "fast"])
@pytest.mark.parametrize("weight, triangle, expected", CASES)
def test_one_triangle_weighs_its_formula(method, weight, triangle, expected):
    if method == "fast":
        pytest.importorskip("numba")
    t = optri.triangulate(triangle, weight, method=method)
    assert t.weight == pytest.approx(expected, rel=1e-12, abs=1e-12)


def test_degenerate_triangle():
    p = [tuple(map(float, v)) for v in FLAT]
    assert triangle_weight(WeightCode.ASPECT_RATIO, p, 0, 1, 2) == math.inf
    assert triangle_weight(WeightCode.MAX_ANGLE, p, 0, 1, 2) == pytest.approx(math.pi)
    assert triangle_weight(WeightCode.AREA, p, 0, 1, 2) == 0.0


def test_diagonal_weight_counts_only_diagonals():
    square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
    # triangle (0, 1, 2) of the square: two sides and half the diagonal (0, 2)
    assert triangle_weight(WeightCode.DIAGONAL, square, 0, 1, 2) == pytest.approx(math.sqrt(2) / 2)
    assert triangle_weight(WeightCode.PERIMETER, square, 0, 1, 2) == pytest.approx(2 + math.sqrt(2))
    for method in ("memo", "fast"):
        if method == "fast":
            pytest.importorskip("numba")
        t = optri.triangulate([list(v) for v in square], "diagonal", method=method)
        assert t.weight == pytest.approx(math.sqrt(2))  # one diagonal, in two triangles
