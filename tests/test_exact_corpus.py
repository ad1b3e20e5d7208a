"""A regression corpus of real rings (tests/data/rings, origins in its README).

Each simple ring's optimum (minimum total triangle perimeter), number of
triangulations and valid-diagonal mask are recomputed here by an independent exact
method (``exact_oracle``: integer-exact predicates, a plain-Python DP and count) and
must equal both the values stored with the ring and optri's answers. Rings that are
not simple (earcut's self-touching fixtures) must be refused, as the oracle says.
Many of these rings have vertices within 1e-15 of a straight border, where the old
tolerance-based predicates rejected valid diagonals.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import optri
from exact_oracle import ccw, exact_count, exact_mask, exact_simple, perimeter_dp
from optri import InvalidPolygonError
from optri.simple import valid_diagonals

DATA = Path(__file__).parent / "data" / "rings"
RINGS = [ring for f in sorted(DATA.glob("*.json")) for ring in json.loads(f.read_text())]


def _open(ring: list) -> np.ndarray:
    pts = np.array(ring, dtype=float)[:, :2]
    while len(pts) > 3 and (pts[0] == pts[-1]).all():
        pts = pts[:-1]
    return pts


def test_corpus_is_there():
    assert len(RINGS) >= 80
    assert sum(r["expected"]["simple"] for r in RINGS) >= 70


@pytest.mark.parametrize("item", RINGS, ids=[r["name"] for r in RINGS])
def test_ring_matches_the_independent_exact_method(item):
    pts = _open(item["ring"])
    want = item["expected"]
    distinct = len(np.unique(pts, axis=0)) == len(pts)
    assert want["simple"] == (distinct and exact_simple(pts))
    if not want["simple"]:
        with pytest.raises(InvalidPolygonError):
            optri.triangulate(item["ring"])
        return
    c = ccw(pts)
    mask = exact_mask(c)
    count, best = exact_count(mask), perimeter_dp(c, mask)
    assert (str(count), best) == (want["triangulations"], want["perimeter_sum"])
    t = optri.triangulate(item["ring"])
    assert t.n == want["n"] and math.isclose(t.weight, best, rel_tol=1e-9)
    t.check()
    assert optri.count_triangulations(item["ring"]) == count
    poly = optri.as_polygon(item["ring"])
    assert poly.convex or np.array_equal(valid_diagonals(poly), mask)
