"""Drivers of the compiled hole-filling searches: memory first, then kernels in chunks.

The kernels are C++ in optri's compiled core (``optri._core.holes``, built with the
package). Each driver checks the memory its arrays need *before* allocating them
(:class:`~optri.errors.TableTooLargeError` otherwise), allocates them, and runs
its kernel over chunks of rows or chord lengths of about
``config.HOLES_CHUNK_WORK`` steps each: a kernel runs without the GIL, and a
Ctrl-C during one surfaces as a plain ``KeyboardInterrupt`` when it returns, so
the search ends within a fraction of a second. The drivers return the patch's
triangles ``(i, k, j)``, ``i < k < j``, or None when the allowed chords (or
candidate triangles) admit no patch.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from .. import config
from ..engines.memory import require_memory
from ..engines.recurrence import triangles_from_splits
from ..errors import OptriError

__all__ = [
    "dense_bytes",
    "exact_bytes",
    "exact_search",
    "fewest_degenerate",
    "fewest_then_weight",
    "liepa_dense",
    "liepa_sparse",
    "mesh_normals",
    "require_exact_memory",
    "state_count",
]

Tris = NDArray[np.int64]


def _kernels() -> Any:
    from .._core import holes

    return holes


def state_count(n: int) -> int:
    """Slots of the exact search's compact state array: (n-1)(n-2)(n-3)/3 + 1 (the root's).

    >>> state_count(5)
    9
    """
    return (n - 1) * (n - 2) * (n - 3) // 3 + 1


def exact_bytes(n: int) -> int:
    """Peak bytes of :func:`exact_search`: one float64 per state, plus n x n tables.

    >>> round(exact_bytes(400) / 1e6)
    172
    """
    return 8 * state_count(n) + 8 * 3 * n * n


def dense_bytes(n: int) -> int:
    """Peak bytes of :func:`liepa_dense`: (key, area, normal) per chord, splits, mask."""
    return (5 * 8 + 4 + 1) * n * n


def _chunks(work: list[float]) -> list[tuple[int, int]]:
    """Consecutive index runs of about ``config.HOLES_CHUNK_WORK`` work each."""
    out, start, acc = [], 0, 0.0
    for i, w in enumerate(work):
        acc += w
        if acc >= config.HOLES_CHUNK_WORK:
            out.append((start, i + 1))
            start, acc = i + 1, 0.0
    if start < len(work):
        out.append((start, len(work)))
    return out


def mesh_normals(Q: NDArray[np.float64], n: int, has_third: bool) -> NDArray[np.float64]:
    """(n, 4) rows (x, y, z, degenerate) of the mesh triangles on the sides (a zero row without)."""
    if not has_third:
        return np.zeros((1, 4))
    return _kernels().mesh_normals(Q, n)  # type: ignore[no-any-return]


def liepa_dense(
    Q: NDArray[np.float64], n: int, has_third: bool, allowed: NDArray[np.bool_]
) -> Tris | None:
    """Liepa's recurrence over every apex; O(n^3) time, about 45 n^2 bytes."""
    K = _kernels()
    require_memory(
        dense_bytes(n),
        f"Liepa's recurrence on a {n}-vertex hole",
        "fill a smaller hole, or use method='delaunay'",
    )
    T = np.zeros((n, 5, n))
    splits = np.full((n, n), -1, dtype=np.int32)
    splits[np.arange(n - 1), np.arange(1, n)] = np.arange(n - 1)
    rows = list(range(n - 3, -1, -1))  # row i costs about (n - i)^2 / 2 apexes
    MN = mesh_normals(Q, n, has_third)
    for a, b in _chunks([(n - i) ** 2 / 2 for i in rows]):
        K.dense_rows(Q, n, has_third, MN, allowed, T, splits, rows[a], rows[b - 1])
    if splits[0, n - 1] < 0:
        return None
    return triangles_from_splits(lambda i, j: int(splits[i, j]), n)


def liepa_sparse(
    Q: NDArray[np.float64], n: int, has_third: bool, tris: NDArray[np.int64]
) -> Tris | None:
    """Liepa's recurrence over the candidate triangles ``tris`` (rows i < k < j)."""
    K = _kernels()
    keys_all = tris[:, 0] * n + tris[:, 2]
    order = np.lexsort((tris[:, 1], keys_all))
    keys_all, apex = keys_all[order], np.ascontiguousarray(tris[order, 1])
    keys, first = np.unique(keys_all, return_index=True)
    ptr = np.append(first, len(apex)).astype(np.int64)
    by_length = np.argsort((keys % n) - (keys // n), kind="stable")
    C = len(keys)
    value, TN = np.empty((C, 2)), np.empty((C, 4))
    split = np.full(C, -1, dtype=np.int64)
    out = np.empty((max(n - 2, 0), 3), dtype=np.int64)
    MN = mesh_normals(Q, n, has_third)
    K.sparse_chords(Q, n, has_third, MN, keys, by_length, ptr, apex, value, TN, split)
    complete = K.sparse_trace(n, keys, split, out)
    return out if complete else None


def require_exact_memory(n: int) -> None:
    """Raise :class:`~optri.errors.TableTooLargeError` if :func:`exact_search` cannot fit."""
    require_memory(
        exact_bytes(n),
        f"the exact Liepa search of a {n}-vertex hole (about n^3/3 states)",
        "use method='liepa' (Liepa's O(n^3) recurrence) or 'auto'",
    )


def exact_search(
    Q: NDArray[np.float64],
    n: int,
    has_third: bool,
    allowed: NDArray[np.bool_],
    bound: float = np.inf,
) -> Tris | None:
    """The exact (max key, area) optimum over all patches using ``allowed`` chords.

    ``bound``: the max key of a known patch (Liepa's); states worse than it are
    pruned, which never changes the optimum. The search and its state layout are
    described in ``src/core/holes_exact.cpp``.
    """
    K = _kernels()
    require_exact_memory(n)
    lengths = list(range(2, n))
    work = [(n - L) * (n - L) * (L - 1) + 1.0 for L in lengths]
    runs = [(lengths[a], lengths[b - 1] + 1) for a, b in _chunks(work)]
    MN = mesh_normals(Q, n, has_third)
    leaf = K.leaf_table(Q, n, MN, has_third)
    off = K.state_offsets(n)
    states = np.empty(state_count(n))
    for L0, L1 in runs:
        K.bottleneck_lengths(Q, n, has_third, MN, leaf, allowed, off, states, bound, L0, L1)
    M = float(states[off[0, n - 1]])
    if M == np.inf:
        return None
    K.mark_pending(states, M)  # pass 2 reuses the array
    for L0, L1 in runs:
        K.area_lengths(Q, n, has_third, MN, leaf, off, states, M, L0, L1)
    out = np.empty((n - 2, 3), dtype=np.int64)
    if not K.trace(Q, n, has_third, MN, leaf, off, states, M, out):
        raise OptriError("internal error: the exact search's trace found no apex")
    return out


def fewest_degenerate(
    P: NDArray[np.float64], Q: NDArray[np.float64], n: int, allowed: NDArray[np.bool_]
) -> tuple[int, Tris] | None:
    """``(count, triangles)``: the patch with the fewest degenerate triangles, then least area.

    Degenerate means exactly collinear (``P``, the points as given); areas are
    the searches' (``Q``). None when the allowed chords admit no patch. O(n^3)
    time, about 20 n^2 bytes; see ``src/core/holes_degenerate.cpp``.

    >>> P = np.array([[0., 0, 0], [1, 0, 0], [2, 0, 0], [1, 1, 0]])
    >>> count, tris = fewest_degenerate(P, P, 4, np.ones((4, 4), dtype=np.bool_))
    >>> count, tris.tolist()
    (0, [[0, 1, 3], [1, 2, 3]])
    """
    return _fewest(n, lambda K: _kernels().fewest_degenerate(P, Q, n, allowed, K))


def fewest_then_weight(
    P: NDArray[np.float64], n: int, code: int, is_max: bool, allowed: NDArray[np.bool_]
) -> tuple[int, Tris] | None:
    """As :func:`fewest_degenerate`, the sum (max) of built-in weight ``code`` second.

    >>> P = np.array([[0., 0, 0], [1, 0, 0], [2, 0, 0], [2, 1, 0]])   # area 2 = code 2
    >>> fewest_then_weight(P, 4, 2, False, np.ones((4, 4), dtype=np.bool_))[1].tolist()
    [[0, 1, 3], [1, 2, 3]]
    """
    return _fewest(n, lambda K: _kernels().fewest_then_weight(P, n, code, is_max, allowed, K))


def _fewest(n: int, run: Any) -> tuple[int, Tris] | None:
    """Memory first, then ``run(K)`` (the kernel: count or -1), then its patch."""
    require_memory(20 * n * n, f"the fewest-degenerate search of a {n}-vertex hole", "")
    K = np.full((n, n), -1, dtype=np.int32)
    count = int(run(K))
    if count < 0:
        return None
    return count, triangles_from_splits(lambda i, j: int(K[i, j]), n)
