"""One objective component over a domain, block by block: the DP where it reaches, else HiGHS.

``"sum"`` blocks are one integer program each. ``"max"`` blocks are solved by
bisection on the threshold: the smallest triangle weight ``t`` such that the
triangles of weight <= ``t`` still triangulate the block (each a feasibility
program). When the time runs out, the best triangulation found so far (the
solver's incumbent, the bridged DP, or the previous phase's) is kept and the
block is marked unproven, with the solver's bound.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .. import config
from ..errors import MissingDependencyError, NoTriangulationError, WeightError
from .bounds import max_floor, sum_floor
from .bridge import bridge_block
from .candidates import Candidates
from .domain import Domain
from .pieces import Gate, solve_walk
from .program import Outcome, side_keys, solve_program
from .reduce import Block, blocks, forced_diagonals, prune, trace_walk
from .weighing import DomainWeight

__all__ = ["Found", "Setup", "solve_component", "total"]


@dataclass
class Setup:
    """Everything the search reads: the domain, its candidates and their weights."""

    domain: Domain
    cand: Candidates
    usable: NDArray[np.bool_]
    weights: tuple[DomainWeight, ...]
    values: NDArray[np.float64]  # (T, components)
    method: str
    deadline: float | None = None
    stats: dict[str, float] = field(default_factory=dict)
    parts: set[str] = field(default_factory=set)
    _index: tuple[NDArray[np.int64], NDArray[np.int64]] | None = field(default=None, repr=False)

    def remaining(self) -> float | None:
        """Seconds left before the deadline (None: no limit)."""
        return None if self.deadline is None else self.deadline - time.perf_counter()

    def ids(self, tris: NDArray[np.int64]) -> NDArray[np.int64]:
        """Candidate ids of triangles given by domain indices."""
        if self._index is None:
            keys = _keys(self.cand.triangles, self.domain.n)
            order = np.argsort(keys)
            self._index = (keys[order], order)
        keys, order = self._index
        want = _keys(tris, self.domain.n)
        pos = np.minimum(np.searchsorted(keys, want), len(keys) - 1)
        if not np.array_equal(keys[pos], want):  # pragma: no cover - DP triangles are candidates
            raise NoTriangulationError("a DP triangle is not a candidate triangle")
        return order[pos].astype(np.int64)

    def count(self, key: str, by: float = 1) -> None:
        """Add ``by`` to statistic ``key``."""
        self.stats[key] = self.stats.get(key, 0) + by


def _keys(tris: NDArray[np.int64], n: int) -> NDArray[np.int64]:
    s = np.sort(tris, axis=1)
    return (s[:, 0] * n + s[:, 1]) * n + s[:, 2]


@dataclass(frozen=True)
class Found:
    """A triangulation (candidate ids), its value, a lower bound, and whether it is proven."""

    chosen: NDArray[np.int64]
    value: float
    bound: float
    proven: bool


def total(values: NDArray[np.float64], component: str) -> float:
    """Sum (exactly rounded) or maximum of triangle weights; ``-inf`` for none under max.

    Raises :class:`~optri.errors.WeightError` when a sum of finite weights passes
    float64's range (its rounded value would be infinite: no optimum to compare).
    """
    if component == "sum":
        try:
            return float(math.fsum(values.tolist()))
        except OverflowError:
            raise WeightError(
                "the triangle weights sum past float64's range (about 1.8e308); "
                "scale the coordinates down"
            ) from None
    return float(values.max()) if len(values) else -math.inf


def solve_component(
    setup: Setup,
    keep: NDArray[np.bool_],
    c: int,
    component: str,
    gates: tuple[Gate, ...] = (),
    incumbent: NDArray[np.int64] | None = None,
) -> Found:
    """Minimize component ``c`` over the triangulations made of ``keep`` triangles."""
    cand = setup.cand
    kept = prune(cand, keep)
    if kept is None:
        raise NoTriangulationError(
            "no triangulation of the polygon with holes uses only triangles of finite weight"
        )
    forced = forced_diagonals(cand, kept)
    setup.count("forced_diagonals", int(forced.sum()))
    fixed = ~cand.is_diagonal | forced
    found = [
        _block(setup, b, fixed, c, component, gates, incumbent) for b in blocks(cand, kept, fixed)
    ]
    chosen = np.concatenate([f.chosen for f in found])
    value = total(setup.values[chosen, c], component)
    bounds = [f.bound for f in found]
    bound = math.fsum(bounds) if component == "sum" else max(bounds)
    # under "max" an unproven block below a proven maximum elsewhere leaves no gap
    proven = all(f.proven for f in found) or _meets(value, bound)
    return Found(chosen, value, value if proven else min(bound, value), proven)


def _meets(value: float, bound: float) -> bool:
    """``value`` is within the proven tolerance of its lower ``bound``, relative at every scale."""
    return value - bound <= config.DOMAIN_PROVEN_RTOL * abs(value)


def _block(
    setup: Setup,
    block: Block,
    fixed: NDArray[np.bool_],
    c: int,
    component: str,
    gates: tuple[Gate, ...],
    incumbent: NDArray[np.int64] | None,
) -> Found:
    points = setup.domain.vertices
    setup.count("blocks")
    walk = None if setup.method == "ip" else trace_walk(points, block.fixed)
    if walk is not None:
        setup.count("dp_blocks")
        setup.parts.add("dp")
        tris, _ = solve_walk(points, setup.usable, walk, setup.weights[c], component, gates)
        ids = setup.ids(tris)
        value = total(setup.values[ids, c], component)
        return Found(ids, value, value, True)
    setup.count("ip_blocks")

    def fallbacks() -> list[NDArray[np.int64]]:
        """Triangulations of the block known without the solver (may be none)."""
        out = [] if incumbent is None else [np.intersect1d(incumbent, block.triangles)]
        tris = bridge_block(
            points, setup.usable, setup.cand, block, fixed, setup.weights[c], component, gates
        )
        return out if tris is None else [*out, setup.ids(tris)]

    if setup.method == "bridge":
        setup.parts.add("bridge")
        return _best(setup, fallbacks(), c, component, _bound(setup, block, fixed, c, component))
    setup.parts.add("ip")
    if component == "sum":
        return _sum_block(setup, block, fixed, c, fallbacks)
    return _max_block(setup, block, fixed, c, fallbacks())


def _best(
    setup: Setup, options: Sequence[NDArray[np.int64]], c: int, component: str, bound: float
) -> Found:
    """The best of ``options``: proven after all when it meets ``bound``."""
    if not options:
        raise NoTriangulationError(
            "the time limit was reached before any triangulation of "
            "the polygon with holes was found"
        )
    values = [total(setup.values[o, c], component) for o in options]
    m = int(np.argmin(values))
    value = values[m]
    proven = _meets(value, bound)
    return Found(options[m], value, value if proven else min(bound, value), proven)


def _solve(
    setup: Setup, tris: NDArray[np.int64], fixed: NDArray[np.bool_], costs: Any, **kw: Any
) -> Outcome:
    out = solve_program(setup.cand, tris, fixed, costs, setup.remaining(), **kw)
    setup.count("solver_calls")
    setup.count("solver_nodes", out.nodes)
    return out


def _sum_block(
    setup: Setup,
    block: Block,
    fixed: NDArray[np.bool_],
    c: int,
    fallbacks: Callable[[], list[NDArray[np.int64]]],
) -> Found:
    out = _solve(setup, block.triangles, fixed, setup.values[block.triangles, c])
    if out.status == "infeasible":  # pragma: no cover - every block has a triangulation
        raise NoTriangulationError(
            "no triangulation of the polygon with holes satisfies the constraints"
        )
    if out.status == "optimal" and out.chosen is not None:
        # re-checked in float64 against the pieces' own weights, not the solver's word
        value = total(setup.values[out.chosen, c], "sum")
        if _meets(value, out.bound):
            return Found(out.chosen, value, value, True)
    setup.parts.add("bridge")
    options = ([] if out.chosen is None else [out.chosen]) + fallbacks()
    floor = sum_floor(setup.cand, block, fixed, setup.values[:, c])
    return _best(setup, options, c, "sum", max(out.bound, floor))


def _bound(setup: Setup, block: Block, fixed: NDArray[np.bool_], c: int, component: str) -> float:
    """A lower bound on the block's optimum: a floor (:mod:`.bounds`), or the LP relaxation."""
    if component == "max":
        return max_floor(setup.cand, block, fixed, setup.values[:, c])
    floor = sum_floor(setup.cand, block, fixed, setup.values[:, c])
    try:
        out = _solve(setup, block.triangles, fixed, setup.values[block.triangles, c], relax=True)
    except MissingDependencyError:
        return floor
    return max(floor, out.bound)


def _max_block(
    setup: Setup, block: Block, fixed: NDArray[np.bool_], c: int, fallbacks: list[NDArray[np.int64]]
) -> Found:
    """Bisection on the threshold over the block's distinct triangle weights."""
    t, vals = block.triangles, setup.values[block.triangles, c]
    floor = max_floor(setup.cand, block, fixed, setup.values[:, c])
    required = side_keys(setup.cand, t, fixed)
    if fallbacks:
        best = min(fallbacks, key=lambda o: total(setup.values[o, c], "max"))
    else:
        out = _solve(setup, t, fixed, None)
        if out.chosen is None:
            return _best(setup, [], c, "max", floor)
        best = out.chosen
    levels = np.unique(vals[(vals >= floor) & (vals < total(setup.values[best, c], "max"))])
    lo, hi = 0, len(levels)  # below levels[lo]: infeasible; best has value <= levels[hi]
    while lo < hi:
        left = setup.remaining()
        if left is not None and left <= 0:
            break
        mid = (lo + hi) // 2
        below = t[vals <= levels[mid]]
        # feasibility; the weights as costs make the relaxation's optimum a 0/1 point more often
        out = _solve(setup, below, fixed, setup.values[below, c], required=required)
        if out.status == "infeasible":
            lo = mid + 1
        elif out.status == "optimal" and out.chosen is not None:
            best = out.chosen
            hi = int(np.searchsorted(levels, total(setup.values[best, c], "max")))
        else:
            break  # time limit
    value = total(setup.values[best, c], "max")
    if lo >= hi:
        return Found(best, value, value, True)
    setup.parts.add("bridge")
    return Found(best, value, float(levels[lo]), False)
