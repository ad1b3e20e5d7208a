"""The per-polygon path: :func:`optri.triangulate` on each vertex array, errors as results.

Holds what every chunk solver shares: :class:`SolveOptions`, the
:data:`Result` type, :class:`HoledRings` and :func:`solve_each`, the reference every faster solver
(:mod:`optri.batch.compiled`) is held to and falls back on.
"""

from __future__ import annotations

import threading
import time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import OptriError
from ..result import Triangulation
from ..solve import triangulate

__all__ = [
    "ChunkSolver",
    "HoledRings",
    "Polygonal",
    "Result",
    "SolveOptions",
    "one_line",
    "solve_each",
]

Result = Triangulation | OptriError


def one_line(message: str) -> str:
    r"""Collapse whitespace so a reason is always a single line.

    >>> one_line("vertex 3\n  is bad")
    'vertex 3 is bad'
    """
    return " ".join(str(message).split()) or "unknown error"


@dataclass(frozen=True)
class SolveOptions:
    """What every polygon of a chunk is solved with (picklable when the weight is).

    ``project`` is the layer's CRS (any text pyproj reads) when polygons are to
    be measured in metres in a local azimuthal equidistant projection, else None.
    ``threads`` bounds the threads of the compiled many-polygon path (None: all
    the core's, :mod:`optri.engines.threads`; batch workers use 1, their
    parallelism being the pool's).
    """

    weight: Any = "perimeter"
    objective: Any = "sum"
    method: str = "auto"
    project: str | None = None
    threads: int | None = None


ChunkSolver = Callable[[Sequence["Polygonal"], SolveOptions], list[Result]]


@dataclass(frozen=True, eq=False)
class HoledRings:
    """A polygon with holes in a batch: its vertices, exterior ring first, and the ring sizes.

    Vertices are numbered as :func:`optri.triangulate` numbers them (exterior,
    then each hole in order, closing vertices dropped), so triangles index
    :attr:`vertices` directly. Behaves as that array for the writers.

    >>> from optri.batch.solver import polygon_rings
    >>> h = polygon_rings([[[0, 0], [3, 0], [3, 3], [0, 3]], [[1, 1], [1, 2], [2, 2], [2, 1]]])
    >>> h.sizes, h.shape
    ((4, 4), (8, 2))
    """

    vertices: NDArray[np.float64]
    sizes: tuple[int, ...]

    @property
    def shape(self) -> tuple[int, ...]:
        """The shape of :attr:`vertices`."""
        return self.vertices.shape

    def __len__(self) -> int:
        return len(self.vertices)

    def __iter__(self) -> Any:
        return iter(self.vertices)

    def __array__(self, dtype: Any = None, copy: Any = None) -> NDArray[Any]:
        return np.asarray(self.vertices, dtype=dtype)

    def tolist(self) -> list:
        """:attr:`vertices` as nested lists."""
        return self.vertices.tolist()

    def with_vertices(self, vertices: NDArray[np.float64]) -> HoledRings:
        """The same rings at other coordinates (a projection of :attr:`vertices`)."""
        return HoledRings(vertices, self.sizes)

    def pair(self) -> tuple[NDArray[np.float64], list[NDArray[np.float64]]]:
        """``(exterior, [holes])``, the form :func:`optri.triangulate` takes."""
        rings = np.split(self.vertices, np.cumsum(self.sizes)[:-1])
        return rings[0], rings[1:]


Polygonal = NDArray[np.float64] | HoledRings

#: ``warnings.catch_warnings`` saves and restores the process's warning filters, so two
#: threads inside it at once can leave the filters of one of them behind (``"always"``
#: or ``"ignore"`` for every warning) and record each other's warnings. Batch workers may
#: be threads (``config.BATCH_THREADS``): every call of theirs that enters it (the
#: per-polygon path, which records a polygon's warnings; ``shapely.is_valid``) holds this
#: lock, one at a time across threads. The compiled kernel, which solves most polygons,
#: never takes it.
WARNINGS_LOCK = threading.RLock()


def solve_each(arrays: Sequence[Polygonal], options: SolveOptions) -> list[Result]:
    """The per-polygon path: :func:`optri.triangulate` on each array, errors as results.

    Any exception a polygon raises (a user weight's included) becomes its
    result, wrapped in an :class:`OptriError` naming the original type.
    ``stats["wall_seconds"]`` is the polygon's whole time, ``stats["warnings"]``
    the warnings it raised.
    """
    out: list[Result] = []
    for arr in arrays:
        start = time.perf_counter()
        with WARNINGS_LOCK, warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                source = arr.pair() if isinstance(arr, HoledRings) else arr
                tri = triangulate(
                    source,
                    weight=options.weight,
                    objective=options.objective,
                    method=options.method,
                )
            except OptriError as exc:
                out.append(exc)
                continue
            except Exception as exc:  # a user weight, or numpy on odd input: this row only
                wrapped = OptriError(f"{type(exc).__name__}: {exc}")
                wrapped.__cause__ = exc
                out.append(wrapped)
                continue
        tri.stats["wall_seconds"] = time.perf_counter() - start  # type: ignore[assignment]
        notes = list(dict.fromkeys(str(w.message) for w in caught))
        if notes:
            tri.stats["warnings"] = notes  # type: ignore[assignment]
        out.append(tri)
    return out
