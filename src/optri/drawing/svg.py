"""SVG drawings without matplotlib, for notebooks (``_repr_svg_``) and web pages."""

from __future__ import annotations

from collections.abc import Sequence
from html import escape
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["drawing_points", "triangulation_svg"]

#: Vertex labels are drawn up to this many vertices (beyond, they overlap).
_MAX_LABELS = 60


def drawing_points(vertices: NDArray[np.float64]) -> NDArray[np.float64]:
    """2-D points to draw a polygon at: its first two coordinates, or a regular n-gon.

    Vertex values (1-D input, e.g. matrix dimensions) have no geometry; they are
    drawn on a regular n-gon, vertex 0 at the top, counter-clockwise.

    >>> drawing_points(np.array([5.0, 1.0, 5.0, 1.0])).round(6).tolist()
    [[0.0, 1.0], [-1.0, 0.0], [-0.0, -1.0], [1.0, -0.0]]
    """
    v = np.asarray(vertices, dtype=np.float64)
    if v.ndim == 1:
        ang = np.pi / 2 + 2 * np.pi * np.arange(len(v)) / len(v)
        return np.column_stack((np.cos(ang), np.sin(ang)))
    return v[:, :2]


def triangulation_svg(
    vertices: NDArray[np.float64],
    triangles: NDArray[np.int64],
    size: int = 300,
    labels: Sequence[str] | None = None,
) -> str:
    """An SVG image of a polygon: ``triangles`` filled, the polygon outlined.

    ``vertices`` are 2-D or 3-D points (drawn from x and y) or 1-D vertex values
    (drawn on a regular n-gon, see :func:`drawing_points`, each labelled with
    its value unless ``labels`` are given).

    >>> svg = triangulation_svg(np.array([[0., 0], [1, 0], [0, 1]]), np.array([[0, 1, 2]]))
    >>> svg.startswith("<svg") and svg.count("<polygon") == 2
    True
    >>> svg = triangulation_svg(np.array([5.0, 1, 5, 1, 5]), np.array([[0, 1, 4]]))
    >>> svg.count("<polygon"), svg.count("<text")
    (2, 5)
    """
    v = np.asarray(vertices, dtype=np.float64)
    if labels is None and v.ndim == 1:
        labels = [f"{i}: {x:g}" for i, x in enumerate(v.tolist())]
    pts = drawing_points(v)
    pad = 34 if labels is not None else 10
    lo, span = pts.min(axis=0), float(np.ptp(pts, axis=0).max()) or 1.0
    xy = (pts - lo) / span * (size - 2 * pad) + pad
    xy[:, 1] = size - xy[:, 1]  # SVG's y axis points down

    def poly(idx: Any, style: str) -> str:
        coords = " ".join(f"{x:.2f},{y:.2f}" for x, y in xy[idx])
        return f'<polygon points="{coords}" style="{style}"/>'

    body = [poly(t, "fill:#cfe3ff;stroke:#3070c0;stroke-width:1") for t in triangles]
    body.append(poly(np.arange(len(pts)), "fill:none;stroke:black;stroke-width:2"))
    if labels is not None and len(pts) <= _MAX_LABELS:
        centre = xy.mean(axis=0)
        for (x, y), text in zip(xy.tolist(), labels):
            d = np.array([x, y]) - centre
            d = d / (float(np.hypot(*d)) or 1.0) * 16
            body.append(
                f'<text x="{x + d[0]:.1f}" y="{y + d[1]:.1f}" font-size="11" '
                f'text-anchor="middle" dominant-baseline="middle">{escape(text)}</text>'
            )
    return (
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{size}" height="{size}">'
        + "".join(body)
        + "</svg>"
    )
