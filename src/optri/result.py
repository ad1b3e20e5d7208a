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
        """The n - 3 diagonals as sorted ``(a, b)`` pairs, ``a < b``."""
        return diagonals_of(self.triangles, self.n)

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
        every diagonal in exactly two; n - 3 diagonals; for planar input every
        triangle counter-clockwise and the triangle areas summing to the
        polygon's area; the cost recomputed from the triangles equal to
        :attr:`weight`.

        Crossings are tested before the edge counts: with every edge count right
        no two diagonals crossed in an exhaustive search up to n = 8, so tested
        after them the crossing test would never fire; first, it names the fault.
        """
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

    def _check_areas(self, rtol: float) -> None:
        p = self.vertices
        a, b, c = p[self.triangles[:, 0]], p[self.triangles[:, 1]], p[self.triangles[:, 2]]
        areas = 0.5 * (
            (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
        )
        scale = float(np.abs(areas).sum()) or 1.0
        _require(bool((areas >= -rtol * scale).all()), "a triangle is clockwise")
        total = abs(signed_area(p))
        _require(
            math.isclose(float(areas.sum()), total, rel_tol=1e-7, abs_tol=rtol * scale),
            f"triangle areas sum to {areas.sum()}, polygon area is {total}",
        )


def diagonals_of(triangles: NDArray[np.int64], n: int) -> NDArray[np.int64]:
    """Sorted unique diagonals (non-side edges) of index triangles."""
    if len(triangles) == 0:
        return np.zeros((0, 2), dtype=np.int64)
    e = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    e = np.sort(e, axis=1)
    gap = e[:, 1] - e[:, 0]
    e = e[(gap != 1) & (gap != n - 1)]
    return np.unique(e, axis=0).astype(np.int64).reshape(-1, 2)


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


def _json_float(v: float) -> float | str:
    return v if math.isfinite(v) else str(v)


def _close(a: Cost, b: Cost, rtol: float) -> bool:
    if isinstance(a, tuple) and isinstance(b, tuple):
        return all(_close(x, y, rtol) for x, y in zip(a, b))
    return bool(math.isclose(a, b, rel_tol=rtol, abs_tol=rtol))  # type: ignore[arg-type]


def _require(cond: bool, msg: str) -> None:
    if not cond:
        raise AssertionError(f"Triangulation.check: {msg}")
