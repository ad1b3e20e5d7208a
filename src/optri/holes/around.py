"""The faces around one hole of a mesh being filled, so that per-hole work stays local.

:func:`optri.fill_holes` refines each patch against the mesh's edge lengths at its
border, fairs it with the rings of faces around it and checks it for crossings with
the faces near it. Handing the whole mesh (and every patch so far) to each of those
steps costs time in proportion to the mesh for every hole: quadratic on a scan with
thousands of small holes. :class:`Around` indexes the mesh once -- its faces at each
vertex, its faces' boxes in a uniform grid -- and keeps the patches added since,
so that each step gets only

* :meth:`Around.rings`: the faces (of the mesh or of a patch so far) within some
  rings of a set of vertices;
* :meth:`Around.boxed`: the faces whose bounding boxes meet a box;

and :meth:`Around.local` writes them with a patch over compact vertex numbers that
keep the global order. The compiled fairing and crossing test select and number
what they use by the vertices' order and the faces' order alone, so on such a
superset of what they use they compute the same numbers as on the whole mesh.

Indexing sorts the mesh's faces, which costs more than a hole or two: the first
``whole_holes`` holes get the whole mesh (the queries answer None, "every face"),
and the mesh is indexed when a later hole first asks.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["Around"]

Ints = NDArray[np.int64]
Floats = NDArray[np.float64]

#: Holes that get the whole mesh before it is indexed (a sort of its faces): a mesh
#: with a few holes is never sorted.
WHOLE_MESH_HOLES = 8

#: A box query widens the box by this fraction of the mesh's extent: more than any
#: tolerance of the crossing test, so the faces it could pair are all returned.
_BOX_SLACK = 1e-6


class Around:
    """A mesh's faces at each vertex and in space, with the patches added to it.

    Vertex ids ``< n`` are the mesh's; later ids are the new vertices added with
    :meth:`add`, in order. Face ids ``< len(faces)`` are the mesh's; later ids are the
    patches' faces, in the order added: the numbering of
    ``np.concatenate([faces, *patches])``.

    Examples
    --------
    >>> import numpy as np
    >>> v = np.array([[0., 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [5, 5, 0]])
    >>> a = Around(v, np.array([[0, 1, 2], [1, 3, 2]]), whole_holes=0)
    >>> a.rings(np.array([0]), 1).tolist(), a.rings(np.array([0]), 2).tolist()
    ([0], [0, 1])
    >>> a.add(np.array([[5.0, 6, 0]]), np.array([[3, 4, 5]]))
    >>> a.rings(np.array([0]), 3).tolist(), a.boxed(np.array([4.5, 4.5, -1]), np.array([6, 7, 1]))
    ([0, 1, 2], array([2]))
    """

    def __init__(self, vertices: Floats, faces: Ints, whole_holes: int | None = None) -> None:
        self.vertices = np.ascontiguousarray(vertices, dtype=np.float64)
        self.faces = np.ascontiguousarray(faces, dtype=np.int64)
        self.n, self.m = len(self.vertices), len(self.faces)
        # patches to add before the queries narrow
        self._whole_left = WHOLE_MESH_HOLES if whole_holes is None else whole_holes
        self._at: tuple[Ints, Ints] | None = None  # faces at each vertex: (start, face ids)
        self._new = np.zeros((0, 3))  # new vertices' coordinates (first _n_new rows)
        self._n_new = 0
        self._patches: list[Ints] = []
        self._pfaces = np.zeros((0, 3), dtype=np.int64)  # patch faces (first _n_pf rows)
        self._n_pf = 0
        self._patches_at: dict[int, list[int]] = {}  # mesh vertex -> patches using it
        self._indexed = 0  # patches whose vertices and box are in _patches_at and _box
        self._new_first = np.zeros(0, dtype=np.int64)  # each patch's first new vertex id
        self._box = np.zeros((0, 6))  # each patch's box (lo, hi), first len(_patches) rows
        self._first = np.zeros(0, dtype=np.int64)  # each patch's first face id
        self._grid: _Grid | None = None  # made at the first box query

    @property
    def whole(self) -> bool:
        """Whether the queries answer None (every face) for the next hole."""
        return self._whole_left > 0

    @property
    def size(self) -> int:
        """Vertices so far: the mesh's and the new ones."""
        return self.n + self._n_new

    def coords(self, ids: Ints) -> Floats:
        """Positions of vertices ``ids`` (mesh or new)."""
        ids = np.asarray(ids, dtype=np.int64)
        out = np.empty((len(ids), 3))
        old = ids < self.n
        out[old] = self.vertices[ids[old]]
        out[~old] = self._new[ids[~old] - self.n]
        return out

    def new_vertices(self) -> Floats:
        """Every new vertex's position, in id order."""
        return self._new[: self._n_new].copy()

    def faces_of(self, ids: Ints) -> Ints:
        """Faces ``ids`` (mesh or patch) as vertex triples."""
        ids = np.asarray(ids, dtype=np.int64)
        out = np.empty((len(ids), 3), dtype=np.int64)
        old = ids < self.m
        out[old] = self.faces[ids[old]]
        out[~old] = self._pfaces[ids[~old] - self.m]
        return out

    def add(self, new_vertices: Floats, patch: Ints) -> None:
        """Append a patch (over mesh ids and ids from ``size`` on) and its new vertices."""
        self._new, self._n_new = _append(self._new, self._n_new, new_vertices)
        patch = np.asarray(patch, dtype=np.int64).reshape(-1, 3)
        self._first, _ = _append(self._first, len(self._patches), np.array([self.m + self._n_pf]))
        self._new_first, _ = _append(
            self._new_first, len(self._patches), np.array([self.size - len(new_vertices)])
        )
        self._pfaces, self._n_pf = _append(self._pfaces, self._n_pf, patch)
        self._patches.append(patch)
        self._whole_left -= 1

    def _index_patches(self) -> None:
        """The vertices and boxes of the patches added since the last query that used them."""
        for j in range(self._indexed, len(self._patches)):
            patch = self._patches[j]
            for v in np.unique(patch[patch < self.n]).tolist():
                self._patches_at.setdefault(v, []).append(j)
            box = np.array([np.inf] * 3 + [-np.inf] * 3)
            if len(patch):
                pts = self.coords(patch.ravel())
                box = np.concatenate([pts.min(axis=0), pts.max(axis=0)])
            self._box, _ = _append(self._box, j, box[None])
        self._indexed = len(self._patches)

    def mesh_faces_at(self, vertices: Ints) -> Ints:
        """Ids of the mesh's faces (not the patches') at any of ``vertices``, ascending.

        Before the mesh is indexed (:attr:`whole`), a scan of every face.
        """
        v = np.asarray(vertices, dtype=np.int64)
        v = v[v < self.n]
        if self.whole:
            mark = np.zeros(self.n, dtype=bool)
            mark[v] = True
            f = self.faces
            return np.flatnonzero(mark[f[:, 0]] | mark[f[:, 1]] | mark[f[:, 2]])
        if self._at is None:
            flat = self.faces.ravel()
            start = np.concatenate(([0], np.cumsum(np.bincount(flat, minlength=self.n))))
            self._at = (start, np.argsort(flat, kind="stable") // 3)
        start, face_at = self._at
        return np.unique(face_at[runs(start[v], start[v + 1] - start[v])])

    def rings(self, seeds: Ints, sweeps: int) -> Ints | None:
        """Face ids reached in ``sweeps`` sweeps from ``seeds``, ascending (None: every face).

        A sweep takes every face at a vertex reached so far and reaches its vertices.
        """
        if self.whole:
            return None
        self._index_patches()
        reached = np.unique(np.asarray(seeds, dtype=np.int64))
        found = np.zeros(0, dtype=np.int64)
        for _ in range(sweeps):
            parts = [found, self.mesh_faces_at(reached)]
            for j in self._patches_touching(reached):
                p = self._patches[j]
                parts.append(self._first[j] + np.flatnonzero(np.isin(p, reached).any(axis=1)))
            found = np.unique(np.concatenate(parts))
            reached = np.union1d(reached, self.faces_of(found).ravel())
        return found

    def _patches_touching(self, vertices: Ints) -> list[int]:
        """Numbers of the patches using any of ``vertices`` (mesh or new), ascending."""
        old = vertices[vertices < self.n].tolist()
        touched = {j for v in old for j in self._patches_at.get(v, ())}
        new = vertices[vertices >= self.n]
        if len(new):
            owner = np.searchsorted(self._new_first[: len(self._patches)], new, side="right")
            touched |= set((owner - 1).tolist())
        return sorted(touched)

    def boxed(self, lo: Floats, hi: Floats) -> Ints | None:
        """Face ids (mesh or patch) whose boxes meet the box ``[lo, hi]``, ascending.

        The box is widened by a millionth of the mesh's extent, so faces that touch it
        within rounding are in. None: every face.
        """
        if self.whole:
            return None
        self._index_patches()
        if self._grid is None:
            self._grid = _Grid(self.vertices, self.faces)
        g = self._grid
        lo = np.asarray(lo, dtype=np.float64) - g.slack
        hi = np.asarray(hi, dtype=np.float64) + g.slack
        out = [g.boxed(lo, hi)]
        box = self._box[: len(self._patches)]
        for j in np.flatnonzero(np.all((box[:, :3] <= hi) & (box[:, 3:] >= lo), axis=1)):
            p = self._patches[j]
            pts = self.coords(p.ravel()).reshape(-1, 3, 3)
            meet = np.all((pts.min(axis=1) <= hi) & (pts.max(axis=1) >= lo), axis=1)
            out.append(self._first[j] + np.flatnonzero(meet))
        return np.concatenate(out).astype(np.int64)

    def local(
        self, face_ids: Ints | None, patch: Ints, pending: Floats
    ) -> tuple[Floats, Ints, Ints, Ints]:
        """``(vertices, faces, patch, ids)``: faces ``face_ids`` then ``patch``, compactly.

        ``patch`` may use the ``len(pending)`` ids from :attr:`size` on, placed at
        ``pending`` (a patch's new vertices, not added yet). ``ids`` are the global ids
        of the local vertices, ascending (the local numbering keeps the global order);
        ``faces`` are the faces ``face_ids`` in the given order followed by the patch,
        and ``patch`` is the patch over the local numbers. ``face_ids=None``: every
        face and vertex so far, numbered as they are.
        """
        patch = np.asarray(patch, dtype=np.int64).reshape(-1, 3)
        if face_ids is None:
            pos = np.concatenate([self.vertices, self._new[: self._n_new], pending])
            faces = np.concatenate([self.faces, self._pfaces[: self._n_pf], patch])
            return pos, faces, patch, np.arange(len(pos), dtype=np.int64)
        glob = np.concatenate([self.faces_of(face_ids), patch])
        ids, inverse = np.unique(glob.ravel(), return_inverse=True)
        known = ids < self.size
        pos = np.empty((len(ids), 3))
        pos[known] = self.coords(ids[known])
        pos[~known] = np.asarray(pending, dtype=np.float64).reshape(-1, 3)[ids[~known] - self.size]
        faces = inverse.reshape(-1, 3).astype(np.int64)
        return pos, faces, faces[len(glob) - len(patch) :], ids


class _Grid:
    """The mesh's face boxes in a uniform grid, each listed at its low corner's cell.

    Cells are twice the median face wide; faces wider than a cell (a few on a mesh of
    even density) are listed apart and tested at every query. The grid doubles its
    cell until at most a twentieth of the faces are wide and the cell count fits int64.
    """

    def __init__(self, vertices: Floats, faces: Ints) -> None:
        a, b, c = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
        self.flo = np.minimum(np.minimum(a, b), c)
        self.fhi = np.maximum(np.maximum(a, b), c)
        self.origin = vertices.min(axis=0) if len(vertices) else np.zeros(3)
        span = (vertices.max(axis=0) - self.origin) if len(vertices) else np.zeros(3)
        self.slack = _BOX_SLACK * float(span.max(initial=0.0))
        d = self.fhi - self.flo
        extent = np.maximum(np.maximum(d[:, 0], d[:, 1]), d[:, 2])
        positive = extent[extent > 0]
        cell = 2.0 * float(np.median(positive)) if len(positive) else 1.0
        cell = max(cell, float(span.max(initial=0.0)) / 2.0**20, 1e-300)
        while True:
            dims = np.floor(span / cell).astype(np.float64) + 1
            wide = extent > cell
            if float(np.prod(dims)) < 2.0**62 and wide.sum() <= len(faces) // 20:
                break
            cell *= 2
        self.cell, self.dims = cell, dims.astype(np.int64)
        self.wide = np.flatnonzero(wide)
        narrow = np.flatnonzero(~wide)
        cells = np.minimum(np.floor((self.flo[narrow] - self.origin) / cell), dims - 1)
        cells = cells.astype(np.int64)
        key = (cells[:, 0] * self.dims[1] + cells[:, 1]) * self.dims[2] + cells[:, 2]
        order = np.argsort(key, kind="stable")
        self.order, self.keys = narrow[order], key[order]

    def boxed(self, lo: Floats, hi: Floats) -> Ints:
        """Ids of the faces whose boxes meet ``[lo, hi]`` (already widened), ascending."""
        # a face's low corner lies in [lo - cell, hi] when its box (at most a cell wide)
        # meets [lo, hi]: the cells of that range, a run of keys per (x, y) column
        first = np.floor((lo - self.cell - self.origin) / self.cell)
        last = np.floor((hi - self.origin) / self.cell)
        first, last = np.maximum(first, 0), np.minimum(last, self.dims - 1)
        found = [self.wide]
        if np.all(first <= last) and np.all(np.isfinite(first)) and np.all(np.isfinite(last)):
            x, y = np.meshgrid(
                np.arange(first[0], last[0] + 1), np.arange(first[1], last[1] + 1), indexing="ij"
            )
            base = (
                x.ravel().astype(np.int64) * self.dims[1] + y.ravel().astype(np.int64)
            ) * self.dims[2]
            a = np.searchsorted(self.keys, base + int(first[2]), side="left")
            b = np.searchsorted(self.keys, base + int(last[2]), side="right")
            found.append(self.order[runs(a, b - a)])
        run = np.concatenate(found)
        keep = np.all((self.flo[run] <= hi) & (self.fhi[run] >= lo), axis=1)
        return np.sort(run[keep])


def runs(start: Ints, count: Ints) -> Ints:
    """The indices ``start[i], ..., start[i] + count[i] - 1`` for each ``i``, concatenated.

    >>> runs(np.array([5, 0, 9]), np.array([2, 0, 3])).tolist()
    [5, 6, 9, 10, 11]
    """
    return np.repeat(start - np.cumsum(count) + count, count) + np.arange(int(count.sum()))


def _append(buffer: NDArray[np.generic], used: int, rows: NDArray[np.generic]) -> tuple[Any, int]:
    """``(buffer, used + len(rows))`` with ``rows`` written after the first ``used`` rows.

    The buffer doubles when full, so appending costs amortized time per row.
    """
    k = len(rows)
    if used + k > len(buffer):
        grown = np.zeros((max(2 * len(buffer), used + k, 64), *buffer.shape[1:]), buffer.dtype)
        grown[:used] = buffer[:used]
        buffer = grown
    buffer[used : used + k] = rows
    return buffer, used + k
