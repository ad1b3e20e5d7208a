"""``optri fill``: fill the holes of a mesh file with optimal patches."""

from __future__ import annotations

import json
import sys
import warnings
from typing import Any

import click
import numpy as np

from .. import config
from ..errors import HoleSkippedWarning, InvalidPolygonError
from ..holes import METHODS, HoleRecord, fill_holes
from ..holes.boundary import edge_summary
from ..io.meshes import mesh_format, read_mesh, write_mesh
from ..meshdata import weld
from .app import main
from .options import input_path, output_option
from .progress import compile_notice, progress_bar
from .stdin import mesh_input


def _summary(rec: HoleRecord) -> str:
    w = rec.weight
    if isinstance(w, tuple):
        value = f"max dihedral {w[0]:.6g} rad, area {w[1]:.6g}"
    else:
        value = "" if w is None else f"weight {w:.6g}"
    extra = rec.detail()
    extra = f"; {extra}" if extra else ""
    if rec.status == "filled":
        return (
            f"hole {rec.index}: {rec.edges} edges, filled with {rec.faces_added} faces "
            f"({rec.method}; {value}; {rec.seconds:.3f} s{extra})"
        )
    return f"hole {rec.index}: {rec.edges} edges, {rec.status.upper()}: {rec.reason}"


def _welded_edges(mesh: Any, rtol: float | None) -> dict[str, int]:
    """:func:`edge_summary` of the mesh welded by position (seams are no boundary)."""
    rtol = config.MESH_MERGE_RTOL if rtol is None else rtol
    return edge_summary(weld(np.asarray(mesh.vertices), np.asarray(mesh.faces), rtol))


def _watertight(mesh: Any, rtol: float | None) -> bool:
    """Every edge of the mesh welded by position has two faces."""
    counts = _welded_edges(mesh, rtol)
    return counts["boundary"] == 0 and counts["nonmanifold"] == 0


def _check_has_holes(mesh: Any, rtol: float | None) -> None:
    """Refuse a mesh that is not closed although no hole boundary can be traced."""
    counts = _welded_edges(mesh, rtol)
    if counts["boundary"] == 0 and counts["nonmanifold"] > 0:
        raise InvalidPolygonError(
            f"the mesh is not closed but has no hole to fill: {counts['nonmanifold']} edges "
            f"are shared by three or more faces (non-manifold), none by a single face; "
            f"nothing was written"
        )


@main.command()
@click.argument("infile", type=input_path)
@output_option("file", "Output mesh (.obj, .ply, .stl, .off).  [required]")
@click.option(
    "--weight",
    "-w",
    default="liepa",
    show_default=True,
    help="liepa (max dihedral, then area), area, perimeter, or any optri weight.",
)
@click.option(
    "--method",
    "-m",
    default="auto",
    show_default=True,
    type=click.Choice(METHODS),
    help="exact (all triangulations), liepa (O(n^3) recurrence), delaunay, auto.",
)
@click.option("--max-hole-edges", type=click.IntRange(min=3), help="Leave larger holes open.")
@click.option(
    "--merge-tolerance",
    type=click.FloatRange(min=0.0, max=1.0),
    default=None,
    help="Merge vertices closer than this fraction of the mesh's size "
    "[default: 0, exactly equal positions only]. Copies with different texture "
    "coordinates, normals or colours are kept and welded only to find holes.",
)
@click.option(
    "--refine",
    is_flag=True,
    help="Refine each patch to the density of the mesh around it (Liepa's splits).",
)
@click.option(
    "--fair",
    type=click.IntRange(0, 2),
    default=None,
    help="Fair the refined patch: continuity 0 (membrane), 1 (thin plate) or 2 "
    "(curvature) at the hole's border. Needs --refine.",
)
@click.option(
    "--density",
    type=click.FloatRange(min=0.0, min_open=True),
    default=2**0.5,
    show_default="sqrt(2)",
    help="Refinement density: larger gives smaller triangles.",
)
@click.option(
    "--no-islands",
    "no_islands",
    is_flag=True,
    help="Fill every boundary loop on its own, even a loop of another piece lying "
    "inside a hole (by default such islands are filled with the hole as one patch).",
)
@click.option("--strict", is_flag=True, help="Exit 1 if a hole is left open.")
@click.option("--json", "as_json", is_flag=True, help="Print the report as one JSON object.")
@click.option("--quiet", "-q", is_flag=True, help="No progress bar.")
def fill(
    infile: str,
    output: str,
    weight: str,
    method: str,
    max_hole_edges: int | None,
    merge_tolerance: float | None,
    refine: bool,
    fair: int | None,
    density: float,
    no_islands: bool,
    strict: bool,
    as_json: bool,
    quiet: bool,
) -> None:
    """Fill the holes of the mesh in INFILE (.obj/.ply/.stl/.off; - for stdin), write OUTPUT.

    Texture coordinates, normals and colours are kept (new vertices get interpolated
    ones); a textured OBJ gets its material and texture image beside OUTPUT.
    """
    mesh_format(output, "output")  # refuse an unknown output suffix before any work
    if fair is not None and not refine:
        raise click.UsageError("--fair moves the vertices --refine adds: give --refine too")
    with mesh_input(infile) as path:
        mesh = read_mesh(path, merge_tolerance)
    _check_has_holes(mesh, merge_tolerance)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", HoleSkippedWarning)
        with (
            compile_notice(not quiet),
            progress_bar("filling holes", not quiet) as progress,
        ):
            filled, records = fill_holes(
                mesh,
                max_hole_edges=max_hole_edges,
                weight=weight,
                method=method,
                refine=refine,
                fair=fair,
                density=density,
                islands=not no_islands,
                merge_rtol=merge_tolerance,
                progress=progress,
            )
    for w in caught:  # skipped holes: never silent, one stderr line each
        if issubclass(w.category, HoleSkippedWarning):
            click.echo(f"optri: warning: {w.message}", err=True)
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    if records and not any(r.status == "filled" for r in records):
        skipped = [r for r in records if r.status == "skipped"]
        if not skipped:
            raise InvalidPolygonError(
                f"none of the {len(records)} holes could be filled ({records[0].reason}); "
                f"nothing was written"
            )
    write_mesh(filled, output)
    _report(infile, output, mesh, filled, records, as_json, _watertight(filled, merge_tolerance))
    if strict and any(r.status != "filled" for r in records):
        sys.exit(1)


def _report(
    infile: str,
    output: str,
    mesh: Any,
    filled: Any,
    records: list[HoleRecord],
    as_json: bool,
    watertight: bool,
) -> None:
    loaded = mesh.metadata.get("optri", {})
    if as_json:
        report = {
            "input": infile,
            "output": output,
            "faces_before": int(len(mesh.faces)),
            "faces_after": int(len(filled.faces)),
            "watertight": watertight,
            "merged_vertices": int(loaded.get("merged_vertices", 0)),
            "dropped_faces": int(loaded.get("dropped_faces", 0)),
            "holes": [r.to_dict() for r in records],
        }
        click.echo(json.dumps(report))
        return
    for rec in records:
        click.echo(_summary(rec))
    done = sum(r.status == "filled" for r in records)
    merged = ""
    if loaded.get("merged_vertices") or loaded.get("dropped_faces"):
        merged = (
            f" (loading merged {loaded.get('merged_vertices', 0)} duplicate vertices, dropped "
            f"{loaded.get('dropped_faces', 0)} zero-area faces)"
        )
    click.echo(
        f"{done} of {len(records)} holes filled; {len(mesh.faces)} -> {len(filled.faces)} faces"
        f"{merged}; watertight: {watertight}; written to {output}"
    )
