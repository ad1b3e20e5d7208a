"""The explorer page: one self-contained HTML file that replays traces.

The page holds the traces optri recorded (as JSON), its script and its styles
inline: no network, no external URL. It shows the polygon (SVG), the n x n
table in the paper's layout, the pseudocode with the current line marked, the
counters, and play / pause / step / back / first / last controls with a speed
slider; hovering a cell draws its sub-polygon and optimal triangles, and the
last step traces the optimal triangulation back. ``window.optri`` exposes
``state()``, ``step()``, ``back()``, ``first()``, ``last()``, ``play()``,
``pause()`` and ``method(name)`` for tests and embedding.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from html import escape
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..drawing.svg import drawing_points
from ..io.atomic import atomic_write
from .board import value_text

if TYPE_CHECKING:  # pragma: no cover
    from .trace import Trace

__all__ = ["embed", "explorer_page", "page_data", "pseudocode", "write_page"]

_KIND_CODE = {"call": 0, "hit": 1, "candidate": 2, "store": 3}
_SIZE, _PAD = 340, 40
_TITLES = {
    "memo": "Algorithm 3.1: the optimal triangulation stored with memoization (top-down)",
    "table": "Square matrix: the same recurrence bottom-up, shortest chords first",
    "naive": "Plain recursion without the table: every request recomputed",
}
_LABELS = {"memo": "memo (Algorithm 3.1)", "table": "table (bottom-up)", "naive": "naive (no memo)"}


def pseudocode(method: str, objective: Any = "sum") -> tuple[list[str], dict[str, int]]:
    """The algorithm's lines for ``method`` and the line each event kind runs.

    Written in the paper's notation (Eq. 3, Algorithm 3.1): ``w[i, j]`` is the
    optimal weight of the sub-polygon v_i ... v_{j+1} (the matrix chain
    A_i ... A_j), ``w[i, i] = 0`` a side.

    >>> lines, at = pseudocode("memo")
    >>> lines[at["hit"]].split("(")[0].strip()
    'if w[i, j] < ∞ then return w[i, j]'
    """
    name = objective if isinstance(objective, str) else "lex"
    zero = {"sum": "0", "max": "−∞"}.get(name, "neutral")
    tri = "w(v_i, v_k+1, v_j+1)"

    def q(a: str, b: str) -> str:
        if name == "sum":
            return f"q = {a} + {b} + {tri}"
        if name == "max":
            return f"q = max({a}, {b}, {tri})"
        return f"q = combine({a}, {b}, {tri})   (lexicographic)"

    side = f"for i = 1 .. n-1:  w[i, i] = {zero}            (a side: no triangle)"
    rows: list[tuple[str, str]]
    if method == "memo":
        rows = [
            (side, ""),
            ("every other w[i, j] = ∞                  (not computed yet)", ""),
            ("return OPT(1, n-1)", "end"),
            ("OPT(i, j):", "call"),
            ("  if w[i, j] < ∞ then return w[i, j]     (answered from the table)", "hit"),
            ("  for k = i .. j-1:", ""),
            ("    " + q("OPT(i, k)", "OPT(k+1, j)"), "candidate"),
            ("    if q < w[i, j] then w[i, j] = q; split = v_k+1", ""),
            ("  return w[i, j]                         (stored)", "store"),
        ]
    elif method == "table":
        rows = [
            (side, ""),
            ("for l = 2 .. n-1:                         (sides spanned)", ""),
            ("  for i = 1 .. n-l:  j = i + l - 1", ""),
            ("    best = ∞", ""),
            ("    for k = i .. j-1:", ""),
            ("      read w[i, k] and w[k+1, j]           (from the table)", "hit"),
            ("      " + q("w[i, k]", "w[k+1, j]"), "candidate"),
            ("      if q < best then best = q; split = v_k+1", ""),
            ("    w[i, j] = best                        (stored)", "store"),
            ("return w[1, n-1]", "end"),
        ]
    else:
        rows = [
            ("return OPT(1, n-1)", "end"),
            ("OPT(i, j):                                (no table is read)", "call"),
            (f"  if i = j then return {zero}                 (a side)", "callSide"),
            ("  best = ∞", ""),
            ("  for k = i .. j-1:", ""),
            ("    " + q("OPT(i, k)", "OPT(k+1, j)"), "candidate"),
            ("    if q < best then best = q; split = v_k+1", ""),
            ("  return best                             (computed again each time)", "store"),
        ]
    lines = [text for text, _ in rows]
    at = {tag: idx for idx, (_, tag) in enumerate(rows) if tag}
    return lines, at


def page_data(traces: Sequence[Trace]) -> dict[str, Any]:
    """Everything the page shows, as JSON-ready data; the first trace is shown first."""
    first = traces[0]
    pts = drawing_points(first.vertices)
    lo, span = pts.min(axis=0), float(np.ptp(pts, axis=0).max()) or 1.0
    xy = (pts - lo) / span * (_SIZE - 2 * _PAD) + _PAD
    xy[:, 1] = _SIZE - xy[:, 1]
    labels = [f"v{i + 1}" for i in range(first.n)]
    if first.vertices.ndim == 1:  # vertex values: show them
        labels = [f"{a}={value_text(v)}" for a, v in zip(labels, first.vertices.tolist())]
    result = first.result
    return {
        "n": first.n,
        "points": np.round(xy, 2).tolist(),
        "labels": labels,
        "weight": result.weight_name,
        "objective": result.objective,
        "start": first.method,
        "traces": {t.method: _trace_data(t) for t in traces},
    }


def _trace_data(t: Trace) -> dict[str, Any]:
    lines, at = pseudocode(t.method, t.result.objective)
    return {
        "label": _LABELS[t.method],
        "title": _TITLES[t.method],
        "events": [[_KIND_CODE[e.kind], e.i, e.j, e.k, _json_value(e.value)] for e in t.events],
        "counts": t.counts(),
        "code": lines,
        "lines": at,
    }


def _json_value(v: Any) -> Any:
    if v is None:
        return None
    if isinstance(v, tuple):
        return [_json_value(x) for x in v]
    v = float(v)
    if math.isinf(v):
        return "inf" if v > 0 else "-inf"
    return int(v) if v.is_integer() and abs(v) < 2**53 else v


def explorer_page(traces: Sequence[Trace], title: str | None = None) -> str:
    """The self-contained HTML page replaying ``traces`` (switchable; the first shown)."""
    data = page_data(traces)
    payload = json.dumps(data, separators=(",", ":"), ensure_ascii=False)
    payload = payload.replace("<", "\\u003c")  # never "</script>" inside the data
    r = traces[0].result

    def name(v: Any) -> str:
        return ", ".join(v) if isinstance(v, tuple) else str(v)

    heading = title or (
        f"optri explorer: n = {r.n}, {name(r.weight_name)} weight, {name(r.objective)}"
    )
    template = _asset("explorer.html")
    return (
        template.replace("{{title}}", escape(heading))
        .replace("{{css}}", _asset("explorer.css"))
        .replace("{{data}}", payload)
        .replace("{{js}}", _asset("explorer.js"))
    )


def embed(html: str, height: int = 700) -> str:
    """``html`` in an ``<iframe srcdoc>``: how a notebook shows a whole page."""
    return (
        f'<iframe srcdoc="{escape(html, quote=True)}" '
        f'style="width:100%;height:{height}px;border:1px solid #ddd"></iframe>'
    )


def write_page(path: str | Path, html: str) -> Path:
    """Write ``html`` to ``path`` atomically (UTF-8); return the path."""
    with atomic_write(path, "wb") as fh:
        fh.write(html.encode("utf-8"))
    return Path(path)


def _asset(name: str) -> str:
    return resources.files("optri.teaching").joinpath("assets").joinpath(name).read_text("utf-8")
