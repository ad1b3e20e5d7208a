"""``Trace.animate``: the table filling beside the polygon, as a GIF or an MP4.

Each frame shows the polygon with the current sub-polygon and candidate
triangle highlighted, the paper's n x n table as the events have left it, and
the counters; the last frame traces the optimal triangulation back. matplotlib
draws; pillow writes GIFs, ffmpeg MP4s (both imported only here, on use).
"""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import config
from .._optional import import_optional
from ..drawing.figures import new_axes
from ..drawing.svg import drawing_points
from ..errors import MissingDependencyError, OptriError, TableTooLargeError
from .board import Board, describe, lower_cell, upper_cell, value_text

if TYPE_CHECKING:  # pragma: no cover
    from .trace import Trace

__all__ = ["animate", "frame_steps"]

_COLOURS = {
    "upper": "#fff4d6",
    "lower": "#e3efff",
    "diagonal": "#eeeeee",
    "current": "#ff9f43",
    "input": "#ffd8a8",
    "optimal": "#ffd08a",
}


def frame_steps(events: Sequence[Any], kinds: Sequence[str]) -> list[int]:
    """Steps shown as frames: 0, one after each event of ``kinds``, and the end again.

    The last step appears twice: once as the store of (0, n - 1), once with the
    optimal triangulation traced back.

    >>> from optri.teaching import trace
    >>> t = trace([5, 1, 5, 1, 5], "product")
    >>> len(frame_steps(t.events, ("candidate", "store")))      # 1 + 10 + 6 + 1
    18
    """
    unknown = set(kinds) - {"call", "side", "hit", "candidate", "store"}
    if unknown:
        raise OptriError(
            f"unknown event kind(s) {sorted(unknown)}; use call, side, hit, candidate or store"
        )
    steps = [0] + [s + 1 for s, e in enumerate(events) if e[0] in kinds]
    return steps + [len(events)]


def animate(trace: Trace, path: str | Path, *, kinds: Sequence[str], fps: float, dpi: int) -> Path:
    """Write the animation of ``trace`` to ``path`` (``.gif`` or ``.mp4``), atomically.

    Raises
    ------
    OptriError
        An unknown suffix or event kind.
    MissingDependencyError
        ``.mp4`` without ffmpeg on the PATH.
    TableTooLargeError
        More frames than :data:`optri.config.ANIMATE_MAX_FRAMES`.
    """
    target = Path(path)
    suffix = target.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise OptriError(f"cannot animate to {target.name!r}: use a .gif or .mp4 file")
    if suffix == ".mp4" and shutil.which("ffmpeg") is None:
        raise MissingDependencyError(
            "writing an .mp4 needs ffmpeg on the PATH (e.g. apt-get install ffmpeg); "
            "a .gif needs only pillow"
        )
    steps = frame_steps(trace.events, kinds)
    if len(steps) > config.ANIMATE_MAX_FRAMES:
        raise TableTooLargeError(
            f"{len(steps)} frames exceed optri.config.ANIMATE_MAX_FRAMES = "
            f"{config.ANIMATE_MAX_FRAMES}; animate fewer kinds (kinds=('store',)) or a "
            "smaller polygon"
        )
    anim_mod = import_optional("matplotlib.animation")
    if suffix == ".gif":
        import_optional("PIL")
        writer = anim_mod.PillowWriter(fps=fps)
    else:
        writer = anim_mod.FFMpegWriter(fps=fps)
    fig = new_axes(None).figure
    fig.clf()
    n = trace.n
    fig.set_size_inches(4.2 + 0.62 * n, max(4.2, 1.4 + 0.42 * n))
    painter = _Painter(trace, fig)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=suffix, dir=target.parent)
    os.close(fd)
    try:
        with writer.saving(fig, tmp, dpi):
            for index, step in enumerate(steps):
                painter.show(step, end=index == len(steps) - 1)
                writer.grab_frame()
        os.replace(tmp, target)
    finally:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        import matplotlib.pyplot as plt

        plt.close(fig)
    return target


class _Painter:
    """The figure's artists, made once; :meth:`show` updates them to a step."""

    def __init__(self, trace: Trace, fig: Any) -> None:
        from matplotlib.patches import Polygon, Rectangle

        self.trace, self.fig, n = trace, fig, trace.n
        self.board = Board(n)
        self.applied = 0
        self.optimal = _optimal_chords(trace)
        pts = self.pts = drawing_points(trace.vertices)
        inverse = np.empty_like(trace.order)
        inverse[trace.order] = np.arange(len(trace.order))
        triangles = inverse[trace.result.triangles].tolist()
        # the polygon: sub-polygon, candidate triangle, chord, optimal triangles, ring, labels
        pax = fig.add_axes((0.0, 0.1, 0.36, 0.74))
        pax.set_aspect("equal")
        pax.axis("off")
        self.sub = pax.add_patch(Polygon(pts[:3], closed=True, fc="#fff3c4", ec="none"))
        self.tri = pax.add_patch(Polygon(pts[:3], closed=True, fc="none", ec="black", lw=1))
        (self.chord,) = pax.plot([], [], color="#d04000", lw=2)
        self.best = [
            pax.add_patch(Polygon(pts[t], closed=True, fc=_COLOURS["optimal"], ec="#b07000"))
            for t in triangles
        ]
        ring = np.vstack([pts, pts[:1]])
        pax.plot(ring[:, 0], ring[:, 1], color="black", lw=1.6)
        centre, span = pts.mean(axis=0), float(np.ptp(pts, axis=0).max()) or 1.0
        for idx, (x, y) in enumerate(pts.tolist()):
            d = np.array([x, y]) - centre
            d = d / (float(np.hypot(*d)) or 1.0) * 0.1 * span
            label = f"v{idx + 1}"
            if trace.vertices.ndim == 1:
                label += f"\n{value_text(trace.vertices[idx])}"
            pax.annotate(label, (x + d[0], y + d[1]), ha="center", va="center", fontsize=8)
        pax.margins(0.15)
        # the table: one rectangle and one text per cell
        tax = fig.add_axes((0.38, 0.1, 0.6, 0.74))
        tax.set_xlim(-1, n)
        tax.set_ylim(n, -1)
        tax.axis("off")
        size = 8 if n <= 7 else 6
        self.rects, self.texts = {}, {}
        for r in range(n):
            tax.text(-0.6, r, str(r + 1), ha="center", va="center", fontsize=8, weight="bold")
            tax.text(r, -0.7, str(r + 1), ha="center", va="center", fontsize=8, weight="bold")
            for c in range(n):
                rect = Rectangle((c - 0.5, r - 0.5), 1, 1, edgecolor="#bbbbbb", lw=0.6)
                self.rects[(r, c)] = tax.add_patch(rect)
                self.texts[(r, c)] = tax.text(c, r, "", ha="center", va="center", fontsize=size)
        self.title = fig.suptitle("", fontsize=9)

    def show(self, step: int, end: bool) -> None:
        """Apply events up to ``step`` and update the artists (``end``: trace back)."""
        while self.applied < step:
            self.board.apply(self.trace.events[self.applied])
            self.applied += 1
        ev = None if end else self.board.last
        self._polygon(ev, end)
        self._table(ev, end)
        self._title(step, end)

    def _polygon(self, ev: Any, end: bool) -> None:
        pts = self.pts
        for patch in self.best:
            patch.set_visible(end)
        self.sub.set_visible(ev is not None)
        self.tri.set_visible(ev is not None and ev[3] is not None)
        self.chord.set_data([], [])
        if ev is None:
            return
        kind, i, j, k, _ = ev
        self.sub.set_xy(pts[i : j + 1])
        self.chord.set_data(pts[[i, j], 0], pts[[i, j], 1])
        if k is not None:
            self.tri.set_xy(pts[[i, k, j]])
            self.tri.set_facecolor(_COLOURS["current"] if kind == "candidate" else "#7ccf7c")

    def _table(self, ev: Any, end: bool) -> None:
        colours = _cell_colours(self.trace.n)
        if end:
            for i, j in self.optimal:
                colours[upper_cell(i, j)] = colours[lower_cell(i, j)] = _COLOURS["optimal"]
        elif ev is not None:
            kind, i, j, k, _ = ev
            if kind == "candidate":
                for a, b in ((i, k), (k, j)):
                    colours[upper_cell(a, b)] = _COLOURS["input"]
            colours[upper_cell(i, j)] = colours[lower_cell(i, j)] = _COLOURS["current"]
        texts = self.board.cell_texts()
        for (r, c), rect in self.rects.items():
            rect.set_facecolor(colours[(r, c)])
            self.texts[(r, c)].set_text(texts[r][c])

    def _title(self, step: int, end: bool) -> None:
        c = self.board.counts
        counters = (
            f"calls {c['call']}   hits {c['hit']}   candidates {c['candidate']}   "
            f"stores {c['store']}"
        )
        ev = self.board.last
        if end:
            what = (
                f"optimum w[1,{self.trace.n - 1}] = {value_text(self.trace.optimum)}: "
                "the optimal triangles traced back"
            )
        elif ev is None:
            what = "the empty table: the diagonal (sides, w[i,i] = 0) is set"
        else:
            what = describe(ev)
        total = len(self.trace.events)
        self.title.set_text(f"{self.trace.method}   step {step}/{total}\n{what}\n{counters}")


def _cell_colours(n: int) -> dict[tuple[int, int], str]:
    def part(r: int, c: int) -> str:
        if r == c or c == n - 1:  # the diagonal and the unused column n (X)
            return "diagonal"
        return "upper" if r < c else "lower"

    return {(r, c): _COLOURS[part(r, c)] for r in range(n) for c in range(n)}


def _optimal_chords(trace: Trace) -> list[tuple[int, int]]:
    splits = trace.splits()
    out, stack = [], [(0, trace.n - 1)]
    while stack:
        i, j = stack.pop()
        k = splits.get((i, j))
        if j - i < 2 or k is None:
            continue
        out.append((i, j))
        stack += [(i, k), (k, j)]
    return out
