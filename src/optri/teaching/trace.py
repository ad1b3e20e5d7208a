"""Record the DP step by step: :func:`trace` and the :class:`Trace` it returns.

A trace is not a second implementation of the recurrence: it runs the Python
engines themselves (:mod:`optri.engines.memo`, :mod:`~optri.engines.table`,
:mod:`~optri.engines.naive`, all driving :meth:`Recurrence.cell`) with an
observer (:attr:`optri.engines.problem.Problem.observer`) that writes down
every step, so its counts are the engines' own ``stats``.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass, field
from html import escape as html_escape
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from .. import config
from ..errors import EngineUnavailableError, OptriError, TableTooLargeError
from ..objective import Cost, ObjectiveLike
from ..result import Triangulation
from ..solve import PolygonLike, build_problem, load_polygon, solution_result, solve_problem
from ..weights import WeightLike
from . import animation, explorer, tree

__all__ = ["KINDS", "METHODS", "Event", "Trace", "explore", "trace"]

#: Event kinds, in the order of a cell's life. A "hit" is a request for a sub-polygon
#: with a triangle (j - i >= 2) answered from the table: one recursion memoization
#: saves, a grey leaf of Figure 3. Reading a side (j = i + 1, the base case w[i, i] = 0,
#: set before the recursion) is a "side" step, never a hit.
KINDS = ("call", "side", "hit", "candidate", "store")
#: Evaluation orders a trace can record.
METHODS = ("memo", "table", "naive")


class Event(NamedTuple):
    """One step of the DP on chord (i, j), i < j: the sub-polygon v_i ... v_j.

    ``kind`` is ``"call"`` (the recursive function is invoked on (i, j); sides
    included), ``"side"`` (a side, j = i + 1, is read: the base case, cost 0),
    ``"hit"`` (a sub-polygon with a triangle, j - i >= 2, is answered from the
    table instead of computed: see :data:`KINDS`), ``"candidate"``
    (split k of (i, j) evaluated: ``value`` is combine(cost(i, k), cost(k, j),
    w(i, k, j))) or ``"store"`` (cell (i, j) filled with ``value``, its optimal
    split ``k``). ``k`` and ``value`` are None where meaningless.
    """

    kind: str
    i: int
    j: int
    k: int | None
    value: Cost | None


@dataclass(eq=False)
class Trace:
    """Every step of one DP evaluation, and its result.

    Attributes
    ----------
    method : {"memo", "table", "naive"}
    events : list of Event
        In the order the engine made them.
    result : Triangulation
        The engine's answer (input vertex indices), as :func:`optri.triangulate`
        gives it.
    vertices : ndarray
        The vertices the event indices refer to: the input for counter-clockwise
        (or value) input; a clockwise polygon is traced reversed, vertex 0 kept
        first, and ``order[i]`` is the input index of vertex ``i``.
    order : ndarray of int64

    Examples
    --------
    >>> import optri
    >>> t = optri.trace([5, 1, 5, 1, 5], "product")
    >>> t.method, len(t.events), t.result.weight
    ('memo', 52, 35)
    """

    method: str
    events: list[Event]
    result: Triangulation
    vertices: NDArray[np.float64]
    order: NDArray[np.int64]
    _counts: dict[str, int] = field(default_factory=dict, repr=False)
    _problem: Any = field(default=None, repr=False)  # the Problem traced (the explorer's weights)

    @property
    def n(self) -> int:
        """Number of vertices."""
        return int(self.vertices.shape[0])

    @property
    def optimum(self) -> Cost:
        """The optimal cost: the value of the last store, cell (0, n - 1)."""
        return self.result.weight

    @property
    def stats(self) -> dict[str, int]:
        """The engine's own instrumentation (:attr:`Triangulation.stats`)."""
        return self.result.stats

    def counts(self) -> dict[str, int]:
        """How many events of each kind: ``{"call": ..., "side": ..., "hit": ..., ...}``.

        ``"hit"`` counts the requests for sub-polygons with a triangle answered from
        the table (the grey leaves of Figure 3); reads of sides are ``"side"``.
        """
        if not self._counts:
            found = Counter(e.kind for e in self.events)
            self._counts.update({kind: found.get(kind, 0) for kind in KINDS})
        return dict(self._counts)

    def splits(self) -> dict[tuple[int, int], int]:
        """The optimal split of every stored chord (its last store)."""
        return {(e.i, e.j): e.k for e in self.events if e.kind == "store" and e.k is not None}

    def recursion_tree(self) -> tree.Node:
        """The calls as a tree (:func:`optri.teaching.tree.recursion_tree`); memo and naive."""
        return tree.recursion_tree(self.events)

    def frames(self, kinds: Sequence[str] = ("candidate", "store")) -> list[int]:
        """Steps an animation shows: 0, one after each event of ``kinds``, then the end."""
        return animation.frame_steps(self.events, kinds)

    def animate(
        self,
        path: str | Path,
        *,
        kinds: Sequence[str] = ("candidate", "store"),
        fps: float = 2.0,
        dpi: int = 100,
    ) -> Path:
        """Write the table filling beside the polygon, frame by frame; return the path.

        A ``.gif`` is written with pillow; an ``.mp4`` needs ffmpeg. One frame
        shows the empty table, one follows each event of ``kinds`` (the current
        sub-polygon and candidate triangle highlighted), and the last traces the
        optimal triangulation back. See :func:`optri.teaching.animation.animate`.
        """
        return animation.animate(self, path, kinds=kinds, fps=fps, dpi=dpi)

    def explorer_html(self) -> str:
        """The explorer page (:func:`optri.teaching.explorer.explorer_page`) of this trace."""
        return explorer.explorer_page([self])

    def _repr_html_(self) -> str:
        """The explorer, embedded for notebooks (an ``<iframe srcdoc>``).

        Above :data:`optri.config.EXPLORE_MAX_N` vertices (the explorer's limit) the
        notebook shows this trace's one-line summary instead of a page.
        """
        if self.n > config.EXPLORE_MAX_N:
            return (
                f"<pre>{html_escape(repr(self))}</pre><p>The explorer shows n &lt;= "
                f"{config.EXPLORE_MAX_N} (optri.config.EXPLORE_MAX_N).</p>"
            )
        return explorer.embed(self.explorer_html())

    def __repr__(self) -> str:
        c = self.counts()
        return (
            f"Trace(method={self.method!r}, n={self.n}, events={len(self.events)}, "
            + ", ".join(f"{k}s={c[k]}" for k in KINDS)
            + f", optimum={self.optimum!r})"
        )


def trace(
    vertices: PolygonLike,
    weight: WeightLike = "perimeter",
    objective: ObjectiveLike = "sum",
    method: str = "memo",
) -> Trace:
    """Solve a polygon with a Python engine and record every step.

    Parameters
    ----------
    vertices, weight, objective
        As for :func:`optri.triangulate` (values with ``weight="product"`` for
        the paper's pentagon 5, 1, 5, 1, 5).
    method : {"memo", "table", "naive"}
        ``"memo"``: the paper's top-down Algorithm 3.1; ``"table"``: bottom-up
        square matrix, by diagonal; ``"naive"``: the recursion without its
        table, which recomputes every sub-polygon (3^(n-2) calls).

    Returns
    -------
    Trace

    Raises
    ------
    EngineUnavailableError
        Another method, a lexicographic objective led by ``"max"`` (solved in two
        passes), or ``"naive"`` above :data:`optri.config.NAIVE_MAX_N`.
    TableTooLargeError
        n above :data:`optri.config.TRACE_MAX_N`.

    Notes
    -----
    On a convex n-gon every method makes C(n, 3) candidates (the paper's
    Eq. 6); memo and table store (n - 1)(n - 2)/2 cells (Eq. 7) and read
    (n - 1)(n - 2) sides; memo makes 2 C(n, 3) + 1 calls, and those that are
    neither stored cells nor sides are its 2 C(n, 3) + 1 - 3 (n - 1)(n - 2)/2
    hits; table reads 2 C(n, 3) cells from the table and makes no call, so
    2 C(n, 3) - (n - 1)(n - 2) hits; naive makes 3^(n - 2) calls and no hit.

    Examples
    --------
    >>> t = trace([5, 1, 5, 1, 5], weight="product")
    >>> t.counts()
    {'call': 21, 'side': 12, 'hit': 3, 'candidate': 10, 'store': 6}
    >>> t.events[-1]
    Event(kind='store', i=0, j=4, k=1, value=35)
    >>> trace([5, 1, 5, 1, 5], "product", method="naive").counts()["call"]
    27
    """
    if method not in METHODS:
        raise EngineUnavailableError(
            f"trace records method 'memo', 'table' or 'naive', not {method!r}"
        )
    polygon = load_polygon(vertices)
    if polygon.n > config.TRACE_MAX_N:
        raise TableTooLargeError(
            f"a trace of n = {polygon.n} would hold about {4 * math.comb(polygon.n, 3):,} "
            f"events; trace takes n <= {config.TRACE_MAX_N} (optri.config.TRACE_MAX_N)"
        )
    problem = build_problem(polygon, weight, objective, keep_table=True)
    if problem.objective.two_phase:
        raise EngineUnavailableError(
            "a lexicographic objective led by 'max' is solved in two passes; trace one "
            "objective at a time"
        )
    events: list[Event] = []

    def record(kind: str, i: int, j: int, k: int | None, value: Any) -> None:
        if kind == "hit" and j - i == 1:
            kind = "side"  # the base case read, not a saved recursion (see KINDS)
        events.append(Event(kind, i, j, k, value))

    problem.observer = record
    name, solution = solve_problem(problem, method)
    if not events or events[-1][:3] != ("store", 0, polygon.n - 1):
        raise OptriError("internal error: the trace does not end with the store of (0, n-1)")
    result = solution_result(problem, name, solution)
    return Trace(method, events, result, polygon.data, polygon.order, _problem=problem)


def explore(
    vertices: PolygonLike,
    weight: WeightLike = "perimeter",
    objective: ObjectiveLike = "sum",
    method: str = "memo",
    path: str | Path | None = None,
) -> str:
    """The explorer page of a polygon: memo and table traces, switchable; ``method`` first.

    The naive trace is included too when ``method="naive"`` or n <= 7. Returns
    the HTML and writes it to ``path`` (atomically) when one is given.

    Raises
    ------
    TableTooLargeError
        n above :data:`optri.config.EXPLORE_MAX_N`.

    Examples
    --------
    >>> html = explore([5, 1, 5, 1, 5], "product")
    >>> html.startswith("<!DOCTYPE html>") and "window.optri" in html
    True
    """
    polygon = load_polygon(vertices)
    if polygon.n > config.EXPLORE_MAX_N:
        raise TableTooLargeError(
            f"the explorer shows n <= {config.EXPLORE_MAX_N} (optri.config.EXPLORE_MAX_N), "
            f"got n = {polygon.n}; use optri.trace for larger polygons"
        )
    if method not in METHODS:
        raise EngineUnavailableError(f"explore shows 'memo', 'table' or 'naive', not {method!r}")
    methods = [method] + [m for m in ("memo", "table") if m != method]
    if method != "naive" and polygon.n <= 7:
        methods.append("naive")
    html = explorer.explorer_page([trace(polygon, weight, objective, m) for m in methods])
    if path is not None:
        explorer.write_page(path, html)
    return html
