"""The integer program of a block, solved by HiGHS through ``scipy.optimize.milp``.

One binary variable ``x_t`` per candidate triangle of the block and, for
triangles ``t`` with side ``e`` on a given side of it:

* each fixed edge (a boundary edge, or a side of a forced diagonal) is
  covered exactly once from the block's side: ``sum x_t = 1``;
* each free diagonal is used on both sides or on neither:
  ``sum_left x_t - sum_right x_t = 0``, and at most once: ``sum_left x_t <= 1``
  (implied for integers, it tightens the relaxation).

Every 0/1 solution is a triangulation of the block's region: summing the
triangles' boundaries (as chains) leaves only the fixed edges, so the
triangles cover the region exactly once. scipy is the optional extra
``optri[holes]``.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .. import config
from .._optional import import_optional
from .candidates import Candidates

__all__ = ["Outcome", "side_keys", "solve_program"]


@dataclass(frozen=True)
class Outcome:
    """What the solver found for a block.

    Attributes
    ----------
    chosen : ndarray of int64 or None
        Candidate triangle ids of the best solution found (None: none found).
    bound : float
        Proven lower bound on the block's optimum (``-inf``: none).
    status : {"optimal", "limit", "infeasible"}
    nodes : int
        Branch-and-bound nodes.
    """

    chosen: NDArray[np.int64] | None
    bound: float
    status: str
    nodes: int = 0


def side_keys(
    cand: Candidates, tris: NDArray[np.int64], fixed: NDArray[np.bool_]
) -> NDArray[np.int64]:
    """Keys ``2 * edge + (left side)`` of the fixed edge sides that ``tris`` cover; sorted."""
    e, g = cand.sides[tris].ravel(), cand.signs[tris].ravel()
    on = fixed[e]
    return np.unique(2 * e[on] + (g[on] > 0))


def _constraints(
    cand: Candidates, tris: NDArray[np.int64], fixed: NDArray[np.bool_], required: Any
) -> tuple[Any, NDArray[np.float64], NDArray[np.float64]] | None:
    """Rows over the columns ``tris``; None when a required fixed side has no triangle."""
    sparse = import_optional("scipy.sparse", extra="holes")
    b = len(tris)
    col = np.repeat(np.arange(b), 3)
    e = cand.sides[tris].ravel()
    g = cand.signs[tris].ravel().astype(np.int64)
    on_fixed = fixed[e]
    # rows: fixed edge sides (= 1), then free-diagonal balances (= 0), then caps (<= 1)
    fkey = 2 * e[on_fixed] + (g[on_fixed] > 0)
    if not np.isin(required, fkey).all():
        return None
    frow = np.searchsorted(required, fkey)
    du, drow = np.unique(e[~on_fixed], return_inverse=True)
    left = ~on_fixed & (g > 0)
    cu, crow = np.unique(e[left], return_inverse=True)
    nf, nd = len(required), len(du)
    rows = np.concatenate((frow, nf + drow, nf + nd + crow))
    cols = np.concatenate((col[on_fixed], col[~on_fixed], col[left]))
    vals = np.concatenate((np.ones(len(frow)), g[~on_fixed], np.ones(len(crow))))
    shape = (nf + nd + len(cu), b)
    a = sparse.csr_array((vals.astype(np.float64), (rows, cols)), shape=shape)
    lo = np.concatenate((np.ones(nf), np.zeros(nd), np.zeros(len(cu))))
    hi = np.concatenate((np.ones(nf), np.zeros(nd), np.ones(len(cu))))
    return a, lo, hi


def solve_program(
    cand: Candidates,
    tris: NDArray[np.int64],
    fixed: NDArray[np.bool_],
    costs: NDArray[np.float64] | None,
    time_limit: float | None,
    required: NDArray[np.int64] | None = None,
    relax: bool = False,
) -> Outcome:
    """Solve the block of candidate triangles ``tris`` (``costs=None``: any solution).

    The linear relaxation is solved first: its optimum is very often a 0/1
    point, which is then optimal for the program too (no branching). Else
    HiGHS's branch and bound runs, with relative gap 0: ``"optimal"`` means
    proven optimal to the solver's tolerance.

    ``required``: the fixed edge sides (:func:`side_keys`) to cover, by default
    those ``tris`` cover; a subset of a block's triangles must still cover
    the block's. ``time_limit`` in seconds (None: none). ``relax``: stop after
    the relaxation, for its bound (``chosen`` is then None unless integral).
    """
    opt = import_optional("scipy.optimize", extra="holes")
    if required is None:
        required = side_keys(cand, tris, fixed)
    rows = _constraints(cand, tris, fixed, required)
    if rows is None:
        return Outcome(None, math.inf, "infeasible")
    a, lo, hi = rows
    c = np.zeros(len(tris)) if costs is None else np.asarray(costs, dtype=np.float64)
    scale = cost_scale(c)
    c = c * scale  # a power of two: exact, and undone exactly on the bounds
    start = time.perf_counter()
    lp = _milp(opt, c, a, lo, hi, False, time_limit)
    if lp.status == 2:
        return Outcome(None, math.inf, "infeasible")
    if lp.status != 0:
        return Outcome(None, -math.inf, "limit")
    bound = float(lp.fun) / scale
    chosen = _integral(lp.x, a, lo, hi, tris)
    if chosen is not None:
        return Outcome(chosen, bound, "optimal")
    if relax:
        return Outcome(None, bound, "limit")
    left = None if time_limit is None else time_limit - (time.perf_counter() - start)
    res = _milp(opt, c, a, lo, hi, True, left)
    nodes = int(getattr(res, "mip_node_count", 0) or 0)
    if res.status == 2:  # pragma: no cover - the relaxation was feasible
        return Outcome(None, math.inf, "infeasible", nodes)
    chosen = None if res.x is None else _integral(np.round(res.x), a, lo, hi, tris)
    dual = getattr(res, "mip_dual_bound", None)
    if dual is not None and np.isfinite(dual):
        bound = max(bound, float(dual) / scale)
    status = "optimal" if res.status == 0 and chosen is not None else "limit"
    return Outcome(chosen, bound, status, nodes)


def cost_scale(costs: NDArray[np.float64]) -> float:
    """The power of two that brings the largest ``|cost|`` to ``2**config.DOMAIN_COST_EXPONENT``.

    HiGHS's tolerances are absolute (about ``1e-7`` on reduced costs, ``1e-6`` on
    the branch-and-bound gap), so a program posed in the data's own units
    (polygons in degrees have triangle weights near ``1e-9``) is "optimal" while
    far from it. Scaled, the program is the same at every scale of the input and
    the tolerances sit many orders of magnitude below the proven tolerance
    ``config.DOMAIN_PROVEN_RTOL``. A power of two scales every cost exactly.

    >>> cost_scale(np.array([0.75, 0.5])) == 2.0**20, cost_scale(np.zeros(2))
    (True, 1.0)
    """
    top = float(np.abs(costs).max(initial=0.0))
    if not (top > 0.0 and math.isfinite(top)):
        return 1.0
    return math.ldexp(1.0, config.DOMAIN_COST_EXPONENT - math.frexp(top)[1])


def _milp(
    opt: Any, c: Any, a: Any, lo: Any, hi: Any, integral: bool, time_limit: float | None
) -> Any:
    # presolve off: on these programs HiGHS's presolve costs far more than it saves
    options: dict[str, Any] = {"disp": False, "mip_rel_gap": 0.0, "presolve": False}
    if time_limit is not None:
        options["time_limit"] = max(float(time_limit), config.DOMAIN_MIN_SOLVER_SECONDS)
    return opt.milp(
        c,
        integrality=np.full(len(c), 1 if integral else 0),
        bounds=opt.Bounds(0, 1),
        constraints=opt.LinearConstraint(a, lo, hi),
        options=options,
    )


def _integral(
    x: Any, a: Any, lo: Any, hi: Any, tris: NDArray[np.int64]
) -> NDArray[np.int64] | None:
    """The triangles of a 0/1 point satisfying every row exactly, else None."""
    x = np.asarray(x)
    if np.abs(x - np.round(x)).max(initial=0.0) > 1e-6:
        return None
    pick = np.round(x) > 0.5
    got = a @ pick.astype(np.float64)
    if np.all(got >= lo - 1e-9) and np.all(got <= hi + 1e-9):  # integer sums: exact
        return tris[pick]
    return None  # pragma: no cover - a 0/1 point of the relaxation satisfies its rows
