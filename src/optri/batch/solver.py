"""The per-chunk solver: many vertex arrays in, one result per array out.

Every polygon of a batch chunk and of :func:`optri.triangulate_many` goes
through :func:`solve_polygons`: inputs become vertex arrays (or error results),
are projected to metres when asked, and are handed, all at once, to the
function :func:`chunk_solver` picks: the compiled solver for many small
polygons (:mod:`optri.batch.compiled`: ragged coordinates + offsets, one
kernel call per chunk) where it applies, else :func:`solve_each`, which calls
:func:`optri.triangulate` polygon by polygon. Both have the signature
``solver(arrays, options) -> results`` and give the same results; everything
around them (records, GeoDataFrames, error rows) is the same for both.

A result is a :class:`~optri.result.Triangulation` or the
:class:`~optri.errors.OptriError` that explains why there is none: bad rows
become error results, never exceptions. Warnings a polygon raises while it is
solved (zero-area triangles, numpy overflow) are kept in the result's
``stats["warnings"]`` instead of reaching stderr.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..engines import ENGINES
from ..errors import EngineUnavailableError, InvalidPolygonError, OptriError
from ..objective import as_objective
from ..polygon import is_ring_pair, normalize_vertices
from ..result import Triangulation
from ..weights import resolve_weights
from .compiled import many_plan, solve_compiled
from .each import ChunkSolver, HoledRings, Polygonal, Result, SolveOptions, solve_each
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
    solver = chunk_solver(options)
    # the compiled solver checks 2-D coordinates itself, exactly as the validator does
    # (declined rows go to triangulate, which validates them): numbers need no second pass
    quick = solver is solve_compiled and options.project is None
    for i, obj in enumerate(polygons):
        try:
            raw = _coordinates(obj) if quick else None
            originals.append(polygon_vertices(obj) if raw is None else raw)
            todo.append(i)
        except OptriError as exc:
            results[i] = exc
    arrays = originals
    if options.project is not None:
        arrays, todo, originals = _projected(originals, todo, options.project, results)
    for i, res, original in zip(todo, solver(arrays, options), originals):
        if options.project is not None and isinstance(res, Triangulation):
            res = replace(res, vertices=np.asarray(original)[: res.n])
        results[i] = res
    return results  # type: ignore[return-value]  # every slot is filled above


def _coordinates(obj: Any) -> NDArray[np.float64] | None:
    """``obj`` as a float64 ``(n, 2)`` array when it is one of plain numbers, else None.

    Only the conversion :func:`optri.polygon.normalize_vertices` starts with
    (integers and floats; booleans, strings, objects and other shapes are left
    to it); the checks that follow are the solver's.
    """
    if isinstance(obj, np.ndarray):
        raw = obj
    elif isinstance(obj, (list, tuple)):
        try:
            raw = np.asarray(obj)
        except (TypeError, ValueError):
            return None
    else:
        return None
    if raw.dtype.kind not in "fiu" or raw.ndim != 2 or raw.shape[1] != 2:
        return None
    return raw.astype(np.float64, copy=False)


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
    """The solver for a chunk under ``options``: the compiled many-polygon path, if it applies.

    :func:`optri.batch.compiled.solve_compiled` when the options suit its
    kernel (a built-in weight on coordinates, ``"sum"`` or ``"max"``, method
    ``"auto"``, ``"table"``, ``"memo"`` or ``"fast"``, numba installed,
    ``config.MANY_COMPILED``), else :func:`solve_each`. Both give the same
    results, polygon by polygon.

    >>> chunk_solver(SolveOptions()).__name__, chunk_solver(SolveOptions(method="brute")).__name__
    ('solve_compiled', 'solve_each')
    """
    return solve_compiled if many_plan(options) is not None else solve_each
