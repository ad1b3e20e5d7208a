"""3-D polylines: input checks and Liepa's objective evaluated exactly.

Liepa's objective of a triangulated polyline is (largest dihedral angle
between adjacent triangles, incl. the mesh triangles across boundary edges
when third points are given; total area). :func:`liepa_objective` computes
it for any index triangulation with the same compiled numbers the searches
use, so comparisons with brute force and with other tools are exact.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .errors import InvalidPolygonError
from .geometry import _require_distinct, _require_finite

__all__ = ["liepa_objective"]


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
    P = _as_points(points3d)
    Q, has_third = _with_third(P, third_points)
    key, area = _liepa_keys(Q, P.shape[0], has_third, np.asarray(triangles, dtype=np.int64))
    return _angle(key), area


def _as_points(points3d: ArrayLike) -> NDArray[np.float64]:
    try:
        arr = np.asarray(points3d, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidPolygonError(f"points must be numbers: {exc}") from exc
    if arr.ndim != 2 or arr.shape[1] not in (2, 3):
        raise InvalidPolygonError(f"expected an (n, 3) array of points, got shape {arr.shape}")
    if arr.shape[1] == 2:
        arr = np.column_stack((arr, np.zeros(len(arr))))
    # optri.geometry's checks, without its planarity and convexity analysis
    _require_finite(arr)
    if arr.shape[0] > 3 and np.array_equal(arr[0], arr[-1]):
        arr = arr[:-1]  # a closing vertex equal to the first
    if arr.shape[0] < 3:
        raise InvalidPolygonError(f"a polygon needs at least 3 vertices, got {arr.shape[0]}")
    _require_distinct(arr)
    P = arr
    centred = P - P.mean(axis=0)
    sv = np.linalg.svd(centred, compute_uv=False)
    if sv[1] <= 1e-12 * sv[0]:
        raise InvalidPolygonError(
            f"all {len(P)} points are collinear: the polyline bounds no surface to fill"
        )
    return np.ascontiguousarray(P)


def _with_third(
    P: NDArray[np.float64], third_points: ArrayLike | None
) -> tuple[NDArray[np.float64], bool]:
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


def _angle(key: float) -> float:
    return float(math.acos(max(-1.0, min(1.0, 1.0 - key))))


def _liepa_keys(
    Q: NDArray[np.float64], n: int, has_third: bool, triangles: NDArray[np.int64]
) -> tuple[float, float]:
    """(max dihedral key, total area) of index triangles; the kernels' own numbers."""
    from . import holes_kernels as hk

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
        side_keys = hk.pair_keys(normals[owner[pos[found]]], mesh[np.flatnonzero(found)])
        worst = max(worst, side_keys.max(initial=0.0))
    return float(worst), float(normals[:, 4].sum())
