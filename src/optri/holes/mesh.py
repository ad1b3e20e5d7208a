"""Fill the holes of a triangle mesh: ``fill_holes``.

Each boundary loop (:mod:`optri.holes.boundary`: pinched vertices split into
simple loops) is filled by :func:`optri.fill_polyline`, with the mesh
triangles along the loop as Liepa's third points. The patch never joins two
vertices the mesh already joins (that edge would get four faces), including
edges added by the holes filled before it; new faces are wound so that every
boundary edge ``(a, b)`` of an existing face appears as ``(b, a)`` in its new
neighbour. With ``refine=True`` each patch is then refined to the density of the
mesh around it (:mod:`optri.holes.refine`), and with ``fair=k`` its new vertices are
faired (:mod:`optri.holes.fair`, two solves: the second takes the Laplacian on the
first's surface); a fairing that would make the patch cross the mesh is undone (the
first solve is tried, then the refined patch is kept) and the record says why.
Each hole's refinement, fairing and crossing check see only the faces around it
(:class:`optri.holes.around.Around`), so the time per hole does not grow with the mesh.
trimesh is imported only when a ``trimesh.Trimesh`` is passed in.
"""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .. import config
from ..errors import (
    HoleSkippedWarning,
    InvalidPolygonError,
    NoTriangulationError,
    TableTooLargeError,
)
from ..meshdata import copies_at_border, mesh_arrays, same_kind, weld, with_attributes
from ..objective import Cost
from ..weights import get_weight
from .around import Around, runs
from .boundary import Loop, trace_loops
from .fair import CONTINUITY, PATCH_PASSES, fair_vertices
from .intersect import intersecting_pairs
from .islands import ISLAND_METHODS, fill_polylines, group_chords, island_groups
from .polyline import METHODS, fill_polyline
from .refine import boundary_scales, refine_patch

__all__ = ["HoleRecord", "fill_holes"]

Ints = NDArray[np.int64]


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
    pinched : list of int
        Pinched (non-manifold) boundary vertices on this loop: it was split
        off a border cycle there.
    forbidden_chords : int
        Chords the patch could not use: pairs of loop vertices the mesh (or a
        patch filled before) already joins.
    degenerate : int
        Zero-area (exactly collinear) triangles the patch added: 0 whenever some
        allowed patch has none, else the fewest any allowed patch has.
    degenerate_unavoidable : bool
        Whether ``degenerate > 0`` and no allowed patch has fewer (proven by an
        exact search over every patch).
    candidates : str
        ``method="delaunay"``: the candidate set that held the patch
        (``"delaunay"``, ``"delaunay-edges"``, ``"knn-8"``... or ``"all"``).
    vertices_added : int
        Vertices the refinement added (0 without ``refine``).
    faired : bool
        Whether the new vertices were faired.
    fair_reason : str
        Why a fairing asked for was not kept ("" when it was, or was not asked for).
    self_intersections : int
        Pairs of a patch face and a face of the mesh or of the patch itself that cross,
        in the final patch.
    islands : list of list of int
        Boundary loops of other pieces of the mesh lying inside this hole, filled
        with it as one patch (each in patch order; they get no record of their own).
    optimality : str
        ``"proven"`` or ``"heuristic"`` for a hole with islands (as
        :func:`optri.fill_polylines` says), "" otherwise.
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
    pinched: list[int] = field(default_factory=list)
    forbidden_chords: int = 0
    degenerate: int = 0
    degenerate_unavoidable: bool = False
    candidates: str = ""
    vertices_added: int = 0
    faired: bool = False
    fair_reason: str = ""
    self_intersections: int = 0
    islands: list[list[int]] = field(default_factory=list)
    optimality: str = ""

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready fields (a tuple weight becomes a list)."""
        out = asdict(self)
        if isinstance(self.weight, tuple):
            out["weight"] = list(self.weight)
        return out

    def detail(self) -> str:
        """One line saying what was done beyond a plain fill ("" if nothing)."""
        notes = []
        if self.islands:
            sizes = ", ".join(str(len(lp)) for lp in self.islands)
            notes.append(f"with {len(self.islands)} island(s) of {sizes} edges ({self.optimality})")
        if self.pinched:
            notes.append(f"split at pinched vertex {', '.join(map(str, self.pinched))}")
        if self.forbidden_chords:
            notes.append(f"{self.forbidden_chords} chords avoided (existing edges)")
        if self.degenerate:
            fewest = "no patch has fewer" if self.degenerate_unavoidable else "fewest found"
            notes.append(f"{self.degenerate} zero-area faces ({fewest})")
        if self.vertices_added:
            notes.append(f"refined: {self.vertices_added} vertices added")
        if self.faired:
            notes.append("faired")
        if self.fair_reason:
            notes.append(f"not faired: {self.fair_reason}")
        if self.self_intersections:
            notes.append(f"{self.self_intersections} crossings with the mesh")
        if self.candidates:
            notes.append(f"candidates: {self.candidates}")
        return "; ".join(notes)


def fill_holes(
    mesh: Any,
    max_hole_edges: int | None = None,
    weight: str | Callable[..., float] = "liepa",
    method: str = "auto",
    *,
    refine: bool = False,
    fair: int | None = None,
    density: float = math.sqrt(2.0),
    islands: bool = True,
    merge_rtol: float | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> tuple[Any, list[HoleRecord]]:
    """Fill every hole of a triangle mesh with an optimal patch, refined and faired if asked.

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
        Liepa's O(n^3) recurrence above (each record names the mode used). With
        ``refine=True``, ``"auto"`` runs the exact search up to
        ``config.HOLES_REFINE_EXACT_MAX_N`` edges and ``"delaunay"`` above: the
        patch is then only where refinement starts.
    refine : bool
        Refine each patch to the density of the mesh around its hole: Liepa's
        centroid splits and edge relaxation (:func:`optri.holes.refine_patch`).
    fair : {None, 0, 1, 2}
        Fair the vertices refinement added, with continuity 0 (membrane), 1 (thin
        plate) or 2 (minimal curvature variation) at the hole's border
        (:func:`optri.fair_region`). Without ``refine`` a patch has no vertex of
        its own and fairing changes nothing; to fair an existing patch, pass its
        vertices to :func:`optri.fair_region`.
    density : float
        Liepa's density factor (> 0): larger gives smaller triangles.
    islands : bool
        Fill each hole together with its islands -- boundary loops of other
        connected pieces of the mesh lying inside it
        (:func:`optri.holes.islands.island_groups`) -- as one patch by
        :func:`optri.fill_polylines` (default); False fills every loop on its own.
    merge_rtol : float, optional
        Vertices closer than this fraction of the bounding-box diagonal are one
        vertex for finding and filling holes; default ``config.MESH_MERGE_RTOL``
        (0: exactly equal positions). The output keeps the input's vertices.
    progress : callable, optional
        ``progress(done, total)`` after each hole.

    Returns
    -------
    (mesh, records)
        A new mesh of the input's kind (old vertices unchanged, refinement's new
        vertices appended after them, new faces appended) and one
        :class:`HoleRecord` per hole (a hole's islands are named in its record). A
        ``trimesh.Trimesh`` keeps its texture coordinates, material, vertex normals,
        colours and vertex and face attributes (:func:`optri.meshdata.with_attributes`); a
        ``(vertices, faces)`` pair has none to keep.

    Raises
    ------
    InvalidPolygonError
        Faces that are not triangles or index missing vertices, or boundary
        edges that do not close into loops; nothing is filled then.

    Notes
    -----
    The filled mesh has no edge used by more than two faces that was not so
    before: a patch never uses a chord joining two vertices the mesh (or an
    earlier patch) already joins; a hole every patch of which would is left
    open (``status="failed"``). Pinched boundary vertices (two loops touching)
    are split as CGAL's border cycles are, so each loop is filled on its own.

    Holes are found on the mesh welded by position: copies of a vertex that a
    texture or normal seam splits (OBJ files keep one per texture coordinate) are
    one vertex, so seams are no holes. The output keeps the copies; each patch face
    uses, along the hole's border, the copies of the mesh face across it, so it meets
    the mesh with that face's texture coordinates and normals. Records name each
    loop vertex by its lowest-numbered copy.

    Fairing solves twice (``fair_vertices(..., passes=2)``): the Laplacian is taken on
    the flat refined patch, then on the surface the first solve gave. A fairing whose
    patch would cross the mesh where the refined patch did not is undone: the first
    solve is tried, then the refined patch stays (``fair_reason`` says so); a system
    that cannot be solved is reported the same way. ``self_intersections`` counts the
    crossings left in each final patch.

    References
    ----------
    .. [1] P. Liepa, "Filling holes in meshes", Symposium on Geometry Processing 2003,
       doi:10.2312/SGP/SGP03/200-206.

    Examples
    --------
    >>> import numpy as np
    >>> v = np.array([[0., 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    >>> f = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3]])    # a tetrahedron minus a face
    >>> (v2, f2), records = fill_holes((v, f))
    >>> f2[-1].tolist(), records[0].status, records[0].edges
    ([0, 3, 2], 'filled', 3)
    >>> (v3, f3), records = fill_holes((v, f), refine=True, fair=1, density=8.0)
    >>> len(v3) - len(v) == records[0].vertices_added > 0, records[0].faired
    (True, True)
    """
    if method not in METHODS:
        raise InvalidPolygonError(f"unknown method {method!r}; choose one of: {', '.join(METHODS)}")
    if not (isinstance(weight, str) and weight == "liepa"):
        get_weight(weight)  # an unknown weight fails here, not once per hole
    if fair is not None and fair not in CONTINUITY:
        raise InvalidPolygonError(f"fair must be None, 0, 1 or 2, got {fair!r}")
    if not (isinstance(density, (int, float)) and density > 0 and math.isfinite(density)):
        raise InvalidPolygonError(f"density must be a positive number, got {density!r}")
    vertices, own_faces, is_trimesh = mesh_arrays(mesh)
    rtol = config.MESH_MERGE_RTOL if merge_rtol is None else merge_rtol
    faces = weld(vertices, own_faces, rtol)  # copies split by seams are one vertex
    loops = trace_loops(faces)
    joined = _Edges(faces, loops, len(vertices))
    records: list[HoleRecord] = []
    patches: list[Ints] = []
    parents: list[Ints] = []  # the corners each new vertex is the centroid of
    # the mesh and the patches so far, indexed: each hole's steps see the faces near it
    around = Around(vertices, faces)
    groups = island_groups(vertices, faces, [lp.vertices for lp in loops]) if islands else {}
    inside = {j for members in groups.values() for j in members}
    for h, loop in enumerate(loops):
        if h in inside:  # filled with the hole around it
            continue
        group = [loops[j] for j in groups.get(h, [])]
        mode = method
        big = len(loop.vertices) > config.HOLES_REFINE_EXACT_MAX_N
        if refine and big and method == "auto" and not group:
            mode = "delaunay"  # the coarse patch is only where refinement starts
        rec, patch = _fill_one(h, vertices, loop, joined, max_hole_edges, weight, mode, group)
        ring = np.concatenate([loop.vertices, *(lp.vertices for lp in group)])
        if patch is not None:
            added = np.zeros((0, 3))
            crossings = None  # of the final patch, once a check has counted them
            if refine:
                scales = boundary_scales(vertices, faces[around.mesh_faces_at(ring)], ring)
                split: list[tuple[int, int, int]] = []
                added, patch = refine_patch(
                    vertices,
                    patch,
                    ring,
                    scales,
                    density,
                    forbidden=joined.pairs_among(ring),
                    parents=split,
                )
                # refinement numbers its vertices from len(vertices); they follow the
                # vertices of the holes filled before
                shift = around.size - len(vertices)
                patch = np.where(patch >= len(vertices), patch + shift, patch)
                corners = np.asarray(split, dtype=np.int64).reshape(-1, 3)
                parents.append(np.where(corners >= len(vertices), corners + shift, corners))
                if len(added):
                    rec.vertices_added = len(added)
                    rec.faces_added = len(patch)
                    if fair is not None:
                        added, crossings = _fair_patch(rec, around, patch, added, fair)
            joined.add(patch)
            if crossings is None:
                crossings = _crossings(around, patch, added)
            around.add(added, patch)
            patches.append(patch)
            rec.self_intersections = crossings
        records.append(rec)
        if progress is not None:
            progress(h + 1, len(loops))
    out_vertices = np.concatenate([vertices, around.new_vertices()])
    patches_all = np.concatenate([np.zeros((0, 3), np.int64), *patches]).astype(np.int64)
    split_all = np.concatenate([np.zeros((0, 3), np.int64), *parents])
    if is_trimesh or faces is not own_faces:  # some vertex has copies (or attributes)
        patches_all, split_all, source = copies_at_border(
            own_faces, faces, patches_all, len(vertices), split_all
        )
    out_faces = np.concatenate([own_faces, patches_all])
    if is_trimesh:
        return with_attributes(mesh, out_vertices, out_faces, split_all, source), records
    return same_kind(out_vertices, out_faces, is_trimesh), records


def _crossings(around: Around, patch: Ints, pending: NDArray[np.float64]) -> int:
    """Crossings of ``patch`` (new vertices at ``pending``) with the faces near it and itself.

    The faces whose boxes meet the patch's box, with the patch, as
    :func:`intersecting_pairs` would count them over the whole mesh.
    """
    if len(patch) == 0:
        return 0
    near = None
    if not around.whole:
        ids = np.unique(patch)
        old = ids < around.size
        pts = np.concatenate([around.coords(ids[old]), pending[ids[~old] - around.size]])
        near = around.boxed(pts.min(axis=0), pts.max(axis=0))
    v, f, p, _ = around.local(near, patch, pending)
    return len(intersecting_pairs(v, f, p))


def _fair_patch(
    rec: HoleRecord,
    around: Around,
    patch: Ints,
    added: NDArray[np.float64],
    continuity: int,
) -> tuple[NDArray[np.float64], int | None]:
    """The patch's new vertices faired; as given when that fails or adds crossings (said in rec).

    ``added`` are the new vertices' positions (ids from ``around.size`` on).
    ``PATCH_PASSES`` solves, each with ``L`` taken where the one before left the patch;
    when the last adds crossings the earlier ones are tried, from the latest back. Also
    the crossings of the patch so returned, when they were counted (else None).

    The solve sees the patch and the faces within ``continuity + 1`` sweeps of its
    border: its operator reaches the faces within ``continuity + 1`` sweeps of the new
    vertices, and a path from a new vertex off the patch passes a border vertex.
    """
    first = around.size
    near = around.rings(np.unique(patch[patch < first]), continuity + 1)
    v, f, _, ids = around.local(near, patch, added)
    free = np.flatnonzero(ids >= first)  # local numbers of the new vertices, in id order
    tried = [added]
    at = v
    for _ in range(PATCH_PASSES):
        res = fair_vertices(at, f, free, continuity)
        if not res.ok:
            break
        at = res.vertices
        tried.append(at[free])
    if len(tried) == 1:
        rec.fair_reason = res.reason
        return added, None
    # the patch against the mesh and against itself (a fold within the patch counts too);
    # the refined patch's count matters only when a faired one has crossings
    before: int | None = None
    after = 0
    for faired in tried[:0:-1]:
        after = _crossings(around, patch, faired)
        if after and before is None:
            before = _crossings(around, patch, added)
        if not after or (before is not None and after <= before):
            rec.faired = True
            return faired, after
    rec.fair_reason = (
        f"the faired patch would cross the mesh ({after} crossings, {before} before); "
        f"the refined patch is kept"
    )
    return added, before


class _Edges:
    """Edges between boundary vertices that the mesh (or a patch so far) has."""

    def __init__(self, faces: Ints, loops: list[Loop], nv: int) -> None:
        self.nv = nv
        on_loop = np.zeros(nv, dtype=np.bool_)
        for lp in loops:
            on_loop[lp.vertices] = True
        from .._core import topology

        # a few, not every edge: each end's partners by end, so a loop looks up its own
        keys = topology.edges_among(np.ascontiguousarray(faces), nv, on_loop)
        a, b = np.divmod(keys, nv)
        ends, partners = np.concatenate([a, b]), np.concatenate([b, a])
        order = np.argsort(ends, kind="stable")
        self._ends, self._partners = ends[order], partners[order]
        self._added: dict[int, set[int]] = {}  # edges the patches made
        self._memo: tuple[bytes, Ints] = (b"", np.zeros(0, dtype=np.int64))

    def add(self, patch: Ints) -> None:
        a = patch.ravel()
        b = patch[:, [1, 2, 0]].ravel()
        old = (a < self.nv) & (b < self.nv)  # refinement's vertices are on no loop
        self._memo = (b"", self._memo[1])
        for x, y in zip(a[old].tolist(), b[old].tolist()):
            self._added.setdefault(x, set()).add(y)
            self._added.setdefault(y, set()).add(x)

    def keys_among(self, vertices: Ints) -> Ints:
        """Keys ``low * nv + high`` of the edges joining two of ``vertices``, ascending."""
        v = np.asarray(vertices, dtype=np.int64)
        memo = v.tobytes()  # a hole asks twice (its chords, then its refinement)
        if self._memo[0] != memo:
            self._memo = (memo, self._keys_among(v))
        return self._memo[1]

    def _keys_among(self, v: Ints) -> Ints:
        ends, partners = self._ends, self._partners
        if len(ends) > 8 * len(v) + 256:  # many loops: look up this one's ends only
            lo = np.searchsorted(ends, v, side="left")
            at = runs(lo, np.searchsorted(ends, v, side="right") - lo)
            ends, partners = ends[at], partners[at]
        on = set(v.tolist())
        nv = self.nv
        keys = {
            min(x, y) * nv + max(x, y)
            for x, y in zip(ends.tolist(), partners.tolist())
            if x in on and y in on
        }
        keys |= {
            min(p, q) * nv + max(p, q)
            for p in on & self._added.keys()
            for q in self._added[p]
            if q in on
        }
        return np.array(sorted(keys), dtype=np.int64)

    def pairs_among(self, loop: Ints) -> set[frozenset[int]]:
        """Vertex pairs of ``loop`` the mesh (or a patch so far) joins."""
        a, b = np.divmod(self.keys_among(loop), self.nv)
        return {frozenset((x, y)) for x, y in zip(a.tolist(), b.tolist())}

    def chords_of(self, loop: Ints) -> Ints:
        """Pairs of loop positions the mesh already joins, sides excluded."""
        n = len(loop)
        pos = {int(v): i for i, v in enumerate(loop.tolist())}
        a, b = np.divmod(self.keys_among(loop), self.nv)
        pairs = [(pos[x], pos[y]) for x, y in zip(a.tolist(), b.tolist())]
        out = np.array(pairs, dtype=np.int64).reshape(-1, 2)
        gap = np.abs(out[:, 0] - out[:, 1])
        return out[(gap != 1) & (gap != n - 1)]


def _fill_one(
    h: int,
    vertices: NDArray[np.float64],
    loop: Loop,
    joined: _Edges,
    max_hole_edges: int | None,
    weight: Any,
    method: str,
    islands: list[Loop],
) -> tuple[HoleRecord, Ints | None]:
    if islands:
        return _fill_group(h, vertices, [loop, *islands], joined, max_hole_edges, weight, method)
    n = len(loop.vertices)
    rec = HoleRecord(h, n, "filled", vertices=loop.vertices.tolist(), pinched=list(loop.pinched))
    if max_hole_edges is not None and n > max_hole_edges:
        return _left_open(rec, "skipped", f"{n} edges > max_hole_edges={max_hole_edges}"), None
    if n < 3:
        return _left_open(rec, "failed", f"a loop of {n} edges bounds no surface"), None
    forbidden = joined.chords_of(loop.vertices)
    rec.forbidden_chords = len(forbidden)
    start = time.perf_counter()
    points, third = vertices[loop.vertices], vertices[loop.third]
    try:
        tri = fill_polyline(points, weight, method, third, forbidden=forbidden)
    except NoTriangulationError as exc:
        if rec.forbidden_chords == 0:
            return _left_open(rec, "failed", str(exc)), None
        reason = (
            f"every patch would reuse one of the {rec.forbidden_chords} edges the mesh "
            f"already has between its vertices (the mesh would not stay edge-manifold)"
        )
        return _left_open(rec, "failed", reason), None
    except (InvalidPolygonError, TableTooLargeError) as exc:
        # this hole's geometry (e.g. collinear) or size: report it, fill the others
        return _left_open(rec, "failed", str(exc)), None
    rec.seconds = time.perf_counter() - start
    rec.weight, rec.method = tri.weight, tri.method
    rec.faces_added = len(tri.triangles)
    rec.degenerate = int(tri.stats.get("degenerate", 0))
    rec.degenerate_unavoidable = bool(tri.stats.get("degenerate_unavoidable", False))
    rec.candidates = str(tri.stats.get("candidates", ""))
    # fill_polyline winds (i, k, j), i < k < j, in the loop's (patch) order
    return rec, loop.vertices[tri.triangles]


def _fill_group(
    h: int,
    vertices: NDArray[np.float64],
    members: list[Loop],
    joined: _Edges,
    max_hole_edges: int | None,
    weight: Any,
    method: str,
) -> tuple[HoleRecord, Ints | None]:
    """A hole and its islands as one patch (:func:`optri.fill_polylines`)."""
    outer = members[0]
    ring = np.concatenate([lp.vertices for lp in members])
    n = len(ring)
    rec = HoleRecord(
        h,
        n,
        "filled",
        vertices=outer.vertices.tolist(),
        pinched=sorted({p for lp in members for p in lp.pinched}),
        islands=[lp.vertices.tolist() for lp in members[1:]],
    )
    if max_hole_edges is not None and n > max_hole_edges:
        reason = f"{n} edges with its islands > max_hole_edges={max_hole_edges}"
        return _left_open(rec, "skipped", reason), None
    forbidden = group_chords(joined.keys_among(ring), joined.nv, [lp.vertices for lp in members])
    rec.forbidden_chords = len(forbidden)
    start = time.perf_counter()
    points = [vertices[lp.vertices] for lp in members]
    third = [vertices[lp.third] for lp in members]
    mode = method if method in ISLAND_METHODS else "auto"
    try:
        tri = fill_polylines(points, weight, mode, third, forbidden=forbidden, orient=False)
    except (InvalidPolygonError, TableTooLargeError) as exc:  # NoTriangulationError too
        return _left_open(rec, "failed", str(exc)), None
    rec.seconds = time.perf_counter() - start
    rec.weight, rec.method = tri.weight, tri.method
    rec.optimality = tri.optimality or ""
    rec.faces_added = len(tri.triangles)
    rec.degenerate = int(tri.stats.get("degenerate", 0))
    return rec, ring[tri.triangles]


def _left_open(rec: HoleRecord, status: str, reason: str) -> HoleRecord:
    rec.status, rec.reason = status, reason
    warnings.warn(f"hole {rec.index} left open: {reason}", HoleSkippedWarning, stacklevel=4)
    return rec
