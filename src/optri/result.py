"""The :class:`Triangulation` result and its invariant checks."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .drawing.figures import plot_triangulation
from .drawing.html import triangulation_html
from .drawing.svg import triangulation_svg
from .io.geo import to_shapely
from .objective import Cost, Objective
from .polygon import signed_area
from .predicates import orient

__all__ = ["Triangulation", "diagonals_of", "chords_cross_free"]


@dataclass(eq=False)
class Triangulation:
    """An optimal triangulation and how it was found.

    Attributes
    ----------
    vertices : ndarray
        Input vertices (closing duplicate removed): ``(n, 2)``, ``(n, 3)`` or
        ``(n,)`` values.
    triangles : ndarray of int64, shape (n - 2, 3)
        Input vertex indices, each triangle counter-clockwise.
    weight : float or tuple of float
        Optimal objective value (a tuple for a lexicographic objective).
    method : str
        Engine that solved it.
    weight_name : str or tuple of str
    objective : str or tuple of str
    orientation : {"ccw", "cw", None}
        Orientation of the input polygon (None: values or 3-D).
    table : ndarray or None
        The paper's n x n table in internal (counter-clockwise) vertex order:
        sub-polygon costs above the diagonal, optimal split vertices below,
        zeros on it. See :func:`optri.format_table`.
    order : ndarray of int64
        ``order[internal] == input`` index (identity for counter-clockwise input).
    stats : dict
        Engine instrumentation (weight evaluations, look-ups, cells...).
    seconds : float
        Wall time of the engine.
    optimality : {"proven", "heuristic"} or None
        How optimality was established: ``"proven"`` (the DP, or an integer
        program solved with gap 0), ``"heuristic"`` (a limit stopped the
        search: :attr:`bound` and :attr:`gap` say how far from optimal it may
        be), None where the producer does not say (enumeration, 3-D search).
    bound : float, tuple or None
        A proven lower bound on the optimum (equal to :attr:`weight` when
        proven; ``-inf`` when nothing is known).
    gap : float or None
        Relative gap ``(weight - bound) / |weight|``: 0 when proven.
    rings : tuple of int
        For a polygon with holes, the vertex counts of the exterior ring and of
        each hole (vertices are numbered in that order); empty for a simple
        polygon.

    Examples
    --------
    >>> import optri
    >>> t = optri.triangulate([[0, 0], [2, 0], [2, 1], [0, 1]])
    >>> t.triangles.tolist(), round(t.weight, 6), t.orientation
    ([[0, 1, 3], [1, 2, 3]], 10.472136, 'ccw')
    >>> t.check()  # raises AssertionError if an invariant fails
    """

    vertices: NDArray[np.float64]
    triangles: NDArray[np.int64]
    weight: Cost
    method: str
    weight_name: str | tuple[str, ...]
    objective: str | tuple[str, ...]
    orientation: str | None
    table: NDArray[np.float64] | None = None
    order: NDArray[np.int64] | None = None
    stats: dict[str, int] = field(default_factory=dict)
    seconds: float = 0.0
    _recompute: Callable[[NDArray[np.int64]], Cost] | None = field(default=None, repr=False)
    optimality: str | None = None
    bound: Cost | None = None
    gap: float | None = None
    rings: tuple[int, ...] = ()

    @property
    def holes(self) -> int:
        """Number of holes of the triangulated polygon (0 for a simple polygon)."""
        return max(len(self.rings) - 1, 0)

    @property
    def n(self) -> int:
        """Number of polygon vertices."""
        return int(self.vertices.shape[0])

    @property
    def cost(self) -> Cost:
        """Alias of :attr:`weight`."""
        return self.weight

    @property
    def diagonals(self) -> NDArray[np.int64]:
        """Diagonals as sorted ``(a, b)`` pairs, ``a < b``: n - 3 (n + 3h - 3 with h holes)."""
        return diagonals_of(self.triangles, self.n, self.rings)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary: n, weight, triangles, diagonals, method, seconds, ..."""
        w = self.weight
        return {
            "n": self.n,
            "weight": list(w) if isinstance(w, tuple) else _json_float(w),
            "triangles": self.triangles.tolist(),
            "diagonals": self.diagonals.tolist(),
            "method": self.method,
            "weight_name": list(self.weight_name)
            if isinstance(self.weight_name, tuple)
            else self.weight_name,
            "objective": list(self.objective)
            if isinstance(self.objective, tuple)
            else self.objective,
            "orientation": self.orientation,
            "seconds": self.seconds,
            "stats": dict(self.stats),
            "optimality": self.optimality,
            "bound": _json_cost(self.bound),
            "gap": None if self.gap is None else _json_float(self.gap),
            **({"rings": list(self.rings)} if self.rings else {}),
        }

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """Draw the triangulation with matplotlib; returns the Axes.

        See :func:`optri.drawing.plot_triangulation` for keyword options.
        """
        return plot_triangulation(self, ax=ax, **kwargs)

    def to_shapely(self) -> Any:
        """The triangles as a ``shapely.GeometryCollection`` (:func:`optri.io.to_shapely`)."""
        return to_shapely(self)

    @property
    def __geo_interface__(self) -> dict[str, Any]:
        """GeoJSON MultiPolygon of the triangles (2-D input only)."""
        if self.vertices.ndim != 2:
            raise TypeError("a triangulation of vertex values has no geometry")
        pts = self.vertices[:, :2].tolist()
        polys = [[[pts[a], pts[b], pts[c], pts[a]]] for a, b, c in self.triangles.tolist()]
        return {"type": "MultiPolygon", "coordinates": polys}

    def _repr_svg_(self) -> str:
        """SVG drawing for notebooks: triangles filled, polygon outlined.

        3-D input is drawn from x and y; vertex values (e.g. the paper's
        pentagon 5, 1, 5, 1, 5) on a regular n-gon labelled with the values.

        >>> import optri
        >>> svg = optri.triangulate([[0, 0], [1, 0], [1, 1], [0, 1]])._repr_svg_()
        >>> svg.startswith("<svg") and svg.count("<polygon") == 3
        True
        >>> svg = optri.triangulate([5, 1, 5, 1, 5], "product")._repr_svg_()
        >>> svg.count("<polygon"), svg.count("<text")
        (4, 5)
        """
        return triangulation_svg(self.vertices, self.triangles)

    def _repr_html_(self) -> str:
        """HTML for notebooks: the drawing with the paper's n x n table beside it.

        >>> import optri
        >>> html = optri.triangulate([5, 1, 5, 1, 5], "product", method="memo")._repr_html_()
        >>> "<svg" in html and "<table" in html and "-1" not in html
        True
        """
        return triangulation_html(self)

    def __repr__(self) -> str:
        return (
            f"Triangulation(n={self.n}, weight={self.weight!r}, method={self.method!r}, "
            f"weight_name={self.weight_name!r}, objective={self.objective!r})"
        )

    def check(self, rtol: float = 1e-9) -> None:
        """Assert every invariant of a triangulation; raise AssertionError if one fails.

        Checks: n - 2 triangles of distinct in-range vertices; pairwise
        non-crossing diagonals; every polygon side in exactly one triangle and
        every diagonal in exactly two; n - 3 diagonals; for 2-D input every
        triangle counter-clockwise (decided exactly) and the triangle areas
        summing to the polygon's area (computed on centred coordinates, so it
        holds at any offset and magnitude); the cost recomputed from the
        triangles equal to :attr:`weight`.

        Crossings are tested before the edge counts: with every edge count right
        no two diagonals crossed in an exhaustive search up to n = 8, so tested
        after them the crossing test would never fire; first, it names the fault.
        """
        if self.rings:
            self._check_domain(rtol)
            return
        n, tris = self.n, self.triangles
        _require(tris.shape == (n - 2, 3), f"expected {n - 2} triangles, got {tris.shape}")
        _require(bool(((tris >= 0) & (tris < n)).all()), "vertex index out of range")
        _require(all(len(set(t)) == 3 for t in tris.tolist()), "degenerate index triangle")
        diags = self.diagonals
        _require(chords_cross_free(diags), "two diagonals cross")
        edges: dict[tuple[int, int], int] = {}
        for a, b, c in tris.tolist():
            for e in ((a, b), (b, c), (c, a)):
                key = (min(e), max(e))
                edges[key] = edges.get(key, 0) + 1
        for (a, b), count in edges.items():
            side = b - a == 1 or (a == 0 and b == n - 1)
            _require(count == (1 if side else 2), f"edge {(a, b)} used {count} times")
        _require(len(edges) == 2 * n - 3, "sides missing from the triangulation")
        _require(len(diags) == n - 3, f"expected {n - 3} diagonals, got {len(diags)}")
        if self.vertices.ndim == 2 and self.vertices.shape[1] == 2:
            self._check_areas(rtol)
        if self._recompute is not None:
            again = self._recompute(self.triangles)
            _require(_close(again, self.weight, rtol), f"cost {self.weight} != recomputed {again}")

    def _check_domain(self, rtol: float) -> None:
        """Invariants of a triangulation of a polygon with holes (:attr:`rings`).

        n + 2h - 2 triangles, all counter-clockwise; as chains, each boundary
        edge once in its ring's inner direction and every other edge once each
        way. Summed, the triangles' boundaries then leave exactly the domain's
        boundary, so the triangles tile the domain; areas are compared too.
        """
        n, tris, h = self.n, self.triangles, self.holes
        _require(sum(self.rings) == n, f"ring sizes {self.rings} do not add up to {n}")
        _require(tris.shape == (n + 2 * h - 2, 3), f"expected {n + 2 * h - 2} triangles")
        _require(bool(((tris >= 0) & (tris < n)).all()), "vertex index out of range")
        inner = set(_ring_edges(self.rings, self._inner_forward()))
        used: dict[tuple[int, int], int] = {}
        for a, b, c in tris.tolist():
            for e in ((a, b), (b, c), (c, a)):
                used[e] = used.get(e, 0) + 1
        for (a, b), count in used.items():
            _require(count == 1, f"edge {(a, b)} used {count} times in the same direction")
            if (a, b) not in inner:
                _require((b, a) in used and (b, a) not in inner, f"edge {(a, b)} unmatched")
        _require(inner <= used.keys(), "a boundary edge is in no triangle")
        _require(len(self.diagonals) == n + 3 * h - 3, "wrong number of diagonals")
        self._check_areas(rtol)
        if self._recompute is not None:
            again = self._recompute(self.triangles)
            _require(_close(again, self.weight, rtol), f"cost {self.weight} != recomputed {again}")

    def _inner_forward(self) -> list[bool]:
        """Per ring, whether walking it in index order keeps the domain on the left."""
        out, start = [], 0
        for k, m in enumerate(self.rings):
            area = signed_area(self.vertices[start : start + m, :2])
            out.append((area > 0) == (k == 0))
            start += m
        return out

    def _check_areas(self, rtol: float) -> None:
        # every triangle counter-clockwise, decided exactly; zero-area ones pass
        p = self.vertices
        t0, t1, t2 = (self.triangles[:, m] for m in range(3))
        _require(bool((orient(p[t0], p[t1], p[t2]) >= 0).all()), "a triangle is clockwise")
        # the signed triangle areas of any triangulation add up to the shoelace area, an
        # identity: compare the two sums on centred coordinates scaled below 1 (exactly, by
        # a power of two), so neither offsets (UTM) nor magnitude (1e300) cost accuracy
        q = _centred_unit(p)
        a, b, c = q[t0], q[t1], q[t2]
        areas = 0.5 * (
            (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
        )
        total = math.fsum(areas.tolist())
        shoelace = _domain_area(q, self.rings)  # triangles are CCW whatever the orientation
        slack = 64 * len(p) * np.finfo(float).eps  # rounding of both sums, |q| < 1
        _require(
            math.isclose(total, shoelace, rel_tol=rtol, abs_tol=slack),
            f"triangle areas sum to {total}, polygon area is {shoelace} (centred, scaled)",
        )


def _domain_area(q: NDArray[np.float64], rings: tuple[int, ...]) -> float:
    """Area of the polygon (less its holes, ``rings`` the ring sizes; empty: one ring)."""
    if not rings:
        return abs(signed_area(q))
    total, start = 0.0, 0
    for k, m in enumerate(rings):
        area = abs(signed_area(q[start : start + m]))
        total += area if k == 0 else -area
        start += m
    return total


def _centred_unit(points: NDArray[np.float64]) -> NDArray[np.float64]:
    """2-D points centred on their bounding box and scaled by a power of two below 1."""
    p = points[:, :2]
    lo, hi = p.min(axis=0), p.max(axis=0)
    q = p - (lo + (hi - lo) / 2)
    big = float(np.abs(q).max())
    return np.ldexp(q, -math.frexp(big)[1]) if big > 0 else q


def diagonals_of(
    triangles: NDArray[np.int64], n: int, rings: tuple[int, ...] = ()
) -> NDArray[np.int64]:
    """Sorted unique diagonals (non-side edges) of index triangles.

    ``rings``: the ring sizes of a polygon with holes (sides are then the edges
    of each ring); empty for a simple polygon.

    >>> diagonals_of(np.array([[0, 1, 4], [1, 2, 4]]), 6, (3, 3)).tolist()
    [[0, 4], [1, 4], [2, 4]]
    """
    if len(triangles) == 0:
        return np.zeros((0, 2), dtype=np.int64)
    e = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    e = np.sort(e, axis=1)
    if rings:
        sides = np.sort(np.array(_ring_edges(rings), dtype=np.int64).reshape(-1, 2), axis=1)
        side_keys = sides[:, 0] * n + sides[:, 1]
        e = e[~np.isin(e[:, 0] * n + e[:, 1], side_keys)]
    else:
        gap = e[:, 1] - e[:, 0]
        e = e[(gap != 1) & (gap != n - 1)]
    return np.unique(e, axis=0).astype(np.int64).reshape(-1, 2)


def _ring_edges(rings: tuple[int, ...], forward: list[bool] | None = None) -> list[tuple[int, int]]:
    """Edges ``(v, next)`` of each ring in index order (reversed where ``forward`` is False)."""
    out, start = [], 0
    for k, m in enumerate(rings):
        for v in range(m):
            a, b = start + v, start + (v + 1) % m
            out.append((a, b) if forward is None or forward[k] else (b, a))
        start += m
    return out


def chords_cross_free(chords: NDArray[np.int64]) -> bool:
    """True when no two chords (a < b) of a convex index polygon cross; O(m log m).

    Chords are non-crossing exactly when, sorted by (a, -b), they nest like
    parentheses: each chord lies inside or beside the ones still open.
    """
    if len(chords) < 2:
        return True
    order = np.lexsort((-chords[:, 1], chords[:, 0]))
    stack: list[int] = []
    for a, b in chords[order].tolist():
        while stack and stack[-1] <= a:
            stack.pop()
        if stack and b > stack[-1]:
            return False
        stack.append(b)
    return True


def recompute_cost(
    evaluate: Callable[[int, int, int], Cost], objective: Objective, order: NDArray[np.int64]
) -> Callable[[NDArray[np.int64]], Cost]:
    """Build a function giving the cost of input-index triangles from scratch."""
    inverse = np.empty_like(order)
    inverse[order] = np.arange(len(order))

    def again(triangles: NDArray[np.int64]) -> Cost:
        vals = []
        for t in inverse[triangles].tolist():
            i, k, j = sorted(t)
            vals.append(evaluate(i, k, j))
        return objective.finalize(objective.aggregate(vals))

    return again


def _json_cost(v: Cost | None) -> Any:
    if v is None:
        return None
    return [_json_float(x) for x in v] if isinstance(v, tuple) else _json_float(v)


def _json_float(v: float) -> float | str:
    return v if math.isfinite(v) else str(v)


def _close(a: Cost, b: Cost, rtol: float) -> bool:
    if isinstance(a, tuple) and isinstance(b, tuple):
        return all(_close(x, y, rtol) for x, y in zip(a, b))
    return bool(math.isclose(a, b, rel_tol=rtol, abs_tol=rtol))  # type: ignore[arg-type]


def _require(cond: bool, msg: str) -> None:
    if not cond:
        raise AssertionError(f"Triangulation.check: {msg}")
