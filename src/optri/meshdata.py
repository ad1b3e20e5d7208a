"""Meshes as the hole-filling functions take and return them: trimesh or (vertices, faces)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._optional import import_optional
from .errors import InvalidPolygonError

__all__ = [
    "copies_at_border",
    "interpolate",
    "mesh_arrays",
    "position_keys",
    "rebuild",
    "same_kind",
    "vertex_columns",
    "weld",
    "with_attributes",
]

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


def weld(vertices: NDArray[np.float64], faces: Ints, rtol: float = 0.0) -> Ints:
    """``faces`` with every vertex replaced by the first vertex at its position.

    Vertices at the same position (``rtol == 0``: exactly; else in the same cell
    of side ``rtol`` times the bounding-box diagonal, as
    :func:`optri.io.meshes.merge_vertices` groups them) are one vertex for the
    topology: a seam that splits a vertex to give it two texture coordinates or
    normals is then no hole. The vertex array is not changed; the welded faces
    refer to the lowest-numbered copy of each position.

    >>> v = np.array([[0., 0, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0], [1, 1, 0]])
    >>> weld(v, np.array([[0, 1, 2], [3, 4, 2]])).tolist()
    [[0, 1, 2], [1, 4, 2]]
    """
    from ._core import topology

    keys = position_keys(vertices, rtol)
    rep = topology.weld_first(np.ascontiguousarray(keys, dtype=np.float64).reshape(-1, 3))
    if (rep == np.arange(len(rep))).all():
        return faces  # no two vertices share a position
    return rep[faces]  # type: ignore[no-any-return]


def position_keys(vertices: NDArray[np.float64], rtol: float) -> NDArray[np.float64]:
    """Rows equal exactly for vertices merged by position.

    ``rtol == 0``: the positions; else the cell of side ``rtol`` times the
    bounding-box diagonal each position falls in.

    >>> position_keys(np.array([[0.0, 0, 0], [0.01, 0, 0], [1, 1, 1]]), 0.1).tolist()
    [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [5.0, 5.0, 5.0]]
    """
    if rtol < 0 or not np.isfinite(rtol):
        raise InvalidPolygonError(f"merge tolerance must be a finite number >= 0, got {rtol}")
    if rtol > 0 and len(vertices):
        lo, hi = vertices.min(axis=0), vertices.max(axis=0)
        cell = rtol * float(np.linalg.norm((hi - lo) / 2.0)) * 2.0  # no overflow at 1e308
        if cell > 0:
            return np.floor((vertices - lo) / cell)  # type: ignore[no-any-return]
    return vertices


def copies_at_border(
    faces: Ints, welded: Ints, patch: Ints, nv: int, parents: Ints | None = None
) -> tuple[Ints, Ints, Ints]:
    """Map a patch over welded ids onto the mesh's own copies of its vertices.

    A patch face with an edge on the hole's border takes, at both ends of that edge,
    the copies the mesh face across it uses, so it meets the mesh with that face's
    texture coordinates and normals; its other corners, and the corners of faces
    inside the patch, take the copy of the mesh face across the border edge that
    leaves the vertex (in patch order). Vertices ``>= nv`` (added by refinement) are
    kept as they are.

    Returns ``(patch, parents, source)``: the patch over the mesh's vertex ids,
    ``parents`` (the triangles refinement split, ``(k, 3)``) mapped the same way as
    inner corners, and for each patch face the mesh face whose face attributes it
    takes (the face across its border edge, else across the edge leaving its first
    old corner, else across the hole's first border edge).

    >>> f = np.array([[0, 1, 2], [3, 4, 2]])            # 3 is a copy of 1
    >>> w = np.array([[0, 1, 2], [1, 4, 2]])
    >>> p, _, src = copies_at_border(f, w, np.array([[0, 2, 4], [0, 4, 1]]), 5)
    >>> p.tolist(), src.tolist()
    ([[0, 2, 4], [0, 4, 3]], [0, 1])
    """
    out = patch.copy()
    src = np.full(len(patch), -1, dtype=np.int64)
    # directed welded edge (a -> b) of each mesh face corner, sorted for look-ups
    key = welded.ravel() * nv + welded[:, [1, 2, 0]].ravel()
    order = np.argsort(key, kind="stable")
    skey = key[order]

    def across(u: Ints, w: Ints) -> tuple[Ints, Ints, Ints, Ints]:
        """For patch edges u -> w: whether a mesh face runs w -> u, which, its copies of u, w."""
        k = w * nv + u
        pos = np.minimum(np.searchsorted(skey, k), max(len(skey) - 1, 0))
        hit = skey[pos] == k
        face, c = np.divmod(order[pos], 3)  # corner c is w; the edge ends at u
        return hit, face, faces[face, (c + 1) % 3], faces[face, c]

    # default copy of each loop vertex: the face across the border edge leaving it
    us, ws = patch.ravel(), patch[:, [1, 2, 0]].ravel()
    both = np.flatnonzero((us < nv) & (ws < nv))
    hit, face, cu, _ = across(us[both], ws[both])
    loop_v, first = np.unique(us[both][hit], return_index=True)
    copy_of, face_of = cu[hit][first], face[hit][first]

    def default(x: Ints) -> tuple[Ints, Ints]:
        """Each vertex's default copy, and the face it comes from (-1: not a loop vertex)."""
        if len(loop_v) == 0:
            return x.copy(), np.full(x.shape, -1, dtype=np.int64)
        pos = np.minimum(np.searchsorted(loop_v, x), len(loop_v) - 1)
        on = loop_v[pos] == x
        return np.where(on, copy_of[pos], x), np.where(on, face_of[pos], -1)

    out, near = default(patch)
    for corner in (2, 1, 0):  # corner 0's edge wins where a face has two border edges
        u, w = patch[:, corner], patch[:, (corner + 1) % 3]
        sel = np.flatnonzero((u < nv) & (w < nv))
        hit, face, cu, cw = across(u[sel], w[sel])
        rows = sel[hit]
        out[rows, corner], out[rows, (corner + 1) % 3] = cu[hit], cw[hit]
        src[rows] = face[hit]
    for corner in (2, 1, 0):
        src = np.where((src < 0) & (near[:, corner] >= 0), near[:, corner], src)
    src[src < 0] = face_of[0] if len(face_of) else 0
    mapped = default(parents)[0] if parents is not None else np.zeros((0, 3), np.int64)
    return out, mapped, src


def interpolate(values: NDArray[Any], parents: Ints) -> NDArray[Any]:
    """Per-vertex ``values`` extended to the vertices refinement added.

    New vertex ``k`` (index ``len(values) + k``) is the centroid of the triangle
    ``parents[k]``, whose corners may be earlier new vertices: its value is the mean
    of theirs, which is linear (barycentric) interpolation over the patch triangle it
    was made in. Integer values (8-bit colours) are rounded back to their type.

    >>> interpolate(np.array([[0.0], [3.0], [6.0]]), np.array([[0, 1, 2], [0, 1, 3]])).tolist()
    [[0.0], [3.0], [6.0], [3.0], [2.0]]
    """
    base = np.asarray(values)
    out = np.concatenate(
        [base.astype(np.float64), np.zeros((len(parents),) + base.shape[1:], np.float64)]
    )
    n = len(base)
    for k, (a, b, c) in enumerate(np.asarray(parents, dtype=np.int64).tolist()):
        out[n + k] = (out[a] + out[b] + out[c]) / 3.0
    if np.issubdtype(base.dtype, np.integer):
        info = np.iinfo(base.dtype)
        return np.clip(np.rint(out), info.min, info.max).astype(base.dtype)
    return out.astype(base.dtype, copy=False)


def with_attributes(
    mesh: Any, vertices: NDArray[np.float64], faces: Ints, parents: Ints, source: Ints
) -> Any:
    """A ``trimesh.Trimesh`` of ``(vertices, faces)`` carrying ``mesh``'s attributes over.

    ``vertices`` and ``faces`` start with ``mesh``'s own, in its layout; the rest are
    the vertices refinement added (made at the centroids of ``parents``) and the patch
    faces (each taking the face attributes of ``source``). Kept: texture coordinates
    and material (``TextureVisuals``), vertex and face colours (``ColorVisuals``),
    vertex normals given with the mesh, and every ``vertex_attributes`` and
    ``face_attributes`` array; new vertices get interpolated values
    (:func:`interpolate`; normals renormalised), new faces their source face's.
    """
    parents = np.asarray(parents, dtype=np.int64).reshape(-1, 3)
    rows = np.concatenate([np.arange(len(mesh.faces), dtype=np.int64), source])
    return rebuild(mesh, vertices, faces, lambda a: interpolate(a, parents), rows)


def rebuild(
    mesh: Any,
    vertices: NDArray[np.float64],
    faces: Ints,
    per_vertex: Callable[[NDArray[Any]], NDArray[Any]],
    face_rows: Ints,
) -> Any:
    """A ``trimesh.Trimesh`` with ``mesh``'s attributes mapped onto new vertices and faces.

    Each per-vertex array ``a`` of ``mesh`` (texture coordinates, given normals, vertex
    colours, ``vertex_attributes``) becomes ``per_vertex(a)``; each per-face array
    (face colours, ``face_attributes``) becomes ``a[face_rows]``. Normals of vertices
    past ``mesh``'s own are renormalised; the material and metadata are shared.
    """
    trimesh = import_optional("trimesh")
    nv, nf = len(mesh.vertices), len(mesh.faces)

    def on_vertices(a: Any) -> Any:
        a = np.asarray(a)
        return per_vertex(a) if a.ndim >= 1 and len(a) == nv else None

    def on_faces(a: Any) -> Any:
        a = np.asarray(a)
        return a[face_rows] if a.ndim >= 1 and len(a) == nf else None

    kwargs: dict[str, Any] = {}
    cached = getattr(getattr(mesh, "_cache", None), "cache", {})
    if "vertex_normals" in cached:  # normals given with the mesh, not computed
        normals = on_vertices(np.asarray(cached["vertex_normals"], dtype=np.float64))
        if normals is not None:
            new = normals[nv:]
            norm = np.linalg.norm(new, axis=1, keepdims=True)
            normals[nv:] = np.divide(new, norm, out=new, where=norm > 0)
            kwargs["vertex_normals"] = normals
    visual: Any = getattr(mesh, "visual", None)
    kind = getattr(visual, "kind", None)
    if isinstance(visual, trimesh.visual.TextureVisuals):
        uv = getattr(visual, "uv", None)
        uv = None if uv is None else on_vertices(np.asarray(uv, dtype=np.float64))
        kwargs["visual"] = trimesh.visual.TextureVisuals(uv=uv, material=visual.material)
    elif kind == "vertex":
        colors = on_vertices(visual.vertex_colors)
        kwargs["visual"] = trimesh.visual.ColorVisuals(vertex_colors=colors)
    elif kind == "face":
        kwargs["visual"] = trimesh.visual.ColorVisuals(face_colors=on_faces(visual.face_colors))
    vattr = {k: on_vertices(a) for k, a in getattr(mesh, "vertex_attributes", {}).items()}
    fattr = {k: on_faces(a) for k, a in getattr(mesh, "face_attributes", {}).items()}
    out = trimesh.Trimesh(
        vertices=vertices,
        faces=faces,
        vertex_attributes={k: a for k, a in vattr.items() if a is not None},
        face_attributes={k: a for k, a in fattr.items() if a is not None},
        process=False,
        **kwargs,
    )
    out.metadata.update(getattr(mesh, "metadata", {}))
    return out


def vertex_columns(mesh: Any) -> NDArray[np.float64]:
    """Every per-vertex attribute of a ``trimesh.Trimesh`` side by side, ``(n, k)``.

    Two vertices with equal rows carry the same texture coordinates, given normals,
    colours and attributes, so merging them loses nothing. ``k`` is 0 for a bare mesh.
    """
    nv = len(mesh.vertices)
    cols: list[NDArray[np.float64]] = [np.zeros((nv, 0))]
    cached = getattr(getattr(mesh, "_cache", None), "cache", {})
    visual: Any = getattr(mesh, "visual", None)
    found = [cached.get("vertex_normals"), getattr(visual, "uv", None)]
    if getattr(visual, "kind", None) == "vertex":
        found.append(visual.vertex_colors)
    found += list(getattr(mesh, "vertex_attributes", {}).values())
    for a in found:
        if a is None:
            continue
        a = np.asarray(a)
        if a.ndim >= 1 and len(a) == nv and np.issubdtype(a.dtype, np.number):
            cols.append(a.reshape(nv, -1).astype(np.float64))
    return np.concatenate(cols, axis=1)
