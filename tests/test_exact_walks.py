"""Every walk over a split table or a triangulation is bounded: corrupt input raises.

Each corrupt input below sends an unguarded walk into an endless loop (or, in the
compiled visibility walk, past the end of its stack); the guards turn it into a
clear internal error.
"""

from __future__ import annotations

import numpy as np
import pytest
from optri._core import simple as core

from optri.chain import _parens
from optri.engines.recurrence import triangles_from_splits, walk
from optri.errors import NoTriangulationError, OptriError
from optri.simple.mask import valid_diagonals_compiled

SQUARE = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])


@pytest.mark.parametrize("bad", ["k == j", "k == i", "k beyond j"])
def test_split_table_walk_raises_on_a_split_outside_its_chord(bad):
    def split(i, j):
        return {"k == j": j, "k == i": i, "k beyond j": j + 3}[bad] if (i, j) == (0, 5) else i + 1

    with pytest.raises(OptriError, match="internal error"):
        triangles_from_splits(split, 6)


def test_split_table_walk_is_bounded_by_its_limit():
    def expand(state):  # every state expands into itself twice: a cycle
        return (0, 1, 2), [state, state]

    with pytest.raises(OptriError, match="exceeds 4 triangles"):
        walk((0, 2), expand, 4)


def test_missing_split_is_no_triangulation():
    with pytest.raises(NoTriangulationError):
        triangles_from_splits(lambda i, j: -1, 5)


@pytest.mark.parametrize("splits", [{(0, 3): 3}, {(0, 3): 0}, {(0, 3): 1, (1, 3): 1}, {}])
def test_chain_parenthesization_walk_raises_on_a_corrupt_table(splits):
    with pytest.raises(OptriError, match="internal error"):
        _parens(splits, 0, 3)


def test_visibility_walk_stops_on_a_corrupt_triangulation():
    x, y = SQUARE[:, 0].copy(), SQUARE[:, 1].copy()
    go = np.zeros(1, dtype=np.int64)
    good = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.int64)
    mask, ok = core.visibility(x, y, good, go, 1)
    assert ok and mask[0, 2] and mask[1, 3]
    # triangle (0, 1, 2) twice, once reversed: the fan around vertex 0 cycles forever
    cyclic = np.array([[0, 1, 2], [2, 1, 0]], dtype=np.int64)
    assert core.visibility(x, y, cyclic, go, 1)[1] is False
    out_of_range = np.array([[0, 1, 2], [0, 2, 9]], dtype=np.int64)
    assert core.visibility(x, y, out_of_range, go, 1)[1] is False


def test_mask_raises_when_its_walk_stops(monkeypatch):
    visibility = core.visibility

    def corrupt_diagonals(x, y, stop, threads):
        cyclic = np.array([[0, 1, 2], [2, 1, 0]], dtype=np.int64)
        return visibility(x, y, cyclic, stop, threads)

    monkeypatch.setattr(core, "diagonals", corrupt_diagonals)
    with pytest.raises(OptriError, match="internal error"):
        valid_diagonals_compiled(SQUARE)
