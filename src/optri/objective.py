"""Objectives: how triangle weights add up to a triangulation's cost.

``"sum"``
    total of the triangle weights (the paper's Eq. 3).
``"max"``
    the largest triangle weight (bottleneck: e.g. minimize the largest angle).
``("max", "sum")`` and other pairs
    lexicographic: first component compared first, ties broken by the second,
    with one weight per component (Liepa 2003 uses (max dihedral, total area)).

Every engine minimizes ``cost(i, j) = best_k combine(cost(i, k), cost(k, j),
w(i, k, j))``; this module defines ``combine``, the order ``less``, and the
neutral cost of a polygon side.
"""

from __future__ import annotations

import math
import operator
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Union

from .errors import WeightError

__all__ = ["Cost", "Objective", "ObjectiveLike", "as_objective"]

Cost = Union[float, tuple[float, ...]]
ObjectiveLike = Union[str, Sequence[str], "Objective"]

_COMPONENTS = ("sum", "max")


@dataclass(frozen=True)
class Objective:
    """A scalar (``"sum"``/``"max"``) or lexicographic objective.

    Examples
    --------
    >>> o = as_objective(("max", "sum"))
    >>> o.combine((1.0, 2.0), (3.0, 4.0), (2.0, 0.5))
    (3.0, 6.5)
    >>> o.less((3.0, 6.5), (3.0, 7.0))
    True
    """

    components: tuple[str, ...]

    @property
    def is_lex(self) -> bool:
        """True for a lexicographic pair."""
        return len(self.components) > 1

    @property
    def name(self) -> str | tuple[str, ...]:
        """``"sum"``, ``"max"`` or the tuple of components."""
        return self.components if self.is_lex else self.components[0]

    @property
    def two_phase(self) -> bool:
        """True for a lexicographic objective led by ``"max"``: solved in two phases.

        Such a pair is not monotone under the recurrence (a sub-polygon with a
        smaller maximum but a larger secondary cost can lose later, once a
        larger maximum elsewhere dominates), so it is solved exactly in two
        phases: first the bottleneck value M* of the primary weight alone, then
        the remaining components over the triangulations whose triangles all
        have primary weight <= M* (a *gate*, :attr:`optri.engines.problem.Problem.gates`).
        A ``"sum"`` primary is monotone and runs as one lexicographic DP.

        >>> as_objective(("max", "sum")).two_phase, as_objective(("sum", "max")).two_phase
        (True, False)
        """
        return self.is_lex and self.components[0] == "max"

    @property
    def neutral(self) -> Cost:
        """Cost of a polygon side (an empty triangulation)."""
        vals = tuple(0.0 if c == "sum" else -math.inf for c in self.components)
        return vals if self.is_lex else vals[0]

    @property
    def worst(self) -> Cost:
        """Cost of an unreachable sub-polygon (no valid split)."""
        return (math.inf,) * len(self.components) if self.is_lex else math.inf

    @property
    def combine(self) -> Callable[[Any, Any, Any], Any]:
        """``combine(a, b, w)``: cost of a split from its two halves and triangle."""
        if not self.is_lex:
            return _sum3 if self.components[0] == "sum" else _max3
        fns = tuple(_sum3 if c == "sum" else _max3 for c in self.components)
        return lambda a, b, w: tuple(f(x, y, z) for f, x, y, z in zip(fns, a, b, w))

    @property
    def less(self) -> Callable[[Any, Any], bool]:
        """Strict order on costs (tuples compare lexicographically)."""
        return operator.lt

    def aggregate(self, weights: Sequence[Cost]) -> Cost:
        """Cost of a whole triangulation from its triangle weights."""
        if not self.is_lex:
            return _fold(self.components[0], weights)  # type: ignore[arg-type]
        cols = list(zip(*weights)) or [()] * len(self.components)
        return tuple(_fold(c, col) for c, col in zip(self.components, cols))

    def finalize(self, cost: Cost) -> Cost:
        """Map the neutral value of a degenerate result to 0 (no triangles)."""
        if self.is_lex:
            return tuple(0.0 if v == -math.inf else v for v in cost)  # type: ignore[union-attr]
        return 0.0 if cost == -math.inf else cost


def as_objective(spec: ObjectiveLike) -> Objective:
    """Parse ``"sum"``, ``"max"``, a pair such as ``("max", "sum")`` or an Objective.

    Raises
    ------
    WeightError
        An unknown component or an empty sequence.
    """
    if isinstance(spec, Objective):
        return spec
    comps = (spec,) if isinstance(spec, str) else tuple(spec)
    if not comps or any(c not in _COMPONENTS for c in comps):
        raise WeightError(
            f"objective must be 'sum', 'max' or a tuple of them (lexicographic), got {spec!r}"
        )
    return Objective(comps)


def _sum3(a: float, b: float, w: float) -> float:
    return a + b + w


def _max3(a: float, b: float, w: float) -> float:
    return max(a, b, w)


def _fold(component: str, values: Sequence[float]) -> float:
    if component == "sum":
        return float(sum(values))
    return float(max(values)) if len(values) else -math.inf
