"""Cut and refill: optri's refined and faired patches against CGAL and MeshLib.

Holes of 20-400 boundary edges are cut from icospheres, tori, analytic height
fields (``z = sin x cos y``, a paraboloid) and real meshes (``tests/data/meshes``,
their own holes capped first), then refilled by

* optri: ``fill_holes(refine=True, fair=1)`` and ``fair=2``;
* CGAL: ``Polygon_mesh_processing.triangulate_refine_and_fair_hole`` (the ``cgal``
  wheel; Liepa's refinement, bi-Laplacian fairing);
* MeshLib: ``fillHoleNicely`` (the ``meshlib`` wheel; subdivision to the mean edge
  length of the mesh, ``smoothCurvature=True``).

Per hole and method: RMS and largest distance of the new vertices to the true
surface (analytic for spheres, tori and height fields; the removed faces for real
meshes), the smallest angle of a new face, the largest dihedral angle across the old
boundary (0 = the patch continues the mesh's tangent plane), crossings of new faces
with the rest of the mesh (:func:`optri.holes.intersect.intersecting_pairs`, the same
test for every method) and the time of the filling call alone (the peers' meshes are
built before their clock starts; optri's clock covers ``fill_holes`` on the whole mesh),
the fastest of ``--repeat`` calls (default 3, each peer on a fresh copy of its mesh).

    PYTHONPATH=src python benchmarks/bench_refill.py                     # 25 holes, ~7 CPU-minutes
    PYTHONPATH=src python benchmarks/bench_refill.py --sizes 20,100,400 --per-size 3
    PYTHONPATH=src python benchmarks/bench_refill.py --families sphere,torus --json out.json
    PYTHONPATH=src python benchmarks/bench_refill.py --seed 53,54,55         # 75 holes, three draws

Needs ``pip install cgal meshlib`` (benchmark only; a missing peer is left out).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import sys
import tempfile
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from optri import fill_holes
from optri.holes.boundary import trace_loops
from optri.holes.intersect import intersecting_pairs

ROOT = Path(__file__).resolve().parents[1]
REAL = ROOT / "tests" / "data" / "meshes"
FAMILIES = ("sphere", "torus", "sincos", "paraboloid", "real")
METHODS = ("optri-fair1", "optri-fair2", "cgal", "meshlib")
DEFAULT_SIZES = (20, 40, 80, 160, 320)

Distance = Callable[[np.ndarray], np.ndarray]


# ---------------------------------------------------------------- surfaces


@dataclass
class Surface:
    """A triangle mesh and, where known, the distance of any point to the surface it samples."""

    family: str
    name: str
    vertices: np.ndarray
    faces: np.ndarray
    distance: Distance | None = None  # None: measure against the removed faces


def icosphere(level: int) -> Surface:
    import trimesh

    m = trimesh.creation.icosphere(subdivisions=level)
    return Surface(
        "sphere",
        f"icosphere-{level}",
        np.asarray(m.vertices, dtype=np.float64),
        np.asarray(m.faces, dtype=np.int64),
        lambda p: np.abs(np.linalg.norm(p, axis=1) - 1.0),
    )


def torus(level: int, major: float = 1.0, minor: float = 0.4) -> Surface:
    nu, nv = 40 * 2**level, 16 * 2**level
    u, v = np.meshgrid(
        np.arange(nu) * 2 * np.pi / nu, np.arange(nv) * 2 * np.pi / nv, indexing="ij"
    )
    ring = major + minor * np.cos(v)
    pts = np.column_stack(
        [(ring * np.cos(u)).ravel(), (ring * np.sin(u)).ravel(), (minor * np.sin(v)).ravel()]
    )
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    a = i * nv + j
    b = ((i + 1) % nu) * nv + j
    c = ((i + 1) % nu) * nv + (j + 1) % nv
    d = i * nv + (j + 1) % nv
    faces = np.concatenate(
        [np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)]
    )

    def dist(p: np.ndarray) -> np.ndarray:
        return np.abs(np.hypot(np.hypot(p[:, 0], p[:, 1]) - major, p[:, 2]) - minor)

    return Surface("torus", f"torus-{nu}x{nv}", pts, faces.astype(np.int64), dist)


def height_field(kind: str, level: int) -> Surface:
    """A grid over a square; ``kind`` is ``"sincos"`` or ``"paraboloid"``."""
    if kind == "sincos":
        half = math.pi

        def h(x, y):
            return np.sin(x) * np.cos(y), np.cos(x) * np.cos(y), -np.sin(x) * np.sin(y)
    else:
        half = 1.5

        def h(x, y):
            return 0.4 * (x * x + y * y), 0.8 * x, 0.8 * y

    n = 30 * 2**level + 1
    g = np.linspace(-half, half, n)
    x, y = np.meshgrid(g, g, indexing="ij")
    pts = np.column_stack([x.ravel(), y.ravel(), h(x, y)[0].ravel()])
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    a, b, c, d = i * n + j, (i + 1) * n + j, (i + 1) * n + j + 1, i * n + j + 1
    faces = np.concatenate(
        [np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)]
    )

    def dist(p: np.ndarray) -> np.ndarray:
        # closest point (u, v, h(u, v)) by Gauss-Newton on the residual (u - x, v - y, h - z)
        u, v = p[:, 0].copy(), p[:, 1].copy()
        for _ in range(30):
            z, hu, hv = h(u, v)
            r = np.stack([u - p[:, 0], v - p[:, 1], z - p[:, 2]], 1)
            a11, a12, a22 = 1 + hu * hu, hu * hv, 1 + hv * hv
            g1, g2 = r[:, 0] + hu * r[:, 2], r[:, 1] + hv * r[:, 2]
            det = a11 * a22 - a12 * a12
            u = u - (a22 * g1 - a12 * g2) / det
            v = v - (a11 * g2 - a12 * g1) / det
        z = h(u, v)[0]
        return np.linalg.norm(np.stack([u, v, z], 1) - p, axis=1)

    return Surface(kind, f"{kind}-{n}x{n}", pts, faces.astype(np.int64), dist)


def real_mesh(path: Path, level: int) -> Surface:
    """A mesh of ``tests/data/meshes``, holes capped flat, split ``level`` times at midpoints."""
    from optri.io.meshes import read_mesh

    m = read_mesh(path)
    v, f = np.asarray(m.vertices, dtype=np.float64), np.asarray(m.faces, dtype=np.int64)
    if trace_loops(f):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            (v, f), _ = fill_holes((v, f))
    for _ in range(level):
        v, f = midpoint_split(v, f)
    return Surface("real", f"{path.stem}-x{4**level}", v, f, None)


def midpoint_split(v: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each triangle into four at its edge midpoints (the surface does not move)."""
    e = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    uniq, inv = np.unique(e, axis=0, return_inverse=True)
    mid = len(v) + inv.reshape(3, -1).T  # midpoints of (0,1), (1,2), (2,0)
    v2 = np.concatenate([v, 0.5 * (v[uniq[:, 0]] + v[uniq[:, 1]])])
    a, b, c = f.T
    ab, bc, ca = mid.T
    f2 = np.concatenate(
        [np.stack(t, 1) for t in ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))]
    )
    return v2, f2


def surface(family: str, level: int) -> list[Surface]:
    if family == "sphere":
        return [icosphere(level + 3)]
    if family == "torus":
        return [torus(level)]
    if family in ("sincos", "paraboloid"):
        return [height_field(family, level)]
    return [real_mesh(REAL / name, level) for name in ("pmp_hemisphere.off", "tm_quadknot.obj")]


# ---------------------------------------------------------------- holes


@dataclass
class Hole:
    """A holed mesh (unused vertices dropped) and what was cut."""

    surface: Surface
    vertices: np.ndarray
    faces: np.ndarray  # the faces kept
    removed: np.ndarray  # the faces cut, over ``vertices``' numbering (-1: a dropped vertex)
    removed_points: np.ndarray  # (k, 3, 3) corners of the faces cut
    loop: np.ndarray  # the hole's boundary, vertex ids of the holed mesh
    other_loops: int  # boundary loops the holed mesh had before the cut

    @property
    def edges(self) -> int:
        return len(self.loop)


def _edge_face_count(faces: np.ndarray) -> dict[tuple[int, int], int]:
    count: dict[tuple[int, int], int] = {}
    for a, b, c in faces.tolist():
        for x, y in ((a, b), (b, c), (c, a)):
            k = (x, y) if x < y else (y, x)
            count[k] = count.get(k, 0) + 1
    return count


def cut_hole(s: Surface, target: int, rng: np.random.Generator, tries: int = 20) -> Hole | None:
    """A disk-shaped hole of at least ``target`` boundary edges around a random vertex.

    Faces are taken in order of their centroid's distance to the centre until the cut's
    boundary has ``target`` edges; the cut must be a topological disk (one boundary loop,
    Euler characteristic 1), away from the mesh's own borders, and at most a quarter of
    the faces. None when no try succeeds.
    """
    v, f = s.vertices, s.faces
    border = np.zeros(len(v), dtype=bool)
    for lp in trace_loops(f):
        border[lp.vertices] = True
    centroid = v[f].mean(axis=1)
    for _ in range(tries):
        centre = v[rng.integers(len(v))]
        if border.any() and np.linalg.norm(v[border] - centre, axis=1).min() < 1e-9:
            continue
        order = np.argsort(np.linalg.norm(centroid - centre, axis=1))
        k = 4
        while k <= len(f) // 4:
            cut = f[order[:k]]
            bnd = [e for e, c in _edge_face_count(cut).items() if c == 1]
            if len(bnd) >= target:
                break
            k = max(k + 1, int(k * 1.08))
        else:
            continue
        if border[cut].any():
            continue
        verts = np.unique(cut)
        n_edges = len(_edge_face_count(cut))
        if len(verts) - n_edges + len(cut) != 1:
            continue
        deg = np.bincount(np.asarray(bnd).ravel(), minlength=len(v))
        if np.any(deg > 2):
            continue  # the boundary touches itself
        keep = np.ones(len(f), dtype=bool)
        keep[order[:k]] = False
        kept = f[keep]
        used = np.unique(kept)
        renum = np.full(len(v), -1)
        renum[used] = np.arange(len(used))
        kept = renum[kept]
        loops = trace_loops(kept)
        bset = set(np.asarray(bnd).ravel().tolist())
        mine = [lp for lp in loops if renum[list(bset)[0]] in set(lp.vertices.tolist())]
        if len(mine) != 1 or len(mine[0].vertices) != len(bnd):
            continue
        return Hole(s, v[used], kept, renum[cut], v[cut], mine[0].vertices, len(loops) - 1)
    return None


# ---------------------------------------------------------------- refills


@dataclass
class Refill:
    """The refilled mesh: old vertices first, new after; old faces first, new after."""

    method: str
    vertices: np.ndarray
    faces: np.ndarray
    old_faces: int
    seconds: float
    error: str = ""
    notes: dict = field(default_factory=dict)


#: Each filling call is timed this many times (on a fresh copy of the peers' meshes: they
#: fill in place) and the fastest counts, as ``timeit`` does: a single millisecond-scale
#: call on a shared machine measures the machine as much as the method.
REPEAT = 3


def refill_optri(hole: Hole, fair: int) -> Refill:
    seconds = math.inf
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # other (larger) borders are left open, and said so
        for _ in range(REPEAT):
            start = time.perf_counter()
            (v, f), records = fill_holes(
                (hole.vertices, hole.faces), max_hole_edges=hole.edges, refine=True, fair=fair
            )
            seconds = min(seconds, time.perf_counter() - start)
    rec = [r for r in records if r.status == "filled"]
    notes = {"fair_reason": rec[0].fair_reason} if rec and rec[0].fair_reason else {}
    return Refill(f"optri-fair{fair}", v, f, len(hole.faces), seconds, notes=notes)


def _write_off(path: str, v: np.ndarray, f: np.ndarray) -> None:
    with open(path, "w") as fh:
        fh.write(f"OFF\n{len(v)} {len(f)} 0\n")
        np.savetxt(fh, v, fmt="%.17g")
        np.savetxt(fh, np.column_stack([np.full(len(f), 3), f]), fmt="%d")


def _order_like(hole: Hole, v: np.ndarray, f: np.ndarray, method: str, seconds: float) -> Refill:
    """A peer's output renumbered: the holed mesh's vertices and faces first, as given."""
    n = len(hole.vertices)
    from scipy.spatial import cKDTree

    dist, near = cKDTree(v).query(hole.vertices)
    if np.any(dist > 1e-5 * max(1.0, float(np.abs(hole.vertices).max()))):
        return Refill(
            method, hole.vertices, hole.faces, len(hole.faces), seconds, "an old vertex moved"
        )
    renum = np.full(len(v), -1)
    renum[near] = np.arange(n)
    new = np.flatnonzero(renum < 0)
    renum[new] = n + np.arange(len(new))
    verts = np.concatenate([hole.vertices, v[new]])
    faces = renum[f]
    old = {tuple(sorted(t)) for t in hole.faces.tolist()}
    is_old = np.array([tuple(sorted(t)) in old for t in faces.tolist()], dtype=bool)
    # an old face the peer split (MeshLib splits long hole sides) counts as new
    faces = np.concatenate([faces[is_old], faces[~is_old]])
    notes = (
        {"old_faces_changed": len(hole.faces) - int(is_old.sum())}
        if is_old.sum() < len(hole.faces)
        else {}
    )
    return Refill(method, verts, faces, int(is_old.sum()), seconds, notes=notes)


def refill_cgal(hole: Hole) -> Refill:
    from CGAL import CGAL_Polygon_mesh_processing as pmp
    from CGAL.CGAL_Polyhedron_3 import Polyhedron_3

    seconds = math.inf
    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.join(tmp, "in.off")
        _write_off(src, hole.vertices, hole.faces)
        ends = {tuple(map(float, hole.vertices[hole.loop[i]])) for i in (0, 1)}
        for _ in range(REPEAT):
            poly = Polyhedron_3(src)  # filled in place: a fresh mesh each time
            border = None
            for h in poly.halfedges():  # the border halfedge along the hole's first side
                if h.is_border():
                    p, q = h.vertex().point(), h.opposite().vertex().point()
                    if {(p.x(), p.y(), p.z()), (q.x(), q.y(), q.z())} == ends:
                        border = h
                        break
            if border is None:
                return Refill(
                    "cgal", hole.vertices, hole.faces, len(hole.faces), 0.0, "no border halfedge"
                )
            facets: list = []
            verts: list = []
            start = time.perf_counter()
            pmp.triangulate_refine_and_fair_hole(poly, border, facets, verts)
            seconds = min(seconds, time.perf_counter() - start)
    # read back through the handles (the OFF writer rounds to 6 digits)
    coords = []
    for i, vh in enumerate(poly.vertices()):
        vh.set_id(i)
        p = vh.point()
        coords.append((p.x(), p.y(), p.z()))
    tris = []
    for fh in poly.facets():
        h = fh.halfedge()
        tris.append((h.vertex().id(), h.next().vertex().id(), h.next().next().vertex().id()))
    v, f = np.array(coords), np.array(tris, dtype=np.int64)
    return _order_like(hole, v, f, "cgal", seconds)


def refill_meshlib(hole: Hole) -> Refill:
    import meshlib.mrmeshnumpy as mn
    import meshlib.mrmeshpy as mm

    loop_pts = {tuple(np.float32(x) for x in p) for p in hole.vertices[hole.loop]}
    settings = mm.FillHoleNicelySettings()
    settings.triangulateOnly = False
    settings.smoothCurvature = True
    side = hole.vertices[hole.faces[:, [1, 2, 0]]] - hole.vertices[hole.faces]
    settings.subdivideSettings.maxEdgeLen = float(np.linalg.norm(side, axis=2).mean())
    settings.subdivideSettings.maxEdgeSplits = 10**7
    seconds = math.inf
    for _ in range(REPEAT):  # filled in place: a fresh mesh each time
        mesh = mn.meshFromFacesVerts(hole.faces.astype(np.int32), hole.vertices.astype(np.float32))
        pick = None
        for e in mesh.topology.findHoleRepresentiveEdges():
            org = mesh.topology.org(e)
            p = mesh.points.vec[org.get()]
            if (np.float32(p.x), np.float32(p.y), np.float32(p.z)) in loop_pts:
                pick = e
                break
        if pick is None:
            return Refill(
                "meshlib", hole.vertices, hole.faces, len(hole.faces), 0.0, "no hole edge"
            )
        start = time.perf_counter()
        mm.fillHoleNicely(mesh, pick, settings)
        seconds = min(seconds, time.perf_counter() - start)
    mesh.pack()
    v = np.asarray(mn.getNumpyVerts(mesh), dtype=np.float64)
    f = np.asarray(mn.getNumpyFaces(mesh.topology), dtype=np.int64)
    # float32 positions: snap the old vertices back to their float64 values
    return _order_like(hole, v, f, "meshlib", seconds)


# ---------------------------------------------------------------- measures


def point_triangle_distance(
    points: np.ndarray, tris: np.ndarray, chunk: int = 200_000
) -> np.ndarray:
    """Distance of each point to the nearest of ``tris`` ((k, 3, 3)), brute force in chunks."""
    out = np.full(len(points), np.inf)
    step = max(1, chunk // max(1, len(tris)))
    a, b, c = tris[:, 0], tris[:, 1], tris[:, 2]
    ab, ac = b - a, c - a
    for s in range(0, len(points), step):
        p = points[s : s + step, None, :]
        # closest point on each triangle (Ericson, Real-Time Collision Detection, 5.1.5),
        # as the nearest of the plane projection (when inside) and the three sides
        n = np.cross(ab, ac)
        nn = np.einsum("ij,ij->i", n, n)
        t = np.einsum("pkj,kj->pk", p - a, n) / np.where(nn > 0, nn, 1)
        proj = p - t[..., None] * n
        w = proj - a
        d00, d01, d11 = (ab * ab).sum(1), (ab * ac).sum(1), (ac * ac).sum(1)
        d20, d21 = np.einsum("pkj,kj->pk", w, ab), np.einsum("pkj,kj->pk", w, ac)
        den = d00 * d11 - d01 * d01
        den = np.where(den != 0, den, 1)
        bv, bw = (d11 * d20 - d01 * d21) / den, (d00 * d21 - d01 * d20) / den
        inside = (bv >= 0) & (bw >= 0) & (bv + bw <= 1) & (nn > 0)
        best = np.where(inside, np.linalg.norm(p - proj, axis=2), np.inf)
        for q0, q1 in ((a, b), (b, c), (c, a)):
            d = q1 - q0
            dd = np.maximum((d * d).sum(1), 1e-300)
            tt = np.clip(np.einsum("pkj,kj->pk", p - q0, d) / dd, 0, 1)
            best = np.minimum(best, np.linalg.norm(p - (q0 + tt[..., None] * d), axis=2))
        out[s : s + step] = best.min(axis=1)
    return out


def min_angle(v: np.ndarray, f: np.ndarray) -> float:
    """Smallest corner angle of the faces, degrees."""
    if len(f) == 0:
        return float("nan")
    p = v[f]
    best = np.inf
    for c in range(3):
        a, b = p[:, (c + 1) % 3] - p[:, c], p[:, (c + 2) % 3] - p[:, c]
        cos = np.einsum("ij,ij->i", a, b) / np.maximum(
            np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1), 1e-300
        )
        best = min(best, float(np.degrees(np.arccos(np.clip(cos, -1, 1))).min()))
    return best


def boundary_dihedral(r: Refill) -> float:
    """Largest angle (degrees) between the normals of an old and a new face sharing an edge."""
    v, f = r.vertices, r.faces
    normal = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
    sides: dict[tuple[int, int], list[int]] = {}
    for t, (a, b, c) in enumerate(f.tolist()):
        for x, y in ((a, b), (b, c), (c, a)):
            sides.setdefault((min(x, y), max(x, y)), []).append(t)
    worst = 0.0
    for ts in sides.values():
        old = [t for t in ts if t < r.old_faces]
        new = [t for t in ts if t >= r.old_faces]
        if old and new:
            cos = float(np.clip(normal[old[0]] @ normal[new[0]], -1, 1))
            worst = max(worst, math.degrees(math.acos(cos)))
    return worst


def measure(hole: Hole, r: Refill) -> dict:
    row = {
        "family": hole.surface.family,
        "mesh": hole.surface.name,
        "edges": hole.edges,
        "method": r.method,
        "seconds": r.seconds,
    }
    if r.error:
        row["error"] = r.error
        return row
    new_v = r.vertices[len(hole.vertices) :]
    new_f = r.faces[r.old_faces :]
    if hole.surface.distance is not None:
        d = hole.surface.distance(new_v) if len(new_v) else np.zeros(0)
    else:
        d = point_triangle_distance(new_v, hole.removed_points) if len(new_v) else np.zeros(0)
    row.update(
        new_vertices=len(new_v),
        new_faces=len(new_f),
        rms=float(np.sqrt(np.mean(d * d))) if len(d) else 0.0,
        max=float(d.max()) if len(d) else 0.0,
        min_angle=min_angle(r.vertices, new_f),
        dihedral=boundary_dihedral(r),
        crossings=len(intersecting_pairs(r.vertices, r.faces, new_f)),
        **r.notes,
    )
    return row


def peers() -> dict[str, Callable[[Hole], Refill]]:
    out: dict[str, Callable[[Hole], Refill]] = {
        "optri-fair1": lambda h: refill_optri(h, 1),
        "optri-fair2": lambda h: refill_optri(h, 2),
    }
    try:
        import CGAL.CGAL_Polygon_mesh_processing  # noqa: F401

        out["cgal"] = refill_cgal
    except ImportError:
        pass
    try:
        import meshlib.mrmeshpy  # noqa: F401

        out["meshlib"] = refill_meshlib
    except ImportError:
        pass
    return out


# ---------------------------------------------------------------- the run


def run(
    families, sizes, per_size: int, seed: int, max_level: int, log=print, first_hole: int = 0
) -> list[dict]:
    rng = np.random.default_rng(seed)
    methods = peers()
    rows: list[dict] = []
    hole_id = first_hole
    for family in families:
        for size in sizes:
            done = 0
            for level in range(max_level + 1):
                for s in surface(family, level):
                    while done < per_size:
                        hole = cut_hole(s, size, rng)
                        if hole is None:
                            break
                        for fn in methods.values():
                            row = measure(hole, fn(hole))
                            row["size"], row["hole"], row["seed"] = size, hole_id, seed
                            rows.append(row)
                            log(
                                json.dumps(
                                    {
                                        k: (round(x, 6) if isinstance(x, float) else x)
                                        for k, x in row.items()
                                    }
                                )
                            )
                        done += 1
                        hole_id += 1
                if done >= per_size:
                    break
            if done < per_size:
                log(
                    f"# {family}: {per_size - done} holes of {size} edges not cut "
                    f"up to level {max_level}"
                )
    return rows


def _median(xs: list[float]) -> float:
    return statistics.median(xs) if xs else float("nan")


COLUMNS = (
    "family",
    "method",
    "holes",
    "edges",
    "RMS",
    "max dist",
    "min angle",
    "dihedral",
    "crossings",
    "ms",
    "RMS <= CGAL",
    "RMS <= MeshLib",
)


def summarize(rows: list[dict]) -> str:
    """A Markdown table: per family and method, medians over holes, crossings, win rates."""
    holes = _group_holes(rows)
    lines = ["| " + " | ".join(COLUMNS) + " |", "|---" * len(COLUMNS) + "|"]
    for family in dict.fromkeys(r["family"] for r in rows):
        for method in dict.fromkeys(r["method"] for r in rows):
            rs = [r for r in rows if r["family"] == family and r["method"] == method]
            rs = [r for r in rs if "error" not in r]
            if not rs:
                continue
            wins = []
            for peer in ("cgal", "meshlib"):
                pairs = [
                    (h[method]["rms"], h[peer]["rms"])
                    for h in holes
                    if "rms" in h.get(method, {})
                    and "rms" in h.get(peer, {})
                    and h[method]["family"] == family
                ]
                won = sum(a <= b for a, b in pairs)
                wins.append(f"{won}/{len(pairs)}" if pairs and method != peer else "")

            def med(key: str, rs: list[dict] = rs) -> float:
                return _median([r[key] for r in rs])

            cells = [
                family,
                method,
                str(len(rs)),
                f"{med('edges'):.0f}",
                f"{med('rms'):.2e}",
                f"{med('max'):.2e}",
                f"{med('min_angle'):.1f}",
                f"{med('dihedral'):.1f}",
                str(sum(r["crossings"] for r in rs)),
                f"{1000 * med('seconds'):.1f}",
                *wins,
            ]
            lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _group_holes(rows: list[dict]) -> list[dict[str, dict]]:
    """The rows of each hole, by method."""
    holes: dict[int, dict[str, dict]] = {}
    for r in rows:
        holes.setdefault(r["hole"], {})[r["method"]] = r
    return list(holes.values())


def totals(rows: list[dict]) -> str:
    """The issue's targets over every hole."""
    holes = _group_holes(rows)
    out = []
    for method in ("optri-fair1", "optri-fair2"):
        both = [h for h in holes if "rms" in h.get(method, {}) and "rms" in h.get("cgal", {})]
        if both:
            win = sum(h[method]["rms"] <= h["cgal"]["rms"] for h in both)
            faster = sum(h[method]["seconds"] <= h["cgal"]["seconds"] for h in both)
            t_ratio = _median(
                [h[method]["seconds"] / max(h["cgal"]["seconds"], 1e-9) for h in both]
            )
            # all holes filled one after another: the time a user filling them all waits
            t_total = sum(h[method]["seconds"] for h in both) / max(
                sum(h["cgal"]["seconds"] for h in both), 1e-9
            )
            out.append(
                f"{method}: RMS <= CGAL's on {win}/{len(both)} holes "
                f"({100 * win / len(both):.0f} %), "
                f"time <= CGAL's on {faster}/{len(both)}, median time ratio {t_ratio:.2f}, "
                f"total time ratio {t_total:.2f}"
            )
    for method in METHODS:
        rs = [h[method] for h in holes if "crossings" in h.get(method, {})]
        if rs:
            out.append(
                f"{method}: {sum(r['crossings'] for r in rs)} crossings over {len(rs)} holes"
            )
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    global REPEAT
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--families", default=",".join(FAMILIES))
    ap.add_argument(
        "--sizes", default=",".join(map(str, DEFAULT_SIZES)), help="target boundary edges"
    )
    ap.add_argument("--per-size", type=int, default=1, help="holes per family and size")
    ap.add_argument("--max-level", type=int, default=3, help="finest mesh level tried for a size")
    ap.add_argument(
        "--seed", default="53", help="the holes' random draw; several (53,54,55) run one by one"
    )
    ap.add_argument("--json", help="write every row here")
    ap.add_argument("--quiet", action="store_true", help="no line per hole")
    ap.add_argument("--repeat", type=int, default=3, help="calls timed per method and hole")
    args = ap.parse_args(argv)
    REPEAT = max(1, args.repeat)
    families = [x for x in args.families.split(",") if x]
    bad = set(families) - set(FAMILIES)
    if bad:
        ap.error(f"unknown families {sorted(bad)}; choose from {', '.join(FAMILIES)}")
    sizes = [int(x) for x in args.sizes.split(",")]
    try:
        seeds = [int(x) for x in args.seed.split(",") if x]
    except ValueError:
        ap.error(f"--seed takes integers separated by commas, got {args.seed!r}")
    start = time.perf_counter()
    rows: list[dict] = []
    for seed in seeds:
        rows += run(
            families,
            sizes,
            args.per_size,
            seed,
            args.max_level,
            log=(lambda *_: None) if args.quiet else print,
            first_hole=1 + max((r["hole"] for r in rows), default=-1),
        )
    print()
    print(summarize(rows))
    print()
    print(totals(rows))
    load = os.getloadavg()
    print(
        f"\nload average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f} on {os.cpu_count()} cpus; "
        f"{time.perf_counter() - start:.0f} s; python {sys.version.split()[0]}"
    )
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
