"""The fairing solve: a symmetric fill-reducing order with diagonal pivots."""

from __future__ import annotations

import numpy as np
import pytest

from optri.holes.fair import _factor_solve

sparse = pytest.importorskip("scipy.sparse")
linalg = pytest.importorskip("scipy.sparse.linalg")


def test_positive_definite_system_is_solved():
    rng = np.random.default_rng(5)
    m = rng.normal(size=(30, 30)) * (rng.random((30, 30)) < 0.2)
    lhs = m @ m.T + 30 * np.eye(30)
    rhs = rng.normal(size=(30, 3))
    x = _factor_solve(linalg, sparse.csc_matrix(lhs), rhs)
    np.testing.assert_allclose(x, np.linalg.solve(lhs, rhs), rtol=1e-10, atol=1e-12)


def test_a_zero_diagonal_is_still_pivoted():
    # nonsingular, but its diagonal is zero in every symmetric order
    lhs = np.array([[0.0, 2], [2, 0]])
    rhs = np.array([[1.0, 0, 2], [3, 0, 1]])
    x = _factor_solve(linalg, sparse.csc_matrix(lhs), rhs)
    np.testing.assert_allclose(x, np.linalg.solve(lhs, rhs), rtol=1e-12, atol=1e-12)


def test_a_singular_system_still_raises():
    lhs = sparse.csc_matrix(np.array([[1.0, 1], [1, 1]]))
    with pytest.raises(RuntimeError):
        _factor_solve(linalg, lhs, np.ones((2, 3)))
