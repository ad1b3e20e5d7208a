"""Hypothesis strategies shared by the test modules."""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st

from optri.weights import WEIGHTS

POINT_WEIGHTS = sorted(w for w, spec in WEIGHTS.items() if spec.needs == "points")


@st.composite
def convex_polygons(draw, min_n: int = 3, max_n: int = 10) -> np.ndarray:
    """Strictly convex polygon, counter-clockwise: sorted angles on an ellipse."""
    n = draw(st.integers(min_n, max_n))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    while True:
        ang = np.sort(rng.uniform(0, 2 * np.pi, n))
        gaps = np.diff(np.append(ang, ang[0] + 2 * np.pi))
        if gaps.min() > 0.05 and gaps.max() < np.pi - 0.05:
            break
    a, b = rng.uniform(0.5, 3.0, 2)
    pts = np.column_stack((a * np.cos(ang), b * np.sin(ang)))
    theta = rng.uniform(0, 2 * np.pi)
    rot = np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])
    return pts @ rot.T + rng.uniform(-5, 5, 2)


@st.composite
def value_sequences(draw, min_n: int = 3, max_n: int = 10) -> list[int]:
    """Vertex values for the product (matrix-chain) weight."""
    return draw(st.lists(st.integers(1, 30), min_size=min_n, max_size=max_n))
