"""``optri fill``: fill the holes of a mesh file with optimal patches."""

from __future__ import annotations

import json
import warnings

import click

from ..errors import HoleSkippedWarning
from ..holes import METHODS, HoleRecord, fill_holes
from ..io.meshes import mesh_format, read_mesh, write_mesh
from .app import main
from .progress import progress_bar


def _summary(rec: HoleRecord) -> str:
    w = rec.weight
    if isinstance(w, tuple):
        value = f"max dihedral {w[0]:.6g} rad, area {w[1]:.6g}"
    else:
        value = "" if w is None else f"weight {w:.6g}"
    if rec.status == "filled":
        return (
            f"hole {rec.index}: {rec.edges} edges, filled with {rec.faces_added} faces "
            f"({rec.method}; {value}; {rec.seconds:.3f} s)"
        )
    return f"hole {rec.index}: {rec.edges} edges, {rec.status.upper()}: {rec.reason}"


@main.command()
@click.argument("infile", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False), help="Output mesh.")
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
@click.option("--json", "as_json", is_flag=True, help="Print the report as one JSON object.")
@click.option("--quiet", "-q", is_flag=True, help="No progress bar.")
def fill(
    infile: str,
    output: str,
    weight: str,
    method: str,
    max_hole_edges: int | None,
    as_json: bool,
    quiet: bool,
) -> None:
    """Fill the holes of the mesh in INFILE (.obj/.ply/.stl/.off) and write OUTPUT."""
    mesh_format(output, "output")  # refuse an unknown output suffix before any work
    mesh = read_mesh(infile)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", HoleSkippedWarning)
        with progress_bar("filling holes", not quiet and not as_json) as progress:
            filled, records = fill_holes(
                mesh,
                max_hole_edges=max_hole_edges,
                weight=weight,
                method=method,
                progress=progress,
            )
    for w in caught:  # skipped holes: never silent, one stderr line each
        if issubclass(w.category, HoleSkippedWarning):
            click.echo(f"optri: warning: {w.message}", err=True)
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    write_mesh(filled, output)
    if as_json:
        click.echo(
            json.dumps(
                {
                    "input": infile,
                    "output": output,
                    "faces_before": int(len(mesh.faces)),
                    "faces_after": int(len(filled.faces)),
                    "watertight": bool(filled.is_watertight),
                    "holes": [r.to_dict() for r in records],
                }
            )
        )
        return
    for rec in records:
        click.echo(_summary(rec))
    done = sum(r.status == "filled" for r in records)
    click.echo(
        f"{done} of {len(records)} holes filled; {len(mesh.faces)} -> {len(filled.faces)} faces; "
        f"watertight: {filled.is_watertight}; written to {output}"
    )
