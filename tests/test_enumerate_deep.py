"""Listing the triangulations of a large non-convex polygon needs no deep recursion."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from click.testing import CliRunner

import optri
from optri.cli import main
from optri.engines.brute import all_index_triangulations
from optri.enumeration.builder import as_enumerable, usable_chords
from optri.enumeration.listing import chord_triangulations, index_triangulations


def _star(n: int, inner: float = 0.6) -> np.ndarray:
    t = 2 * math.pi * np.arange(n) / n
    r = np.where(np.arange(n) % 2 == 0, 1.0, inner)
    return np.column_stack((r * np.cos(t), r * np.sin(t)))


@pytest.mark.parametrize("seed", range(6))
def test_the_listing_equals_the_recursive_one_in_order(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(5, 11))
    pts = _star(n, float(rng.uniform(0.3, 0.8)))
    poly = as_enumerable(pts)

    ok = usable_chords(poly) or [[True] * n for _ in range(n)]  # None: convex
    want = list(all_index_triangulations(n, ok))
    assert list(chord_triangulations(n, ok)) == want and len(want) > 1
    if usable_chords(poly) is not None:
        assert list(index_triangulations(poly)) == [[list(t) for t in w] for w in want]


def test_a_6000_vertex_star_lists_without_recursion_error(tmp_path):
    pts = _star(6000)
    first = list(itertools.islice(optri.enumerate_triangulations(pts), 2))
    assert len(first) == 2
    for tri in first:
        tri.check()
    src = tmp_path / "star.csv"
    src.write_text("x,y\n" + "".join(f"{float(x)!r},{float(y)!r}\n" for x, y in pts))
    res = CliRunner().invoke(main, ["enumerate", str(src), "-n", "1"])
    assert res.exit_code == 0, res.output[-500:]
    assert res.output.split()[0] == "1"
