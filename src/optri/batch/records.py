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
"""

from __future__ import annotations

import base64
import datetime
import decimal
import json
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from .. import config
from ..result import Triangulation
from .each import one_line
from .solver import Result, SolveOptions, solve_polygons

__all__ = [
    "RESULT_FIELDS",
    "TIMING_FIELDS",
    "ChunkTask",
    "Item",
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
#: The fields a batch adds to each input feature (besides its id).
RESULT_FIELDS = ("status", "n", "cost", "triangles", "diagonals", "reason", "seconds")


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


@dataclass(frozen=True)
class ChunkTask:
    """A partition of the input: its index, items and the solve options (picklable)."""

    index: int
    items: Sequence[Item]
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


def record_of(item: Item, result: Result) -> dict:
    """The record of ``item`` from its solver result (a Triangulation or an error)."""
    if not isinstance(result, Triangulation):
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
    """Records of ``items`` in order; items a reader already refused keep their reason."""
    todo = [it for it in items if it.reason is None]
    results = iter(solve_polygons([it.coords for it in todo], options))
    return [
        error_record(it.id, it.reason, _count(it.coords))
        if it.reason is not None
        else record_of(it, next(results))
        for it in items
    ]


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
