"""Candidate triangles for hole filling: faces of the 3-D Delaunay tetrahedralization.

Zou et al. (2013) restrict the hole-filling search to triangles that are faces
of the Delaunay tetrahedralization of the hole's vertices: O(n) candidates in
practice instead of O(n^3). Planar (or nearly planar) holes have no proper
tetrahedralization; their candidates are the 2-D Delaunay triangles in the
best-fit plane.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from .._optional import import_optional

__all__ = ["candidate_lists", "delaunay_faces"]


def delaunay_faces(points: NDArray[np.float64]) -> NDArray[np.int64]:
    """Unique sorted vertex triples that are Delaunay faces of ``points`` (n, 3).

    Rows ``(a, b, c)``, ``a < b < c``, ordered by ``(a, c)`` and then ``b``.

    Examples
    --------
    >>> tet = np.array([[0., 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    >>> delaunay_faces(tet).tolist()
    [[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]]
    """
    spatial = import_optional("scipy.spatial")
    try:
        simplices = spatial.Delaunay(points).simplices
        combos = ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3))
    except (spatial.QhullError, ValueError):
        # flat input: triangulate in the best-fit plane instead
        centred = points - points.mean(axis=0)
        basis = np.linalg.svd(centred, full_matrices=False)[2][:2]
        try:
            simplices = spatial.Delaunay(centred @ basis.T).simplices
        except (spatial.QhullError, ValueError):
            return np.zeros((0, 3), dtype=np.int64)
        combos = ((0, 1, 2),)  # type: ignore[assignment]  # a planar hole: triangles only
    faces = np.sort(np.concatenate([simplices[:, list(c)] for c in combos]), axis=1)
    n = len(points)
    # one int64 key per triple, ordered (first, last, middle): chord then apex
    keys = np.unique((faces[:, 0].astype(np.int64) * n + faces[:, 2]) * n + faces[:, 1])
    chord, mid = np.divmod(keys, n)
    first, last = np.divmod(chord, n)
    return np.column_stack((first, mid, last)).astype(np.int64)


def candidate_lists(
    points: NDArray[np.float64],
) -> tuple[NDArray[np.int64], NDArray[np.int64], int]:
    """CSR lists of candidate apexes per chord: ``ks[ptr[i*n+j]:ptr[i*n+j+1]]``.

    Returns ``(ptr, ks, number_of_faces)``; apexes of a chord are increasing.
    """
    n = len(points)
    faces = delaunay_faces(points)  # ordered by chord (first, last), then apex
    keys = faces[:, 0] * n + faces[:, 2]
    ks = np.ascontiguousarray(faces[:, 1])
    counts = np.bincount(keys, minlength=n * n)
    ptr = np.zeros(n * n + 1, dtype=np.int64)
    np.cumsum(counts, out=ptr[1:])
    return ptr, ks, int(len(faces))
