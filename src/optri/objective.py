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

Ties in lexicographic objectives
--------------------------------
Two float values of a leading component that differ by at most
:data:`LEX_TIE_RTOL` times the larger magnitude are a **tie**, and the next
component decides. Primaries that are equal in exact arithmetic (two
triangulations of a grid polygon with the same total perimeter, summed in
another order) differ by a few rounding errors, so without this the secondary
would never be consulted. Every engine applies the same rule: the Python
engines and brute force through :attr:`Objective.less`, the compiled core
through its twin of :func:`lex_better` (``src/core/objective.hpp``), and the
two-phase "max"-led pairs through a gate loosened by the same tolerance
(:func:`tie_ceiling`). Integer values (the product weight on integer input)
compare exactly.
"""

from __future__ import annotations

import math
import operator
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from enum import IntEnum
from typing import Any, Union

from .errors import WeightError

__all__ = [
    "LEX_TIE_RTOL",
    "Cost",
    "Objective",
    "ObjectiveCode",
    "ObjectiveLike",
    "as_objective",
    "lex_better",
    "lex_less",
    "tie_ceiling",
]

Cost = Union[float, tuple[float, ...]]
ObjectiveLike = Union[str, Sequence[str], "Objective"]

_COMPONENTS = ("sum", "max")

#: Leading components of a lexicographic objective within this relative distance tie
#: (part of the objective's definition, compiled into the kernels: not a tunable).
#: Rounding of a sum of m terms stays below about m * 1.1e-16 relatively, so ties are
#: recognized for triangulations of up to about 10**4 vertices.
LEX_TIE_RTOL = 1e-12


class ObjectiveCode(IntEnum):
    """Id by which the compiled core selects an objective (``enum class Objective``).

    ``SUM`` and ``MAX`` also name the rule of each component of a pair; ``LEX``
    is a lexicographic pair as a whole.
    """

    SUM = 0
    MAX = 1
    LEX = 2


def lex_better(a1, a2, b1, b2):  # type: ignore[no-untyped-def]
    """Whether ``(a1, a2)`` is lexicographically below ``(b1, b2)``, ties within LEX_TIE_RTOL.

    The compiled core's ``lex_better`` (``src/core/objective.hpp``) is this
    function with the same operations; numba compiles this one into its kernels.

    >>> lex_better(3.0, 1.0, 3.0 + 1e-15, 2.0), lex_better(3.0, 1.0, 3.1, 0.0)
    (True, True)
    """
    if a1 != b1:
        if abs(a1) == math.inf or abs(b1) == math.inf:
            return a1 < b1
        tol = LEX_TIE_RTOL * max(abs(a1), abs(b1))
        if a1 < b1 - tol:
            return True
        if a1 > b1 + tol:
            return False
    return a2 < b2


def lex_less(a: Sequence[Any], b: Sequence[Any]) -> bool:
    """Lexicographic order of cost tuples, leading components tied within LEX_TIE_RTOL.

    Integers (exact costs) tie only when equal.

    >>> lex_less((1.0, 5.0), (1.0 + 1e-14, 4.0)), lex_less((1, 5), (2, 4))
    (False, True)
    """
    for x, y in zip(a[:-1], b[:-1]):
        if x == y or _tied(x, y):
            continue
        return bool(x < y)
    return bool(a[-1] < b[-1])


def _tied(x: Any, y: Any) -> bool:
    if isinstance(x, int) and isinstance(y, int):
        return False
    if not (math.isfinite(x) and math.isfinite(y)):
        return False
    return abs(x - y) <= LEX_TIE_RTOL * max(abs(x), abs(y))


def tie_ceiling(value: float) -> float:
    """The largest value tied with ``value`` from above: a gate loosened by LEX_TIE_RTOL.

    >>> tie_ceiling(1.0) > 1.0, tie_ceiling(4) == 4
    (True, True)
    """
    if isinstance(value, int) or not math.isfinite(value):
        return value
    return value + LEX_TIE_RTOL * abs(value)


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
    def code(self) -> ObjectiveCode:
        """The compiled core's id of the whole objective (``LEX`` for a pair).

        >>> as_objective("max").code, as_objective(("max", "sum")).code
        (<ObjectiveCode.MAX: 1>, <ObjectiveCode.LEX: 2>)
        """
        if self.is_lex:
            return ObjectiveCode.LEX
        return ObjectiveCode.SUM if self.components[0] == "sum" else ObjectiveCode.MAX

    @property
    def component_codes(self) -> tuple[ObjectiveCode, ...]:
        """Each component's rule, ``SUM`` or ``MAX``.

        >>> [int(c) for c in as_objective(("max", "sum")).component_codes]
        [1, 0]
        """
        codes = {"sum": ObjectiveCode.SUM, "max": ObjectiveCode.MAX}
        return tuple(codes[c] for c in self.components)

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
        return self.neutral_for(integer=False)

    def neutral_for(self, integer: bool) -> Cost:
        """:attr:`neutral`, with an integer 0 for "sum" when the weights are integers.

        Integer weights (the product weight on integer values) then add up in
        Python ints, exactly.

        >>> as_objective("sum").neutral_for(True), as_objective("sum").neutral
        (0, 0.0)
        """
        zero = 0 if integer else 0.0
        vals = tuple(zero if c == "sum" else -math.inf for c in self.components)
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
        """Strict order on costs: ``<``, or :func:`lex_less` for a lexicographic pair."""
        return lex_less if self.is_lex else operator.lt

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
    comps = (spec,) if isinstance(spec, str) else tuple(spec) if _is_seq(spec) else ()
    if not comps or any(not isinstance(c, str) or c not in _COMPONENTS for c in comps):
        raise WeightError(
            f"objective must be 'sum', 'max' or a tuple of them (lexicographic), got {spec!r}"
        )
    return Objective(comps)


def _is_seq(spec: object) -> bool:
    return isinstance(spec, (tuple, list))


def _sum3(a: float, b: float, w: float) -> float:
    return a + b + w


def _max3(a: float, b: float, w: float) -> float:
    return max(a, b, w)


def _fold(component: str, values: Sequence[float]) -> float:
    if component == "sum":
        total = sum(values)
        return total if isinstance(total, int) else float(total)  # ints stay exact
    if not len(values):
        return -math.inf
    top = max(values)
    return top if isinstance(top, int) else float(top)
