import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import optri


def test_clrs_example():
    c = optri.matrix_chain([30, 35, 15, 5, 10, 20, 25])
    assert c.cost == 15125
    assert c.parenthesization == "((A1(A2A3))((A4A5)A6))"


def test_second_published_chain():
    assert optri.matrix_chain([5, 10, 3, 12, 5, 50, 6]).cost == 2010


def test_two_matrices():
    c = optri.matrix_chain([2, 3, 4])
    assert (c.cost, c.parenthesization) == (24, "(A1A2)")


def _naive_chain(d):
    m = len(d) - 1
    cost = [[0] * (m + 1) for _ in range(m + 1)]
    for length in range(2, m + 1):
        for i in range(1, m - length + 2):
            j = i + length - 1
            cost[i][j] = min(
                cost[i][k] + cost[k + 1][j] + d[i - 1] * d[k] * d[j] for k in range(i, j)
            )
    return cost[1][m]


@settings(max_examples=40, deadline=None)
@given(st.lists(st.integers(1, 50), min_size=3, max_size=12))
def test_chain_equals_textbook_recursion(dims):
    c = optri.matrix_chain(dims)
    assert c.cost == _naive_chain(dims)
    assert c.parenthesization.count("A") == len(dims) - 1


@pytest.mark.parametrize("dims", [[1, 2], [3, 0, 4], [2, -1, 3], [2.5, 3, 4]])
def test_bad_dimensions(dims):
    with pytest.raises(optri.InvalidPolygonError):
        optri.matrix_chain(dims)
