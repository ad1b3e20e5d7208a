"""Reading and writing mesh files (OBJ, PLY, STL, OFF) through trimesh.

Loading never depends on the mesh's size: trimesh's own processing (which
merges vertices closer than an absolute 1e-8 and so collapses a mesh drawn
in nanometres, or splits one whose OBJ seams carry texture coordinates) is
off, and vertices are merged here by position only: exactly equal positions
by default, or positions closer than a fraction of the bounding-box diagonal
(``config.MESH_MERGE_RTOL``, ``merge_rtol``). Faces that merging leaves with
a repeated vertex are dropped. ``mesh.metadata["optri"]`` says what was done.
"""

from __future__ import annotations

import os
import re
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .. import config
from .._optional import import_optional
from ..errors import InvalidPolygonError
from ..meshdata import position_keys, rebuild, vertex_columns
from .atomic import atomic_write

__all__ = ["MESH_FORMATS", "mesh_format", "merge_vertices", "read_mesh", "write_mesh"]

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


def read_mesh(
    path: str | os.PathLike[str], merge_rtol: float | None = None, *, attributes: bool = True
) -> Any:
    """Load a triangle mesh file as a ``trimesh.Trimesh`` (extra ``optri[mesh]``).

    Parameters
    ----------
    path : path
        An ``.obj``, ``.ply``, ``.stl`` or ``.off`` file.
    merge_rtol : float, optional
        Merge vertices closer than this fraction of the bounding-box diagonal;
        default ``config.MESH_MERGE_RTOL`` (0: exactly equal positions only).
    attributes : bool
        Keep texture coordinates (with the OBJ material and its texture image),
        vertex normals, vertex and face colours and PLY's other vertex and face
        properties. Vertices are then merged only where their attributes are equal
        too: an OBJ seam (one position, two texture coordinates) stays split, and
        :func:`optri.fill_holes` welds it for finding holes (give it the same
        ``merge_rtol``). ``False`` merges by position alone and keeps no attribute.

    Raises
    ------
    InvalidPolygonError
        Unsupported suffix, missing file, unreadable content, non-finite
        coordinates or no triangles.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> lines = ["v 0 0 0", "v 1 0 0", "v 0 1 0", "vt 0 0", "vt 1 0", "vt 0 1", "f 1/1 2/2 3/3"]
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     path = pathlib.Path(tmp, "t.obj")
    ...     _ = path.write_text(chr(10).join(lines))
    ...     read_mesh(path).visual.uv.tolist()
    [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]
    """
    fmt = mesh_format(path, "input")
    trimesh = import_optional("trimesh")
    if not Path(path).is_file():
        raise InvalidPolygonError(f"cannot read {path}: no such file")
    try:
        loaded = trimesh.load(path, file_type=fmt, process=False)
        if not isinstance(loaded, trimesh.Trimesh):  # several objects: one mesh
            loaded = trimesh.load(path, file_type=fmt, force="mesh", process=False)
    except Exception as exc:  # noqa: BLE001  (parsers raise anything on bad bytes)
        raise InvalidPolygonError(f"cannot read mesh {path}: {exc}") from exc
    faces = np.asarray(getattr(loaded, "faces", np.zeros((0, 3))), dtype=np.int64)
    if faces.ndim != 2 or faces.shape[1] != 3 or len(faces) == 0:
        raise InvalidPolygonError(f"{path}: no triangle faces found")
    vertices = np.asarray(loaded.vertices, dtype=np.float64)
    if not np.isfinite(vertices).all():
        raise InvalidPolygonError(f"{path}: a vertex has a non-finite coordinate")
    rtol = config.MESH_MERGE_RTOL if merge_rtol is None else float(merge_rtol)
    extra = vertex_columns(loaded) if attributes else np.zeros((len(vertices), 0))
    kept, remap = _merge_groups(vertices, rtol, extra)
    f = remap[faces]
    keep = (f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 0] != f[:, 2])
    if not keep.any():
        raise InvalidPolygonError(f"{path}: every face has a repeated vertex (zero area)")
    if attributes:
        mesh = rebuild(loaded, vertices[kept], f[keep], lambda a: a[kept], np.flatnonzero(keep))
    else:
        mesh = trimesh.Trimesh(vertices=vertices[kept], faces=f[keep], process=False)
    mesh.metadata["optri"] = {
        "merged_vertices": int(len(vertices) - len(kept)),
        "dropped_faces": int((~keep).sum()),
    }
    return mesh


def merge_vertices(
    vertices: NDArray[np.float64], faces: NDArray[np.int64], rtol: float = 0.0
) -> tuple[NDArray[np.float64], NDArray[np.int64], int]:
    """Merge vertices by position; ``(vertices, faces, merged count)``.

    ``rtol == 0``: exactly equal positions (any scale); else positions that
    round to the same cell of side ``rtol`` times the bounding-box diagonal.
    Unreferenced vertices are kept; the first of each group gives the position,
    and the survivors keep their order.

    >>> v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1e-9, 0, 0], [1, 0, 0]]) * 1e-9
    >>> nv, nf, merged = merge_vertices(v, np.array([[0, 1, 2], [3, 4, 2]]))
    >>> len(nv), nf.tolist(), merged
    (4, [[0, 1, 2], [3, 1, 2]], 1)
    """
    if len(vertices) == 0:
        return vertices, faces, 0
    kept, remap = _merge_groups(vertices, rtol, np.zeros((len(vertices), 0)))
    return vertices[kept], remap[faces], int(len(vertices) - len(kept))


def _merge_groups(
    vertices: NDArray[np.float64], rtol: float, extra: NDArray[np.float64]
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """``(kept, remap)``: the first vertex of each group in file order, old id -> new id.

    A group is the vertices whose positions (or cells, ``rtol > 0``) and ``extra``
    columns are all equal.
    """
    keys = np.concatenate([position_keys(vertices, rtol), extra], axis=1)
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    kept = np.sort(first)  # survivors in file order: no duplicates, no renumbering
    rank = np.empty(len(first), dtype=np.int64)
    rank[np.argsort(first)] = np.arange(len(first))
    return kept.astype(np.int64), rank[inverse.reshape(-1)]


def write_mesh(mesh: Any, path: str | os.PathLike[str]) -> None:
    """Write a ``trimesh.Trimesh`` to ``path`` atomically, in the format of its suffix.

    Texture coordinates, given vertex normals and vertex colours are written where
    the format holds them (OBJ ``vt``/``vn``, PLY properties). A textured mesh
    written as OBJ gets its material file ``<stem>.mtl`` and texture image
    ``<stem>_texture.<format>`` beside ``path`` (``stem``: the output's name, other
    characters than letters, digits, ``-`` and ``_`` made ``_``): names taken from
    the input never choose where anything is written. Each file is written
    atomically, the mesh last.
    """
    target = Path(path)
    fmt = mesh_format(target, "output")
    sidecars: dict[str, bytes] = {}
    if fmt == "obj":
        data, sidecars = _obj_text(mesh, target)
    else:
        data = mesh.export(file_type=fmt)
    for name, blob in sidecars.items():
        if Path(name).name != name or name.startswith(".") or name == target.name:
            raise InvalidPolygonError(f"refusing to write the material file {name!r}")
        with atomic_write(target.parent / name, "wb") as fh:
            fh.write(blob)
    with atomic_write(target, "wb") as fh:
        fh.write(data.encode() if isinstance(data, str) else data)


def _obj_text(mesh: Any, target: Path) -> tuple[str, dict[str, bytes]]:
    """OBJ text of ``mesh`` and its material files ``{name: bytes}``, named after ``target``."""
    trimesh = import_optional("trimesh")
    visual = getattr(mesh, "visual", None)
    material = getattr(visual, "material", None)
    if not isinstance(visual, trimesh.visual.TextureVisuals) or material is None:
        return str(trimesh.exchange.obj.export_obj(mesh, include_texture=False)), {}
    stem = re.sub(r"[^A-Za-z0-9_-]", "_", target.stem) or "mesh"
    simple = material.to_simple() if hasattr(material, "to_simple") else material.copy()
    simple.name = f"{stem}_texture"  # the image is written as <material name>.<format>
    named = mesh.copy(include_cache=True)
    named.visual = trimesh.visual.TextureVisuals(uv=visual.uv, material=simple)
    if "vertex_normals" in getattr(getattr(mesh, "_cache", None), "cache", {}):
        named.vertex_normals = mesh.vertex_normals
    text, files = trimesh.exchange.obj.export_obj(
        named, include_texture=True, return_texture=True, mtl_name=f"{stem}.mtl"
    )
    return str(text), {str(k): bytes(v) for k, v in files.items()}
