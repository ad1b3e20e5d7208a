"""Fill the holes of a triangle mesh: ``fill_holes`` and ``boundary_loops``.

Each hole's boundary loop is filled by :func:`optri.fill_polyline`, with the
mesh triangles along the loop as Liepa's third points, and the new faces are
wound so that every boundary edge ``(a, b)`` of an existing face appears as
``(b, a)`` in its new neighbour. trimesh is imported only when a
``trimesh.Trimesh`` is passed in.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._optional import import_optional
from ..errors import HoleSkippedWarning, InvalidPolygonError, TableTooLargeError
from ..objective import Cost
from ..weights import get_weight
from .polyline import METHODS, fill_polyline

__all__ = ["HoleRecord", "boundary_loops", "fill_holes"]


@dataclass
class HoleRecord:
    """What happened to one hole.

    Attributes
    ----------
    index : int
        Hole number (loops ordered by their smallest vertex id).
    edges : int
        Boundary edges (= vertices) of the hole.
    status : {"filled", "skipped", "failed"}
    reason : str
        Why a hole was skipped or failed ("" when filled).
    weight : float, tuple or None
        Optimal objective value of the patch.
    method : str
        Search mode that filled it (``"exact"``, ``"liepa"``, ``"delaunay"``...).
    seconds : float
    faces_added : int
        ``edges - 2`` when filled, else 0.
    vertices : list of int
        The loop's mesh vertex ids in patch order.
    """

    index: int
    edges: int
    status: str
    reason: str = ""
    weight: Cost | None = None
    method: str = ""
    seconds: float = 0.0
    faces_added: int = 0
    vertices: list[int] | None = None

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready fields (a tuple weight becomes a list)."""
        out = asdict(self)
        if isinstance(self.weight, tuple):
            out["weight"] = list(self.weight)
        return out


def boundary_loops(faces: NDArray[np.int64]) -> list[tuple[NDArray[np.int64], NDArray[np.int64]]]:
    """Closed boundary loops of a triangle mesh, each as ``(loop, third)``.

    ``loop`` lists vertex ids in *patch* order: each consecutive pair
    ``(loop[i], loop[i+1])`` is a boundary edge that an existing face runs the
    other way. ``third[i]`` is that face's third vertex.

    Raises
    ------
    InvalidPolygonError
        A vertex with more than two boundary edges (non-manifold boundary) or
        boundary edges whose faces are inconsistently wound.

    Examples
    --------
    >>> loop, third = boundary_loops(np.array([[0, 1, 2], [0, 2, 3]]))[0]
    >>> loop.tolist(), third.tolist()
    ([0, 3, 2, 1], [2, 0, 0, 2])
    """
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    directed = np.concatenate([f[:, [0, 1, 2]], f[:, [1, 2, 0]], f[:, [2, 0, 1]]])
    key = np.sort(directed[:, :2], axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    bnd = directed[counts[inverse.ravel()] == 1]  # rows (a, b, c): face edge a->b
    nxt: dict[int, tuple[int, int]] = {}
    for a, b, c in bnd.tolist():
        if a in nxt:
            raise InvalidPolygonError(
                f"non-manifold boundary at vertex {a}: it has more than two boundary edges "
                f"(or its faces are inconsistently wound); fix the mesh before filling"
            )
        nxt[a] = (b, c)
    loops = []
    for start in sorted(nxt):
        if start not in nxt:
            continue
        verts, thirds, v = [], [], start
        while v in nxt:
            b, c = nxt.pop(v)
            verts.append(v)
            thirds.append(c)
            v = b
        if v != start:
            raise InvalidPolygonError(
                f"boundary at vertex {v} does not close into a loop (non-manifold or "
                f"inconsistently wound faces)"
            )
        # faces run a->b; the patch must run b->a: reverse, third of (b, a) stays c
        loop = np.array(verts[::-1], dtype=np.int64)
        third = np.roll(np.array(thirds[::-1], dtype=np.int64), -1)
        first = int(np.argmin(loop))  # start at the smallest id: deterministic output
        loops.append((np.roll(loop, -first), np.roll(third, -first)))
    return loops


def fill_holes(
    mesh: Any,
    max_hole_edges: int | None = None,
    weight: str | Callable[..., float] = "liepa",
    method: str = "auto",
    *,
    progress: Callable[[int, int], None] | None = None,
) -> tuple[Any, list[HoleRecord]]:
    """Fill every hole of a triangle mesh with an optimal patch.

    Parameters
    ----------
    mesh : trimesh.Trimesh or (vertices, faces)
        A triangle mesh; its faces should be consistently wound.
    max_hole_edges : int, optional
        Leave holes with more boundary edges open; each one is reported
        (``status="skipped"``) and warned about (:class:`HoleSkippedWarning`).
    weight, method
        As in :func:`optri.fill_polyline`; default ``method="auto"`` runs the
        exact search on holes up to ``config.HOLES_EXACT_MAX_N`` edges and
        Liepa's O(n^3) recurrence above (each record names the mode used).
    progress : callable, optional
        ``progress(done, total)`` after each hole.

    Returns
    -------
    (mesh, records)
        A new mesh of the input's kind (vertices unchanged, new faces
        appended) and one :class:`HoleRecord` per hole.

    Raises
    ------
    InvalidPolygonError
        Faces that are not triangles or index missing vertices, or a
        non-manifold boundary; nothing is filled then.

    Examples
    --------
    >>> import numpy as np
    >>> v = np.array([[0., 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    >>> f = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3]])    # a tetrahedron minus a face
    >>> (v2, f2), records = fill_holes((v, f))
    >>> f2[-1].tolist(), records[0].status, records[0].edges
    ([0, 3, 2], 'filled', 3)
    """
    if method not in METHODS:
        raise InvalidPolygonError(f"unknown method {method!r}; choose one of: {', '.join(METHODS)}")
    if not (isinstance(weight, str) and weight == "liepa"):
        get_weight(weight)  # an unknown weight fails here, not once per hole
    vertices, faces, is_trimesh = _mesh_arrays(mesh)
    loops = boundary_loops(faces)
    records: list[HoleRecord] = []
    new_faces = [faces]
    for h, (loop, third) in enumerate(loops):
        rec, patch = _fill_one(h, vertices, loop, third, max_hole_edges, weight, method)
        if patch is not None:
            new_faces.append(patch)
        records.append(rec)
        if progress is not None:
            progress(h + 1, len(loops))
    out_faces = np.concatenate(new_faces).astype(np.int64)
    if is_trimesh:
        trimesh = import_optional("trimesh")
        return trimesh.Trimesh(vertices=vertices.copy(), faces=out_faces, process=False), records
    return (vertices.copy(), out_faces), records


def _fill_one(
    h: int,
    vertices: NDArray[np.float64],
    loop: NDArray[np.int64],
    third: NDArray[np.int64],
    max_hole_edges: int | None,
    weight: Any,
    method: str,
) -> tuple[HoleRecord, NDArray[np.int64] | None]:
    n = len(loop)
    rec = HoleRecord(h, n, "filled", vertices=loop.tolist())
    if max_hole_edges is not None and n > max_hole_edges:
        rec.status = "skipped"
        rec.reason = f"{n} edges > max_hole_edges={max_hole_edges}"
        warnings.warn(f"hole {h} left open: {rec.reason}", HoleSkippedWarning, stacklevel=3)
        return rec, None
    start = time.perf_counter()
    try:
        tri = fill_polyline(vertices[loop], weight, method, vertices[third])
    except (InvalidPolygonError, TableTooLargeError) as exc:
        # this hole's geometry (e.g. collinear) or size: report it, fill the others
        rec.status, rec.reason = "failed", str(exc)
        warnings.warn(f"hole {h} left open: {exc}", HoleSkippedWarning, stacklevel=3)
        return rec, None
    rec.seconds = time.perf_counter() - start
    rec.weight, rec.method = tri.weight, tri.method
    rec.faces_added = len(tri.triangles)
    # fill_polyline winds (i, k, j), i < k < j, in the loop's (patch) order
    return rec, loop[tri.triangles]


def _mesh_arrays(mesh: Any) -> tuple[NDArray[np.float64], NDArray[np.int64], bool]:
    is_trimesh = hasattr(mesh, "vertices") and hasattr(mesh, "faces")
    if is_trimesh:
        vertices, faces = mesh.vertices, mesh.faces
    else:
        try:
            vertices, faces = mesh
        except (TypeError, ValueError) as exc:
            raise InvalidPolygonError(
                "expected a trimesh.Trimesh or a (vertices, faces) pair"
            ) from exc
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces)
    if v.ndim != 2 or v.shape[1] != 3:
        raise InvalidPolygonError(f"mesh vertices must be (n, 3), got shape {v.shape}")
    if f.ndim != 2 or f.shape[1] != 3 or not np.issubdtype(f.dtype, np.integer):
        raise InvalidPolygonError(f"mesh faces must be (m, 3) integer triangles, got {f.shape}")
    if len(f) == 0:
        raise InvalidPolygonError("the mesh has no faces")
    if f.min() < 0 or f.max() >= len(v):
        raise InvalidPolygonError("a face refers to a vertex that does not exist")
    if not np.isfinite(v).all():
        raise InvalidPolygonError("a mesh vertex has a non-finite coordinate")
    return v, f.astype(np.int64), is_trimesh
