"""One output record per input polygon, and the chunk function every scheduler runs.

A record is a plain dict with a fixed key order, so the same input always gives
the same bytes::

    {"id", "status", "n", "cost", "triangles", "diagonals", "reason", "seconds"}

``status`` is ``"ok"`` or ``"error"``; an error record has ``reason`` (one line)
and null ``cost``/``triangles``/``diagonals``; an ok record's ``reason`` holds
the warnings its polygon raised, if any. ``seconds`` is the only field that
changes between runs (wall time of that polygon); :func:`strip_timing` drops it.
The input feature's attributes travel beside the records in the parent process
(workers never see them) and are joined to them by the writers.

A MultiPolygon is one row: its parts (:class:`PolygonParts`) are solved one by
one and their results joined, vertices numbered part after part (each part
exterior first, then its holes), ``n`` counting them all, the cost combined by
the objective (``"sum"`` adds the parts' costs, ``"max"`` takes the largest; a
lexicographic objective combines component by component, each part optimal on
its own). A part that fails fails the row, its reason naming the part.
"""

from __future__ import annotations

import base64
import datetime
import decimal
import json
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import config
from ..errors import InvalidPolygonError, OptriError
from ..objective import as_objective
from ..result import Triangulation
from .each import one_line
from .solver import Polygonal, Result, SolveOptions, polygon_vertices, solve_polygons

__all__ = [
    "RESULT_FIELDS",
    "TIMING_FIELDS",
    "ChunkTask",
    "Item",
    "PolygonParts",
    "error_record",
    "json_id",
    "json_safe",
    "one_line",
    "record_of",
    "solve_chunk",
    "solve_item",
    "strip_timing",
]

#: Record fields that vary from run to run; everything else is deterministic.
TIMING_FIELDS = ("seconds",)
#: The fields a batch adds to each input feature (besides its id); ``triangle`` numbers
#: the rows of an exploded feature.
RESULT_FIELDS = ("status", "n", "cost", "triangles", "diagonals", "reason", "seconds", "triangle")


@dataclass(frozen=True)
class Item:
    """One input polygon: its id and exterior-ring coordinates, or why it has none.

    ``coords`` is a list of ``[x, y]`` (or ``[x, y, z]``) lists or an array as
    read, not yet validated; ``reason`` is set instead when the reader already
    knows the input is unusable (a hole, a wrong JSON shape, a line that is not
    JSON). ``props`` are the feature's attributes (None: the input has none).
    """

    id: Any
    coords: Any = None
    reason: str | None = None
    props: dict[str, Any] | None = None

    def for_worker(self) -> Item:
        """The item without its attributes: what a worker process needs."""
        return self if self.props is None else Item(self.id, self.coords, self.reason)


@dataclass(frozen=True, eq=False)
class PolygonParts:
    """The parts of a MultiPolygon, each a vertex array or HoledRings, solved part by part.

    Behaves as the array of all its vertices, part after part, for the writers:
    a row's triangles index it.

    >>> parts = PolygonParts((np.zeros((3, 2)), np.ones((4, 2))))
    >>> parts.shape, len(parts)
    ((7, 2), 7)
    """

    parts: tuple[Polygonal, ...]

    @property
    def vertices(self) -> np.ndarray:
        """Every part's vertices, concatenated."""
        return np.concatenate([np.asarray(p, dtype=np.float64) for p in self.parts])

    @property
    def shape(self) -> tuple[int, ...]:
        """The shape of :attr:`vertices`."""
        return (len(self), np.asarray(self.parts[0]).shape[1])

    def __len__(self) -> int:
        return sum(len(p) for p in self.parts)

    def __array__(self, dtype: Any = None, copy: Any = None) -> np.ndarray:
        return np.asarray(self.vertices, dtype=dtype)

    def tolist(self) -> list:
        """:attr:`vertices` as nested lists."""
        return self.vertices.tolist()


def feature_vertices(geom: Any) -> Polygonal | PolygonParts:
    """The vertices of a shapely Polygon, or the parts of a MultiPolygon of several.

    Raises InvalidPolygonError (naming the part) when a part is unusable.
    """
    kind = getattr(geom, "geom_type", None)
    if kind is not None and kind not in ("Polygon", "MultiPolygon") and not geom.is_empty:
        raise InvalidPolygonError(f"geometry type {kind!r} is not a Polygon or MultiPolygon")
    if kind != "MultiPolygon" or len(geom.geoms) < 2:
        return polygon_vertices(geom)
    return multi_parts(list(geom.geoms))


def multi_parts(
    parts: Sequence[Any], convert: Callable[[Any], Polygonal] = polygon_vertices
) -> PolygonParts:
    """:class:`PolygonParts` of a MultiPolygon's parts, each read by ``convert``.

    (shapely Polygons by default; GeoJSON ring lists with ``polygon_rings``.)
    """
    out = []
    for k, part in enumerate(parts):
        try:
            out.append(convert(part))
        except OptriError as exc:
            raise InvalidPolygonError(f"MultiPolygon part {k}: {exc}") from None
    dims = {np.asarray(p).shape[1] for p in out}
    if len(dims) > 1:
        raise InvalidPolygonError("the parts of a MultiPolygon mix 2-D and 3-D coordinates")
    return PolygonParts(tuple(out))


@dataclass(frozen=True, kw_only=True)
class TaskOptions:
    """What every task of a batch carries besides its rows: the solve options (picklable)."""

    weight: Any = "perimeter"
    objective: Any = "sum"
    method: str = "auto"
    project: str | None = None
    #: Set on a one-polygon task cut from a chunk whose worker died: the polygon's position.
    offset: int | None = None

    @property
    def options(self) -> SolveOptions:
        """The options every polygon of this chunk is solved with.

        One thread: a batch's parallelism is its workers (processes), not the kernel's.
        """
        return SolveOptions(self.weight, self.objective, self.method, self.project, threads=1)


@dataclass(frozen=True)
class ChunkTask(TaskOptions):
    """A partition of the input: its index, items and the solve options (picklable)."""

    index: int
    items: Sequence[Item]


def error_record(item_id: Any, reason: str, n: int | None = None, seconds: float = 0.0) -> dict:
    """The record of a polygon that could not be triangulated.

    >>> error_record(7, "a polygon needs at least 3 vertices, got 2")["status"]
    'error'
    """
    return {
        "id": item_id,
        "status": "error",
        "n": n,
        "cost": None,
        "triangles": None,
        "diagonals": None,
        "reason": one_line(reason),
        "seconds": seconds,
    }


def record_of(item: Item, result: Result | _Joined) -> dict:
    """The record of ``item`` from its solver result (a Triangulation or an error)."""
    if not isinstance(result, (Triangulation, _Joined)):
        return error_record(item.id, str(result), _count(item.coords))
    notes = result.stats.get("warnings")
    return {
        "id": item.id,
        "status": "ok",
        "n": result.n,
        "cost": _json_cost(result.weight),
        "triangles": result.triangles.tolist(),
        "diagonals": result.diagonals.tolist(),
        "reason": one_line("warning: " + "; ".join(notes)) if notes else None,  # type: ignore[arg-type]
        "seconds": float(result.stats.get("wall_seconds", result.seconds)),
    }


def solve_records(items: Sequence[Item], options: SolveOptions) -> list[dict]:
    """Records of ``items`` in order; items a reader already refused keep their reason.

    The parts of every MultiPolygon go to the solver with the other polygons,
    one polygon each, and are joined again (:func:`join_parts`).
    """
    todo = [it for it in items if it.reason is None]
    polygons: list[Any] = []
    for it in todo:
        polygons.extend(it.coords.parts if isinstance(it.coords, PolygonParts) else [it.coords])
    results = iter(solve_polygons(polygons, options))
    out = []
    for it in items:
        if it.reason is not None:
            out.append(error_record(it.id, it.reason, _count(it.coords)))
        elif isinstance(it.coords, PolygonParts):
            got = [next(results) for _ in it.coords.parts]
            out.append(record_of(it, join_parts(got, it.coords, options.objective)))
        else:
            out.append(record_of(it, next(results)))
    return out


def join_parts(results: Sequence[Result], parts: PolygonParts, objective: Any) -> Result | _Joined:
    """One result for a MultiPolygon from its parts' results (see the module's docstring)."""
    for k, res in enumerate(results):
        if not isinstance(res, Triangulation):
            return OptriError(f"MultiPolygon part {k}: {res}")
    tris = [r for r in results if isinstance(r, Triangulation)]
    starts = np.cumsum([0] + [len(p) for p in parts.parts])[:-1]
    obj = as_objective(objective)
    notes = [w for r in tris for w in r.stats.get("warnings", [])]  # type: ignore[union-attr]
    stats: dict[str, Any] = {"wall_seconds": sum(_seconds(r) for r in tris)}
    if notes:
        stats["warnings"] = list(dict.fromkeys(notes))
    return _Joined(
        n=int(sum(r.n for r in tris)),
        weight=obj.aggregate([r.weight for r in tris]),
        triangles=np.concatenate([r.triangles + s for r, s in zip(tris, starts)]),
        diagonals=np.concatenate(
            [np.asarray(r.diagonals, np.int64).reshape(-1, 2) + s for r, s in zip(tris, starts)]
        ),
        stats=stats,
    )


@dataclass
class _Joined:
    """What :func:`record_of` reads of a Triangulation, for a MultiPolygon's joined parts."""

    n: int
    weight: Any
    triangles: np.ndarray
    diagonals: np.ndarray
    stats: dict[str, Any]
    seconds: float = 0.0


def _seconds(tri: Triangulation) -> float:
    return float(tri.stats.get("wall_seconds", tri.seconds))  # type: ignore[arg-type]


def solve_item(
    item: Item,
    weight: Any = "perimeter",
    objective: Any = "sum",
    method: str = "auto",
    project: str | None = None,
) -> dict:
    """Triangulate one item; never raises for bad input (returns an error record).

    Examples
    --------
    >>> rec = solve_item(Item("sq", [[0, 0], [1, 0], [1, 1], [0, 1]]), method="memo")
    >>> rec["status"], round(rec["cost"], 6), rec["triangles"], rec["diagonals"]
    ('ok', 6.828427, [[0, 1, 3], [1, 2, 3]], [[1, 3]])
    >>> solve_item(Item(1, [[0, 0], [1, 1]]))["reason"]
    'a polygon needs at least 3 vertices, got 2'
    """
    return solve_records([item], SolveOptions(weight, objective, method, project))[0]


def solve_chunk(task: ChunkTask) -> tuple[int, list[dict]]:
    """Solve every item of a partition; the one function the pool and Dask both run.

    Returns ``(task.index, records)`` in input order.
    """
    return task.index, solve_records(task.items, task.options)


def strip_timing(record: dict) -> dict:
    """A copy of ``record`` without its run-dependent fields (``seconds``).

    >>> strip_timing({"id": 1, "status": "ok", "seconds": 0.2})
    {'id': 1, 'status': 'ok'}
    """
    return {k: v for k, v in record.items() if k not in TIMING_FIELDS}


def json_id(value: Any, index: int) -> Any:
    """A feature id that JSON can hold: ``index`` when missing, non-finite numbers as text.

    >>> json_id(None, 4), json_id(float("nan"), 0), json_id(float("-inf"), 0), json_id([1], 0)
    (4, 'NaN', '-Infinity', '[1]')
    """
    value = _plain(value)
    if value is None:
        return index
    if isinstance(value, (str, bool, int)):
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else _NONFINITE[_nonfinite_key(value)]
    try:
        return json.dumps(json_safe(value), separators=(",", ":"), allow_nan=False)
    except (TypeError, ValueError):
        return str(value)


_NONFINITE = {"nan": "NaN", "inf": "Infinity", "-inf": "-Infinity"}


def _nonfinite_key(value: float) -> str:
    return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")


def json_safe(value: Any, depth: int = 0) -> Any:
    r"""``value`` as plain JSON data: non-finite floats, dates, decimals and bytes as text.

    Raises ValueError for values nested deeper than ``config.BATCH_MAX_JSON_DEPTH``.

    >>> json_safe({"a": float("inf"), "b": (1, b"\x01")})
    {'a': 'Infinity', 'b': [1, 'AQ==']}
    """
    if depth > config.BATCH_MAX_JSON_DEPTH:
        raise ValueError(f"attributes nested deeper than {config.BATCH_MAX_JSON_DEPTH} levels")
    value = _plain(value)
    if value is None or isinstance(value, (str, bool, int)):
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else _NONFINITE[_nonfinite_key(value)]
    if isinstance(value, dict):
        return {str(k): json_safe(v, depth + 1) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_safe(v, depth + 1) for v in value]
    if isinstance(value, (datetime.date, datetime.time)):
        return value.isoformat()
    if isinstance(value, decimal.Decimal):
        return str(value)
    if isinstance(value, (bytes, bytearray, memoryview)):
        return base64.b64encode(bytes(value)).decode("ascii")
    return str(value)


def _plain(value: Any) -> Any:
    # numpy scalars and arrays -> Python, so they serialize as JSON
    if hasattr(value, "tolist") and not isinstance(value, (str, bytes)):
        return value.tolist()
    return value


def _json_cost(cost: Any) -> Any:
    if isinstance(cost, tuple):
        return [_json_cost(c) for c in cost]
    value = float(cost)
    # JSON has no infinity; keep it readable and lossless as a string
    return value if math.isfinite(value) else str(value)


def _count(coords: Any) -> int | None:
    # the vertex count triangulate would see: a closing vertex equal to the first is dropped
    if not isinstance(coords, (list, tuple)) and not hasattr(coords, "shape"):
        return None
    try:
        pts = [list(map(float, p)) for p in coords]
    except (TypeError, ValueError, OverflowError):
        return len(coords)
    closed = len(pts) > 3 and pts[0] == pts[-1]
    return len(pts) - 1 if closed else len(pts)
