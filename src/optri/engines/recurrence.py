"""The paper's recurrence, written once: the split rule, one cell, and the walk back.

Every optimal triangulation optri computes is the solution of

    cost(i, j) = best over usable k, i < k < j, of combine(cost(i, k), cost(k, j), w(i, k, j)),
    cost(i, i + 1) = neutral

(the paper's Eq. 3 in 0-based vertex indices, Klincsek 1980 for chord masks),
where ``combine`` and ``best`` come from the objective (sum, max or a
lexicographic pair) and ``w`` from the weight. This module holds, for the
readable Python engines and everything built on the same recurrence:

* the split rule: which k may split chord (i, j) (:func:`split_points`), in
  increasing order, ties kept by the first (smallest) k;
* the bottom-up order of the chords (:func:`chords_by_length`);
* one cell of the recurrence, :meth:`Recurrence.cell`, a generator that asks
  for the sub-chords it needs and returns ``(cost, k)``: the top-down
  (memo), bottom-up (table) and traced evaluations all drive this one cell;
* the walk from optimal splits back to triangles (:func:`walk`,
  :func:`triangles_from_splits`), bounded, with clear errors.

The compiled engines (:mod:`optri.engines._jit_kernels`,
:mod:`optri.engines._gpu_kernels`) evaluate the same recurrence in other
orders; the test suite holds them to these engines and to brute force.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Generator, Iterable, Iterator, Sequence
from typing import Any, TypeVar

import numpy as np
from numpy.typing import NDArray

from ..errors import NoTriangulationError, OptriError
from ..objective import Cost, Objective
from .memory import require_memory
from .problem import Problem

__all__ = [
    "PY_BYTES_PER_CELL",
    "Recurrence",
    "chords_by_length",
    "export_table",
    "new_tables",
    "split_points",
    "triangles_from_splits",
    "walk",
]

Rows = Sequence[Sequence[bool]]
#: One cell's evaluation: yields the sub-chords it needs, is sent their costs,
#: returns (cost, optimal k); k is -1 when no split is usable.
Cell = Generator[tuple[int, int], Cost, tuple[Cost, int]]
State = TypeVar("State")

#: Two nested-list tables of Python objects plus the exported float64 array.
PY_BYTES_PER_CELL = 2 * (8 + 24) + 8


def split_points(i: int, j: int, ok: Rows | None) -> Iterable[int]:
    """The k that may split chord (i, j): both (i, k) and (k, j) usable, increasing.

    ``ok`` is the chord mask as nested rows (sides set), None for every chord.

    >>> list(split_points(0, 4, None))
    [1, 2, 3]
    >>> ok = [[0, 1, 0, 1], [1, 0, 1, 1], [0, 1, 0, 1], [1, 1, 1, 0]]
    >>> list(split_points(0, 3, ok))
    [1]
    """
    if ok is None:
        return range(i + 1, j)
    oi = ok[i]
    return [k for k in range(i + 1, j) if oi[k] and ok[k][j]]


def chords_by_length(n: int, ok: Rows | None) -> Iterator[tuple[int, int]]:
    """Usable chords (i, j), j - i >= 2, shortest first: both halves of a split come earlier.

    >>> list(chords_by_length(4, None))
    [(0, 2), (1, 3), (0, 3)]
    """
    for d in range(2, n):
        for i in range(n - d):
            j = i + d
            if ok is None or ok[i][j]:
                yield i, j


class Recurrence:
    """The recurrence of one :class:`Problem`, as the Python engines evaluate it.

    Attributes
    ----------
    n : int
    objective : Objective
    ok : nested rows of bool or None
        The chord mask (sides set), None for every chord.
    evaluations : int
        Triangle weights evaluated so far by :meth:`cell`.
    watch : callable or None
        The problem's observer (:attr:`Problem.observer`), told of each
        candidate split :meth:`cell` evaluates.
    """

    def __init__(self, problem: Problem) -> None:
        self.n = problem.n
        self.objective: Objective = problem.objective
        self.ok = problem.allowed_rows()
        self.weight = problem.evaluator()
        self.evaluations = 0
        self.watch = problem.observer

    def splits(self, i: int, j: int) -> Iterable[int]:
        """:func:`split_points` of chord (i, j) under this problem's mask."""
        return split_points(i, j, self.ok)

    def chords(self) -> Iterator[tuple[int, int]]:
        """:func:`chords_by_length` under this problem's mask."""
        return chords_by_length(self.n, self.ok)

    def cell(self, i: int, j: int) -> Cell:
        """Evaluate cost(i, j): yield each needed sub-chord, receive its cost, return (best, k).

        Splits are tried in increasing k and a later one wins only when strictly
        better, so ties go to the smallest k in every engine. The observer, if
        any, is told of each candidate: ``watch("candidate", i, j, k, value)``.
        """
        combine, less, w = self.objective.combine, self.objective.less, self.weight
        watch = self.watch
        best: Any = self.objective.worst
        arg = -1
        for k in self.splits(i, j):
            a = yield i, k
            b = yield k, j
            self.evaluations += 1
            c = combine(a, b, w(i, k, j))
            if watch is not None:
                watch("candidate", i, j, k, c)
            if less(c, best):
                best, arg = c, k
        return best, arg

    def top_down(
        self,
        known: Callable[[int, int], Any],
        store: Callable[[int, int, Any, int], None],
        hits: bool,
    ) -> int:
        """Evaluate cell (0, n - 1) top-down on an explicit stack; return the requests made.

        A trampoline drives the :meth:`cell` generators, so Python's recursion
        limit never applies. Each request (p, q) is answered by ``known(p, q)``,
        or computed as a new cell when that is None; each computed cell is
        handed to ``store(i, j, best, k)``. The observer hears every "call" and
        "store" and, with ``hits``, every request ``known`` answered ("hit").
        Memoization and the naive recursion differ only in ``known``.
        """
        watch = self.watch
        root = self.n - 1
        stack: list[tuple[int, int, Cell]] = [(0, root, self.cell(0, root))]
        if watch is not None:
            watch("call", 0, root, None, None)
        requests = 0
        value: Any = None  # what the top frame asked for, or None when it starts
        while stack:
            i, j, frame = stack[-1]
            try:
                p, q = frame.send(value)
            except StopIteration as done:
                best, arg = done.value
                store(i, j, best, arg)
                stack.pop()
                value = best
                if watch is not None:
                    watch("store", i, j, arg if arg >= 0 else None, best)
                continue
            requests += 1
            if watch is not None:
                watch("call", p, q, None, None)
            value = known(p, q)
            if value is None:  # not known: compute it
                stack.append((p, q, self.cell(p, q)))
            elif hits and watch is not None:
                watch("hit", p, q, None, value)
        return requests


def walk(
    root: State, expand: Callable[[State], tuple[tuple[int, int, int], Sequence[State]]], limit: int
) -> list[tuple[int, int, int]]:
    """Triangles of an optimal solution, from the ``root`` state down.

    ``expand(state)`` gives the state's triangle ``(i, k, j)`` and its child
    states (none for a side). Every triangle must satisfy ``i < k < j``, and at
    most ``limit`` are produced, so a corrupt split table raises instead of
    looping.

    Raises
    ------
    NoTriangulationError
        A state has no usable split (``k < 0``).
    OptriError
        A split outside its chord or more than ``limit`` triangles: an internal
        inconsistency, reported rather than followed.
    """
    tris: list[tuple[int, int, int]] = []
    stack = [root]
    while stack:
        tri, children = expand(stack.pop())
        i, k, j = tri
        if k < 0:
            raise NoTriangulationError(
                f"no valid triangulation of sub-polygon ({i}, {j}): every split has "
                f"an infinite or invalid cost",
                (i, j),
            )
        if not i < k < j or len(tris) >= limit:
            raise OptriError(
                f"internal error: split {k} of chord ({i}, {j}) is not inside it, or the "
                f"walk exceeds {limit} triangles; please report this input"
            )
        tris.append(tri)
        stack.extend(reversed(children))
    return tris


def triangles_from_splits(split: Callable[[int, int], int], n: int) -> NDArray[np.int64]:
    """Walk the optimal splits from chord (0, n-1) down; O(n) look-ups.

    ``split(i, j)`` returns the apex k of the optimal triangle on chord (i, j)
    (negative when it has none).

    >>> triangles_from_splits(lambda i, j: i + 1, 5).tolist()
    [[0, 1, 4], [1, 2, 4], [2, 3, 4]]
    """

    def expand(chord: tuple[int, int]) -> tuple[tuple[int, int, int], list[tuple[int, int]]]:
        i, j = chord
        k = int(split(i, j))
        return (i, k, j), [c for c in ((i, k), (k, j)) if c[1] - c[0] >= 2]

    tris = walk((0, n - 1), expand, max(n - 2, 0)) if n >= 3 else []
    return np.array(tris, dtype=np.int64).reshape(-1, 3)


def new_tables(problem: Problem, unset: Any) -> tuple[list[list[Any]], list[list[int]]]:
    """Allocate cost and split tables; sides (i, i+1) hold the neutral cost."""
    n = problem.n
    require_memory(
        PY_BYTES_PER_CELL * n * n,
        f"the pure-Python DP tables for n = {n}",
        "use method='fast' (compiled, one float64 table)",
    )
    cost: list[list[Any]] = [[unset] * n for _ in range(n)]
    split = [[-1] * n for _ in range(n)]
    neutral = problem.objective.neutral_for(problem.integer_costs)  # ints stay exact
    for i in range(n - 1):
        cost[i][i + 1] = neutral
    return cost, split


def export_table(
    cost: list[list[Any]], split: list[list[int]], objective: Objective, unset: Any
) -> NDArray[np.float64]:
    """The paper's n x n table: costs above the diagonal, splits below, 0 on it.

    Cells of sides and unreached chords hold 0 above the diagonal (no triangle)
    resp. -1 below (no split); unreachable chords hold inf above.
    """
    n = len(cost)
    out = np.zeros((n, n), dtype=np.float64)
    for i in range(n):
        row = cost[i]
        for j in range(i + 1, n):
            c = row[j]
            if c is unset:
                continue
            v = c[0] if objective.is_lex else c
            out[i, j] = 0.0 if v == -math.inf else v
            out[j, i] = split[i][j]
    return out
