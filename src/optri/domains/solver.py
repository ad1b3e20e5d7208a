"""``triangulate_domain``: the optimal triangulation of a polygon with holes."""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import config
from ..errors import EngineUnavailableError, WeightError
from ..objective import Cost, Objective, ObjectiveLike, as_objective
from ..result import Triangulation
from ..weights import WeightLike, resolve_weights
from .candidates import find_candidates
from .domain import Domain, as_domain
from .pieces import Gate
from .search import Found, Setup, solve_component, total
from .weighing import DomainWeight, domain_weights

__all__ = ["METHODS", "triangulate_domain"]

#: ``method=`` values for a polygon with holes.
METHODS = {
    "auto": "exact: the DP on every simply connected block, HiGHS on the rest",
    "ip": "exact: HiGHS on every block (no DP), for cross-checks",
    "bridge": "heuristic: holes bridged along short diagonals, then the exact DP",
}


def triangulate_domain(
    exterior: ArrayLike | Domain,
    holes: Sequence[ArrayLike] = (),
    weight: WeightLike | Sequence[WeightLike] = "perimeter",
    objective: ObjectiveLike = "sum",
    method: str = "auto",
    *,
    time_limit: float | None = None,
) -> Triangulation:
    """Optimal triangulation of a polygon with holes (an integer program, DP where it reaches).

    Parameters
    ----------
    exterior : array_like or Domain
        ``(n, 2)`` outer ring (either orientation, closing vertex optional),
        or a :class:`~optri.domains.Domain`.
    holes : sequence of array_like
        The holes' rings. Vertices are numbered exterior first, then each hole
        in order.
    weight : str, callable or pair
        Any weight of :data:`optri.weights.WEIGHTS` that reads coordinates,
        or a callable ``w(i, k, j)`` / ``w(vertices, i, k, j)`` called with the
        triangle's indices in increasing order.
    objective : {"sum", "max"} or tuple
        ``"sum"``, ``"max"``, or a lexicographic tuple whose ``"sum"`` (if any)
        comes last, such as ``("max", "sum")``.
    method : {"auto", "ip", "bridge"}
        See :data:`METHODS`.
    time_limit : float, optional
        Seconds for the search (default :data:`optri.config.DOMAIN_TIME_LIMIT`,
        None: no limit). When it runs out, the best triangulation found is
        returned with ``optimality="heuristic"`` and a proven lower bound.

    Returns
    -------
    Triangulation
        ``n + 2 h - 2`` counter-clockwise triangles over the domain's vertex
        numbering; ``optimality``, ``bound``, ``gap`` say how good it is
        proven to be; ``rings`` holds the ring sizes.

    Raises
    ------
    InvalidPolygonError
        A ring that is not simple, rings that meet, a hole outside the exterior...
    WeightError
        A weight for vertex values, an objective with ``"sum"`` before another
        component, a weight returning NaN.
    EngineUnavailableError
        An unknown ``method``.
    MissingDependencyError
        scipy is missing where the integer program is needed
        (``pip install 'optri[holes]'``).

    Notes
    -----
    Candidate triangles (empty, sides on the boundary or valid diagonals) are
    the variables of a 0/1 program whose constraints cover each boundary edge
    once and use each diagonal on both sides or neither. Diagonals that no
    other crosses are forced; they cut the domain into blocks, and a block
    with no hole is solved by the DP over its boundary walk. Optimal
    triangulation of polygons with holes is NP-hard in general (Mulzer and
    Rote 2008): time grows quickly with the holes' number and the vertices'
    mutual visibility.

    References
    ----------
    .. [1] W. Mulzer, G. Rote, "Minimum-weight triangulation is NP-hard",
       J. ACM 55(2), 2008, https://doi.org/10.1145/1346330.1346336
    .. [2] G. T. Klincsek, "Minimal triangulations of polygonal domains",
       Annals of Discrete Mathematics 9, 1980.

    Examples
    --------
    >>> t = triangulate_domain([[0, 0], [3, 0], [3, 3], [0, 3]],
    ...                        [[[1, 1], [2, 1], [2, 2], [1, 2]]], weight="diagonal")
    >>> len(t.triangles), t.optimality, round(t.weight, 6)    # 8 + 2 - 2 triangles
    (8, 'proven', 14.601126)
    >>> t.check()
    """
    domain = exterior if isinstance(exterior, Domain) else as_domain(exterior, holes)
    obj = as_objective(objective)
    _check_objective(obj)
    if method not in METHODS:
        raise EngineUnavailableError(
            f"unknown method {method!r} for a polygon with holes; choose one of: "
            f"{', '.join(METHODS)}"
        )
    limit = config.DOMAIN_TIME_LIMIT if time_limit is None else time_limit
    start = time.perf_counter()
    weights = domain_weights(domain, resolve_weights(weight, len(obj.components)))
    cand = find_candidates(domain)
    values = np.column_stack([w.on(cand) for w in weights])
    usable = np.zeros((domain.n, domain.n), dtype=bool)
    usable[cand.edges[:, 0], cand.edges[:, 1]] = True
    usable |= usable.T
    setup = Setup(
        domain,
        cand,
        usable,
        weights,
        values,
        method,
        None if limit is None else start + float(limit),
    )
    setup.stats.update(
        candidate_triangles=len(cand.triangles),
        valid_diagonals=len(cand.edges) - cand.n_boundary,
        candidates_seconds=time.perf_counter() - start,
    )
    phases = _phases(setup, obj)
    return _result(setup, obj, phases, time.perf_counter() - start)


def _check_objective(obj: Objective) -> None:
    comps = obj.components
    if "sum" in comps[:-1]:
        raise WeightError(
            f"objective {obj.name!r}: for a polygon with holes a 'sum' component must come "
            f"last (supported: 'sum', 'max', ('max', 'sum'), ...)"
        )


def _phases(setup: Setup, obj: Objective) -> list[Found]:
    """Each component in turn; a ``"max"`` optimum gates the triangles of those after it."""
    keep = np.all(np.isfinite(setup.values), axis=1)  # an infinite weight forbids a triangle
    gates: tuple[Gate, ...] = ()
    incumbent = None
    out = []
    for c, comp in enumerate(obj.components):
        found = solve_component(setup, keep, c, comp, gates, incumbent)
        out.append(found)
        if comp == "max":
            keep = keep & (setup.values[:, c] <= found.value)
            gates = (*gates, Gate(setup.weights[c], found.value))
            incumbent = found.chosen
    return out


def _result(setup: Setup, obj: Objective, phases: list[Found], seconds: float) -> Triangulation:
    domain, last = setup.domain, phases[-1]
    chosen = np.sort(last.chosen)
    tris = setup.cand.triangles[chosen]
    parts = [total(setup.values[chosen, c], comp) for c, comp in enumerate(obj.components)]
    proven = all(f.proven for f in phases)
    bounds = [f.bound for f in phases]
    # a later component's bound holds only once the earlier ones are proven
    for m in range(1, len(bounds)):
        if not phases[m - 1].proven:
            bounds[m] = -math.inf
    first_open = next((m for m, f in enumerate(phases) if not f.proven), None)
    gap = 0.0 if first_open is None else _gap(parts[first_open], bounds[first_open])
    weight: Cost = tuple(parts) if obj.is_lex else parts[0]
    bound: Cost = tuple(bounds) if obj.is_lex else bounds[0]
    names = tuple(w.weight.name for w in setup.weights)
    stats = dict(setup.stats)
    return Triangulation(
        vertices=domain.vertices,
        triangles=tris,
        weight=obj.finalize(weight),
        method="+".join(sorted(setup.parts)) or "dp",
        weight_name=names if obj.is_lex else names[0],
        objective=obj.name,
        orientation=domain.orientation,
        order=np.arange(domain.n, dtype=np.int64),
        stats=stats,  # type: ignore[arg-type]
        seconds=seconds,
        _recompute=_recompute(setup.weights, obj),
        optimality="proven" if proven else "heuristic",
        bound=bound,
        gap=gap,
        rings=domain.sizes,
    )


def _gap(value: float, bound: float) -> float:
    """Relative gap ``(value - bound) / |value|`` (inf without a bound)."""
    if not math.isfinite(bound):
        return math.inf
    return max(0.0, value - bound) / max(abs(value), 1e-300)


def _recompute(weights: tuple[DomainWeight, ...], obj: Objective) -> Any:
    def again(triangles: NDArray[np.int64]) -> Cost:
        cols = [[w(*t) for t in triangles.tolist()] for w in weights]
        parts = [total(np.array(col), comp) for col, comp in zip(cols, obj.components)]
        return obj.finalize(tuple(parts) if obj.is_lex else parts[0])

    return again
