"""Reading polygons from files and writing outputs atomically."""

from __future__ import annotations

import contextlib
import csv
import json
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import IO, Any

import numpy as np
from numpy.typing import NDArray

from .errors import InvalidPolygonError

__all__ = ["atomic_write", "read_polygon", "write_json"]


def read_polygon(path: str | os.PathLike[str]) -> NDArray[np.float64]:
    """Read polygon vertices from a CSV, JSON, GeoJSON or WKT file.

    CSV: ``x,y`` or ``x,y,z`` per line, an optional header, ``#`` comments; a
    single column is read as vertex values. JSON: a list of pairs or numbers,
    or an object with a ``vertices``/``coordinates``/``points``/``values`` key.
    GeoJSON (an object with a ``type``) and ``.wkt`` files: the exterior ring of
    one polygon; a polygon with holes is refused (:mod:`optri.interop`).

    Raises
    ------
    InvalidPolygonError
        Missing file, unparsable content; the message names the file and line.
    """
    p = Path(path)
    try:
        text = p.read_text()
    except OSError as exc:
        raise InvalidPolygonError(f"cannot read {p}: {exc.strerror or exc}") from exc
    suffix = p.suffix.lower()
    if suffix == ".wkt":
        from .interop import polygon_from_wkt

        return polygon_from_wkt(text)
    if suffix in (".json", ".geojson"):
        return _parse_json(text, p)
    return _parse_csv(text, p)


def _parse_json(text: str, path: Path) -> NDArray[np.float64]:
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise InvalidPolygonError(f"{path}:{exc.lineno}: invalid JSON ({exc.msg})") from exc
    if isinstance(data, dict) and "type" in data:  # GeoJSON: exterior ring, holes refused
        from .interop import polygon_from_geojson

        return polygon_from_geojson(data)
    if isinstance(data, dict):
        for key in ("vertices", "coordinates", "points", "values"):
            if key in data:
                data = data[key]
                break
    try:
        arr = np.asarray(data, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidPolygonError(f"{path}: expected a list of [x, y] pairs or numbers") from exc
    return arr


def _parse_csv(text: str, path: Path) -> NDArray[np.float64]:
    rows: list[list[float]] = []
    for lineno, row in enumerate(csv.reader(text.splitlines()), start=1):
        cells = [c.strip() for c in row if c.strip() != ""]
        if not cells or cells[0].startswith("#"):
            continue
        try:
            rows.append([float(c) for c in cells])
        except ValueError:
            if not rows:  # a header line
                continue
            raise InvalidPolygonError(f"{path}:{lineno}: not a number in {row!r}") from None
    if not rows:
        raise InvalidPolygonError(f"{path}: no vertices found")
    width = {len(r) for r in rows}
    if len(width) != 1:
        raise InvalidPolygonError(f"{path}: rows have different numbers of columns {sorted(width)}")
    arr = np.asarray(rows, dtype=np.float64)
    return arr[:, 0] if arr.shape[1] == 1 else arr


@contextlib.contextmanager
def atomic_write(path: str | os.PathLike[str], mode: str = "w") -> Iterator[IO[Any]]:
    """Open a temporary file beside ``path``; rename it over ``path`` on success.

    On any exception (or interruption) the temporary file is removed and an
    existing ``path`` is left untouched.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "a.txt"
    >>> with atomic_write(out) as fh:
    ...     _ = fh.write("done")
    >>> out.read_text()
    'done'
    """
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes 0600; give the usual file mode
    try:
        with os.fdopen(fd, mode) as fh:
            yield fh
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_json(path: str | os.PathLike[str], obj: Any) -> None:
    """Write ``obj`` as indented JSON, atomically."""
    with atomic_write(path) as fh:
        json.dump(obj, fh, indent=2)
        fh.write("\n")
