"""Standard input (``-``) for the commands whose readers need a named file.

Mesh files and batch layers are read by libraries that take a path and tell the
format by its suffix, so ``-`` is copied into a temporary folder under a name
whose suffix is the format told from the first bytes. The folder is removed on
every way out (success, error, Ctrl-C, SIGTERM: both unwind). Standard input is
read up to ``$OPTRI_MAX_INPUT_BYTES`` (:func:`optri.io.files.max_input_bytes`).
"""

from __future__ import annotations

import contextlib
import shutil
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path

from ..errors import InvalidPolygonError
from ..io.files import copy_stdin

__all__ = [
    "contour_input",
    "layer_input",
    "mesh_input",
    "sniff_contours",
    "sniff_layer",
    "sniff_mesh",
]

STDIN = "-"


def sniff_mesh(head: bytes) -> str:
    r"""The mesh format (obj, ply, stl, off) of a file starting with ``head``.

    >>> sniff_mesh(b"ply\nformat ascii 1.0\n"), sniff_mesh(b"# cube\nv 0 0 0\n")
    ('ply', 'obj')
    """
    text = head.lstrip()
    if text.startswith(b"ply"):
        return "ply"
    if text[:4] in (b"OFF\n", b"OFF\r", b"OFF ") or text.startswith((b"COFF", b"NOFF")):
        return "off"
    if text.startswith(b"solid") or b"\x00" in head[:200]:
        return "stl"  # ASCII STL, or binary STL (an 80-byte header and packed floats)
    lines = [line.split() for line in text.splitlines()[:200]]
    if any(parts and parts[0] in (b"v", b"f", b"vn", b"o", b"g") for parts in lines):
        return "obj"
    raise InvalidPolygonError(
        "standard input: cannot tell the mesh format (OBJ, PLY, STL or OFF) from its content"
    )


def sniff_layer(head: bytes) -> str:
    r"""The batch input format of a layer starting with ``head`` (stdin has no suffix).

    >>> sniff_layer(b'{"type": "FeatureCollection", "features": []}')
    'geojson'
    >>> sniff_layer(b'{"id": 1, "coordinates": [[0, 0], [1, 0], [0, 1]]}\n{"id": 2}')
    'ndjson'
    """
    if head.startswith(b"PAR1"):
        return "parquet"
    if head.startswith(b"SQLite format 3"):
        return "gpkg"
    if head.startswith(b"fgb"):
        return "fgb"
    if b'"FeatureCollection"' in head[:4096]:
        return "geojson"
    if head.lstrip().startswith(b"{"):
        return "ndjson"
    raise InvalidPolygonError(
        "standard input: cannot tell the layer format from its content; pass --format"
    )


@contextlib.contextmanager
def _spooled(suffix_of: object) -> Iterator[Path]:
    folder = tempfile.mkdtemp(prefix="optri-stdin-")
    try:
        spool = Path(folder) / "stdin"
        with open(spool, "wb") as fh:  # streamed to disk, up to the input limit
            copy_stdin(fh)
        with open(spool, "rb") as fh:
            head = fh.read(65536)
        path = spool.rename(Path(folder) / f"stdin.{suffix_of(head)}")  # type: ignore[operator]
        yield path
    finally:
        shutil.rmtree(folder, ignore_errors=True)


@contextlib.contextmanager
def mesh_input(path: str) -> Iterator[str]:
    """``path`` itself, or for ``-`` a temporary copy of stdin named by its mesh format."""
    with _sniffed(path, sniff_mesh) as named:
        yield named


@contextlib.contextmanager
def _sniffed(path: str, sniff: Callable[[bytes], str]) -> Iterator[str]:
    """``path`` itself, or for ``-`` a temporary copy of stdin named by ``sniff``."""
    if path != STDIN:
        yield path
        return
    with _spooled(sniff) as spooled:
        yield str(spooled)


@contextlib.contextmanager
def layer_input(path: str, fmt: str | None) -> Iterator[str]:
    """``path`` itself, or for ``-`` a temporary copy of stdin (``fmt`` or sniffed)."""
    if path != STDIN:
        yield path
        return
    with _spooled(lambda head: fmt or sniff_layer(head)) as spooled:
        yield str(spooled)


def sniff_contours(head: bytes) -> str:
    r"""The contour format (dcm, json, csv) of a file starting with ``head``.

    >>> sniff_contours(b'{"slices": []}'), sniff_contours(b"x,y,z,contour\n")
    ('json', 'csv')
    """
    if head[128:132] == b"DICM":
        return "dcm"
    return "json" if head.lstrip()[:1] in (b"{", b"[") else "csv"


@contextlib.contextmanager
def contour_input(path: str) -> Iterator[str]:
    """``path`` itself, or for ``-`` a temporary copy of stdin named by its contour format."""
    with _sniffed(path, sniff_contours) as named:
        yield named
