"""One output record per input polygon, and the chunk function every scheduler runs.

A record is a plain dict with a fixed key order, so the same input always gives
the same bytes::

    {"id", "status", "n", "cost", "triangles", "diagonals", "reason", "seconds"}

``status`` is ``"ok"`` or ``"error"``; an error record has ``reason`` (one line)
and null ``cost``/``triangles``/``diagonals``. ``seconds`` is the only field that
changes between runs (wall time of that polygon); :func:`strip_timing` drops it.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from ..errors import OptriError
from ..polygon import normalize_vertices
from ..solve import triangulate

__all__ = [
    "TIMING_FIELDS",
    "ChunkTask",
    "Item",
    "error_record",
    "solve_chunk",
    "solve_item",
    "strip_timing",
]

#: Record fields that vary from run to run; everything else is deterministic.
TIMING_FIELDS = ("seconds",)


@dataclass(frozen=True)
class Item:
    """One input polygon: its id and exterior-ring coordinates, or why it has none.

    ``coords`` is a list of ``[x, y]`` (or ``[x, y, z]``) lists as read, not yet
    validated; ``reason`` is set instead when the reader already knows the
    input is unusable (a hole, a wrong JSON shape).
    """

    id: Any
    coords: Any = None
    reason: str | None = None


@dataclass(frozen=True)
class ChunkTask:
    """A partition of the input: its index, items and the solve options (picklable)."""

    index: int
    items: Sequence[Item]
    weight: Any = "perimeter"
    objective: Any = "sum"
    method: str = "auto"


def one_line(message: str) -> str:
    r"""Collapse whitespace so a reason is always a single line.

    >>> one_line("vertex 3\n  is bad")
    'vertex 3 is bad'
    """
    return " ".join(str(message).split()) or "unknown error"


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


def solve_item(item: Item, weight: Any = "perimeter", objective: Any = "sum", method: str = "auto"):
    """Triangulate one item; never raises for bad input (returns an error record).

    Examples
    --------
    >>> rec = solve_item(Item("sq", [[0, 0], [1, 0], [1, 1], [0, 1]]), method="memo")
    >>> rec["status"], round(rec["cost"], 6), rec["triangles"], rec["diagonals"]
    ('ok', 6.828427, [[0, 1, 3], [1, 2, 3]], [[1, 3]])
    >>> solve_item(Item(1, [[0, 0], [1, 1]]))["reason"]
    'a polygon needs at least 3 vertices, got 2'
    """
    if item.reason is not None:
        return error_record(item.id, item.reason, _count(item.coords))
    start = time.perf_counter()
    try:
        # the shared validator (closing vertices, numbers, shape), then an array, never a
        # str: triangulate would take a string for a file name
        vertices = normalize_vertices(item.coords)
        tri = triangulate(vertices, weight=weight, objective=objective, method=method)
    except (OptriError, ValueError, TypeError, OverflowError) as exc:
        # ValueError/TypeError: coordinates numpy cannot even read (ragged, strings)
        return error_record(item.id, str(exc), _count(item.coords), time.perf_counter() - start)
    return {
        "id": item.id,
        "status": "ok",
        "n": tri.n,
        "cost": _json_cost(tri.weight),
        "triangles": tri.triangles.tolist(),
        "diagonals": tri.diagonals.tolist(),
        "reason": None,
        "seconds": time.perf_counter() - start,
    }


def solve_chunk(task: ChunkTask) -> tuple[int, list[dict]]:
    """Solve every item of a partition; the one function the pool and Dask both run.

    Returns ``(task.index, records)`` in input order.
    """
    records = [solve_item(it, task.weight, task.objective, task.method) for it in task.items]
    return task.index, records


def strip_timing(record: dict) -> dict:
    """A copy of ``record`` without its run-dependent fields (``seconds``).

    >>> strip_timing({"id": 1, "status": "ok", "seconds": 0.2})
    {'id': 1, 'status': 'ok'}
    """
    return {k: v for k, v in record.items() if k not in TIMING_FIELDS}


def _json_cost(cost: Any) -> Any:
    if isinstance(cost, tuple):
        return [_json_cost(c) for c in cost]
    value = float(cost)
    # JSON has no infinity; keep it readable and lossless as a string
    return value if math.isfinite(value) else str(value)


def _count(coords: Any) -> int | None:
    # the vertex count triangulate would see: a closing vertex equal to the first is dropped
    if not isinstance(coords, (list, tuple)):
        return None
    closed = len(coords) > 3 and coords[0] == coords[-1]
    return len(coords) - 1 if closed else len(coords)
