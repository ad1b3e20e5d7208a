"""Drawing contour bands and stacked-contour meshes on matplotlib's 3-D axes."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["plot_surface"]


def plot_surface(
    vertices: NDArray[np.float64],
    faces: NDArray[np.int64],
    rings: Sequence[int] = (),
    ax: Any = None,
    *,
    color: str = "#9ecae1",
    edgecolor: str = "#3182bd",
    alpha: float = 0.6,
) -> Any:
    """Draw triangles (and the closed rings of consecutive vertex counts ``rings``).

    Returns the 3-D axes (a new figure's when ``ax`` is None); matplotlib is
    imported here, on use.
    """
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    if ax is None:
        ax = plt.figure().add_subplot(projection="3d")
    ax.add_collection3d(
        Poly3DCollection(
            vertices[faces], facecolor=color, edgecolor=edgecolor, linewidth=0.3, alpha=alpha
        )
    )
    start = 0
    for k in rings:
        ring = vertices[np.r_[start : start + k, start]]
        ax.plot(ring[:, 0], ring[:, 1], ring[:, 2], color="k", linewidth=1.0)
        start += k
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    centre, half = (lo + hi) / 2, max(float((hi - lo).max()) / 2, 1e-12)
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    return ax
