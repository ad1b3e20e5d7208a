"""Sample data shipped with optri, so the documented commands work after ``pip install``.

The files sit beside this module inside the installed package:

``octagon.csv``
    the paper's convex octagon, one ``x,y`` vertex per line (header ``x,y``);
``footprints.ndjson``
    31 building footprints, one GeoJSON Feature per line, one bow-tie among
    them (a batch run reports it and goes on);
``italy.geojson``
    a real ring: mainland Italy's outline (65 vertices, longitude/latitude)
    from Natural Earth's 1:110m countries (public domain), a GeoJSON Feature;
``sphere_two_holes.obj``
    an icosphere (``trimesh.creation.icosphere(subdivisions=2)``) with two
    holes cut into it, for :func:`optri.fill_holes` and ``optri fill``.

From the shell, ``optri data`` lists them, ``optri data octagon.csv`` prints
one path and ``optri data -o examples`` copies them into ``examples/`` (the
paths the README's commands use).

Examples
--------
>>> import optri
>>> optri.data.names()
['footprints.ndjson', 'italy.geojson', 'octagon.csv', 'sphere_two_holes.obj']
>>> optri.triangulate(optri.data.path("octagon.csv")).n
8
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path

from ..errors import OutputExistsError, UnknownSampleError
from ..io.atomic import atomic_write

__all__ = ["copy_to", "names", "path"]

_HERE = Path(__file__).resolve().parent
_SUFFIXES = (".csv", ".ndjson", ".obj", ".json", ".geojson", ".wkt", ".ply", ".stl")


def names() -> list[str]:
    """The names of the bundled sample files, sorted.

    Returns
    -------
    list of str
        File names to pass to :func:`path` or :func:`copy_to`.

    Examples
    --------
    >>> "octagon.csv" in names()
    True
    """
    return sorted(p.name for p in _HERE.iterdir() if p.suffix in _SUFFIXES)


def path(name: str) -> Path:
    """The absolute path of the bundled sample file ``name``.

    Parameters
    ----------
    name : str
        One of :func:`names`, such as ``"octagon.csv"``.

    Returns
    -------
    pathlib.Path
        A file inside the installed package; read it, do not write it.

    Raises
    ------
    UnknownSampleError
        ``name`` is not a bundled file (the message lists those that are).

    Examples
    --------
    >>> path("octagon.csv").read_text().splitlines()[:2]
    ['x,y', '4.0,0.0']
    >>> path("square.csv")
    Traceback (most recent call last):
    ...
    optri.errors.UnknownSampleError: no sample file 'square.csv'; the samples are ...
    """
    available = names()
    if name not in available:
        raise UnknownSampleError(f"no sample file {name!r}; the samples are {', '.join(available)}")
    return _HERE / name


def copy_to(
    directory: str | os.PathLike[str],
    which: Iterable[str] | None = None,
    overwrite: bool = False,
) -> list[Path]:
    """Copy sample files into ``directory`` (created if missing), each written atomically.

    Parameters
    ----------
    directory : str or path-like
        Where the copies go. A file already there with the sample's bytes is
        left as it is; one with other bytes (a file of yours) is replaced only
        with ``overwrite``.
    which : iterable of str, optional
        Names to copy (default: all of :func:`names`).
    overwrite : bool
        Replace files of the same name whatever they hold.

    Returns
    -------
    list of pathlib.Path
        The files written, in the order of ``which``.

    Raises
    ------
    UnknownSampleError
        One of ``which`` is not a bundled file; nothing is written then.
    OutputExistsError
        ``directory`` holds a different file of a sample's name and
        ``overwrite`` is false; nothing is written then.

    Examples
    --------
    >>> import tempfile
    >>> [p.name for p in copy_to(tempfile.mkdtemp(), ["octagon.csv"])]
    ['octagon.csv']
    """
    sources = [path(name) for name in (names() if which is None else which)]
    targets = [Path(directory) / source.name for source in sources]
    if not overwrite:
        theirs = [t for s, t in zip(sources, targets) if _differs(t, s)]
        if theirs:
            raise OutputExistsError(
                f"{', '.join(map(str, theirs))}: already there with other contents; "
                "pass --overwrite (overwrite=True) to replace, or copy elsewhere"
            )
    for source, target in zip(sources, targets):
        if overwrite or not target.exists() or _differs(target, source):
            with atomic_write(target, "wb") as fh:
                fh.write(source.read_bytes())
    return targets


def _differs(target: Path, source: Path) -> bool:
    """True when ``target`` exists (as anything) and is not a copy of ``source``."""
    if not os.path.lexists(target):
        return False
    try:
        return target.is_symlink() or target.read_bytes() != source.read_bytes()
    except OSError:
        return True
