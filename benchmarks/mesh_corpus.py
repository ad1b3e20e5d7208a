"""Fill every mesh of a folder and check the result: a manifold stays a manifold.

For each mesh file and each method it reports the border cycles found, the
holes filled, edges used by more than two faces that were not before, new
zero-area faces, and whether the result is watertight (trimesh's test). The
checks are written here, independently of optri's own code.

    PYTHONPATH=src python benchmarks/mesh_corpus.py [FOLDER ...] [--methods auto,liepa,delaunay]
    PYTHONPATH=src python benchmarks/mesh_corpus.py benchmarks/data --cut z:0.5   # big ragged holes

Default folder: tests/data/external (see tests/data/README.md for where the
files come from). Run it with an older optri on PYTHONPATH for "before" figures.
"""

from __future__ import annotations

import argparse
import collections
import json
import time
import warnings
from pathlib import Path

import numpy as np

from optri import fill_holes
from optri.errors import OptriError
from optri.io.meshes import read_mesh

SUFFIXES = {".obj", ".off", ".ply", ".stl"}


def edge_counts(faces: np.ndarray) -> collections.Counter:
    """Faces per undirected edge."""
    count: collections.Counter = collections.Counter()
    for a, b, c in faces.tolist():
        for x, y in ((a, b), (b, c), (c, a)):
            count[(min(x, y), max(x, y))] += 1
    return count


def zero_area(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Faces whose sine at the first corner is <= 1e-12 (or that repeat a vertex)."""
    p = vertices[faces]
    u, v = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    cross = np.linalg.norm(np.cross(u, v), axis=1)
    size = np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1)
    return (cross <= 1e-12 * size) | (size == 0)


def load_exact(path: Path):
    """The mesh with exactly equal positions merged (any optri version fills the same mesh)."""
    import trimesh

    m = trimesh.load(path, force="mesh", process=False)
    _, first, inverse = np.unique(m.vertices, axis=0, return_index=True, return_inverse=True)
    faces = inverse.reshape(-1)[np.asarray(m.faces)]
    faces = faces[
        (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])
    ]
    return trimesh.Trimesh(np.asarray(m.vertices)[first], faces, process=False)


def cut(mesh, spec: str):
    """The mesh without its faces below a plane: ``"z:0.5"`` = below the median height."""
    import trimesh

    axis, q = "xyz".index(spec[0]), float(spec.split(":")[1])
    height = np.asarray(mesh.triangles_center)[:, axis]
    keep = np.asarray(mesh.faces)[height >= np.quantile(height, q)]
    return trimesh.Trimesh(np.asarray(mesh.vertices), keep, process=False)


def check(path: Path, method: str, loader: str = "optri", plane: str = "") -> dict:
    row: dict = {"mesh": path.name + (f" cut {plane}" if plane else ""), "method": method}
    try:
        mesh = read_mesh(path) if loader == "optri" else load_exact(path)
    except (OptriError, ValueError) as exc:
        row["error"] = f"load: {exc}"
        return row
    if plane:
        mesh = cut(mesh, plane)
    v, before = np.asarray(mesh.vertices), np.asarray(mesh.faces)
    start = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            filled, records = fill_holes(mesh, method=method)
    except OptriError as exc:
        row["error"] = f"fill: {str(exc)[:90]}"
        return row
    row["seconds"] = round(time.perf_counter() - start, 3)
    after = np.asarray(filled.faces)
    old, new = edge_counts(before), edge_counts(after)
    added = after[len(before) :]
    row.update(
        holes=len(records),
        filled=sum(r.status == "filled" for r in records),
        pinched_loops=sum(bool(getattr(r, "pinched", [])) for r in records),
        new_nonmanifold_edges=sum(1 for e, c in new.items() if c > 2 and old.get(e, 0) <= 2),
        new_zero_area_faces=int(zero_area(v, added).sum()) if len(added) else 0,
        open_edges_after=sum(1 for c in new.values() if c == 1),
        watertight=bool(filled.is_watertight),
    )
    return row


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folders", nargs="*", default=["tests/data/external"], help="folders or files")
    ap.add_argument("--methods", default="auto,liepa,delaunay")
    ap.add_argument("--json", help="write the rows here")
    ap.add_argument("--cut", default="", help="first remove the faces below a plane, e.g. z:0.5")
    ap.add_argument(
        "--loader",
        choices=("optri", "exact"),
        default="optri",
        help="optri.io.read_mesh, or trimesh + exact-position merging done here",
    )
    args = ap.parse_args()
    paths = [p for f in map(Path, args.folders) for p in ([f] if f.is_file() else f.glob("*"))]
    files = sorted(p for p in paths if p.suffix.lower() in SUFFIXES)
    rows = []
    for path in files:
        for method in args.methods.split(","):
            row = check(path, method, args.loader, args.cut)
            rows.append(row)
            print(json.dumps(row), flush=True)
    ok = [r for r in rows if "error" not in r]
    print(
        f"\n{len(files)} meshes x {len(args.methods.split(','))} methods: "
        f"{sum(r['filled'] for r in ok)} of {sum(r['holes'] for r in ok)} holes filled, "
        f"{sum(r['watertight'] for r in ok)} of {len(rows)} results watertight, "
        f"{sum(r['new_nonmanifold_edges'] > 0 for r in ok)} with new non-manifold edges, "
        f"{sum(r['new_zero_area_faces'] for r in ok)} new zero-area faces, "
        f"{len(rows) - len(ok)} errors"
    )
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
