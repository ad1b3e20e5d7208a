"""A polygon with holes labelled "proven" is optimal at every scale of its coordinates.

The ring is martinez's ``issue96`` clipping fixture (origin in tests/data/README.md): 946
vertices, one hole, coordinates in degrees. Its integer program used to be posed in the
data's units, where HiGHS's absolute tolerances stopped the search early and the answer
was still called "proven". Oracle: the bridge heuristic's tiling, a valid triangulation,
is an upper bound on the optimum, and scaling by a power of two scales every weight
exactly, so the optimum scales exactly too.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import optri

pytest.importorskip("scipy")

RINGS = Path(__file__).parent / "data" / "rings" / "martinez_issue96.geojson"


def _issue96() -> tuple[np.ndarray, list[np.ndarray]]:
    feature = json.loads(RINGS.read_text())["features"][0]
    outer, hole = feature["geometry"]["coordinates"][0]
    return np.array(outer[:-1]), [np.array(hole[:-1])]


@pytest.mark.slow
@pytest.mark.parametrize("exponent", [-20, 0, 20])
def test_proven_means_optimal_at_every_scale(exponent: int) -> None:
    outer, holes = _issue96()
    s = math.ldexp(1.0, exponent)
    polygon = (outer * s, [h * s for h in holes])
    got = optri.triangulate(polygon, "diagonal")
    tiling = optri.triangulate(polygon, "diagonal", method="bridge")
    assert got.n == 946
    got.check()
    # never worse than a known tiling; "proven" may not hide a gap the tiling shows
    assert got.weight <= tiling.weight * (1 + 1e-12)
    assert got.bound <= got.weight
    if got.optimality == "proven":
        assert got.weight - tiling.weight <= 1e-9 * tiling.weight
    else:
        assert got.gap == pytest.approx((got.weight - got.bound) / got.weight)
    # the same program at every scale: the answer in the data's units scales exactly
    assert got.weight / s == pytest.approx(0.23525686641164514, rel=1e-12)


@pytest.mark.parametrize("method", ["auto", "ip", "bridge"])
def test_weights_summing_past_float64_are_a_clear_error(method: str) -> None:
    # every triangle's perimeter is finite, their sum is not
    outer = np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float) * 2e306
    hole = np.array([[4, 4], [4, 6], [6, 6], [6, 4]], float) * 2e306
    with pytest.raises(optri.WeightError, match="float64"):
        optri.triangulate((outer, [hole]), "perimeter", method=method)


def test_a_solver_optimum_that_misses_its_bound_is_not_called_proven(monkeypatch) -> None:
    # a solver saying "optimal" with a bound its solution does not meet in float64
    import optri.domains.search as search

    real = search.solve_program

    def lying(*args, **kwargs):
        out = real(*args, **kwargs)
        if out.status != "optimal" or kwargs.get("relax"):
            return out
        return type(out)(out.chosen, out.bound - 0.25 * abs(out.bound), out.status, out.nodes)

    monkeypatch.setattr(search, "solve_program", lying)
    outer = [[0, 0], [10, 0], [10, 10], [0, 10]]
    hole = [[4, 4], [4, 6], [6, 6], [6, 4]]
    got = optri.triangulate((outer, [hole]), "perimeter", method="ip")
    got.check()
    assert got.optimality == "heuristic", (got.optimality, got.bound, got.weight)
    assert got.bound <= got.weight and got.gap > 0
