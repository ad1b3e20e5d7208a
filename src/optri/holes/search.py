"""Drivers of the compiled hole-filling searches: memory first, then kernels in chunks.

Each driver checks the memory its arrays need *before* allocating them
(:class:`~optri.errors.TableTooLargeError` otherwise), allocates them, and runs
its kernel over chunks of rows or chord lengths of about
``config.HOLES_CHUNK_WORK`` steps each, so Ctrl-C ends the search within a
fraction of a second as a plain ``KeyboardInterrupt``. The drivers return the
patch's triangles ``(i, k, j)``, ``i < k < j``, or None when the allowed
chords (or candidate triangles) admit no patch.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .. import config
from ..engines.interrupts import interruptible
from ..engines.memory import require_memory
from ..engines.recurrence import triangles_from_splits
from ..errors import OptriError

__all__ = [
    "dense_bytes",
    "interruptible",
    "kernels_cached",
    "exact_bytes",
    "exact_search",
    "liepa_dense",
    "liepa_sparse",
    "require_exact_memory",
]

Tris = NDArray[np.int64]


def kernels_cached() -> bool:
    """True when the searches' compiled kernels are in numba's disk cache (no compile).

    Imports numba (via :mod:`optri.engines.compiled`); the CLI asks before a
    first fill, to say that compiling takes a while.
    """
    from ..engines.compiled import cache_dir

    root = Path(cache_dir())
    wanted = ("_liepa.dense_rows-", "_exact.bottleneck_lengths-", "_exact.area_lengths-")
    return all(any(root.glob(f"holes*/{w}*.nbi")) for w in wanted)


def exact_bytes(n: int) -> int:
    """Peak bytes of :func:`exact_search`: one float64 per state, plus n x n tables.

    >>> round(exact_bytes(400) / 1e6)
    172
    """
    from ._exact import state_count  # light: no numba needed for the count

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


def _mesh_normals(K: Any, Q: NDArray[np.float64], n: int, has_third: bool) -> Any:
    return K.mesh_normals(Q, n) if has_third else np.zeros((1, 4))


def liepa_dense(
    Q: NDArray[np.float64], n: int, has_third: bool, allowed: NDArray[np.bool_]
) -> Tris | None:
    """Liepa's recurrence over every apex; O(n^3) time, about 45 n^2 bytes."""
    from . import _kernels as K
    from . import _liepa as L

    require_memory(
        dense_bytes(n),
        f"Liepa's recurrence on a {n}-vertex hole",
        "fill a smaller hole, or use method='delaunay'",
    )
    T = np.zeros((n, 5, n))
    splits = np.full((n, n), -1, dtype=np.int32)
    splits[np.arange(n - 1), np.arange(1, n)] = np.arange(n - 1)
    C = np.empty((2, n))
    rows = list(range(n - 3, -1, -1))  # row i costs about (n - i)^2 / 2 apexes
    with interruptible():
        MN = _mesh_normals(K, Q, n, has_third)
        for a, b in _chunks([(n - i) ** 2 / 2 for i in rows]):
            L.dense_rows(Q, n, has_third, MN, allowed, T, splits, C, rows[a], rows[b - 1])
    if splits[0, n - 1] < 0:
        return None
    return triangles_from_splits(lambda i, j: int(splits[i, j]), n)


def liepa_sparse(
    Q: NDArray[np.float64], n: int, has_third: bool, tris: NDArray[np.int64]
) -> Tris | None:
    """Liepa's recurrence over the candidate triangles ``tris`` (rows i < k < j)."""
    from . import _kernels as K
    from . import _liepa as L

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
    with interruptible():
        MN = _mesh_normals(K, Q, n, has_third)
        L.sparse_chords(Q, n, has_third, MN, keys, by_length, ptr, apex, value, TN, split)
        complete = L.sparse_trace(n, keys, split, out)
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
    pruned, which never changes the optimum. See :mod:`optri.holes._exact`.
    """
    from . import _exact as E
    from . import _kernels as K

    require_exact_memory(n)
    lengths = list(range(2, n))
    work = [(n - L) * (n - L) * (L - 1) + 1.0 for L in lengths]
    runs = [(lengths[a], lengths[b - 1] + 1) for a, b in _chunks(work)]
    with interruptible():
        MN = _mesh_normals(K, Q, n, has_third)
        leaf = E.leaf_table(Q, n, MN, has_third)
        off = E.state_offsets(n)
        states = np.empty(E.state_count(n))
        buf = np.empty((10, n))
        for L0, L1 in runs:
            E.bottleneck_lengths(
                Q, n, has_third, MN, leaf, allowed, off, states, bound, L0, L1, buf
            )
        M = float(states[off[0, n - 1]])
        if M == np.inf:
            return None
        E.mark_pending(states, M)  # pass 2 reuses the array
        for L0, L1 in runs:
            E.area_lengths(Q, n, has_third, MN, leaf, off, states, M, L0, L1, buf)
        out = np.empty((n - 2, 3), dtype=np.int64)
        if not E.trace(Q, n, has_third, MN, leaf, off, states, M, out):
            raise OptriError("internal error: the exact search's trace found no apex")
    return out
