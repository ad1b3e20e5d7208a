"""Reading and writing mesh files (OBJ, PLY, STL, OFF) through trimesh."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from .._optional import import_optional
from ..errors import InvalidPolygonError
from .atomic import atomic_write

__all__ = ["MESH_FORMATS", "mesh_format", "read_mesh", "write_mesh"]

#: Mesh formats read and written (trimesh's names).
MESH_FORMATS = ("obj", "ply", "stl", "off")


def mesh_format(path: str | os.PathLike[str], role: str = "mesh") -> str:
    """The format of a mesh file from its suffix.

    >>> mesh_format("bunny.PLY")
    'ply'

    Raises
    ------
    InvalidPolygonError
        An unsupported suffix; ``role`` ("input", "output") names the file's part.
    """
    ext = Path(path).suffix.lower().lstrip(".")
    if ext not in MESH_FORMATS:
        raise InvalidPolygonError(
            f"{role} {str(path)!r}: unsupported mesh format {ext or '(none)'!r}; use one of "
            f"{', '.join('.' + f for f in MESH_FORMATS)}"
        )
    return ext


def read_mesh(path: str | os.PathLike[str]) -> Any:
    """Load a triangle mesh file as a ``trimesh.Trimesh`` (extra ``optri[mesh]``).

    Raises
    ------
    InvalidPolygonError
        Unsupported suffix, missing file, unreadable content or no triangles.
    """
    fmt = mesh_format(path, "input")
    trimesh = import_optional("trimesh")
    if not Path(path).is_file():
        raise InvalidPolygonError(f"cannot read {path}: no such file")
    try:
        mesh = trimesh.load(path, file_type=fmt, force="mesh")
    except Exception as exc:  # noqa: BLE001  (parsers raise anything on bad bytes)
        raise InvalidPolygonError(f"cannot read mesh {path}: {exc}") from exc
    if not hasattr(mesh, "faces") or len(mesh.faces) == 0:
        raise InvalidPolygonError(f"{path}: no triangle faces found")
    return mesh


def write_mesh(mesh: Any, path: str | os.PathLike[str]) -> None:
    """Write a ``trimesh.Trimesh`` to ``path`` atomically, in the format of its suffix."""
    data = mesh.export(file_type=mesh_format(path, "output"))
    with atomic_write(path, "wb") as fh:
        fh.write(data.encode() if isinstance(data, str) else data)
