"""Hypothesis strategies shared by the test modules."""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st

from optri.weights import WEIGHTS

POINT_WEIGHTS = sorted(w for w, spec in WEIGHTS.items() if spec.needs == "points")


def ellipse_polygon(n: int, seed: int, dims: int = 2) -> np.ndarray:
    """Jittered angles on an ellipse: strictly convex, counter-clockwise, no near-duplicates."""
    rng = np.random.default_rng(seed)
    ang = 2 * np.pi * (np.arange(n) + 0.8 * rng.random(n)) / n
    pts = np.c_[1000 * np.cos(ang), 600 * np.sin(ang)]
    if dims == 3:  # a tilted plane: planar 3-D input
        pts = np.c_[pts, 0.3 * pts[:, 0] - 0.2 * pts[:, 1] + 5.0]
    return pts


#: (n, seed) of ellipse polygons on which one lexicographic pass of ("max", "sum") with
#: ("max_angle", "perimeter") or ("aspect_ratio", "diagonal") misses the optimum, and the
#: second component's unconstrained optimum breaks the bottleneck: the two-phase rule and
#: its gate both decide the answer.
TWO_PHASE_CASES = [(7, 18), (8, 27)]
MAX_LED_EDGE_PAIRS = [("max_angle", "perimeter"), ("aspect_ratio", "diagonal")]


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
