"""3-D polylines: input checks and Liepa's objective evaluated exactly.

Liepa's objective of a triangulated polyline is (largest dihedral angle
between adjacent triangles, incl. the mesh triangles across boundary edges
when third points are given; total area). :func:`liepa_objective` computes
it for any index triangulation with the same compiled numbers the searches
use (``optri._core.holes``), so comparisons with brute force and with other
tools are exact.

Coordinates of any magnitude: the searches and the evaluator work on the
points scaled by a power of two (:func:`power_of_two_scale`), which changes
no rounding (unit normals and degeneracy tests come out bit-identical) but
keeps squares and cross products of 1e300-sized or 1e-300-sized coordinates
from overflowing or underflowing.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InvalidPolygonError
from ..polygon import normalize_vertices

__all__ = [
    "angle_of_key",
    "as_points3d",
    "liepa_keys",
    "liepa_objective",
    "power_of_two_scale",
    "with_third_points",
]


def liepa_objective(
    points3d: ArrayLike, triangles: ArrayLike, third_points: ArrayLike | None = None
) -> tuple[float, float]:
    """Liepa's objective of any triangulation of the polyline, evaluated exactly.

    Returns (largest dihedral angle in radians, total area). Triangles are
    index triples in any vertex order (they are wound in the polyline's order).

    Examples
    --------
    >>> sq = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    >>> liepa_objective(sq, [[0, 1, 2], [0, 2, 3]])
    (0.0, 1.0)
    """
    P = as_points3d(points3d)
    Q, has_third = with_third_points(P, third_points)
    Qs, e = power_of_two_scale(Q)
    n = P.shape[0]
    wrong = f"triangles must be index triples of vertices 0..{n - 1}"
    try:
        tris = np.asarray(triangles, dtype=np.int64)
    except (TypeError, ValueError):
        raise InvalidPolygonError(wrong) from None
    if tris.size % 3 or (tris.size and (tris.min() < 0 or tris.max() >= n)):
        raise InvalidPolygonError(wrong)
    key, area = liepa_keys(Qs, n, has_third, tris)
    return angle_of_key(key), math.ldexp(area, 2 * e)


def power_of_two_scale(Q: NDArray[np.float64]) -> tuple[NDArray[np.float64], int]:
    """``(Q / 2**e, e)`` with the largest coordinate in [0.5, 1): exact, no rounding.

    >>> power_of_two_scale(np.array([[3.0, -1e300, 0.0]]))[1]
    997
    """
    top = float(np.abs(Q).max())
    e = math.frexp(top)[1] if top > 0 else 0
    return np.ascontiguousarray(np.ldexp(Q, -e)), e


def as_points3d(points3d: ArrayLike) -> NDArray[np.float64]:
    """A closed 3-D polyline as a checked ``(n, 3)`` array (2-D input lifted to z = 0).

    Shares :func:`optri.polygon.normalize_vertices` with every other entry
    point, then refuses a polyline whose points are all collinear.
    """
    P = normalize_vertices(points3d, values=False)
    if P.shape[1] == 2:
        P = np.column_stack((P, np.zeros(len(P))))
    scaled = power_of_two_scale(P)[0]  # no overflow in the centring and the SVD
    centred = scaled - scaled.mean(axis=0)
    sv = np.linalg.svd(centred, compute_uv=False)
    if sv[1] <= 1e-12 * sv[0]:
        raise InvalidPolygonError(
            f"all {len(P)} points are collinear: the polyline bounds no surface to fill"
        )
    return np.ascontiguousarray(P)


def with_third_points(
    P: NDArray[np.float64], third_points: ArrayLike | None
) -> tuple[NDArray[np.float64], bool]:
    """``(Q, has_third)``: the points with the third points stacked under them (if given).

    ``third_points[s]`` is the third vertex of the mesh triangle on boundary
    edge ``(s, s + 1)``.
    """
    if third_points is None:
        return P, False
    T = np.asarray(third_points, dtype=np.float64)
    if T.shape != P.shape:
        raise InvalidPolygonError(
            f"third_points must have one 3-D point per polyline edge, shape {P.shape}; "
            f"got {T.shape}"
        )
    if not np.isfinite(T).all():
        raise InvalidPolygonError("third_points has a non-finite coordinate")
    return np.ascontiguousarray(np.vstack((P, T))), True


def angle_of_key(key: float) -> float:
    """The dihedral angle (radians) of a key ``1 - cos``."""
    return float(math.acos(max(-1.0, min(1.0, 1.0 - key))))


def liepa_keys(
    Q: NDArray[np.float64], n: int, has_third: bool, triangles: NDArray[np.int64]
) -> tuple[float, float]:
    """(max dihedral key, total area) of index triangles; the kernels' own numbers.

    ``Q`` as the searches see it (scaled by :func:`power_of_two_scale`).
    """
    from .._core import holes as hk

    tris = np.sort(triangles.reshape(-1, 3), axis=1)
    normals = hk.triangle_normals(Q, tris)
    # every edge (a < b) with its triangle, sorted: equal neighbours share an edge
    edges = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [0, 2]]])
    keys = edges[:, 0] * n + edges[:, 1]
    order = np.argsort(keys, kind="stable")
    keys, owner = keys[order], np.tile(np.arange(len(tris)), 3)[order]
    same = keys[1:] == keys[:-1]
    worst = hk.pair_keys(normals[owner[:-1][same]], normals[owner[1:][same]]).max(initial=0.0)
    if has_third:
        sides = np.append(np.arange(n - 1) * (n + 1) + 1, n - 1)  # (s, s+1), then (0, n-1)
        pos = np.minimum(np.searchsorted(keys, sides), len(keys) - 1)
        found = keys[pos] == sides
        mesh = hk.mesh_normals(Q, n)
        side = np.flatnonzero(found).astype(np.int64)
        side_keys = hk.mesh_pair_keys(normals[owner[pos[found]]], mesh, side)
        worst = max(worst, side_keys.max(initial=0.0))
    return float(worst), float(normals[:, 4].sum())
