"""Self-intersections between a patch and the faces around it.

Two triangles that share no vertex intersect when an edge of one crosses the other;
two that share one vertex intersect away from it when the edge of one opposite the
shared vertex crosses the other; two that share an edge are neighbours, never counted.
Each test is a segment against a triangle (Moller and Trumbore 1997), with a small
relative tolerance so that touching at a shared boundary is not a crossing. Only
faces whose bounding boxes overlap a patch face's are tested.

:func:`intersecting_pairs` runs in the compiled core; :func:`reference_intersecting_pairs`
is the same test in numpy, which the tests hold the core equal to.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["intersecting_pairs", "reference_intersecting_pairs"]

_EPS = 1e-9  # relative: a crossing closer than this to an end or a side is a touch
_BLOCK = 1 << 20  # candidate pairs per block
_WIDE = 8.0  # a face wider in x than this many median widths is paired directly


def intersecting_pairs(
    vertices: NDArray[np.float64], faces: NDArray[np.int64], patch: NDArray[np.int64]
) -> NDArray[np.int64]:
    """Pairs ``(p, f)``: patch face ``patch[p]`` crosses mesh face ``faces[f]``.

    ``faces`` may include the patch's own faces (pairs of a face with itself or a
    neighbour are skipped). Returns an ``(k, 2)`` int array sorted by ``p`` then ``f``,
    empty when none cross.

    >>> import numpy as np
    >>> v = np.array([[0., 0, 0], [2, 0, 0], [0, 2, 0],
    ...               [0.5, 0.5, -1], [0.5, 0.5, 1], [3, 3, 0]])
    >>> intersecting_pairs(v, np.array([[0, 1, 2]]), np.array([[3, 4, 5]])).tolist()
    [[0, 0]]
    """
    from .. import _core

    out: NDArray[np.int64] = _core.refine.intersecting_pairs(
        np.ascontiguousarray(vertices, dtype=np.float64).reshape(-1, 3),
        np.ascontiguousarray(faces, dtype=np.int64).reshape(-1, 3),
        np.ascontiguousarray(patch, dtype=np.int64).reshape(-1, 3),
    )
    return out


def reference_intersecting_pairs(
    vertices: NDArray[np.float64], faces: NDArray[np.int64], patch: NDArray[np.int64]
) -> NDArray[np.int64]:
    """Pairs ``(p, f)``: patch face ``patch[p]`` crosses mesh face ``faces[f]``.

    :func:`intersecting_pairs` in numpy: the reference the compiled core must equal.

    >>> import numpy as np
    >>> v = np.array([[0., 0, 0], [2, 0, 0], [0, 2, 0],
    ...               [0.5, 0.5, -1], [0.5, 0.5, 1], [3, 3, 0]])
    >>> reference_intersecting_pairs(v, np.array([[0, 1, 2]]), np.array([[3, 4, 5]])).tolist()
    [[0, 0]]
    """
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    p = np.asarray(patch, dtype=np.int64).reshape(-1, 3)
    if len(f) == 0 or len(p) == 0:
        return np.empty((0, 2), dtype=np.int64)
    flo, fhi = v[f].min(axis=1), v[f].max(axis=1)
    plo, phi = v[p].min(axis=1), v[p].max(axis=1)
    lo = np.minimum(flo.min(axis=0), plo.min(axis=0))
    span = float((np.maximum(fhi.max(axis=0), phi.max(axis=0)) - lo).max())
    pad = _EPS * max(span, 1e-300)
    # only faces whose box meets the whole patch's box can meet one of its faces' boxes:
    # one vectorized test, so the scan below runs over the patch's neighbourhood only
    near = np.flatnonzero(
        np.all((flo <= phi.max(axis=0) + pad) & (fhi >= plo.min(axis=0) - pad), axis=1)
    )
    f, flo, fhi = f[near], flo[near], fhi[near]
    if len(f) == 0:
        return np.empty((0, 2), dtype=np.int64)
    # candidate pairs: nearby faces sorted by their box's low x; a patch face's candidates
    # are the run whose low x lies in [its low x - the widest face, its high x]. Faces much
    # wider than the rest (slivers, long faces) would widen every run: they are paired
    # with the patch faces directly
    extent = fhi[:, 0] - flo[:, 0]
    wide = extent > _WIDE * max(float(np.median(extent)), pad)
    pairs = []
    for w in np.flatnonzero(wide).tolist():
        q = np.flatnonzero(np.all((flo[w] <= phi + pad) & (fhi[w] >= plo - pad), axis=1))
        if len(q):
            pairs.append(np.column_stack([q, np.full(len(q), w)]))
    narrow = np.flatnonzero(~wide)
    order = narrow[np.argsort(flo[narrow, 0], kind="stable")]
    lo_sorted = flo[order, 0]
    width = float(extent[narrow].max()) if len(narrow) else 0.0
    start = np.searchsorted(lo_sorted, plo[:, 0] - width - pad, side="left")
    stop = np.searchsorted(lo_sorted, phi[:, 0] + pad, side="right")
    count = np.maximum(stop - start, 0)
    bounds = np.searchsorted(np.cumsum(count), np.arange(0, int(count.sum()), _BLOCK), "right")
    for s0, s1 in zip(bounds.tolist(), (bounds[1:].tolist() + [len(p)])):
        n = count[s0:s1]
        q = np.repeat(np.arange(s0, s1), n)
        offset = np.arange(int(n.sum())) - np.repeat(np.cumsum(n) - n, n)
        c = order[np.repeat(start[s0:s1], n) + offset]
        ok = np.all((flo[c] <= phi[q] + pad) & (fhi[c] >= plo[q] - pad), axis=1)
        if ok.any():
            pairs.append(np.column_stack([q[ok], c[ok]]))
    if not pairs:
        return np.empty((0, 2), dtype=np.int64)
    pq = np.concatenate(pairs)
    A, B = p[pq[:, 0]], f[pq[:, 1]]
    shared = (A[:, :, None] == B[:, None, :]).sum(axis=(1, 2))
    keep = shared <= 1
    pq, A, B, shared = pq[keep], A[keep], B[keep], shared[keep]
    hit = np.zeros(len(pq), dtype=bool)
    for s_count in (0, 1):
        sel = np.flatnonzero(shared == s_count)
        if len(sel) == 0:
            continue
        a, b = A[sel], B[sel]
        for first, second in ((a, b), (b, a)):
            for e in range(3):
                s0, s1 = first[:, e], first[:, (e + 1) % 3]
                if s_count == 1:  # only the edge opposite the shared vertex
                    opposite = (
                        (s0[:, None] != second).all(axis=1) & (s1[:, None] != second).all(axis=1)
                    )
                else:
                    opposite = np.ones(len(sel), dtype=bool)
                crosses = _segment_hits_triangle(v[s0], v[s1], v[second])
                hit[sel] |= opposite & crosses
    out = pq[hit]
    out[:, 1] = near[out[:, 1]]  # back to the caller's face numbers
    return out[np.lexsort((out[:, 1], out[:, 0]))]


def _segment_hits_triangle(
    s0: NDArray[np.float64], s1: NDArray[np.float64], tri: NDArray[np.float64]
) -> NDArray[np.bool_]:
    """Row by row, whether the open segment ``s0 s1`` crosses the open triangle ``tri``."""
    d = s1 - s0
    e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    h = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, h)
    scale = np.linalg.norm(e1, axis=1) * np.linalg.norm(e2, axis=1) * np.linalg.norm(d, axis=1)
    good = np.abs(det) > 1e-12 * np.maximum(scale, 1e-300)  # not parallel
    inv = np.where(good, 1.0 / np.where(good, det, 1.0), 0.0)
    sv = s0 - tri[:, 0]
    u = inv * np.einsum("ij,ij->i", sv, h)
    q = np.cross(sv, e1)
    w = inv * np.einsum("ij,ij->i", d, q)
    t = inv * np.einsum("ij,ij->i", e2, q)
    eps = _EPS
    return good & (u > eps) & (w > eps) & (u + w < 1 - eps) & (t > eps) & (t < 1 - eps)
