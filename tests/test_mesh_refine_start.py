"""Where ``fill_holes(refine=True)`` starts: the search mode of the coarse patch.

With ``method="auto"`` a refined hole of more than ``config.HOLES_REFINE_EXACT_MAX_N``
edges starts from Liepa's recurrence over Delaunay candidates; every other case keeps
the mode ``fill_holes`` uses without refinement. The threshold is lowered here so that
a small hole crosses it.
"""

from __future__ import annotations

import numpy as np
import pytest

from optri import config, fill_holes
from optri.holes.intersect import intersecting_pairs

pytest.importorskip("scipy")


def _cap_hole():
    """A sphere (unit, 642 vertices) with the cap above z = 0.6 cut off: one loop."""
    trimesh = pytest.importorskip("trimesh")
    s = trimesh.creation.icosphere(subdivisions=3)
    keep = s.vertices[s.faces].mean(axis=1)[:, 2] < 0.6
    return np.asarray(s.vertices), np.asarray(s.faces)[keep]


@pytest.fixture
def low_threshold(monkeypatch):
    monkeypatch.setattr(config, "HOLES_REFINE_EXACT_MAX_N", 10)


@pytest.mark.parametrize(
    ("method", "refine", "expected"),
    [
        ("auto", True, "delaunay"),
        ("auto", False, "exact"),
        ("exact", True, "exact"),
        ("liepa", True, "liepa"),
    ],
)
def test_mode_of_the_coarse_patch(low_threshold, method, refine, expected):
    v, f = _cap_hole()
    (v2, f2), records = fill_holes((v, f), method=method, refine=refine, fair=1 if refine else None)
    (rec,) = records
    assert rec.edges > config.HOLES_REFINE_EXACT_MAX_N
    assert rec.status == "filled" and rec.method == expected
    if refine:
        assert rec.vertices_added > 0 and rec.faired
        assert rec.self_intersections == len(intersecting_pairs(v2, f2, f2[len(f) :])) == 0
        # the new vertices lie near the unit sphere the cap was cut from (a flat cap: 0.4)
        assert np.abs(np.linalg.norm(v2[len(v) :], axis=1) - 1).max() < 0.1


def test_small_refined_holes_start_from_the_exact_patch():
    v, f = _cap_hole()
    _, records = fill_holes((v, f), refine=True, fair=1)
    assert records[0].edges <= config.HOLES_REFINE_EXACT_MAX_N
    assert records[0].method == "exact"
