"""Compiled geometry shared by the hole-filling searches (numba, ``cache=True``).

Vertex array ``Q`` holds the ``n`` polyline points, followed (when the mesh
around the hole is known) by the ``n`` third points: ``Q[n + s]`` is the third
vertex of the mesh triangle on boundary edge ``(s, s + 1)``. Every triangle
normal is computed by :func:`unit_normal` from its *sorted* vertex indices, so
the searches and the evaluator (:func:`triangle_normals`) see bit-identical
values and their max-dihedral comparisons agree exactly.

The dihedral "key" of two adjacent, consistently oriented triangles is
``1 - cos(angle between their normals)`` in [0, 2]: monotone in the angle, so
comparing keys compares angles without an ``acos`` in the inner loops. A
degenerate (zero-area) *patch* triangle gets :data:`DEGENERATE_KEY` = 3 against
every neighbour: worse than any real fold (2), so a patch with a zero-area
triangle wins only when every patch has one. A degenerate *mesh* triangle has
no normal to compare with: the key across its edge is 0.
"""

from __future__ import annotations

import math

import numpy as np

from ..engines.compiled import kernel

__all__ = [
    "DEGENERATE_KEY",
    "FOLD_KEY",
    "key_of",
    "mesh_key",
    "mesh_normals",
    "mesh_pair_keys",
    "pair_keys",
    "sorted_normal",
    "triangle_normals",
    "unit_normal",
]

#: Key of any pair involving a zero-area patch triangle: worse than a full fold.
DEGENERATE_KEY = 3.0
#: Key of a full fold (angle pi), the worst a real pair of triangles can have.
FOLD_KEY = 2.0
#: A triangle whose squared sine of the angle at its first vertex is at most this
#: is degenerate (sine <= 1e-12).
DEGENERATE_SINE2 = 1e-24


@kernel()
def _cross(Q, a, b, c):
    # (b - a) x (c - a) and the squared lengths of both edge vectors
    ux = Q[b, 0] - Q[a, 0]
    uy = Q[b, 1] - Q[a, 1]
    uz = Q[b, 2] - Q[a, 2]
    vx = Q[c, 0] - Q[a, 0]
    vy = Q[c, 1] - Q[a, 1]
    vz = Q[c, 2] - Q[a, 2]
    nx = uy * vz - uz * vy
    ny = uz * vx - ux * vz
    nz = ux * vy - uy * vx
    return nx, ny, nz, ux * ux + uy * uy + uz * uz, vx * vx + vy * vy + vz * vz


@kernel()
def unit_normal(Q, a, b, c):
    """Unit normal of triangle a->b->c, a degenerate flag and the area."""
    nx, ny, nz, uu, vv = _cross(Q, a, b, c)
    n2 = nx * nx + ny * ny + nz * nz
    nn = math.sqrt(n2)
    if n2 <= DEGENERATE_SINE2 * (uu * vv):
        return 0.0, 0.0, 0.0, True, 0.5 * nn
    inv = 1.0 / nn
    return nx * inv, ny * inv, nz * inv, False, 0.5 * nn


@kernel()
def sorted_normal(Q, a, b, c):
    """:func:`unit_normal` of the triangle's vertices sorted (the same rounding always)."""
    if a > b:
        a, b = b, a
    if b > c:
        b, c = c, b
    if a > b:
        a, b = b, a
    return unit_normal(Q, a, b, c)


@kernel()
def key_of(x1, y1, z1, d1, x2, y2, z2, d2):
    """Key of two patch triangles (unit normals, degenerate flags)."""
    if d1 or d2:
        return DEGENERATE_KEY
    k = 1.0 - (x1 * x2 + y1 * y2 + z1 * z2)
    return min(max(k, 0.0), FOLD_KEY)


@kernel()
def mesh_key(MN, s, x, y, z, d, has_third):
    """Key of patch triangle (x, y, z, d) against the mesh triangle on side ``s``."""
    if not has_third:
        return 0.0
    if d:
        return DEGENERATE_KEY
    if MN[s, 3] != 0.0:
        return 0.0  # a zero-area mesh triangle has no normal to fold against
    k = 1.0 - (x * MN[s, 0] + y * MN[s, 1] + z * MN[s, 2])
    return min(max(k, 0.0), FOLD_KEY)


@kernel()
def mesh_normals(Q, n):
    """(n, 4) rows (x, y, z, degenerate) of the mesh triangles (p[s+1], p[s], t[s])."""
    out = np.zeros((n, 4))
    for s in range(n):
        x, y, z, d, _ = unit_normal(Q, (s + 1) % n, s, n + s)
        out[s, 0] = x
        out[s, 1] = y
        out[s, 2] = z
        out[s, 3] = 1.0 if d else 0.0
    return out


@kernel()
def triangle_normals(Q, tris):
    """(m, 5) rows (x, y, z, degenerate, area) of index triangles (sorted first)."""
    m = tris.shape[0]
    out = np.zeros((m, 5))
    for t in range(m):
        x, y, z, d, area = sorted_normal(Q, tris[t, 0], tris[t, 1], tris[t, 2])
        out[t, 0] = x
        out[t, 1] = y
        out[t, 2] = z
        out[t, 3] = 1.0 if d else 0.0
        out[t, 4] = area
    return out


@kernel()
def pair_keys(U, V):
    """Keys of row pairs (x, y, z, degenerate, ...) of two patch-normal tables."""
    out = np.empty(U.shape[0])
    for r in range(U.shape[0]):
        out[r] = key_of(
            U[r, 0], U[r, 1], U[r, 2], U[r, 3] != 0.0, V[r, 0], V[r, 1], V[r, 2], V[r, 3] != 0.0
        )
    return out


@kernel()
def mesh_pair_keys(U, MN, sides):
    """Keys of patch-normal rows ``U`` against the mesh triangles on ``sides``."""
    out = np.empty(U.shape[0])
    for r in range(U.shape[0]):
        out[r] = mesh_key(MN, sides[r], U[r, 0], U[r, 1], U[r, 2], U[r, 3] != 0.0, True)
    return out
