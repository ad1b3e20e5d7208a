"""Meshes as the hole-filling functions take and return them: trimesh or (vertices, faces)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._optional import import_optional
from ..errors import InvalidPolygonError

__all__ = ["mesh_arrays", "same_kind"]

Ints = NDArray[np.int64]


def mesh_arrays(mesh: Any) -> tuple[NDArray[np.float64], Ints, bool]:
    """``(vertices, faces, is_trimesh)`` of a mesh, checked.

    Bad input raises :class:`~optri.errors.InvalidPolygonError`.
    """
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


def same_kind(vertices: NDArray[np.float64], faces: Ints, is_trimesh: bool) -> Any:
    """``(vertices, faces)`` as a ``trimesh.Trimesh`` when the input was one, else the pair."""
    if is_trimesh:
        trimesh = import_optional("trimesh")
        return trimesh.Trimesh(vertices=vertices, faces=faces, process=False)
    return vertices, faces
