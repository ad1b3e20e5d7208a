"""What every engine receives (:class:`Problem`) and returns (:class:`Solution`)."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import WeightError
from ..objective import Cost, Objective
from ..polygon import Polygon
from ..weights import Weight, WeightCode

__all__ = ["Observer", "Problem", "ProgressFn", "Solution", "chord_rows", "with_sides"]

ProgressFn = Callable[[int, int], None]
#: ``observer(kind, i, j, k, value)``: told each step of a Python engine (see
#: :attr:`Problem.observer`); ``k`` and ``value`` are None where meaningless.
Observer = Callable[[str, int, int, "int | None", Any], None]


@dataclass
class Problem:
    """One optimal-triangulation instance in the engines' internal vertex order.

    Attributes
    ----------
    polygon : Polygon
        Validated input (internal order counter-clockwise).
    weights : tuple of Weight
        One weight per objective component.
    objective : Objective
    allowed : ndarray of bool or None
        ``allowed[i, j]`` for ``i < j``: may chord (i, j) be used? None means
        every chord (convex polygon). Polygon sides are always allowed.
    progress : callable or None
        ``progress(done, total)``, called now and then by long-running engines:
        split evaluations of the table done and in all
        (:func:`optri.engines.progress.table_work`).
    keep_table : bool
        Ask the engine for the n x n table (costs above the diagonal, splits
        below) where it can give one.
    dtype : numpy dtype
        Float type of compiled tables (float64 default).
    gates : tuple of (Weight, float)
        Triangle filters: a triangle whose gate weight exceeds the threshold is
        forbidden (its weight becomes +inf). Lexicographic objectives with a
        ``"max"`` primary are solved in two phases, the second gated by the
        first's optimum (see :attr:`optri.objective.Objective.two_phase`).
    options : dict
        Engine-specific extras.
    observer : callable or None
        ``observer(kind, i, j, k, value)``, told every step of the Python
        engines (memo, table, naive): ``"call"`` (a sub-polygon requested),
        ``"hit"`` (a request answered from the table), ``"candidate"`` (split k
        of chord (i, j) evaluated, its value) and ``"store"`` (chord (i, j)
        filled: its optimal k and value). :func:`optri.trace` records them;
        compiled engines ignore it.
    """

    polygon: Polygon
    weights: tuple[Weight, ...]
    objective: Objective
    allowed: NDArray[np.bool_] | None = None
    progress: ProgressFn | None = None
    keep_table: bool = True
    dtype: Any = np.float64
    gates: tuple[tuple[Weight, float], ...] = ()
    options: dict[str, Any] = field(default_factory=dict)
    observer: Observer | None = None

    @property
    def n(self) -> int:
        """Number of vertices."""
        return self.polygon.n

    def evaluator(self) -> Callable[[int, int, int], Cost]:
        """Python ``w(i, k, j)`` giving a float (or tuple), raising on NaN."""
        fns = [w.evaluator(self.polygon) for w in self.weights]
        names = [w.name for w in self.weights]
        order = self.polygon.order

        def nan_error(i: int, k: int, j: int, name: str) -> WeightError:
            tri = (int(order[i]), int(order[k]), int(order[j]))
            return WeightError(f"weight {name!r} returned NaN for triangle {tri}")

        if self.gates:
            gates = [(g.evaluator(self.polygon), thr) for g, thr in self.gates]
            inner = fns[0]

            def gated(i: int, k: int, j: int) -> float:
                for g, thr in gates:
                    if g(i, k, j) > thr:
                        return math.inf
                return inner(i, k, j)

            fns = [gated, *fns[1:]]

        if len(fns) == 1:
            (f,), (name,) = fns, names

            def w1(i: int, k: int, j: int) -> float:
                v = f(i, k, j)
                if v != v:
                    raise nan_error(i, k, j, name)
                return v

            return w1

        def wn(i: int, k: int, j: int) -> tuple[float, ...]:
            vals = tuple(f(i, k, j) for f in fns)
            for v, name in zip(vals, names):
                if v != v:
                    raise nan_error(i, k, j, name)
            return vals

        return wn

    @property
    def integer_costs(self) -> bool:
        """Costs are exact integers: the product weight on integer vertex values."""
        return self.polygon.ints is not None and all(
            w.code == WeightCode.PRODUCT for w in self.weights
        )

    @property
    def needs_big_ints(self) -> bool:
        """Integer costs a float table of ``dtype`` cannot hold exactly.

        Every partial cost is at most ``(n - 2) * max|v|^3``; below ``2**(p + 1)``
        (p the float type's mantissa bits: 2**53 for float64) float arithmetic is
        exact, above it only integer arithmetic is.
        """
        if not self.integer_costs or self.polygon.ints is None:
            return False
        top = max(abs(v) for v in self.polygon.ints)
        kind = np.dtype(self.dtype)
        mantissa = np.finfo(kind).nmant if kind.kind == "f" else 52
        return (self.n - 2) * top**3 >= 2 ** (mantissa + 1)

    def allowed_rows(self) -> list[list[bool]] | None:
        """``allowed`` as nested lists (fast to index from Python), sides set True."""
        return None if self.allowed is None else chord_rows(self.allowed)


def with_sides(mask: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """Chord mask ``mask`` as a C-contiguous bool array with every polygon side allowed.

    Returns ``mask`` itself when it already qualifies; never writes the caller's
    array.
    """
    ok = np.ascontiguousarray(mask, dtype=np.bool_)
    k = np.arange(ok.shape[0])
    nxt = (k + 1) % len(k)
    if not ok[k, nxt].all():
        ok = ok.copy()
        ok[k, nxt] = ok[nxt, k] = True
    return ok


def chord_rows(mask: NDArray[np.bool_]) -> list[list[bool]]:
    """``mask`` with the sides allowed, as nested lists (fast to index from Python)."""
    return with_sides(mask).tolist()  # type: ignore[no-any-return]


@dataclass
class Solution:
    """An engine's answer, in internal vertex indices.

    Attributes
    ----------
    cost : float or tuple
        Optimal objective value.
    triangles : ndarray of int64, shape (n - 2, 3)
        Triangles ``(i, k, j)`` with ``i < k < j`` (counter-clockwise).
    table : ndarray or None
        n x n table: costs above the diagonal (primary component), split
        vertices below it, zeros on it.
    stats : dict
        Instrumentation (weight evaluations, look-ups, cells, ...).
    """

    cost: Cost
    triangles: NDArray[np.int64]
    table: NDArray[np.float64] | None = None
    stats: dict[str, int] = field(default_factory=dict)
