"""Fairing: move chosen vertices so the surface through them is as smooth as its surroundings.

The free vertices solve ``L^(k+1) x = 0`` with every other vertex fixed, where ``L`` is
the cotangent Laplace-Beltrami operator with mixed Voronoi areas (Meyer, Desbrun,
Schroder and Barr 2003) and ``k`` is the continuity asked for at the fixed ring:
``k = 0`` a membrane (``L x = 0``, position continuity), ``k = 1`` a thin plate
(``L^2 x = 0``, tangent continuity), ``k = 2`` minimal curvature variation
(``L^3 x = 0``, curvature continuity); as in Liepa (2003), CGAL's
``fair`` and MeshLib's hole filling. One sparse factorization serves x, y and z.

Rows of ``L^(k+1)`` reach ``k + 1`` rings out from a free vertex, so the fixed
vertices within that many rings act as the boundary condition: a whole mesh may be
passed; only the free vertices' neighbourhood enters the system.

``L`` depends on the positions it acts on. One solve takes it from the positions
given (for a hole, the flat refined patch, as CGAL does); ``passes=2`` solves again
with ``L`` taken from the first solution, whose cotangents and areas are those of the
curved surface: ``fill_holes`` fairs so (over a large hole the flat patch's areas and
angles are far from the surface's, and ``L^3`` taken there overshoots).

:func:`fair_vertices` solves in the compiled core (one sparse ``L D L^T`` factorization
of the symmetric system under a nested-dissection order); :func:`reference_fair_vertices`
is the same solve in numpy and scipy (``laplacian`` and SuperLU), which the tests hold
the core equal to within rounding.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._optional import import_optional
from ..errors import InvalidPolygonError
from ..meshdata import mesh_arrays, same_kind

__all__ = ["FairResult", "fair_region", "fair_vertices", "laplacian", "reference_fair_vertices"]

#: Continuity orders :func:`fair_region` accepts.
CONTINUITY = (0, 1, 2)
#: Solves ``fill_holes`` fairs a patch with (``passes`` of :func:`fair_vertices`).
PATCH_PASSES = 2
# a corner whose sine is below this (relative to its sides) counts as degenerate: its
# cotangent is clamped there, so a zero-area face never puts an infinity in the system
# (the compiled core's fair.cpp uses the same floor)
_SINE_FLOOR = 1e-12
# why a solve failed, by the compiled core's status
_NO_AREA = "a vertex to fair has no area around it"
_NOT_FINITE = "the fairing system gave non-finite positions"
_FAILED = {
    1: _NO_AREA,
    2: "the fairing system could not be solved (a zero or non-finite pivot)",
    3: _NOT_FINITE,
}


@dataclass
class FairResult:
    """What :func:`fair_vertices` did.

    Attributes
    ----------
    vertices : ndarray, shape (n, 3)
        All vertices; the free ones moved when ``ok``, else as given.
    ok : bool
        Whether the system was solved (a singular or non-finite system keeps the input).
    reason : str
        Why not, when not ``ok``.
    """

    vertices: NDArray[np.float64]
    ok: bool
    reason: str = ""


def laplacian(vertices: NDArray[np.float64], faces: NDArray[np.int64]) -> tuple[Any, Any]:
    """The cotangent stiffness matrix ``C`` and the mixed Voronoi areas ``A`` of a mesh.

    ``C`` is symmetric, ``C[i, j] = -(cot a + cot b) / 2`` over the two corners facing
    edge ``(i, j)``, ``C[i, i] = -sum_j C[i, j]``; the Laplace-Beltrami operator is
    ``L = -A^-1 C``. A flat mesh is in the kernel of ``C`` for linear functions.

    Returns
    -------
    (C, A)
        A ``scipy.sparse.csr_matrix`` and an ``(n,)`` array of areas (each > 0 for a
        vertex of a non-degenerate face).

    Examples
    --------
    >>> import numpy as np
    >>> v = np.array([[0., 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]])
    >>> f = np.array([[0, 1, 2], [0, 2, 3]])
    >>> C, A = laplacian(v, f)
    >>> (C @ v[:, 0]).tolist(), A.tolist()
    ([-0.5, 0.5, 0.5, -0.5], [0.25, 0.25, 0.25, 0.25])
    """
    sparse = import_optional("scipy.sparse", "mesh")
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    n = len(v)
    p = v[f]  # (m, 3 corners, 3)
    cot = np.empty((len(f), 3))
    area = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    sq = np.empty((len(f), 3))  # squared length of the side facing each corner
    for c in range(3):
        a, b = p[:, (c + 1) % 3] - p[:, c], p[:, (c + 2) % 3] - p[:, c]
        cross = np.linalg.norm(np.cross(a, b), axis=1)
        dot = np.einsum("ij,ij->i", a, b)
        scale = np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1)
        cot[:, c] = dot / np.maximum(cross, _SINE_FLOOR * np.maximum(scale, 1e-300))
        sq[:, c] = np.einsum("ij,ij->i", b - a, b - a)
    rows, cols, vals = [], [], []
    for c in range(3):
        i, j = f[:, (c + 1) % 3], f[:, (c + 2) % 3]
        w = -0.5 * cot[:, c]
        rows += [i, j, i, j]
        cols += [j, i, i, j]
        vals += [w, w, -w, -w]
    C = sparse.csr_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)
    )
    A = np.zeros(n)
    obtuse = cot < 0  # a corner past 90 degrees
    any_obtuse = obtuse.any(axis=1)
    for c in range(3):
        # Voronoi part of corner c: |side to c+1|^2 cot(c+2) + |side to c+2|^2 cot(c+1), / 8
        c1, c2 = (c + 1) % 3, (c + 2) % 3
        vor = (sq[:, c2] * cot[:, c2] + sq[:, c1] * cot[:, c1]) / 8
        share = np.where(any_obtuse, np.where(obtuse[:, c], area / 2, area / 4), vor)
        np.add.at(A, f[:, c], share)
    return C, A


def fair_vertices(
    vertices: NDArray[np.float64],
    faces: NDArray[np.int64],
    free: NDArray[np.int64],
    continuity: int = 1,
    *,
    passes: int = 1,
) -> FairResult:
    """Solve ``L^(continuity+1) x = 0`` for the ``free`` vertices, the rest fixed.

    Parameters
    ----------
    vertices : (n, 3) array
    faces : (m, 3) int array
        Consistently wound triangles.
    free : int array
        Indices of the vertices to move.
    continuity : {0, 1, 2}
        Smoothness across the fixed ring: position, tangent plane, curvature.
    passes : int
        Solves (>= 1), each with ``L`` taken from the positions the one before gave.

    Returns
    -------
    FairResult
        The vertices (moved when every solve succeeded) and whether they did.

    Examples
    --------
    >>> import numpy as np
    >>> g = np.stack(np.meshgrid(np.arange(5.0), np.arange(5.0)), -1).reshape(-1, 2)
    >>> v = np.column_stack([g, np.zeros(25)])
    >>> f = np.array([[r*5+c, r*5+c+1, r*5+c+6] for r in range(4) for c in range(4)]
    ...              + [[r*5+c, r*5+c+6, r*5+c+5] for r in range(4) for c in range(4)])
    >>> v[12, 2] = 3.0                                   # a spike in the middle
    >>> res = fair_vertices(v, f, np.array([12]), continuity=0)
    >>> res.ok, bool(abs(res.vertices[12, 2]) < 1e-12)
    (True, True)
    """
    v, f, free = _checked(vertices, faces, free, continuity, passes)
    if len(free) == 0:
        return FairResult(v.copy(), True)
    from .._core import fair as core

    status, _, x = core.solve(v, f, free, continuity, int(passes))
    if status:
        return FairResult(v.copy(), False, _FAILED[status])
    out = v.copy()
    out[free] = x
    return FairResult(out, True)


def reference_fair_vertices(
    vertices: NDArray[np.float64],
    faces: NDArray[np.int64],
    free: NDArray[np.int64],
    continuity: int = 1,
    *,
    passes: int = 1,
) -> FairResult:
    """:func:`fair_vertices` in numpy and scipy: the reference the compiled core must equal.

    The same selection, operator and system (:func:`laplacian`, sparse products),
    factored by SuperLU; the positions agree with :func:`fair_vertices` to rounding
    (the sums run in other orders), a failure is reported alike.

    Examples
    --------
    >>> import numpy as np
    >>> v = np.array([[1.0, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0], [0.1, 0.2, 1]])
    >>> f = np.array([[4, 0, 1], [4, 1, 2], [4, 2, 3], [4, 3, 0]])  # a fan around 4
    >>> a = reference_fair_vertices(v, f, [4], 0).vertices[4]       # pulled into the plane
    >>> b = fair_vertices(v, f, [4], 0).vertices[4]
    >>> abs(float(a[2])), bool(np.abs(a - b).max() < 1e-15)
    (0.0, True)
    """
    v, f, free = _checked(vertices, faces, free, continuity, passes)
    res = FairResult(v.copy(), True)
    if len(free) == 0:
        return res
    for _ in range(int(passes)):
        res = _solve(res.vertices, f, free, continuity)
        if not res.ok:
            return FairResult(v.copy(), False, res.reason)
    return res


def _checked(
    vertices: Any, faces: Any, free: Any, continuity: int, passes: int
) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.int64]]:
    """The arguments of a fairing as contiguous arrays; InvalidPolygonError when bad."""
    if continuity not in CONTINUITY:
        raise InvalidPolygonError(f"continuity must be 0, 1 or 2, got {continuity!r}")
    if not (isinstance(passes, (int, np.integer)) and passes >= 1):
        raise InvalidPolygonError(f"passes must be a positive integer, got {passes!r}")
    v = np.ascontiguousarray(vertices, dtype=np.float64)
    f = np.ascontiguousarray(faces, dtype=np.int64)
    if v.ndim != 2 or v.shape[1] != 3 or f.ndim != 2 or f.shape[1] != 3:
        raise InvalidPolygonError("vertices and faces must be (n, 3) and (m, 3) arrays")
    free = np.unique(np.asarray(free, dtype=np.int64))
    if len(free) and (free[0] < 0 or free[-1] >= len(v)):
        raise InvalidPolygonError("a vertex to fair does not exist")
    if f.size and (f.min() < 0 or f.max() >= len(v)):
        raise InvalidPolygonError("a face names a vertex that does not exist")
    return v, f, free


def _solve(
    v: NDArray[np.float64], f: NDArray[np.int64], free: NDArray[np.int64], continuity: int
) -> FairResult:
    """One solve of :func:`reference_fair_vertices`, ``L`` taken at ``v``."""
    linalg = import_optional("scipy.sparse.linalg", "mesh")
    # only faces within continuity + 1 rings of the free vertices enter the operator
    near = np.zeros(len(v), dtype=bool)
    near[free] = True
    for _ in range(continuity + 2):
        touch = near[f].any(axis=1)
        near[f[touch].ravel()] = True
    local = f[near[f].any(axis=1)]
    C, A = laplacian(v, local)
    if not np.all(A[free] > 0):
        return FairResult(v.copy(), False, _NO_AREA)
    inv_area = np.zeros(len(v))
    used = A > 0
    inv_area[used] = 1.0 / A[used]
    op = C
    for _ in range(continuity):
        op = C @ op.multiply(inv_area[:, None]).tocsr()
    op = op.tocsr()
    fixed = np.setdiff1d(np.flatnonzero(near), free)
    rows = op[free]
    lhs = rows[:, free].tocsc()
    rhs = -(rows[:, fixed] @ v[fixed])
    try:
        x = _factor_solve(linalg, lhs, rhs)
    except (RuntimeError, ValueError) as exc:  # singular: keep the input
        return FairResult(v.copy(), False, f"the fairing system could not be solved ({exc})")
    if not np.all(np.isfinite(x)):
        return FairResult(v.copy(), False, _NOT_FINITE)
    out = v.copy()
    out[free] = x
    return FairResult(out, True)


def _factor_solve(linalg: Any, lhs: Any, rhs: NDArray[np.float64]) -> NDArray[np.float64]:
    """``lhs^-1 rhs``; ``lhs`` is symmetric positive definite up to rounding.

    ``(C A^-1)^k C`` restricted to the free vertices, ``C`` the stiffness matrix: a
    symmetric fill-reducing order taking the diagonal as pivots (SuperLU still pivots
    where a diagonal entry is zero) factors it several times faster than COLAMD with
    partial pivoting.
    """
    lu = linalg.splu(
        lhs, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True}
    )
    return lu.solve(rhs)  # type: ignore[no-any-return]


def fair_region(mesh: Any, vertices: Any, continuity: int = 1, *, passes: int = 1) -> Any:
    """Fair any set of vertices of a mesh: the rest of the mesh stays where it is.

    Parameters
    ----------
    mesh : trimesh.Trimesh or (vertices, faces)
    vertices : array of int
        The vertices to move (for example the new vertices of a filled hole).
    continuity : {0, 1, 2}
        0: membrane (``L x = 0``), 1: thin plate (``L^2 x = 0``, the default),
        2: minimal curvature variation (``L^3 x = 0``); cotangent weights, Voronoi areas.
    passes : int
        Solves, each with ``L`` taken where the one before left the vertices
        (``fill_holes`` fairs its patches with ``PATCH_PASSES`` = 2).

    Returns
    -------
    trimesh.Trimesh or (vertices, faces)
        A new mesh of the input's kind, faces unchanged.

    Raises
    ------
    InvalidPolygonError
        A bad mesh or vertex index, or a system that cannot be solved (a vertex with no
        area around it, a singular system): nothing is moved then.

    References
    ----------
    .. [1] P. Liepa, "Filling holes in meshes", Symposium on Geometry Processing 2003,
       doi:10.2312/SGP/SGP03/200-206.
    .. [2] M. Meyer, M. Desbrun, P. Schroder, A. H. Barr, "Discrete differential-geometry
       operators for triangulated 2-manifolds", Visualization and Mathematics III (2003),
       doi:10.1007/978-3-662-05105-4_2.

    Examples
    --------
    >>> import numpy as np
    >>> g = np.stack(np.meshgrid(np.arange(6.0), np.arange(6.0)), -1).reshape(-1, 2)
    >>> v = np.column_stack([g, np.zeros(36)])
    >>> f = np.array([[r*6+c, r*6+c+1, r*6+c+7] for r in range(5) for c in range(5)]
    ...              + [[r*6+c, r*6+c+7, r*6+c+6] for r in range(5) for c in range(5)])
    >>> v[[14, 15, 20, 21], 2] = 1.0                      # a bump of four vertices
    >>> v2, f2 = fair_region((v, f), [14, 15, 20, 21], continuity=1)
    >>> float(abs(v2[:, 2]).max()) < 1e-9
    True
    """
    v, f, is_trimesh = mesh_arrays(mesh)
    res = fair_vertices(
        v, f, np.asarray(vertices, dtype=np.int64).ravel(), continuity, passes=passes
    )
    if not res.ok:
        raise InvalidPolygonError(f"fairing failed: {res.reason}")
    return same_kind(res.vertices, f, is_trimesh)
