"""The search modes of :func:`optri.fill_polyline` and its result.

``fill_all`` runs the exact search or Liepa's recurrence over every triangle
(for triangle weights: the normal engines over a chord mask);
``fill_delaunay`` tries the candidate sets of :mod:`optri.holes.candidates`
one after the other. Both return the patch's triangles or None when the
allowed chords admit no patch.

Degenerate (zero-area) triangles come first in every mode: a patch has the
fewest that any patch over the allowed chords has, and among those the best
objective. A triangle is degenerate when its points are exactly collinear
(:func:`degenerate_count`). A patch a search returns without one is kept as
it is; one with some is replaced by the least (count, objective) patch:

* Liepa's objective: a degenerate triangle is worse than any fold in both
  searches, so their patch has one only when every patch has one; every patch
  is then worth (pi, area), and :func:`optri.holes.search.fewest_degenerate`
  (the least (count, area) patch) is the exact optimum of (count, objective);
* triangle weights: the least (count, objective) patch, by a compiled search
  for built-in weights (see ``_engine_fill`` for callables and pairs);
* ``"delaunay"``: a candidate set whose patch has a degenerate triangle is
  widened like one holding no patch, unless no patch at all avoids them.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from .. import config
from ..engines.memory import available_memory_bytes
from ..engines.problem import Problem
from ..errors import InvalidPolygonError, NoTriangulationError, OptriError, WeightError
from ..objective import Cost, ObjectiveLike, as_objective
from ..polygon import Polygon
from ..result import Triangulation, recompute_cost
from ..solve import build_problem, solve_problem
from ..weights import Weight, WeightCode, custom_weight, resolve_weights
from . import search
from .candidates import candidate_sets
from .liepa import angle_of_key, liepa_keys

__all__ = [
    "METHODS",
    "Hole",
    "degenerate_count",
    "fill_all",
    "fill_delaunay",
    "problem_of",
    "recompute_of",
    "result",
]

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
        return _engine_fill(hole, hole.allowed, stats), "exact"
    n = hole.n
    fits = search.exact_bytes(n) <= available_memory_bytes()
    exact = method == "exact" or (method == "auto" and n <= config.HOLES_EXACT_MAX_N and fits)
    if exact:
        search.require_exact_memory(n)  # refuse before Liepa's bound is computed
    tris = search.liepa_dense(hole.Q, n, hole.has_third, hole.allowed)
    if not exact or tris is None:
        return _fewest(hole, tris, hole.allowed, stats), "liepa"
    bound, _ = liepa_keys(hole.Q, n, hole.has_third, tris)
    stats["bound"] = angle_of_key(bound)  # Liepa's largest angle: the exact search's bound
    tris = search.exact_search(hole.Q, n, hole.has_third, hole.allowed, bound)
    return _fewest(hole, tris, hole.allowed, stats), "exact"


def fill_delaunay(
    hole: Hole, stats: dict[str, Any], faces: Tris | None = None
) -> tuple[Tris | None, str]:
    """The best patch over the first candidate set holding one, else over all triangles.

    A set whose best patch has a degenerate triangle counts as holding none
    while some patch over all triangles has none. ``faces``: the Delaunay faces
    to start from (see :func:`~optri.holes.candidates.candidate_sets`).
    """
    n = hole.n
    fewest: int | None = None  # over all allowed chords, known once a set needs it
    for name, tris in candidate_sets(hole.Q[:n], faces):
        tris = tris[_uses_allowed(tris, hole.allowed)]
        sub: dict[str, Any] = {}
        if hole.liepa:
            found = search.liepa_sparse(hole.Q, n, hole.has_third, tris)
        else:
            found = _engine_fill(hole, hole.allowed & _chords_of(tris, n), sub)
        if found is not None and degenerate_count(hole.P, found):
            if fewest is None:
                least = search.fewest_degenerate(hole.P, hole.Q, n, hole.allowed)
                fewest = least[0] if least is not None else 0
            if fewest > 0:
                break  # no set avoids them: the search over all triangles counts them
            found = None
        if found is not None:
            stats.update(candidates=name, candidate_triangles=len(tris), fallback=0)
            return found, "delaunay"
    stats.update(candidates="all", fallback=1)
    found, used = fill_all(hole, "auto", stats)
    return found, f"delaunay->{used}"


def _fewest(
    hole: Hole, tris: Tris | None, allowed: NDArray[np.bool_], stats: dict[str, Any]
) -> Tris | None:
    """``tris`` when it has no degenerate triangle, else the least (count, area) patch.

    Only for Liepa's objective, whose searches return a degenerate triangle only
    when every patch has one (then every patch is worth (pi, area)).
    """
    if tris is None or degenerate_count(hole.P, tris) == 0:
        return tris
    found = search.fewest_degenerate(hole.P, hole.Q, hole.n, allowed)
    if found is None:  # cannot happen: tris is a patch over these chords
        raise OptriError("internal error: the fewest-degenerate search found no patch")
    stats["degenerate_minimum"] = found[0]
    return found[1]


def _uses_allowed(tris: Tris, allowed: NDArray[np.bool_]) -> NDArray[np.bool_]:
    i, k, j = tris[:, 0], tris[:, 1], tris[:, 2]
    return allowed[i, k] & allowed[k, j] & allowed[i, j]  # type: ignore[no-any-return]


def _chords_of(tris: Tris, n: int) -> NDArray[np.bool_]:
    """Chord mask of candidate triangles: their sides (polygon sides are always allowed)."""
    mask = np.zeros((n, n), dtype=np.bool_)
    for a, b in ((0, 1), (1, 2), (0, 2)):
        mask[tris[:, a], tris[:, b]] = mask[tris[:, b], tris[:, a]] = True
    return mask


def degenerate_count(P: NDArray[np.float64], tris: Tris) -> int:
    """Degenerate triangles among ``tris``: their points are exactly collinear.

    Decided by exact orientation tests (no tolerance): a triangle of ``P``'s
    rows is degenerate when its projections on the three coordinate planes all
    have orientation 0.

    >>> P = np.array([[0., 0, 0], [1, 0, 0], [2, 0, 0], [1, 1e-300, 0]])
    >>> degenerate_count(P, np.array([[0, 1, 2], [0, 1, 3], [0, 2, 3]]))
    1
    """
    from .._core import holes

    if len(tris) == 0:
        return 0
    return int(holes.collinear(P, np.ascontiguousarray(tris, dtype=np.int64)).sum())


# --- triangle weights: the normal engines -------------------------------------------


def recompute_of(hole: Hole) -> Callable[[Tris], Cost]:
    """The cost of a patch from scratch under the hole's triangle weights and objective."""
    problem = problem_of(hole, None)
    return recompute_cost(problem.evaluator(), problem.objective, problem.polygon.order)


def problem_of(hole: Hole, allowed: NDArray[np.bool_] | None) -> Problem:
    """The engines' problem for a triangle-weight hole, ``allowed`` as its chord mask."""
    # a 3-D polyline: every index triangulation is a surface, so every chord may be used
    P = hole.P
    polygon = Polygon(P, P, np.arange(hole.n, dtype=np.int64), None, True)
    problem = build_problem(polygon, hole.weight, hole.objective, keep_table=False)
    problem.allowed = None if allowed is None or allowed.all() else allowed
    return problem


def _engine_dp(
    hole: Hole, allowed: NDArray[np.bool_], problem: Problem | None = None
) -> Tris | None:
    problem = problem_of(hole, allowed) if problem is None else problem
    try:
        with warnings.catch_warnings():  # the user's callable already runs in Python
            warnings.filterwarnings("ignore", "weight 'degenerate'", RuntimeWarning)
            return solve_problem(problem, "auto")[1].triangles
    except NoTriangulationError:
        if problem.allowed is None and not problem.gates:
            raise
        return None  # the allowed chords (or non-degenerate triangles) hold no patch


def _degenerate_weight(hole: Hole) -> Weight:
    """1.0 on an exactly collinear triangle, else 0.0 (input indices are polyline indices)."""
    from .._core import holes

    P = hole.P

    def degenerate(i: int, k: int, j: int) -> float:
        return 1.0 if holes.is_collinear(P, i, k, j) else 0.0

    return custom_weight(degenerate, "degenerate")


def _engine_fill(hole: Hole, allowed: NDArray[np.bool_], stats: dict[str, Any]) -> Tris | None:
    """The least (degenerate count, objective) patch over the allowed chords.

    The engines' optimum when it has no degenerate triangle. Otherwise, for a
    built-in weight and a one-component objective, the compiled (count, sum or
    max) search; for a user callable (which runs in Python anyway) the engines
    with degenerate triangles gated out exactly, or with the pair (count,
    objective) when every patch has some; for a pair objective, which cannot
    take a third component, the fewest and then the least area.
    """
    tris = _engine_dp(hole, allowed)
    if tris is None or degenerate_count(hole.P, tris) == 0:
        return tris
    components = as_objective(hole.objective).components
    weights = resolve_weights(hole.weight, len(components))
    weight = weights[0]
    builtin = weight.code != WeightCode.CUSTOM
    if builtin and len(weights) == 1:
        found = search.fewest_then_weight(
            hole.P, hole.n, int(weight.code), components[0] == "max", allowed
        )
    else:
        found = search.fewest_degenerate(hole.P, hole.Q, hole.n, allowed)
    if found is None:  # cannot happen: tris is a patch over these chords
        raise OptriError("internal error: the fewest-degenerate search found no patch")
    stats["degenerate_minimum"] = found[0]
    if builtin or len(weights) > 1:
        return found[1]
    flag = _degenerate_weight(hole)
    if found[0] == 0:
        problem = problem_of(hole, allowed)
        problem.gates = (*problem.gates, (flag, 0.5))
    else:
        polygon = Polygon(hole.P, hole.P, np.arange(hole.n, dtype=np.int64), None, True)
        problem = build_problem(polygon, (flag, weight), ("sum", components[0]), keep_table=False)
        problem.allowed = None if allowed.all() else allowed
    return _engine_dp(hole, allowed, problem)


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
        problem = problem_of(hole, None)
        again = recompute_cost(problem.evaluator(), problem.objective, problem.polygon.order)
        names = tuple(w.name for w in problem.weights)
        name = names[0] if len(names) == 1 else names
        obj_name = problem.objective.name
    value = again(tris)
    if isinstance(value, float) and math.isnan(value):
        raise WeightError("the weight returned NaN")
    stats["degenerate"] = count = degenerate_count(hole.P, tris)
    # a patch with some is the fewest over the allowed chords: every path proves it
    stats["degenerate_unavoidable"] = count > 0 and stats.get("degenerate_minimum") == count
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
