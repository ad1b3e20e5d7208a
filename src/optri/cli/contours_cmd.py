"""``optri contours``: a stack of planar contours to one closed surface mesh."""

from __future__ import annotations

import json

import click

from ..contours import CONTOUR_WEIGHTS, contours_to_mesh
from ..io.contours import read_contours
from ..io.meshes import mesh_format
from .app import main
from .options import input_path, output_option
from .progress import progress_bar
from .stdin import contour_input


@main.command()
@click.argument("infile", type=input_path)
@output_option("file", "Output mesh (.ply, .obj, .stl, .off).  [required]")
@click.option(
    "--weight",
    "-w",
    default="area",
    show_default=True,
    type=click.Choice(CONTOUR_WEIGHTS),
    help="Tiling weight between slices.",
)
@click.option(
    "--objective",
    "-O",
    default="sum",
    show_default=True,
    type=click.Choice(["sum", "max"]),
    help="Minimize the total or the largest tiling triangle weight.",
)
@click.option("--roi", help="RTSTRUCT: the structure's name or number [default: the first].")
@click.option(
    "--unmatched",
    default="cap",
    show_default=True,
    type=click.Choice(["cap", "error"]),
    help="A contour no contour of the next slice overlaps: cap it flat, or fail.",
)
@click.option("--json", "as_json", is_flag=True, help="Print the report as one JSON object.")
@click.option("--quiet", "-q", is_flag=True, help="No progress bar.")
def contours(
    infile: str,
    output: str,
    weight: str,
    objective: str,
    roi: str | None,
    unmatched: str,
    as_json: bool,
    quiet: bool,
) -> None:
    """Build a closed surface from the planar contours in INFILE, write OUTPUT.

    INFILE (- for stdin): JSON/GeoJSON polygons with a z, CSV with columns
    x,y,z,contour, or a DICOM RTSTRUCT (.dcm, extra optri[contours]). Matched
    contours of adjacent slices are joined by optimal tilings, branches through
    bridged contours half-way, ends by optimal caps.
    """
    mesh_format(output, "output")  # refuse an unknown output suffix before any work
    with contour_input(infile) as path:
        rings = read_contours(path, roi)
    with progress_bar("tiling slices", not quiet) as progress:
        mesh = contours_to_mesh(rings, weight, objective, unmatched=unmatched, progress=progress)
    mesh.write(output)
    report = {
        "input": infile,
        "output": output,
        "vertices": int(len(mesh.vertices)),
        "faces": int(len(mesh.faces)),
        "volume": mesh.volume,
        "area": mesh.area,
        "weight": mesh.weight,
        **mesh.stats,
    }
    if as_json:
        click.echo(json.dumps(report))
        return
    s = mesh.stats
    click.echo(
        f"{s['contours']} contours on {s['slices']} slices -> {len(mesh.faces)} faces "
        f"({s['tilings']} tilings, {s['branchings']} branchings, {s['caps']} caps); "
        f"volume {mesh.volume:.6g}; written to {output}"
    )
