"""Random polygons with holes, for tests, benchmarks and examples."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ..errors import InvalidPolygonError

__all__ = ["random_domain"]


def random_domain(
    n: int, holes: int = 1, *, seed: int | None = None, depth: float = 0.4
) -> tuple[NDArray[np.float64], list[NDArray[np.float64]]]:
    """A random polygon with ``holes`` holes and ``n`` vertices in all: ``(exterior, holes)``.

    The exterior is star-shaped around the origin (jittered angles, radii in
    [1 - ``depth``, 1]: deeper is spikier), counter-clockwise; about half the
    vertices go to the holes, small star-shaped rings placed apart from each
    other and from the exterior, clockwise.

    Raises
    ------
    InvalidPolygonError
        ``n`` too small: each hole needs 3 vertices and the exterior 8.

    Examples
    --------
    >>> ext, hs = random_domain(20, holes=2, seed=1)
    >>> len(ext), [len(h) for h in hs]
    (10, [5, 5])
    """
    if holes < 0 or n < 3 * holes + (8 if holes else 3):
        raise InvalidPolygonError(
            f"{n} vertices cannot make {holes} hole(s) of 3 vertices and an exterior of 8"
        )
    rng = np.random.default_rng(seed)
    k = min(max(3, n // (2 * holes)), (n - 8) // holes) if holes else 0
    n_ext = n - k * holes
    ext = _star(rng, n_ext, 1.0 - depth, 1.0)
    if holes == 0:
        return ext, []
    a, b = ext, np.roll(ext, -1, axis=0)
    reach = _segment_distance(np.zeros(2), a, b).min()  # the origin's disk inside the exterior
    size = 0.9 * reach / (1.0 + 2.4 * math.sqrt(holes))
    centres = _apart(rng, holes, 0.9 * reach - size, 2.2 * size)
    return ext, [c + size * _star(rng, k, 0.6, 1.0)[::-1] for c in centres]


def _star(rng: np.random.Generator, m: int, lo: float, hi: float) -> NDArray[np.float64]:
    ang = 2 * np.pi * (np.arange(m) + rng.uniform(-0.3, 0.3, m)) / m
    r = rng.uniform(lo, hi, m)
    return np.column_stack((r * np.cos(ang), r * np.sin(ang)))


def _segment_distance(
    p: NDArray[np.float64], a: NDArray[np.float64], b: NDArray[np.float64]
) -> NDArray[np.float64]:
    d = b - a
    t = np.clip(((p - a) * d).sum(axis=1) / (d * d).sum(axis=1), 0.0, 1.0)
    return np.hypot(*(a + t[:, None] * d - p).T)


def _apart(rng: np.random.Generator, count: int, radius: float, gap: float) -> NDArray[np.float64]:
    """``count`` points in the disk of ``radius``, pairwise at least ``gap`` apart."""
    for _ in range(200):
        pts: list[NDArray[np.float64]] = []
        for _ in range(200 * count):
            r, t = radius * math.sqrt(rng.uniform()), rng.uniform(0, 2 * np.pi)
            q = np.array([r * math.cos(t), r * math.sin(t)])
            if all(np.hypot(*(q - p)) >= gap for p in pts):
                pts.append(q)
                if len(pts) == count:
                    return np.array(pts)
    raise InvalidPolygonError(f"could not place {count} holes apart")  # pragma: no cover
