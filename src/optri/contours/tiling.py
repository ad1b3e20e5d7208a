"""Optimal tiling between two closed contours: :func:`tile_contours`.

A tiling of contours ``a`` (m vertices) and ``b`` (n vertices) is a band of
m + n triangles, each made of one contour side and one vertex of the other
contour, consecutive triangles sharing a span (an edge from a vertex of ``a``
to one of ``b``). Fuchs, Kedem and Uselton (1977) read the tilings as monotone
paths on a toroidal grid and find the best one by shortest paths; this module
builds the two tables of triangle weights and hands them to the compiled
search (``optri._core.contours``; ``_reference.py`` is its Python twin).
"""

from __future__ import annotations

import importlib
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._optional import import_optional
from ..errors import InvalidParameterError, InvalidPolygonError, WeightError
from .figure import plot_surface

__all__ = [
    "CONTOUR_WEIGHTS",
    "ContourTiling",
    "as_contour",
    "tile_contours",
    "weight_tables",
]

#: Built-in weights of a tiling triangle: its area, the length of the span it
#: adds, or that length squared.
CONTOUR_WEIGHTS = ("area", "span", "span_squared")
#: How a tiling's triangle weights combine.
CONTOUR_OBJECTIVES = ("sum", "max")
#: Where the search may start: every span (optimal), or the closest pair of vertices.
STARTS = ("best", "closest")

ContourWeight = (
    str | Callable[[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]], float]
)


def as_contour(points: ArrayLike, name: str = "contour") -> NDArray[np.float64]:
    """A closed contour as a float ``(k, 3)`` array (2-D input gets z = 0).

    A closing vertex equal to the first is dropped. At least three vertices,
    finite coordinates and no two consecutive vertices equal.

    >>> as_contour([[0, 0], [1, 0], [0, 1], [0, 0]]).shape
    (3, 3)
    """
    try:
        arr = np.array(points, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidPolygonError(f"{name}: not an array of numbers ({exc})") from exc
    if arr.ndim != 2 or arr.shape[1] not in (2, 3):
        raise InvalidPolygonError(
            f"{name}: expected (k, 3) or (k, 2) vertex coordinates, got shape {arr.shape}"
        )
    if not np.isfinite(arr).all():
        raise InvalidPolygonError(f"{name}: a vertex has a non-finite coordinate")
    if arr.shape[1] == 2:
        arr = np.column_stack([arr, np.zeros(len(arr))])
    while len(arr) > 1 and np.array_equal(arr[0], arr[-1]):
        arr = arr[:-1]
    if len(arr) < 3:
        raise InvalidPolygonError(f"{name}: a closed contour needs at least 3 distinct vertices")
    same = np.flatnonzero(np.all(arr == np.roll(arr, -1, axis=0), axis=1))
    if same.size:
        k = int(same[0])
        raise InvalidPolygonError(
            f"{name}: vertex {(k + 1) % len(arr)} repeats vertex {k}; remove duplicates"
        )
    return np.ascontiguousarray(arr)


def weight_tables(
    a: NDArray[np.float64], b: NDArray[np.float64], weight: ContourWeight = "area"
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The two tables of triangle weights the search reads.

    ``wp[i, j]`` weighs triangle ``(a[i], a[i+1], b[j])`` and ``wq[i, j]``
    triangle ``(a[i], b[j+1], b[j])`` (indices modulo m and n). ``"span"``
    is the length of the span the triangle adds: ``a[i+1] - b[j]`` for the
    first kind, ``a[i] - b[j+1]`` for the second.

    >>> a = np.array([[0., 0, 0], [1, 0, 0], [0, 1, 0]])
    >>> wp, wq = weight_tables(a, a + [0, 0, 1], "span_squared")
    >>> float(wp[0, 0]), float(wq[0, 0])
    (2.0, 2.0)
    """
    a1, b1 = np.roll(a, -1, axis=0), np.roll(b, -1, axis=0)
    if callable(weight):
        return _called_tables(a, b, a1, b1, weight)
    if weight == "area":
        wp = _area(a[:, None, :], a1[:, None, :], b[None, :, :])
        wq = _area(a[:, None, :], b1[None, :, :], b[None, :, :])
    elif weight in ("span", "span_squared"):
        dp = a1[:, None, :] - b[None, :, :]
        dq = a[:, None, :] - b1[None, :, :]
        wp = dp[..., 0] * dp[..., 0] + dp[..., 1] * dp[..., 1] + dp[..., 2] * dp[..., 2]
        wq = dq[..., 0] * dq[..., 0] + dq[..., 1] * dq[..., 1] + dq[..., 2] * dq[..., 2]
        if weight == "span":
            wp, wq = np.sqrt(wp), np.sqrt(wq)
    else:
        raise WeightError(
            f"unknown contour weight {weight!r}; use one of {', '.join(CONTOUR_WEIGHTS)} "
            f"or a callable w(p, q, r) -> float over a triangle's three vertices"
        )
    return np.ascontiguousarray(wp), np.ascontiguousarray(wq)


def _area(p: NDArray[np.float64], q: NDArray[np.float64], r: NDArray[np.float64]) -> Any:
    u, v = q - p, r - p
    cx = u[..., 1] * v[..., 2] - u[..., 2] * v[..., 1]
    cy = u[..., 2] * v[..., 0] - u[..., 0] * v[..., 2]
    cz = u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]
    return 0.5 * np.sqrt(cx * cx + cy * cy + cz * cz)


def _called_tables(
    a: NDArray[np.float64],
    b: NDArray[np.float64],
    a1: NDArray[np.float64],
    b1: NDArray[np.float64],
    weight: Callable[..., float],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    m, n = len(a), len(b)
    wp, wq = np.empty((m, n)), np.empty((m, n))
    try:
        for i in range(m):
            for j in range(n):
                wp[i, j] = float(weight(a[i], a1[i], b[j]))
                wq[i, j] = float(weight(a[i], b1[j], b[j]))
    except (TypeError, ValueError) as exc:
        raise WeightError(f"the weight callable failed: {exc}") from exc
    return wp, wq


def _newell(c: NDArray[np.float64]) -> NDArray[np.float64]:
    centred = c - c.mean(axis=0)
    return np.cross(centred, np.roll(centred, -1, axis=0)).sum(axis=0)


@dataclass
class ContourTiling:
    """The best tiling between two closed contours.

    Attributes
    ----------
    vertices : ndarray, shape (m + n, 3)
        ``a`` then ``b`` (closing duplicates removed).
    triangles : ndarray of int64, shape (m + n, 3)
        Indices into :attr:`vertices`. Each holds one contour side and one vertex
        of the other contour; ``a``'s sides run forward (``a[i] -> a[i+1]``) and
        ``b``'s against ``a``'s sense of rotation, so the band is consistently
        oriented: for ``a`` below ``b``, both counter-clockwise seen from above,
        the normals point outward.
    weight : float
        The optimal objective value.
    m, n : int
        Vertex counts of ``a`` and ``b``.
    start : tuple of int
        The first span ``(i, j)`` of the search's path (``a[i]`` to ``b[j]``).
    weight_name, objective, method : str
        The weight (``"callable"`` for a function), ``"sum"`` or ``"max"``, and
        ``"best"`` (every start searched) or ``"closest"`` (fixed first span).
    seconds : float
        Time spent in the search (tables included).
    """

    vertices: NDArray[np.float64]
    triangles: NDArray[np.int64]
    weight: float
    m: int
    n: int
    start: tuple[int, int]
    weight_name: str
    objective: str
    method: str
    seconds: float = 0.0
    _weight: ContourWeight = field(default="area", repr=False)

    def terms(self) -> NDArray[np.float64]:
        """The terms the objective combines, recomputed from the vertices.

        One per triangle for ``"area"`` and a callable (called on the
        triangle's vertices in :attr:`triangles` order: a callable weight
        should not depend on that order); one per span for ``"span"`` and
        ``"span_squared"``, since every span is the one added by exactly one
        triangle of the closed band.
        """
        v, t = self.vertices, self.triangles
        if callable(self._weight):
            return np.array([float(self._weight(v[x], v[y], v[z])) for x, y, z in t])
        if self._weight == "area":
            return np.asarray(_area(v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]), dtype=np.float64)
        spans = self.spans()
        d = v[spans[:, 0]] - v[spans[:, 1]]
        sq = (d * d).sum(axis=1)
        return np.asarray(np.sqrt(sq) if self._weight == "span" else sq, dtype=np.float64)

    def spans(self) -> NDArray[np.int64]:
        """The m + n spans ``(a index, b index)`` of the band, as vertex indices, sorted."""
        m = self.m
        found = set()
        for tri in self.triangles.tolist():
            for k in range(3):
                p, q = tri[k], tri[(k + 1) % 3]
                if (p < m) != (q < m):
                    found.add((min(p, q), max(p, q)))
        return np.array(sorted(found), dtype=np.int64).reshape(-1, 2)

    def check(self, rtol: float = 1e-9) -> None:
        """Assert the tiling's invariants; raises AssertionError naming the first one broken.

        m + n triangles; each is one side of a contour and a vertex of the
        other; every side of ``a`` is used once, forward, and every side of
        ``b`` once, backward (for contours of the same sense); every span is
        shared by exactly two triangles in opposite directions; the weight equals
        the recomputed sum or maximum.
        """
        m, n, t = self.m, self.n, self.triangles
        _require(t.shape == (m + n, 3), f"expected {m + n} triangles, got {t.shape}")
        directed: dict[tuple[int, int], int] = {}
        for tri in t.tolist():
            in_a = [v < m for v in tri]
            _require(sum(in_a) in (1, 2), f"triangle {tri} has no vertex of one contour")
            for k in range(3):
                e = (tri[k], tri[(k + 1) % 3])
                _require(e not in directed, f"edge {e} is used twice in one direction")
                directed[e] = 1
        for i in range(m):
            _require((i, (i + 1) % m) in directed, f"side {i}-{(i + 1) % m} of a is not used")
        b_forward = all((m + j, m + (j + 1) % n) in directed for j in range(n))
        b_backward = all((m + (j + 1) % n, m + j) in directed for j in range(n))
        _require(b_forward or b_backward, "the sides of b are not all used in one direction")
        for p, q in directed:
            if (p < m) != (q < m):
                _require((q, p) in directed, f"span {p}-{q} bounds only one triangle")
        _require(len(self.spans()) == m + n, f"expected {m + n} spans, got {len(self.spans())}")
        w = self.terms()
        again = float(w.sum() if self.objective == "sum" else w.max())
        _require(
            math.isclose(again, self.weight, rel_tol=rtol, abs_tol=1e-300),
            f"weight {self.weight!r} but the triangles give {again!r}",
        )

    def to_trimesh(self) -> Any:
        """The band as a ``trimesh.Trimesh`` (extra ``optri[mesh]``)."""
        trimesh = import_optional("trimesh")
        return trimesh.Trimesh(self.vertices, self.triangles, process=False)

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """Draw the band and both contours on a 3-D matplotlib axes; returns the axes."""
        return plot_surface(self.vertices, self.triangles, [self.m, self.n], ax=ax, **kwargs)

    def __repr__(self) -> str:
        return (
            f"ContourTiling(m={self.m}, n={self.n}, weight={self.weight!r}, "
            f"weight_name={self.weight_name!r}, objective={self.objective!r}, "
            f"method={self.method!r}, start={self.start})"
        )


def _require(cond: bool, msg: str) -> None:
    if not cond:
        raise AssertionError(msg)


def tile_contours(
    a: ArrayLike,
    b: ArrayLike,
    weight: ContourWeight = "area",
    objective: str = "sum",
    *,
    start: str = "best",
    align: bool = True,
) -> ContourTiling:
    """Optimal tiling between two closed 3-D contours (Fuchs-Kedem-Uselton).

    Among all bands of m + n triangles that join contour ``a`` to contour
    ``b`` (each triangle one contour side plus a vertex of the other contour,
    neighbours sharing a span), finds one of least total (or largest) triangle
    weight, over every possible first span.

    Parameters
    ----------
    a, b : array_like, shape (m, 3) and (n, 3)
        Closed contours (usually on two parallel planes); 2-D input is lifted
        to z = 0, and a closing vertex equal to the first is dropped.
    weight : {"area", "span", "span_squared"} or callable
        ``"area"``: the band's surface area; ``"span"``: the length of the span
        each triangle adds (Christiansen's and Ganapathy-Dennehy's kind of
        rule); ``"span_squared"``: its square; a callable ``w(p, q, r)`` gets a
        triangle's three vertices (arrays of 3) and returns a float.
    objective : {"sum", "max"}
        Minimize the total, or the largest triangle weight.
    start : {"best", "closest"}
        ``"best"`` searches every first span (the optimum). ``"closest"`` fixes
        the first span at the closest pair of vertices, the rule of SlicerRT's
        and MeshLib's contour stitching, kept as a baseline.
    align : bool
        When ``a`` and ``b`` turn in opposite senses (their area vectors point
        apart), tile ``b`` in reverse so the band does not twist; the triangles
        still index ``b`` as given.

    Returns
    -------
    ContourTiling
        ``triangles`` index ``np.vstack([a, b])``; ``weight`` is the optimum.

    Raises
    ------
    InvalidPolygonError
        A contour with fewer than 3 distinct vertices, a repeated consecutive
        vertex or a non-finite coordinate.
    WeightError
        An unknown weight, a callable that fails or returns NaN.
    InvalidParameterError
        An unknown objective or start.

    Notes
    -----
    The sum is found by Fuchs, Kedem and Uselton's divide and conquer [1]_: every
    tiling contains a span from ``a[0]``, the shortest paths of different
    first spans can be chosen not to cross, so each one is searched between
    two already found: O(m n log n) time with n the shorter contour, O(m n)
    memory. For the maximum every first span is searched on the whole grid,
    O(m n^2), since bottleneck paths with ties do not obey the non-crossing
    argument. Ties go to the triangle along ``a``, then to the smaller first
    span. The search runs in the compiled core, bit for bit equal to
    ``optri.contours._reference``.

    References
    ----------
    .. [1] Fuchs, H., Kedem, Z. M., Uselton, S. P. (1977). Optimal surface
       reconstruction from planar contours. Communications of the ACM 20(10),
       693-702. https://doi.org/10.1145/359842.359846

    Examples
    --------
    A unit square under a unit square one unit higher: four side quads of area 1.

    >>> import optri
    >>> sq = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    >>> t = optri.tile_contours(sq, [[x, y, 1] for x, y, _ in sq])
    >>> round(t.weight, 12), t.triangles.shape
    (4.0, (8, 3))
    >>> t.check()
    """
    t0 = time.perf_counter()
    pa, pb = as_contour(a, "contour a"), as_contour(b, "contour b")
    if objective not in CONTOUR_OBJECTIVES:
        raise InvalidParameterError(
            f"unknown objective {objective!r}; use one of {', '.join(CONTOUR_OBJECTIVES)}"
        )
    if start not in STARTS:
        raise InvalidParameterError(f"unknown start {start!r}; use one of {', '.join(STARTS)}")
    if not (callable(weight) or isinstance(weight, str)):
        raise WeightError(f"weight must be a name or a callable, got {type(weight).__name__}")
    m, n = len(pa), len(pb)
    ia = np.arange(m)
    ib = np.arange(n)
    if align and float(_newell(pa) @ _newell(pb)) < 0:
        ib = ib[::-1].copy()
    triangles, cost, first = _search(pa, pb, ia, ib, weight, objective == "max", start)
    name = weight if isinstance(weight, str) else "callable"
    return ContourTiling(
        vertices=np.vstack([pa, pb]),
        triangles=triangles,
        weight=cost,
        m=m,
        n=n,
        start=first,
        weight_name=name,
        objective=objective,
        method=start,
        seconds=time.perf_counter() - t0,
        _weight=weight,
    )


def _search(
    pa: NDArray[np.float64],
    pb: NDArray[np.float64],
    ia: NDArray[np.int64],
    ib: NDArray[np.int64],
    weight: ContourWeight,
    is_max: bool,
    start: str,
) -> tuple[NDArray[np.int64], float, tuple[int, int]]:
    """Run the compiled search with the longer contour as the kernel's ``a``.

    ``ia``, ``ib`` give the order in which each contour is walked (input
    indices). Returns the triangles (indices into ``vertices``), the cost and
    the first span in input indices.
    """
    m = len(pa)
    swap = len(pb) > len(pa)
    # kernel order: (A, B) with B the shorter; global indices of their vertices
    ga, gb = (m + ib, ia) if swap else (ia, m + ib)
    va, vb = (pb[ib], pa[ia]) if swap else (pa[ia], pb[ib])
    j0 = -1
    if start == "closest":
        d = ((va[:, None, :] - vb[None, :, :]) ** 2).sum(axis=2)
        i_star, j0 = (int(x) for x in np.unravel_index(int(np.argmin(d)), d.shape))
        ga, va = np.roll(ga, -i_star), np.roll(va, -i_star, axis=0)
    wp, wq = weight_tables(va, vb, weight)
    if np.isnan(wp).any() or np.isnan(wq).any():
        raise WeightError("the weight is NaN for some triangle")
    core = importlib.import_module("optri._core")  # loaded on first use, not by import optri
    cost, j0, steps = core.contours.tile(wp, wq, is_max, j0)
    if j0 < 0:
        raise WeightError("no tiling has a finite weight (the weight is infinite everywhere)")
    tris = _band(ga, gb, j0, steps)
    if swap:
        tris = tris[:, [0, 2, 1]]  # keep the convention: a's sides forward
    first = (int(ga[0]), int(gb[j0])) if not swap else (int(gb[j0]), int(ga[0]))
    return tris, float(cost), (first[0], first[1] - m)


def _band(ga: NDArray[np.int64], gb: NDArray[np.int64], j0: int, steps: bytes) -> NDArray[np.int64]:
    """The triangles of a path: step 0 adds (A_i, A_i+1, B_j), step 1 (A_i, B_j+1, B_j)."""
    ka, kb = len(ga), len(gb)
    i, j = 0, j0
    out = np.empty((len(steps), 3), dtype=np.int64)
    for s, step in enumerate(steps):
        if step == 0:
            out[s] = (ga[i % ka], ga[(i + 1) % ka], gb[j % kb])
            i += 1
        else:
            out[s] = (ga[i % ka], gb[(j + 1) % kb], gb[j % kb])
            j += 1
    return out
