"""SVG drawings without matplotlib, for notebooks (``_repr_svg_``)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["triangulation_svg"]


def triangulation_svg(
    vertices: NDArray[np.float64], triangles: NDArray[np.int64], size: int = 300
) -> str:
    """An SVG image of 2-D ``vertices``: ``triangles`` filled, the polygon outlined.

    >>> svg = triangulation_svg(np.array([[0., 0], [1, 0], [0, 1]]), np.array([[0, 1, 2]]))
    >>> svg.startswith("<svg") and svg.count("<polygon") == 2
    True
    """
    pts = vertices[:, :2]
    lo, span = pts.min(axis=0), float(np.ptp(pts, axis=0).max()) or 1.0
    margin = 10
    xy = (pts - lo) / span * (size - 2 * margin) + margin
    xy[:, 1] = size - xy[:, 1]  # SVG's y axis points down

    def poly(idx: Any, style: str) -> str:
        coords = " ".join(f"{x:.2f},{y:.2f}" for x, y in xy[idx])
        return f'<polygon points="{coords}" style="{style}"/>'

    body = [poly(t, "fill:#cfe3ff;stroke:#3070c0;stroke-width:1") for t in triangles]
    body.append(poly(np.arange(len(pts)), "fill:none;stroke:black;stroke-width:2"))
    return (
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{size}" height="{size}">'
        + "".join(body)
        + "</svg>"
    )
