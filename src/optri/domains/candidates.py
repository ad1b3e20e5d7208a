"""What a triangulation of a domain may use: valid diagonals and candidate triangles.

A *valid diagonal* joins two vertices through the domain's interior: it starts
into the domain at both ends (in-cone test at each end, against the two
boundary edges there), crosses no boundary edge and passes through no vertex.
A *candidate triangle* has three sides that are boundary edges (run in the
boundary's direction, so the triangle lies on the domain's side) or valid
diagonals, positive area, and no hole inside it. Every triangulation of the
domain is a set of candidate triangles, and every candidate triangle lies in
some triangulation.

Both sets are computed by the compiled core (``optri._core.domains``) with the
exact orientation predicate, so they are the sets exact arithmetic defines.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .domain import Domain

__all__ = [
    "Candidates",
    "diagonals_and_turns",
    "find_candidates",
    "side_signs",
    "valid_diagonals",
]


@dataclass(frozen=True)
class Candidates:
    """The candidate triangles of a domain and the edges they are made of.

    Attributes
    ----------
    edges : ndarray of int64, shape (E, 2)
        Sorted vertex pairs ``(a, b)``, ``a < b``: the N boundary edges first
        (edge ``v`` joins ``v`` and ``nxt[v]``), then the valid diagonals in
        increasing order of ``(a, b)``.
    n_boundary : int
        Number of boundary edges (the domain's vertex count).
    triangles : ndarray of int64, shape (T, 3)
        Candidate triangles, counter-clockwise, the smallest vertex first, in
        increasing order of ``(t0, t1, t2)``.
    sides : ndarray of int64, shape (T, 3)
        Edge ids of sides ``(t0, t1)``, ``(t1, t2)``, ``(t2, t0)``.
    signs : ndarray of int8, shape (T, 3)
        +1 where the side runs from its smaller vertex to its larger one, else -1:
        which side of the edge the triangle lies on.
    turns : ndarray of int8, shape (E - N, N)
        ``orient(a, b, v)`` of every vertex ``v`` against each diagonal ``(a, b)``
        (row ``e - N`` for edge ``e``): crossing tests become look-ups.
    """

    edges: NDArray[np.int64]
    n_boundary: int
    triangles: NDArray[np.int64]
    sides: NDArray[np.int64]
    signs: NDArray[np.int8]
    turns: NDArray[np.int8]

    @property
    def is_diagonal(self) -> NDArray[np.bool_]:
        """Per edge: True for a diagonal, False for a boundary edge."""
        return np.arange(len(self.edges)) >= self.n_boundary


def valid_diagonals(domain: Domain) -> NDArray[np.int64]:
    """The valid diagonals of ``domain`` as sorted pairs ``(a, b)``, ``a < b``; (D, 2).

    See :func:`diagonals_and_turns`.

    Examples
    --------
    >>> from optri.domains import as_domain
    >>> d = as_domain([[0, 0], [3, 0], [3, 3], [0, 3]], [[[1, 1], [2, 1], [2, 2], [1, 2]]])
    >>> valid_diagonals(d).tolist()   # each corner sees three hole corners
    [[0, 4], [0, 5], [0, 7], [1, 4], [1, 5], [1, 6], [2, 5], [2, 6], [2, 7], [3, 4], [3, 6], [3, 7]]
    """
    return diagonals_and_turns(domain)[0]


def diagonals_and_turns(domain: Domain) -> tuple[NDArray[np.int64], NDArray[np.int8]]:
    """The valid diagonals of ``domain``, and every vertex's side of each; (D, 2), (D, N).

    Notes
    -----
    Each vertex pair passes the in-cone tests at both ends (look-ups in the
    table of every vertex's side of every boundary edge), then the boundary
    edges near its ends, then every edge whose line separates its ends; only
    a diagonal gets its row of N turns. O(N^3) look-ups at worst, O(D N)
    orientation tests, threads over the first vertex.
    """
    from .._core import domains as core

    return core.diagonals(*_arrays(domain))  # type: ignore[no-any-return]


def side_signs(points: NDArray[np.float64], seg: NDArray[np.int64]) -> NDArray[np.int8]:
    """``orient(a, b, v)`` of every point ``v`` against each segment ``(a, b)`` of ``seg``.

    Returns an ``(S, P)`` int8 array.

    >>> side_signs(np.array([[0., 0.], [1., 0.], [0., 1.]]), np.array([[0, 1]])).tolist()
    [[0, 0, 1]]
    """
    from .._core import domains as core

    pts = np.ascontiguousarray(points, dtype=np.float64)
    pairs = np.ascontiguousarray(np.asarray(seg, dtype=np.int64).reshape(-1, 2))
    return core.side_signs(pts, pairs)  # type: ignore[no-any-return]


def find_candidates(domain: Domain) -> Candidates:
    """Every candidate triangle of ``domain`` with its sides' edge ids.

    A hole inside a triangle whose sides cross nothing lies wholly inside it
    but for corners, so four vertices of each hole (not all corners) decide
    whether a triangle is empty.

    Examples
    --------
    >>> from optri.domains import as_domain
    >>> d = as_domain([[0, 0], [3, 0], [3, 3], [0, 3]], [[[1, 1], [2, 1], [2, 2], [1, 2]]])
    >>> c = find_candidates(d)
    >>> len(c.edges), len(c.triangles)      # 8 boundary edges + 12 diagonals
    (20, 16)
    """
    from .._core import domains as core

    reps = [s + np.arange(min(4, m)) for s, m in zip(domain.starts[1:], domain.sizes[1:])]
    holes = np.concatenate(reps).astype(np.int64) if reps else np.zeros(0, dtype=np.int64)
    diagonals, turns, tris, sides, signs = core.candidates(*_arrays(domain), holes)
    k = np.arange(domain.n)
    boundary = np.sort(np.column_stack((k, domain.nxt)), axis=1)
    edges = np.concatenate((boundary, diagonals)).astype(np.int64)
    return Candidates(edges, domain.n, tris, sides, signs, turns)


def _arrays(domain: Domain) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """The domain as the core reads it: C-contiguous coordinates and successors."""
    pts = np.ascontiguousarray(domain.vertices, dtype=np.float64)
    return pts, np.ascontiguousarray(domain.nxt, dtype=np.int64)
