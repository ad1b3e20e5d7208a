"""The per-chunk solver: many vertex arrays in, one result per array out.

Every polygon of a batch chunk and of :func:`optri.triangulate_many` goes
through :func:`solve_polygons`: inputs become vertex arrays (or error results),
are projected to metres when asked, and are handed, all at once, to the
function :func:`chunk_solver` picks. Today that is :func:`solve_each`, which
calls :func:`optri.triangulate` polygon by polygon; a compiled solver for many
small polygons (ragged coordinates + offsets, one kernel call per chunk) plugs
in there with the same signature, ``solver(arrays, options) -> results``, and
everything around it (records, GeoDataFrames, error rows) stays as it is.

A result is a :class:`~optri.result.Triangulation` or the
:class:`~optri.errors.OptriError` that explains why there is none: bad rows
become error results, never exceptions. Warnings a polygon raises while it is
solved (zero-area triangles, numpy overflow) are kept in the result's
``stats["warnings"]`` instead of reaching stderr.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..engines import ENGINES
from ..errors import EngineUnavailableError, InvalidPolygonError, OptriError
from ..objective import as_objective
from ..polygon import is_ring_pair, normalize_vertices
from ..result import Triangulation
from ..solve import triangulate
from ..weights import resolve_weights
from .project import local_projector

__all__ = [
    "ChunkSolver",
    "HoledRings",
    "Result",
    "SolveOptions",
    "check_options",
    "chunk_solver",
    "polygon_rings",
    "polygon_vertices",
    "solve_each",
    "solve_polygons",
]

Result = Triangulation | OptriError


@dataclass(frozen=True)
class SolveOptions:
    """What every polygon of a chunk is solved with (picklable when the weight is).

    ``project`` is the layer's CRS (any text pyproj reads) when polygons are to
    be measured in metres in a local azimuthal equidistant projection, else None.
    """

    weight: Any = "perimeter"
    objective: Any = "sum"
    method: str = "auto"
    project: str | None = None


def check_options(weight: Any, objective: Any, method: str) -> dict[str, Any]:
    """Check weight, objective and method before any work (raise the library's errors)."""
    resolve_weights(weight, len(as_objective(objective).components))
    if not isinstance(method, str):
        raise EngineUnavailableError(f"method must be a name such as 'auto', got {method!r}")
    if method != "auto":
        spec = ENGINES.get(method)
        if spec is None:
            known = ", ".join(["auto", *ENGINES])
            raise EngineUnavailableError(f"unknown method {method!r}; choose one of: {known}")
        check = getattr(spec.load(), "unavailable", None)
        reason = check() if check is not None else None
        if reason is not None:
            raise EngineUnavailableError(reason)
    return dict(weight=weight, objective=objective, method=method)


ChunkSolver = Callable[[Sequence["Polygonal"], SolveOptions], list[Result]]


@dataclass(frozen=True, eq=False)
class HoledRings:
    """A polygon with holes in a batch: its vertices, exterior ring first, and the ring sizes.

    Vertices are numbered as :func:`optri.triangulate` numbers them (exterior,
    then each hole in order, closing vertices dropped), so triangles index
    :attr:`vertices` directly. Behaves as that array for the writers.

    >>> h = polygon_rings([[[0, 0], [3, 0], [3, 3], [0, 3]], [[1, 1], [1, 2], [2, 2], [2, 1]]])
    >>> h.sizes, h.shape
    ((4, 4), (8, 2))
    """

    vertices: NDArray[np.float64]
    sizes: tuple[int, ...]

    @property
    def shape(self) -> tuple[int, ...]:
        """The shape of :attr:`vertices`."""
        return self.vertices.shape

    def __len__(self) -> int:
        return len(self.vertices)

    def __iter__(self) -> Any:
        return iter(self.vertices)

    def __array__(self, dtype: Any = None, copy: Any = None) -> NDArray[Any]:
        return np.asarray(self.vertices, dtype=dtype)

    def tolist(self) -> list:
        """:attr:`vertices` as nested lists."""
        return self.vertices.tolist()

    def with_vertices(self, vertices: NDArray[np.float64]) -> HoledRings:
        """The same rings at other coordinates (a projection of :attr:`vertices`)."""
        return HoledRings(vertices, self.sizes)

    def pair(self) -> tuple[NDArray[np.float64], list[NDArray[np.float64]]]:
        """``(exterior, [holes])``, the form :func:`optri.triangulate` takes."""
        rings = np.split(self.vertices, np.cumsum(self.sizes)[:-1])
        return rings[0], rings[1:]


Polygonal = NDArray[np.float64] | HoledRings


def polygon_vertices(obj: Any) -> Polygonal:
    """The vertices of one polygon: an ``(n, 2)``/``(n, 3)`` array-like or a shapely Polygon.

    A MultiPolygon of one part is that part; a Polygon with holes, or an
    ``(exterior, [holes])`` pair, gives :class:`HoledRings`. Raises
    InvalidPolygonError otherwise (never a numpy or shapely error).

    >>> polygon_vertices([[0, 0], [1, 0], [0, 1]]).shape
    (3, 2)
    """
    if obj is None:
        raise InvalidPolygonError("empty or missing geometry")
    if isinstance(obj, HoledRings):  # read and checked already
        return obj
    if hasattr(obj, "geom_type"):  # shapely, without importing it
        return _shapely_vertices(obj)
    if is_ring_pair(obj):
        return polygon_rings([obj[0], *obj[1]])
    # the shared validator: numbers, shape, closing vertices, repeats
    return normalize_vertices(obj, values=False)


def polygon_rings(rings: Sequence[Any]) -> Polygonal:
    """The vertices of a polygon given as rings (exterior first, then holes).

    One ring is a simple polygon (an array); more give :class:`HoledRings`,
    each ring checked by the shared validator (closing vertices dropped).
    """
    if len(rings) == 1:
        return polygon_vertices(rings[0])
    arrays = []
    for k, ring in enumerate(rings):
        try:
            arrays.append(normalize_vertices(ring, values=False))
        except InvalidPolygonError as exc:
            name = "exterior ring" if k == 0 else f"hole {k - 1}"
            raise InvalidPolygonError(f"{name}: {exc}") from None
    if any(a.shape[1] != arrays[0].shape[1] for a in arrays):
        raise InvalidPolygonError("the rings of a polygon mix 2-D and 3-D coordinates")
    return HoledRings(np.concatenate(arrays), tuple(len(a) for a in arrays))


def _shapely_vertices(geom: Any) -> Polygonal:
    if geom.is_empty:
        raise InvalidPolygonError("empty or missing geometry")
    if geom.geom_type == "MultiPolygon":
        if len(geom.geoms) != 1:
            raise InvalidPolygonError(f"MultiPolygon with {len(geom.geoms)} parts; split it")
        geom = geom.geoms[0]
    if geom.geom_type != "Polygon":
        raise InvalidPolygonError(f"geometry type {geom.geom_type!r} is not a Polygon")
    rings = [geom.exterior, *geom.interiors]
    return polygon_rings([np.asarray(r.coords, dtype=np.float64) for r in rings])


def solve_polygons(polygons: Sequence[Any], options: SolveOptions) -> list[Result]:
    """Solve many polygons; one :data:`Result` per input, in order, never raising for a row.

    With ``options.project`` each polygon is measured in metres, and the
    result's ``vertices`` are the input coordinates again.

    >>> from optri.batch.solver import SolveOptions, solve_polygons
    >>> out = solve_polygons([[[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 0]]], SolveOptions())
    >>> round(out[0].weight, 6), type(out[1]).__name__
    (6.828427, 'InvalidPolygonError')
    """
    results: list[Result | None] = [None] * len(polygons)
    todo: list[int] = []
    originals: list[Polygonal] = []
    for i, obj in enumerate(polygons):
        try:
            originals.append(polygon_vertices(obj))
            todo.append(i)
        except OptriError as exc:
            results[i] = exc
    arrays = originals
    if options.project is not None:
        arrays, todo, originals = _projected(originals, todo, options.project, results)
    for i, res, original in zip(todo, chunk_solver(options)(arrays, options), originals):
        if options.project is not None and isinstance(res, Triangulation):
            res = replace(res, vertices=np.asarray(original)[: res.n])
        results[i] = res
    return results  # type: ignore[return-value]  # every slot is filled above


def _projected(
    originals: list[Polygonal],
    todo: list[int],
    crs: str,
    results: list[Result | None],
) -> tuple[list[Polygonal], list[int], list[Polygonal]]:
    project = local_projector(crs)
    arrays: list[Polygonal] = []
    kept: list[int] = []
    kept_originals: list[Polygonal] = []
    for i, arr in zip(todo, originals):
        try:
            if isinstance(arr, HoledRings):
                arrays.append(arr.with_vertices(project(arr.vertices)))
            else:
                arrays.append(project(arr))
            kept.append(i)
            kept_originals.append(arr)
        except OptriError as exc:
            results[i] = exc
    return arrays, kept, kept_originals


def chunk_solver(options: SolveOptions) -> ChunkSolver:
    """The solver for a chunk under ``options``: where a compiled many-polygon path plugs in."""
    return solve_each


def solve_each(arrays: Sequence[Polygonal], options: SolveOptions) -> list[Result]:
    """The per-polygon path: :func:`optri.triangulate` on each array, errors as results.

    Any exception a polygon raises (a user weight's included) becomes its
    result, wrapped in an :class:`OptriError` naming the original type.
    ``stats["wall_seconds"]`` is the polygon's whole time, ``stats["warnings"]``
    the warnings it raised.
    """
    out: list[Result] = []
    for arr in arrays:
        start = time.perf_counter()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                source = arr.pair() if isinstance(arr, HoledRings) else arr
                tri = triangulate(
                    source,
                    weight=options.weight,
                    objective=options.objective,
                    method=options.method,
                )
            except OptriError as exc:
                out.append(exc)
                continue
            except Exception as exc:  # a user weight, or numpy on odd input: this row only
                wrapped = OptriError(f"{type(exc).__name__}: {exc}")
                wrapped.__cause__ = exc
                out.append(wrapped)
                continue
        tri.stats["wall_seconds"] = time.perf_counter() - start  # type: ignore[assignment]
        notes = list(dict.fromkeys(str(w.message) for w in caught))
        if notes:
            tri.stats["warnings"] = notes  # type: ignore[assignment]
        out.append(tri)
    return out
