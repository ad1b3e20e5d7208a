"""The search modes of :func:`optri.fill_polyline` and its result.

``fill_all`` runs the exact search or Liepa's recurrence over every triangle
(for triangle weights: the normal engines over a chord mask);
``fill_delaunay`` tries the candidate sets of :mod:`optri.holes.candidates`
one after the other. Both return the patch's triangles or None when the
allowed chords admit no patch.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from .. import config
from ..engines.memory import available_memory_bytes
from ..engines.problem import Problem
from ..errors import InvalidPolygonError, NoTriangulationError, WeightError
from ..objective import Cost, ObjectiveLike
from ..polygon import Polygon
from ..result import Triangulation, recompute_cost
from ..solve import build_problem, solve_problem
from ..weights import get_weight
from . import search
from .candidates import candidate_sets
from .liepa import angle_of_key, liepa_keys

__all__ = ["METHODS", "Hole", "degenerate_count", "fill_all", "fill_delaunay", "result"]

#: Accepted ``method`` values.
METHODS = ("auto", "exact", "liepa", "delaunay")

Tris = NDArray[np.int64]


class Hole(NamedTuple):
    """One fill request: points, what to minimize, which chords may be used.

    ``Q``: the points (+ third points) scaled by ``2 ** -exponent``
    (:func:`optri.holes.liepa.power_of_two_scale`); ``P``: the points as given.
    """

    P: NDArray[np.float64]
    Q: NDArray[np.float64]
    exponent: int
    n: int
    has_third: bool
    weight: Any
    objective: ObjectiveLike
    liepa: bool
    allowed: NDArray[np.bool_]


def fill_all(hole: Hole, method: str, stats: dict[str, Any]) -> tuple[Tris | None, str]:
    """The best patch over every triangle (None if the allowed chords admit none)."""
    if not hole.liepa:  # a sum or max of triangle weights: the normal engines
        return _engine_fill(hole, hole.allowed), "exact"
    n = hole.n
    fits = search.exact_bytes(n) <= available_memory_bytes()
    exact = method == "exact" or (method == "auto" and n <= config.HOLES_EXACT_MAX_N and fits)
    if exact:
        search.require_exact_memory(n)  # refuse before Liepa's bound is computed
    tris = search.liepa_dense(hole.Q, n, hole.has_third, hole.allowed)
    if not exact or tris is None:
        return tris, "liepa"
    bound, _ = liepa_keys(hole.Q, n, hole.has_third, tris)
    stats["bound"] = angle_of_key(bound)  # Liepa's largest angle: the exact search's bound
    return search.exact_search(hole.Q, n, hole.has_third, hole.allowed, bound), "exact"


def fill_delaunay(hole: Hole, stats: dict[str, Any]) -> tuple[Tris | None, str]:
    """The best patch over the first candidate set holding one, else over all triangles."""
    n = hole.n
    for name, tris in candidate_sets(hole.Q[:n]):
        tris = tris[_uses_allowed(tris, hole.allowed)]
        if hole.liepa:
            found = search.liepa_sparse(hole.Q, n, hole.has_third, tris)
        else:
            found = _engine_fill(hole, hole.allowed & _chords_of(tris, n))
        if found is not None:
            stats.update(candidates=name, candidate_triangles=len(tris), fallback=0)
            return found, "delaunay"
    stats.update(candidates="all", fallback=1)
    found, used = fill_all(hole, "auto", stats)
    return found, f"delaunay->{used}"


def _uses_allowed(tris: Tris, allowed: NDArray[np.bool_]) -> NDArray[np.bool_]:
    i, k, j = tris[:, 0], tris[:, 1], tris[:, 2]
    return allowed[i, k] & allowed[k, j] & allowed[i, j]  # type: ignore[no-any-return]


def _chords_of(tris: Tris, n: int) -> NDArray[np.bool_]:
    """Chord mask of candidate triangles: their sides (polygon sides are always allowed)."""
    mask = np.zeros((n, n), dtype=np.bool_)
    for a, b in ((0, 1), (1, 2), (0, 2)):
        mask[tris[:, a], tris[:, b]] = mask[tris[:, b], tris[:, a]] = True
    return mask


def degenerate_count(Q: NDArray[np.float64], tris: Tris) -> int:
    """Zero-area triangles among ``tris`` (the searches' own test: sine <= 1e-12)."""
    from .._core import holes

    if len(tris) == 0:
        return 0
    return int(holes.triangle_normals(Q, np.sort(tris, axis=1))[:, 3].sum())


# --- triangle weights: the normal engines -------------------------------------------


def _problem(hole: Hole, allowed: NDArray[np.bool_] | None) -> Problem:
    # a 3-D polyline: every index triangulation is a surface, so every chord may be used
    P = hole.P
    polygon = Polygon(P, P, np.arange(hole.n, dtype=np.int64), None, True)
    problem = build_problem(polygon, hole.weight, hole.objective, keep_table=False)
    problem.allowed = None if allowed is None or allowed.all() else allowed
    return problem


def _engine_dp(hole: Hole, allowed: NDArray[np.bool_], gated: bool = False) -> Tris | None:
    problem = _problem(hole, allowed)
    if gated:
        gate = (get_weight("aspect_ratio"), float(config.HOLES_DEGENERATE_ASPECT))
        problem.gates = (*problem.gates, gate)
    try:
        return solve_problem(problem, "auto")[1].triangles
    except NoTriangulationError:
        if problem.allowed is None and not gated:
            raise
        return None  # the allowed chords (or non-degenerate triangles) hold no patch


def _engine_fill(hole: Hole, allowed: NDArray[np.bool_]) -> Tris | None:
    """The engines' optimum; one without zero-area triangles instead when it ties."""
    tris = _engine_dp(hole, allowed)
    if tris is None or degenerate_count(hole.Q, tris) == 0:
        return tris
    alt = _engine_dp(hole, allowed, gated=True)
    if alt is None or degenerate_count(hole.Q, alt) > 0:
        return tris
    again = _recompute(hole)
    return alt if _ties(again(alt), again(tris)) else tris


def _ties(a: Cost, b: Cost) -> bool:
    xs = a if isinstance(a, tuple) else (a,)
    ys = b if isinstance(b, tuple) else (b,)
    rtol = config.HOLES_TIE_RTOL
    return all(math.isclose(x, y, rel_tol=rtol, abs_tol=0.0) for x, y in zip(xs, ys))


def _recompute(hole: Hole) -> Callable[[Tris], Cost]:
    problem = _problem(hole, None)
    return recompute_cost(problem.evaluator(), problem.objective, problem.polygon.order)


# --- the result -----------------------------------------------------------------------


def result(
    hole: Hole, tris: Tris, method: str, stats: dict[str, Any], seconds: float
) -> Triangulation:
    """The :class:`Triangulation` of a patch, its value recomputed by the evaluator."""
    n = hole.n
    tris = tris[np.lexsort((tris[:, 2], tris[:, 1], tris[:, 0]))].astype(np.int64)
    again: Callable[[Tris], Cost]
    if hole.liepa:
        scale = 2 * hole.exponent

        def liepa_cost(t: Tris) -> Cost:
            key, area = liepa_keys(hole.Q, n, hole.has_third, t)
            try:
                return (angle_of_key(key), math.ldexp(area, scale))
            except OverflowError:
                raise InvalidPolygonError(
                    f"the patch's area overflows float64 (coordinates up to "
                    f"{float(np.abs(hole.P).max()):.3g}); scale the input down"
                ) from None

        again = liepa_cost
        name: Any = ("liepa_dihedral", "area")
        obj_name: Any = ("max", "sum")
    else:
        problem = _problem(hole, None)
        again = recompute_cost(problem.evaluator(), problem.objective, problem.polygon.order)
        names = tuple(w.name for w in problem.weights)
        name = names[0] if len(names) == 1 else names
        obj_name = problem.objective.name
    value = again(tris)
    if isinstance(value, float) and math.isnan(value):
        raise WeightError("the weight returned NaN")
    stats["degenerate"] = degenerate_count(hole.Q, tris)
    return Triangulation(
        vertices=hole.P,
        triangles=tris,
        weight=value,
        method=method,
        weight_name=name,
        objective=obj_name,
        orientation=None,
        order=np.arange(n, dtype=np.int64),
        stats=stats,
        seconds=seconds,
        _recompute=again,
    )
