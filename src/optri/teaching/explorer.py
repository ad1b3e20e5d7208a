"""The explorer page: one self-contained HTML file that replays the DP.

The page holds the polygon, its chord mask and its C(n, 3) triangle weights (as
JSON data), its script and its styles inline: no network, no external URL. Its
script runs the recurrence in the same orders as optri's Python engines (memo,
table, naive) and checks its counts against the traces optri recorded, so the
page stays small at n = 40 (a few hundred kilobytes) however many steps the DP
takes. It shows the polygon (SVG), the n x n table in the paper's layout
(scrolled to the cell in view, zoomable), the pseudocode with the current line
marked, the counters, the cells in the order they are stored (each expands to
its candidates with their arithmetic in the paper's notation), and controls:
play / pause / step / back / next store / next cell / to the end, a speed
slider, a "predict the split" mode with a score, and the student's own input
(typed values for the product weight, clicked vertices for perimeter and area).
``window.optri`` exposes the same for tests and embedding.

User text (titles, weight names, labels) is data: it is HTML-escaped where it
is markup and reaches the script as JSON, which the script writes as text only.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Sequence
from html import escape
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import config
from ..drawing.svg import drawing_points
from ..errors import OptriError, TableTooLargeError
from ..io.atomic import atomic_write
from .board import value_text

if TYPE_CHECKING:  # pragma: no cover
    from .trace import Trace

__all__ = ["embed", "explorer_page", "page_data", "pseudocode", "write_page"]

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
    if "hit" in at:
        at["side"] = at["hit"]  # a side is read on the same line as a hit
    return lines, at


def page_data(traces: Sequence[Trace]) -> dict[str, Any]:
    """Everything the page shows, as JSON-ready data; the first trace is shown first.

    The data is the problem, not the steps: drawing points, labels, the chord
    mask (``"1"``/``"0"`` for each chord (i, j), i < j, row by row; None when every
    chord is usable) and the weight w(i, k, j) of every usable triangle, in the
    order i, then j, then k. Each trace adds its name, pseudocode and counts,
    which the page checks its own run against.

    Raises
    ------
    TableTooLargeError
        n above :data:`optri.config.EXPLORE_MAX_N`.
    OptriError
        A value the page's float64 arithmetic cannot hold exactly (an integer
        beyond 2**53).
    """
    first = traces[0]
    n = first.n
    if n > config.EXPLORE_MAX_N:
        raise TableTooLargeError(
            f"the explorer shows n <= {config.EXPLORE_MAX_N} (optri.config.EXPLORE_MAX_N), "
            f"got n = {n}; use optri.trace for larger polygons"
        )
    problem = first._problem
    if problem is None:
        raise OptriError("this trace does not carry its problem; record it with optri.trace")
    pts = drawing_points(first.vertices)
    lo, span = pts.min(axis=0), float(np.ptp(pts, axis=0).max()) or 1.0
    xy = (pts - lo) / span * (_SIZE - 2 * _PAD) + _PAD
    xy[:, 1] = _SIZE - xy[:, 1]
    values = None
    if first.vertices.ndim == 1:  # vertex values: p0 ... p(n-1), as the matrix chain's
        values = [_json_value(v) for v in first.vertices.tolist()]
        labels = [f"p{i}={value_text(v)}" for i, v in enumerate(first.vertices.tolist())]
    else:
        labels = [f"v{i + 1}" for i in range(n)]
    ok = problem.allowed_rows()
    weight = problem.evaluator()
    tw = []
    for i in range(n):
        for j in range(i + 2, n):
            if ok is not None and not ok[i][j]:
                continue
            for k in range(i + 1, j):
                if ok is None or (ok[i][k] and ok[k][j]):
                    tw.append(_json_value(weight(i, k, j)))
    for t in traces:  # every value the page computes must be a float64 exactly
        for e in t.events:
            if e.kind == "store":
                _json_value(e.value)
    mask = None
    if ok is not None:
        mask = "".join("1" if ok[i][j] else "0" for i in range(n) for j in range(i + 1, n))
    result = first.result
    return {
        "n": n,
        "points": np.round(xy, 2).tolist(),
        "labels": labels,
        "values": values,
        "weight": _name(result.weight_name),
        "objective": list(result.objective)
        if isinstance(result.objective, tuple)
        else [result.objective],
        "mask": mask,
        "tw": tw,
        "start": first.method,
        "maxN": config.EXPLORE_MAX_N,
        "naiveMax": config.NAIVE_MAX_N,
        "methods": {t.method: _trace_data(t) for t in traces},
    }


def _trace_data(t: Trace) -> dict[str, Any]:
    lines, at = pseudocode(t.method, t.result.objective)
    return {
        "label": _LABELS[t.method],
        "title": _TITLES[t.method],
        "counts": t.counts(),
        "code": lines,
        "lines": at,
    }


def _json_value(v: Any) -> Any:
    if v is None:
        return None
    if isinstance(v, tuple):
        return [_json_value(x) for x in v]
    if isinstance(v, (int, np.integer)) and not isinstance(v, bool) and abs(int(v)) > 2**53:
        raise OptriError(
            f"the explorer computes in float64 and cannot show {int(v)} exactly (beyond 2**53); "
            "use optri.trace for these values"
        )
    v = float(v)
    if math.isinf(v):
        return "inf" if v > 0 else "-inf"
    return int(v) if v.is_integer() and abs(v) < 2**53 else v


def _name(v: Any) -> str:
    return ", ".join(str(x) for x in v) if isinstance(v, tuple) else str(v)


#: Page-template placeholders, replaced in one pass: text put in never becomes a placeholder.
_SLOT = re.compile(r"\{\{(title|css|data|js)\}\}")


def explorer_page(traces: Sequence[Trace], title: str | None = None) -> str:
    """The self-contained HTML page replaying ``traces`` (switchable; the first shown).

    ``title`` (default: n, weight and objective) is text, escaped in the page.

    >>> from optri.teaching import trace
    >>> page = explorer_page([trace([5, 1, 5, 1, 5], "product")], title="{{js}} <b>")
    >>> "<title>{{js}} &lt;b&gt;</title>" in page
    True
    """
    data = page_data(traces)
    payload = json.dumps(data, separators=(",", ":"), ensure_ascii=False, allow_nan=False)
    # inside <script>: no "</script>", "<!--" or line separators JavaScript would trip on
    for ch, code in (("<", "\\u003c"), (">", "\\u003e"), ("&", "\\u0026")):
        payload = payload.replace(ch, code)
    payload = payload.replace("\u2028", "\\u2028").replace("\u2029", "\\u2029")
    r = traces[0].result
    heading = title or (
        f"optri explorer: n = {r.n}, {_name(r.weight_name)} weight, {_name(r.objective)}"
    )
    slots = {
        "title": escape(heading),
        "css": _asset("explorer.css"),
        "data": payload,
        "js": _asset("explorer.js"),
    }
    return _SLOT.sub(lambda m: slots[m.group(1)], _asset("explorer.html"))


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
