"""Columns in, columns out: many polygons as ragged arrays, their triangulations as arrays.

A layer's polygons become one :class:`Ragged` (all coordinates in one array,
plus offsets: rings, polygon parts, rows), built by
:func:`ragged_from_shapely` with ``shapely.to_ragged_array`` (or
:func:`ragged_from_arrow` from a WKB column). :func:`solve_ragged` solves
every part: the simple 2-D parts the compiled kernel takes go to
``optri._core.many.solve``, one call per chunk, with offsets computed by numpy
(no Python object per polygon); holed parts, 3-D parts, projected parts and
parts the kernel declines go to the per-polygon path (:func:`optri.triangulate`,
through :func:`optri.batch.solver.solve_polygons` and
:func:`optri.batch.each.solve_each`), which gives their exact results, errors
and warnings. The answer is a :class:`Solved`: status, cost, reason and
vertex count per row, and every triangle as three indices into
``Ragged.coords``. A :class:`~optri.result.Triangulation` is built only for a
row a caller asks for (:meth:`Solved.triangulation`).

A row is one feature: a MultiPolygon's parts are solved one by one and the
row's cost combines theirs by the objective, component by component (``"sum"``
adds, ``"max"`` takes the largest). Each part gets its own optimal
triangulation, so a row's cost is the optimum of the parts taken together for
``"sum"``, ``"max"`` and lexicographic pairs led by ``"sum"``; for a pair led by
``"max"`` it is the combined cost of the parts' own optima (a part whose
maximum stays below the row's could trade a larger maximum for a smaller second
component; it does not). A part that fails makes its row an error row whose
reason names the part (``"part 2: ..."``, numbered from 0).

Output geometry (:func:`triangle_geometries`, :func:`triangle_wkb`) is built
from the coordinate arrays in a few vectorised shapely calls: per row a valid
GeometryCollection of triangle Polygons (what ``shapely.constrained_delaunay_triangles``
returns), or one Polygon per triangle with its row (``explode=True``), with Z
where the input has it.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .. import config
from .._optional import import_optional
from ..errors import InvalidPolygonError, OptriError
from ..objective import Objective, as_objective
from ..result import Triangulation
from .compiled import ManyPlan, kernel_result, many_plan, run_kernel
from .each import WARNINGS_LOCK, Polygonal, Result, SolveOptions, one_line, solve_each
from .solver import polygon_rings, solve_polygons

__all__ = [
    "ERROR",
    "OK",
    "Ragged",
    "Solved",
    "ragged_from_arrow",
    "ragged_from_shapely",
    "solve_ragged",
    "triangle_geojson",
    "triangle_geometries",
    "triangle_wkb",
]

#: :attr:`Solved.status` of a triangulated row.
OK = 0
#: :attr:`Solved.status` of a row without a triangulation (:attr:`Solved.reason` says why).
ERROR = 1

#: Reason of a null or empty geometry.
EMPTY = "empty or missing geometry"

Ints = NDArray[np.int64]


@dataclass(frozen=True, eq=False)
class Ragged:
    """Many polygonal rows as flat arrays (the layout of ``shapely.to_ragged_array``).

    Attributes
    ----------
    coords : ndarray, shape (V, 2) or (V, 3), float64
        Every vertex of every ring, rings closed as read (the closing vertex included).
    ring_offsets : ndarray, shape (R + 1,), int64
        Ring ``r`` is ``coords[ring_offsets[r]:ring_offsets[r + 1]]``.
    part_offsets : ndarray, shape (P + 1,), int64
        Polygon part ``p`` has rings ``part_offsets[p]`` to ``part_offsets[p + 1] - 1``,
        the exterior first.
    row_offsets : ndarray, shape (rows + 1,), int64
        Row ``i`` has parts ``row_offsets[i]`` to ``row_offsets[i + 1] - 1``: one for a
        Polygon, several for a MultiPolygon, none for a row with a :attr:`reason`.
    has_z : bool
        Whether ``coords`` has a third column.
    reason : ndarray, shape (rows,), object
        None, or one line saying why the row is unusable before any solving (null,
        empty, not polygonal).
    row_z : ndarray, shape (rows,), bool
        Whether the row's own coordinates have Z (in a layer mixing 2-D and 3-D rows,
        the Z column of a 2-D row is NaN and is ignored).

    Examples
    --------
    >>> import shapely
    >>> r = ragged_from_shapely([shapely.box(0, 0, 1, 1), None, shapely.Point(0, 0)])
    >>> len(r), r.coords.shape, r.row_offsets.tolist(), r.reason[1]
    (3, (5, 2), [0, 1, 1, 1], 'empty or missing geometry')
    >>> r.reason[2]
    "geometry type 'Point' is not a Polygon or MultiPolygon"
    """

    coords: NDArray[np.float64]
    ring_offsets: Ints
    part_offsets: Ints
    row_offsets: Ints
    has_z: bool
    reason: NDArray[np.object_]
    row_z: NDArray[np.bool_]

    def __len__(self) -> int:
        return len(self.row_offsets) - 1

    @property
    def part_row(self) -> Ints:
        """The row of each part, shape (P,)."""
        return np.repeat(np.arange(len(self), dtype=np.int64), np.diff(self.row_offsets))

    def rings_of(self, part: int) -> list[NDArray[np.float64]]:
        """The rings of one part as arrays (exterior first; 2-D unless its row has Z)."""
        width = 3 if self.row_z[self.part_row[part]] else 2
        lo, hi = self.part_offsets[part], self.part_offsets[part + 1]
        bounds = self.ring_offsets[lo : hi + 1]
        return [self.coords[a:b, :width] for a, b in zip(bounds[:-1], bounds[1:])]


def _object_array(geoms: Any) -> NDArray[np.object_]:
    if isinstance(geoms, np.ndarray) and geoms.dtype == object and geoms.ndim == 1:
        return geoms
    values = getattr(geoms, "values", geoms)  # a GeoSeries: its GeometryArray
    if type(values).__name__ == "GeometryArray":
        return np.asarray(values, dtype=object)
    return np.fromiter(list(geoms), dtype=object, count=len(geoms))


def _why(obj: Any) -> str:
    """The reason a row that is not a non-empty Polygon or MultiPolygon is unusable."""
    if obj is None or getattr(obj, "is_empty", False):
        return EMPTY
    kind = getattr(obj, "geom_type", None)
    if kind is not None:
        return f"geometry type {kind!r} is not a Polygon or MultiPolygon"
    return f"expected a shapely geometry, got {type(obj).__name__}"


def ragged_from_shapely(geoms: Any) -> Ragged:
    """The polygonal rows of ``geoms`` as a :class:`Ragged`; other rows get a reason.

    Parameters
    ----------
    geoms : sequence, numpy object array or GeoSeries
        shapely geometries: Polygons and MultiPolygons (mixed freely, 2-D or with Z).
        None, empty geometries, other geometry types and other objects become rows with
        a :attr:`Ragged.reason` and no parts; nothing raises for a row.

    Examples
    --------
    >>> import shapely
    >>> two = shapely.MultiPolygon([shapely.box(0, 0, 1, 1), shapely.box(2, 0, 3, 1)])
    >>> r = ragged_from_shapely([two, shapely.box(0, 0, 1, 1)])
    >>> r.row_offsets.tolist(), r.part_offsets.tolist(), r.ring_offsets.tolist()
    ([0, 2, 3], [0, 1, 2, 3], [0, 5, 10, 15])
    """
    shapely = import_optional("shapely")
    arr = _object_array(geoms)
    rows = len(arr)
    good = np.zeros(rows, dtype=bool)
    is_geom = shapely.is_geometry(arr)
    if is_geom.any():
        g = arr[is_geom]
        kind = shapely.get_type_id(g)
        good[is_geom] = ((kind == 3) | (kind == 6)) & ~shapely.is_empty(g)
    reason = np.full(rows, None, dtype=object)
    for i in np.flatnonzero(~good):
        reason[i] = _why(arr[i])
    row_z = np.zeros(rows, dtype=bool)
    parts_per_row = np.zeros(rows, dtype=np.int64)
    if not good.any():
        zero = np.zeros(1, dtype=np.int64)
        empty = np.zeros((0, 2), dtype=np.float64)
        return Ragged(empty, zero, zero, np.zeros(rows + 1, np.int64), False, reason, row_z)
    kept = arr[good]
    parts, per_row = _polygon_parts(shapely, kept)
    holes = shapely.get_num_interior_rings(parts).astype(np.int64)
    part_offsets = np.zeros(len(parts) + 1, dtype=np.int64)
    np.cumsum(holes + 1, out=part_offsets[1:])
    rings = parts
    if holes.any():  # every part's rings in order; a hole-free part stands for its exterior
        rings = np.empty(int(part_offsets[-1]), dtype=object)
        rings[part_offsets[:-1][holes == 0]] = parts[holes == 0]
        holed = np.flatnonzero(holes)
        found, owner = shapely.get_rings(parts[holed], return_index=True)
        size = holes[holed] + 1
        within = np.arange(len(found)) - (np.cumsum(size) - size)[owner]
        rings[part_offsets[holed][owner] + within] = found
    has_z = bool(shapely.has_z(kept).any())
    coords, owner = shapely.get_coordinates(rings, include_z=has_z, return_index=True)
    ring_offsets = np.zeros(len(rings) + 1, dtype=np.int64)
    np.cumsum(np.bincount(owner, minlength=len(rings)), out=ring_offsets[1:])
    parts_per_row[good] = per_row
    row_offsets = np.zeros(rows + 1, dtype=np.int64)
    np.cumsum(parts_per_row, out=row_offsets[1:])
    if has_z:
        row_z[good] = shapely.has_z(kept)
    coords = np.ascontiguousarray(coords, dtype=np.float64)
    return Ragged(coords, ring_offsets, part_offsets, row_offsets, has_z, reason, row_z)


def _polygon_parts(shapely: Any, kept: NDArray[np.object_]) -> tuple[NDArray[np.object_], Ints]:
    """The non-empty Polygons of non-empty (Multi)Polygons in row order, and how many per row."""
    multi = shapely.get_type_id(kept) == 6
    if not multi.any():
        return kept, np.ones(len(kept), dtype=np.int64)
    found, owner = shapely.get_parts(kept[multi], return_index=True)
    full = ~shapely.is_empty(found)
    found, owner = found[full], np.flatnonzero(multi)[owner[full]]
    single = np.flatnonzero(~multi)
    row = np.concatenate([single, owner])
    order = np.argsort(row, kind="stable")  # get_parts keeps each row's parts in order
    parts = np.concatenate([kept[single], found])[order]
    return parts, np.bincount(row, minlength=len(kept)).astype(np.int64)


def ragged_from_arrow(column: Any) -> Ragged:
    """A :class:`Ragged` from a pyarrow geometry column (WKB, e.g. pyogrio's ``read_arrow``).

    ``column`` is a pyarrow Array or ChunkedArray of WKB values (binary or large
    binary, or the ``geoarrow.wkb`` extension type over them), nulls allowed;
    unreadable WKB becomes a row with a reason. GeoArrow's native (coordinate)
    encodings are not read: ask pyogrio for WKB, its default.

    Examples
    --------
    >>> import pyarrow as pa, shapely
    >>> col = pa.array([shapely.to_wkb(shapely.box(0, 0, 1, 1)), None, b"junk"])
    >>> ragged_from_arrow(col).reason.tolist()[1:]
    ['empty or missing geometry', 'unreadable WKB']
    """
    shapely = import_optional("shapely")
    pa = import_optional("pyarrow")
    if isinstance(column, pa.ChunkedArray):
        column = column.combine_chunks()
    if isinstance(column.type, pa.ExtensionType):  # geoarrow.wkb, where registered
        column = column.storage
    if pa.types.is_large_binary(column.type):
        column = column.cast(pa.binary())
    if not pa.types.is_binary(column.type):
        raise InvalidPolygonError(f"expected a WKB (binary) column, got type {column.type}")
    raw = column.to_numpy(zero_copy_only=False)
    geoms = shapely.from_wkb(raw, on_invalid="ignore")
    ragged = ragged_from_shapely(geoms)
    unreadable = np.flatnonzero(shapely.is_missing(geoms) & ~column.is_null().to_numpy(False))
    for i in unreadable:
        ragged.reason[i] = "unreadable WKB"
    return ragged


@dataclass(frozen=True, eq=False)
class Solved:
    """The triangulations of a :class:`Ragged`'s rows, as columns.

    Attributes
    ----------
    status : ndarray, shape (rows,), int8
        :data:`OK` (0) or :data:`ERROR` (1).
    cost : ndarray, float64
        The row's optimal cost, shape (rows,); shape (rows, k) for a lexicographic
        objective of k components. NaN on error rows.
    reason : ndarray, shape (rows,), object
        The error of an error row, the warnings of an ok row (``"warning: ..."``), else
        None; one line each.
    n : ndarray, shape (rows,), int64
        Vertices per row (closing vertices dropped, all rings of all parts); 0 for a
        row without polygons.
    triangles : ndarray, shape (T, 3), int64
        Every triangle of every ok row, as indices into ``Ragged.coords``.
    triangle_offsets : ndarray, shape (rows + 1,), int64
        Row ``i``'s triangles are ``triangles[triangle_offsets[i]:triangle_offsets[i + 1]]``,
        part after part (``n - 2`` per simple part, ``n + 2h - 2`` with h holes).
    seconds : ndarray, shape (rows,), float64
        Solving time per row (a kernel chunk's time shared in proportion to n^3).
    part_triangle_offsets : ndarray, shape (P + 1,), int64
        The same per part (parts of error rows have none).
    ring_n : ndarray, shape (R,), int64
        Vertices of each ring as solved: closing vertices dropped (one, before any
        check, for a ring of an error row).

    Examples
    --------
    >>> import shapely
    >>> r = ragged_from_shapely([shapely.box(0, 0, 2, 1), None])
    >>> s = solve_ragged(r, SolveOptions())
    >>> len(s), s.status.tolist(), round(float(s.cost[0]), 6), s.triangles.tolist()
    (2, [0, 1], 10.472136, [[0, 1, 3], [1, 2, 3]])
    """

    status: NDArray[np.int8]
    cost: NDArray[np.float64]
    reason: NDArray[np.object_]
    n: Ints
    triangles: Ints
    triangle_offsets: Ints
    seconds: NDArray[np.float64]
    part_triangle_offsets: Ints
    ring_n: Ints
    ragged: Ragged
    options: SolveOptions
    # per part: solved by the kernel, its orientation and its raw kernel cost
    _kernel: NDArray[np.bool_]
    _cw: NDArray[np.bool_]
    _raw: NDArray[np.float64]
    # the per-polygon path's results, by part, and the errors, by row
    _results: dict[int, Triangulation]
    _errors: dict[int, OptriError]

    def __len__(self) -> int:
        return len(self.status)

    @property
    def ok(self) -> NDArray[np.bool_]:
        """Rows with a triangulation."""
        return self.status == OK

    @property
    def triangle_row(self) -> Ints:
        """The row of each triangle, shape (T,)."""
        counts = np.diff(self.triangle_offsets)
        return np.repeat(np.arange(len(self), dtype=np.int64), counts)

    def cost_of(self, row: int) -> Any:
        """Row ``row``'s cost as a float, or a tuple (lexicographic); None on error."""
        if self.status[row] != OK:
            return None
        value = self.cost[row]
        return tuple(float(v) for v in value) if value.ndim else float(value)

    def error(self, row: int) -> OptriError | None:
        """Why row ``row`` has no triangulation (None for an ok row)."""
        if self.status[row] == OK:
            return None
        return self._errors.get(row) or InvalidPolygonError(str(self.reason[row]))

    def triangulation(self, row: int) -> Triangulation | list[Triangulation]:
        """Row ``row`` as :func:`optri.triangulate` returns it, built now.

        A list of Triangulations, one per part, for a row of several parts. Its
        ``vertices`` are the input coordinates (the part's rings, closing vertices
        dropped), its ``triangles`` index them.

        Raises
        ------
        OptriError
            The row's error (:meth:`error`) for an error row.
        """
        if self.status[row] != OK:
            raise self.error(row)  # type: ignore[misc]  # an error row has one
        lo, hi = self.ragged.row_offsets[row], self.ragged.row_offsets[row + 1]
        parts = [self._part(int(p)) for p in range(lo, hi)]
        return parts[0] if len(parts) == 1 else parts

    def result(self, row: int) -> Result | list[Triangulation]:
        """:meth:`triangulation`, or the row's error instead of raising it."""
        err = self.error(row)
        return err if err is not None else self.triangulation(row)

    def local_triangles(self) -> Ints:
        """:attr:`triangles` numbered within each row, as :meth:`row_vertices` lists them.

        A row's vertices are its parts' rings in order, closing vertices dropped:
        for a one-part row, the numbering of :func:`optri.triangulate` (exterior,
        then each hole).

        >>> import shapely
        >>> r = ragged_from_shapely([shapely.box(0, 0, 1, 1), shapely.box(5, 0, 7, 1)])
        >>> s = solve_ragged(r, SolveOptions())
        >>> s.triangles.tolist(), s.local_triangles().tolist()
        ([[0, 1, 3], [1, 2, 3], [5, 6, 8], [6, 7, 8]], [[0, 1, 3], [1, 2, 3], [0, 1, 3], [1, 2, 3]])
        """
        rg = self.ragged
        ring = np.searchsorted(rg.ring_offsets, self.triangles, side="right") - 1
        part_of_ring = np.repeat(np.arange(len(rg.part_offsets) - 1), np.diff(rg.part_offsets))
        row_of_ring = rg.part_row[part_of_ring]
        before = np.zeros(len(self.ring_n) + 1, dtype=np.int64)
        np.cumsum(self.ring_n, out=before[1:])
        first_ring = rg.part_offsets[rg.row_offsets[:-1]]
        start = before[:-1] - before[first_ring[row_of_ring]]  # ring start within its row
        return start[ring] + (self.triangles - rg.ring_offsets[ring])

    def row_vertices(self, row: int) -> NDArray[np.float64]:
        """The vertices of row ``row`` that :meth:`local_triangles` numbers (``(n, 2|3)``)."""
        rg = self.ragged
        width = 3 if rg.row_z[row] else 2
        parts = range(rg.row_offsets[row], rg.row_offsets[row + 1])
        rings = [r for p in parts for r in range(rg.part_offsets[p], rg.part_offsets[p + 1])]
        pieces = [
            rg.coords[rg.ring_offsets[r] : rg.ring_offsets[r] + self.ring_n[r], :width]
            for r in rings
        ]
        return np.concatenate(pieces) if pieces else np.zeros((0, width))

    def _part(self, part: int) -> Triangulation:
        if not self._kernel[part]:
            return self._results[part]
        plan = many_plan(self.options)
        assert plan is not None  # a kernel part exists only under a plan
        first = self.ragged.ring_offsets[self.ragged.part_offsets[part]]
        lo, hi = self.part_triangle_offsets[part], self.part_triangle_offsets[part + 1]
        n = int(hi - lo) + 2
        vertices = self.ragged.coords[first : first + n, :2]
        tris = self.triangles[lo:hi] - first
        return kernel_result(
            plan, self.options, vertices, tris, float(self._raw[part]), bool(self._cw[part])
        )


def solve_ragged(ragged: Ragged, options: SolveOptions, progress: Any = None) -> Solved:
    """Solve every row of ``ragged``: one :class:`Solved`, errors as rows, never raising for a row.

    Equal to :func:`optri.triangulate` part by part: the same triangles (as
    ``Ragged.coords`` indices), the same cost bits, the same errors and warnings.
    Simple 2-D parts go to the compiled kernel in chunks of
    ``config.MANY_KERNEL_CHUNK`` (the kernel drops closing vertices and checks
    each polygon itself); the rest go to the per-polygon path.

    Parameters
    ----------
    ragged : Ragged
        The rows (:func:`ragged_from_shapely`).
    options : SolveOptions
        Weight, objective, method, projection and threads (checked by the caller:
        :func:`optri.batch.solver.check_options`).
    progress : callable, optional
        Called with the number of parts handled so far, after each kernel chunk and
        at the end.

    Examples
    --------
    >>> import shapely
    >>> two = shapely.MultiPolygon([shapely.box(0, 0, 1, 1), shapely.box(2, 0, 3, 1)])
    >>> s = solve_ragged(ragged_from_shapely([two]), SolveOptions())
    >>> s.status.tolist(), round(float(s.cost[0]), 6), s.n.tolist(), len(s.triangles)
    ([0], 13.656854, [8], 4)
    """
    parts = _Parts(ragged)
    plan = many_plan(options) if options.project is None else None
    declined = np.zeros(parts.count, dtype=bool)
    if plan is not None:
        declined = parts.run_kernel(plan, options, progress)
    parts.run_rest(options, declined)
    return parts.solved(options, progress)


class _Parts:
    """Per-part bookkeeping of :func:`solve_ragged`."""

    def __init__(self, ragged: Ragged) -> None:
        self.ragged = ragged
        self.count = count = len(ragged.part_offsets) - 1
        self.row = ragged.part_row
        self.first_ring = ragged.part_offsets[:-1]
        self.start = ragged.ring_offsets[self.first_ring]  # first vertex of each part
        self.ring_n = _ring_sizes(ragged)
        self.n = _row_sums(self.ring_n, ragged.part_offsets)
        self.raw = np.full(count, np.nan)  # the kernel's cost
        self.cw = np.zeros(count, dtype=bool)
        self.kernel = np.zeros(count, dtype=bool)
        self.tri_count = np.zeros(count, dtype=np.int64)
        self.seconds = np.zeros(count)
        self.chunks: list[tuple[Ints, Ints, Ints]] = []  # (parts, their first rows, triangles)
        self.results: dict[int, Triangulation] = {}
        self.errors: dict[int, OptriError] = {}

    def run_kernel(self, plan: ManyPlan, options: SolveOptions, progress: Any) -> NDArray[np.bool_]:
        """Solve the simple 2-D parts by the compiled kernel; returns the parts it declined."""
        rg = self.ragged
        count = rg.ring_offsets[self.first_ring + 1] - self.start
        fits = (np.diff(rg.part_offsets) == 1) & ~rg.row_z[self.row]
        fits &= (count >= 3) & (count <= config.MANY_MAX_N + 1)
        take = np.flatnonzero(fits)
        declined = np.zeros(self.count, dtype=bool)
        xy = np.ascontiguousarray(rg.coords[:, :2]) if rg.has_z else rg.coords
        step = max(1, int(config.MANY_KERNEL_CHUNK))
        for lo in range(0, len(take), step):
            idx = take[lo : lo + step]
            begin = time.perf_counter()
            status, sizes, cw, costs, tris, first = run_kernel(
                plan, options, xy, self.start[idx], count[idx]
            )
            seconds = time.perf_counter() - begin
            good = status == 0
            mine = idx[good]
            declined[idx[~good]] = True
            self.kernel[mine] = True
            self.cw[mine] = cw[good]
            self.raw[mine] = costs[good]
            self.n[mine] = sizes[good]
            self.ring_n[self.first_ring[mine]] = sizes[good]
            self.tri_count[mine] = sizes[good] - 2
            work = sizes[good].astype(np.float64) ** 3
            self.seconds[mine] = work * (seconds / max(float(work.sum()), 1.0))
            self.chunks.append((mine, first[good], tris))
            if progress is not None:
                progress(lo + len(idx))
        return declined

    def run_rest(self, options: SolveOptions, declined: NDArray[np.bool_]) -> None:
        """The per-polygon path for every part the kernel did not solve."""
        direct = np.flatnonzero(declined).tolist()
        checked: list[int] = []
        polygons: list[Polygonal] = []
        for p in np.flatnonzero(~self.kernel & ~declined).tolist():
            try:
                polygons.append(polygon_rings(self.ragged.rings_of(p)))
                checked.append(p)
            except OptriError as exc:
                self.errors[p] = exc
        # a part the kernel declined is solved as solve_compiled would: triangulate itself
        got = solve_each([self.ragged.rings_of(p)[0] for p in direct], options)
        got += solve_polygons(polygons, options)
        for p, res in zip(direct + checked, got):
            if isinstance(res, Triangulation):
                self.results[p] = res
                self.tri_count[p] = len(res.triangles)
                self.n[p] = res.n
                sizes = res.rings or (res.n,)
                first = self.ragged.part_offsets[p]
                self.ring_n[first : first + len(sizes)] = sizes
                self.seconds[p] = float(res.stats.get("wall_seconds", res.seconds))
            else:
                self.errors[p] = res

    def solved(self, options: SolveOptions, progress: Any) -> Solved:
        """The rows: a failed part fails its row; costs combined, triangles in row order."""
        rg = self.ragged
        status, reason, errors = self._row_errors()
        ok_part = status[self.row] == OK
        counts = np.where(ok_part, self.tri_count, 0)
        offsets = np.zeros(self.count + 1, dtype=np.int64)
        np.cumsum(counts, out=offsets[1:])
        triangles = np.empty((int(offsets[-1]), 3), dtype=np.int64)
        for parts, firsts, tris in self.chunks:
            keep = ok_part[parts]
            _scatter(triangles, tris, parts[keep], firsts[keep], offsets, counts, self.start)
        for p, res in self.results.items():
            if ok_part[p]:
                mapped = self._vertex_map(p, res)[res.triangles]
                triangles[offsets[p] : offsets[p] + len(mapped)] = mapped
        objective = as_objective(options.objective)
        cost = _row_costs(objective, self._part_costs(objective), rg.row_offsets, status)
        self._warnings(status, reason)
        if progress is not None:
            progress(self.count)
        return Solved(
            status=status,
            cost=cost if objective.is_lex else cost[:, 0],
            reason=reason,
            n=_row_sums(self.n, rg.row_offsets),
            triangles=triangles,
            triangle_offsets=offsets[rg.row_offsets],
            seconds=_row_sums(self.seconds, rg.row_offsets),
            part_triangle_offsets=offsets,
            ring_n=self.ring_n,
            ragged=rg,
            options=options,
            _kernel=self.kernel,
            _cw=self.cw,
            _raw=self.raw,
            _results=self.results,
            _errors=errors,
        )

    def _row_errors(self) -> tuple[NDArray[np.int8], NDArray[np.object_], dict[int, OptriError]]:
        rg = self.ragged
        reason = rg.reason.copy()
        status = np.where(reason.astype(bool), ERROR, OK).astype(np.int8)  # None is falsy
        errors: dict[int, OptriError] = {}
        for p in sorted(self.errors):
            i = int(self.row[p])
            if i in errors:
                continue  # the row's first failing part speaks for it
            exc = self.errors[p]
            if rg.row_offsets[i + 1] - rg.row_offsets[i] > 1:
                exc = _part_error(exc, p - int(rg.row_offsets[i]))
            errors[i] = exc
            status[i] = ERROR
            reason[i] = one_line(str(exc))
        return status, reason, errors

    def _part_costs(self, objective: Objective) -> NDArray[np.float64]:
        width = len(objective.components)
        cost = np.full((self.count, width), np.nan)
        raw = self.raw[self.kernel]
        cost[self.kernel, 0] = np.where(raw == -np.inf, 0.0, raw)  # Objective.finalize
        for p, res in self.results.items():
            cost[p] = res.weight if objective.is_lex else float(res.weight)  # type: ignore[arg-type]
        return cost

    def _warnings(self, status: NDArray[np.int8], reason: NDArray[np.object_]) -> None:
        notes: dict[int, list[str]] = {}
        for p, res in self.results.items():
            i = int(self.row[p])
            if status[i] == OK and res.stats.get("warnings"):
                notes.setdefault(i, []).extend(res.stats["warnings"])  # type: ignore[arg-type]
        for i, said in notes.items():
            reason[i] = one_line("warning: " + "; ".join(dict.fromkeys(said)))

    def _vertex_map(self, part: int, res: Triangulation) -> Ints:
        """``Ragged.coords`` rows of the vertices of ``res`` (each ring's leading rows)."""
        sizes = res.rings or (res.n,)
        r0 = self.ragged.part_offsets[part]
        starts = self.ragged.ring_offsets[r0 : r0 + len(sizes)]
        return np.concatenate([np.arange(s, s + m, dtype=np.int64) for s, m in zip(starts, sizes)])


def _part_error(exc: OptriError, k: int) -> OptriError:
    """``exc`` with its part named, of the same type where the type allows."""
    try:
        wrapped = type(exc)(f"part {k}: {exc}")
    except TypeError:
        wrapped = OptriError(f"part {k}: {exc}")
    wrapped.__cause__ = exc.__cause__ if exc.__cause__ is not None else exc
    return wrapped


def _ring_sizes(ragged: Ragged) -> Ints:
    """Vertices of each ring without a closing vertex (before any check)."""
    lo, hi = ragged.ring_offsets[:-1], ragged.ring_offsets[1:]
    sizes = hi - lo
    closed = sizes > 3
    ends = np.flatnonzero(closed)
    if len(ends):
        c = ragged.coords[:, :2]
        closed[ends] = (c[lo[ends]] == c[hi[ends] - 1]).all(axis=1)
    return sizes - closed


def _row_sums(values: NDArray[Any], offsets: Ints) -> NDArray[Any]:
    """Sums of ``values`` over consecutive groups ``offsets[i]:offsets[i + 1]``."""
    cum = np.zeros(len(values) + 1, dtype=values.dtype)
    np.cumsum(values, out=cum[1:])
    return cum[offsets[1:]] - cum[offsets[:-1]]


def _row_costs(
    objective: Objective, part_cost: NDArray[np.float64], offsets: Ints, status: NDArray[np.int8]
) -> NDArray[np.float64]:
    """Each ok row's cost from its parts': one part's bits as they are, more combined in order."""
    rows = len(status)
    cost = np.full((rows, part_cost.shape[1]), np.nan)
    counts = np.diff(offsets)
    ok = status == OK
    one = ok & (counts == 1)
    cost[one] = part_cost[offsets[:-1][one]]
    multi = np.flatnonzero(ok & (counts > 1))
    if len(multi):
        starts, m = offsets[multi], counts[multi]
        acc = part_cost[starts].copy()
        for j in range(1, int(m.max())):
            sel = m > j
            nxt = part_cost[starts[sel] + j]
            for c, rule in enumerate(objective.components):
                fold = np.add if rule == "sum" else np.maximum
                acc[sel, c] = fold(acc[sel, c], nxt[:, c])
        cost[multi] = acc
    return cost


def _scatter(
    out: Ints, tris: Ints, parts: Ints, firsts: Ints, offsets: Ints, counts: Ints, start: Ints
) -> None:
    """Copy kernel triangles of ``parts`` (from rows ``firsts`` of ``tris``) to their places."""
    cnt = counts[parts]
    total = int(cnt.sum())
    if not total:
        return
    rel = np.arange(total, dtype=np.int64) - np.repeat(np.cumsum(cnt) - cnt, cnt)
    src = np.repeat(firsts, cnt) + rel
    dst = np.repeat(offsets[parts], cnt) + rel
    out[dst] = tris[src] + np.repeat(start[parts], cnt)[:, None]


def triangle_geometries(
    ragged: Ragged, solved: Solved, explode: bool = False
) -> tuple[NDArray[np.object_], Ints]:
    """The triangles as shapely geometry: per row, or one Polygon per triangle.

    Returns ``(geoms, row)``. By default ``geoms`` has one entry per row: a
    GeometryCollection of triangle Polygons (as ``shapely.constrained_delaunay_triangles``
    returns), None for an error row, and ``row`` is ``arange(rows)``. With
    ``explode`` it has one Polygon per triangle and ``row`` gives each one's row.
    Coordinates are the input's, with Z where the row has Z. Every geometry is
    valid (``shapely.is_valid``): a triangle of zero area in the x-y plane (of an ok
    row whose reason warns of it, or of an upright 3-D polygon such as a wall) is
    left out of the geometry, not out of :attr:`Solved.triangles`.

    Examples
    --------
    >>> import shapely
    >>> r = ragged_from_shapely([shapely.box(0, 0, 2, 1), None])
    >>> geoms, row = triangle_geometries(r, solve_ragged(r, SolveOptions()))
    >>> geoms[0].geom_type, len(geoms[0].geoms), geoms[1], row.tolist()
    ('GeometryCollection', 2, None, [0, 1])
    >>> parts, row = triangle_geometries(r, solve_ragged(r, SolveOptions()), explode=True)
    >>> [g.geom_type for g in parts], row.tolist()
    (['Polygon', 'Polygon'], [0, 0])
    """
    shapely = import_optional("shapely")
    tris, row = _drawn(shapely, ragged, solved)
    if explode:
        out = np.empty(len(tris), dtype=object)
        for z, sel in _by_dimension(ragged, row):
            out[sel] = _polygons(shapely, ragged.coords[:, : 3 if z else 2], tris[sel])
        return out, row
    # whole rows as WKB, read by GEOS in one call: no Python object per triangle
    wkb = _collections_wkb(ragged, solved, tris, row)
    return shapely.from_wkb(wkb), np.arange(len(solved), dtype=np.int64)


def triangle_wkb(
    ragged: Ragged, solved: Solved, explode: bool = False
) -> tuple[NDArray[np.object_], Ints]:
    """:func:`triangle_geometries` as ISO WKB (bytes; None for an error row), built by numpy.

    Little-endian WKB, 3-D rows with Z (types 1003, 1007), the others in 2-D;
    the same geometries as :func:`triangle_geometries`, without building them.

    Examples
    --------
    >>> import shapely
    >>> r = ragged_from_shapely([shapely.box(0, 0, 2, 1)])
    >>> wkb, row = triangle_wkb(r, solve_ragged(r, SolveOptions()))
    >>> shapely.from_wkb(wkb[0]).geom_type, row.tolist()
    ('GeometryCollection', [0])
    """
    shapely = import_optional("shapely")
    tris, row = _drawn(shapely, ragged, solved)
    if not explode:
        return _collections_wkb(ragged, solved, tris, row), np.arange(len(solved), dtype=np.int64)
    out = np.empty(len(tris), dtype=object)
    for z, sel in _by_dimension(ragged, row):
        records = _triangle_records(ragged.coords, tris[sel], z)
        out[sel] = _split(records.tobytes(), records.dtype.itemsize)
    return out, row


def triangle_geojson(
    ragged: Ragged, solved: Solved, explode: bool = False
) -> tuple[NDArray[np.object_], Ints]:
    """:func:`triangle_geometries` as GeoJSON geometry text (None for an error row), for writers.

    Coordinates round-trip exactly (shortest repr), with Z where the row has it.

    Examples
    --------
    >>> import shapely
    >>> r = ragged_from_shapely([shapely.Polygon([(0, 0, 1), (1, 0, 2), (0, 1, 3)])])
    >>> text, row = triangle_geojson(r, solve_ragged(r, SolveOptions()))
    >>> text[0]
    '{"type":"GeometryCollection","geometries":[{"type":"Polygon","coordinates":[[[0.0,0.0,1.0],[1.0,0.0,2.0],[0.0,1.0,3.0],[0.0,0.0,1.0]]]}]}'
    """
    shapely = import_optional("shapely")
    geoms, row = triangle_geometries(ragged, solved, explode)
    return shapely.to_geojson(geoms), row


def _drawn(shapely: Any, ragged: Ragged, solved: Solved) -> tuple[Ints, Ints]:
    """The triangles to draw and their rows: all but those of zero area in the plane.

    Only a row that warned, or a 3-D row (upright in the plane: a wall), can hold one.
    """
    tris, row = solved.triangles, solved.triangle_row
    flagged = np.flatnonzero((solved.status == OK) & (solved.reason.astype(bool) | ragged.row_z))
    if not len(flagged):
        return tris, row
    suspect = np.flatnonzero(np.isin(row, flagged))
    polys = _polygons(shapely, ragged.coords[:, :2], tris[suspect])
    with WARNINGS_LOCK:  # shapely.is_valid enters warnings.catch_warnings: one thread at a time
        valid = shapely.is_valid(polys)
    bad = suspect[~valid]
    keep = np.ones(len(tris), dtype=bool)
    keep[bad] = False
    return tris[keep], row[keep]


def _by_dimension(ragged: Ragged, row: Ints) -> list[tuple[bool, NDArray[np.bool_] | slice]]:
    """``(has_z, selection)`` of triangles, per coordinate dimension present."""
    if not ragged.has_z:
        return [(False, slice(None))]
    z = ragged.row_z[row]
    return [(flag, sel) for flag, sel in ((True, z), (False, ~z)) if sel.any()]


def _polygons(shapely: Any, coords: NDArray[np.float64], tris: Ints) -> NDArray[np.object_]:
    """One Polygon per triangle, ``coords[tris[t]]`` closed (from_ragged_array: one C pass)."""
    count = len(tris)
    rings = np.concatenate([tris, tris[:, :1]], axis=1)
    flat = np.ascontiguousarray(coords[rings.reshape(-1)])
    offsets = (np.arange(0, 4 * count + 1, 4, dtype=np.int64), np.arange(count + 1, dtype=np.int64))
    return shapely.from_ragged_array(shapely.GeometryType.POLYGON, flat, offsets)


#: WKB geometry types (ISO): Polygon, GeometryCollection; +1000 with Z.
_WKB_POLYGON, _WKB_COLLECTION, _WKB_Z = 3, 7, 1000
_WKB_HEADER = np.dtype([("order", "u1"), ("kind", "<u4"), ("count", "<u4")])


def _triangle_records(coords: NDArray[np.float64], tris: Ints, z: bool) -> NDArray[np.void]:
    """The WKB of each triangle as a Polygon: one packed record per triangle."""
    dim = 3 if z else 2
    record = np.dtype(
        [
            ("order", "u1"),
            ("kind", "<u4"),
            ("rings", "<u4"),
            ("points", "<u4"),
            ("xy", "<f8", (4, dim)),
        ]
    )
    out = np.empty(len(tris), dtype=record)
    out["order"] = 1  # little-endian
    out["kind"] = _WKB_POLYGON + (_WKB_Z if z else 0)
    out["rings"] = 1
    out["points"] = 4
    out["xy"][:, :3] = coords[tris][..., :dim]
    out["xy"][:, 3] = out["xy"][:, 0]
    return out


def _split(raw: bytes, size: int) -> list[bytes]:
    """``raw`` cut into pieces of ``size`` bytes."""
    return [raw[a : a + size] for a in range(0, len(raw), size)]


def _collections_wkb(ragged: Ragged, solved: Solved, tris: Ints, row: Ints) -> NDArray[np.object_]:
    """Per row the WKB of a GeometryCollection of its triangles (None for an error row).

    Rows with the same number of triangles are laid out as one packed array
    (header, then the triangles' records) and cut apart: one bytes object per row.
    """
    out = np.full(len(solved), None, dtype=object)
    for z in (False, True) if ragged.has_z else (False,):
        rows = np.flatnonzero(solved.ok & (ragged.row_z == z))
        if not len(rows):
            continue
        sel = np.flatnonzero(ragged.row_z[row] == z)
        records = _triangle_records(ragged.coords, tris[sel], z)
        count = np.bincount(row[sel], minlength=len(solved))
        first = np.zeros(len(solved) + 1, dtype=np.int64)
        np.cumsum(count, out=first[1:])
        for k in np.unique(count[rows]).tolist():
            group = rows[count[rows] == k]
            layout = np.dtype([("head", _WKB_HEADER), ("tris", records.dtype, (k,))])
            packed = np.empty(len(group), dtype=layout)
            packed["head"]["order"] = 1
            packed["head"]["kind"] = _WKB_COLLECTION + (_WKB_Z if z else 0)
            packed["head"]["count"] = k
            packed["tris"] = records[first[group][:, None] + np.arange(k)]
            out[group] = _split(packed.tobytes(), layout.itemsize)
    return out
