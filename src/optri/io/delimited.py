"""Vertices from delimited text: sniffed delimiter, optional header, chosen columns.

A CSV of vertices comes in many shapes: ``x,y``; ``lon;lat`` (Excel in much
of Europe); tab or space separated; with a header or without; with text
columns such as a name beside the coordinates. :func:`parse_delimited`
finds the delimiter (``,``, tab, ``;`` or runs of spaces, whichever gives the
most numeric columns), takes the first line as a header when it holds text
where later lines hold numbers, and picks the coordinate columns: the ones
``columns`` names, else header names it knows (x/y/z, lon/lat, longitude/
latitude, easting/northing), else the first two numeric columns (three when
the file has exactly three columns, all numeric: x, y, z). A file with one
numeric column gives vertex values.
"""

from __future__ import annotations

import csv
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from ..errors import InvalidPolygonError

__all__ = ["parse_columns", "parse_delimited"]

#: Candidate delimiters, preferred in this order when they tie; " " means runs of blanks.
_DELIMITERS = (",", "\t", ";", " ")
#: Lines looked at to choose the delimiter and the numeric columns.
_SAMPLE = 50
#: Header names of coordinate columns, tried in order (lower case).
_NAMED = (
    ("x", "y", "z"),
    ("lon", "lat", "alt"),
    ("lng", "lat", "alt"),
    ("long", "lat", "alt"),
    ("longitude", "latitude", "altitude"),
    ("longitude", "latitude", "elevation"),
    ("easting", "northing", "elevation"),
)


def parse_columns(spec: str) -> tuple[str, ...]:
    """``"x,y"`` or ``"2,3"`` -> a tuple of column names or 1-based numbers (as text).

    >>> parse_columns(" lon , lat ")
    ('lon', 'lat')

    Raises
    ------
    InvalidPolygonError
        Not two or three names.
    """
    parts = tuple(p.strip() for p in spec.split(","))
    if len(parts) not in (2, 3) or not all(parts):
        raise InvalidPolygonError(
            f"--columns takes two or three column names or numbers such as x,y or 2,3; got {spec!r}"
        )
    return parts


def parse_delimited(
    text: str, name: str, columns: Sequence[str] | None = None
) -> NDArray[np.float64]:
    r"""Vertices (n x 2 or n x 3) or vertex values (n,) from delimited text.

    Parameters
    ----------
    text : str
        The file's text; blank lines and lines starting with ``#`` are skipped.
    name : str
        The file's name, for messages.
    columns : sequence of str, optional
        Two or three header names or 1-based column numbers (``("lon", "lat")``).

    Raises
    ------
    InvalidPolygonError
        No vertices, no two numeric columns, an unknown column, a cell that
        is not a number (the message names the line).

    Examples
    --------
    >>> parse_delimited("lon;lat;name\n0;0;a\n1;0;b\n0;1;c\n", "f.csv").tolist()
    [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]
    >>> parse_delimited("id x y\n7 0 0\n8 2 0\n9 0 2\n", "f", ["x", "y"]).tolist()
    [[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]]
    """
    lines = [
        (lineno, line)
        for lineno, line in enumerate(text.splitlines(), start=1)
        if line.strip() and not line.lstrip().startswith("#")
    ]
    if not lines:
        raise InvalidPolygonError(f"{name}: no vertices found")
    delimiter = _sniff([line for _, line in lines[: _SAMPLE + 1]])
    rows = [(lineno, _split(line, delimiter)) for lineno, line in lines]
    header: list[str] | None = None
    if len(rows) > 1 and _is_header(rows[0][1], rows[1][1]):
        header = [c.lower() for c in rows.pop(0)[1]]
    width = max(len(cells) for _, cells in rows[:_SAMPLE])
    numeric = [c for c in range(width) if _numeric_column(rows[:_SAMPLE], c)]
    picked = _pick(columns, header, numeric, width, name)
    return _gather(rows, picked, header, name)


def _split(line: str, delimiter: str) -> list[str]:
    if delimiter == " ":
        return line.split()
    cells = [c.strip() for c in next(csv.reader([line], delimiter=delimiter))]
    while cells and cells[-1] == "":
        cells.pop()
    return cells


def _is_number(cell: str) -> bool:
    try:
        float(cell)
    except ValueError:
        return False
    return True


def _sniff(sample: list[str]) -> str:
    """The delimiter giving the most numeric columns over the sample (ties: earliest)."""
    body = sample[1:] or sample  # the first line may be a header
    best, best_score = ",", (-1, 0)
    for delimiter in _DELIMITERS:
        split = [_split(line, delimiter) for line in body]
        width = min(len(cells) for cells in split)
        numeric = sum(all(_is_number(cells[c]) for cells in split) for c in range(width))
        score = (numeric, -len({len(cells) for cells in split}))
        if score > best_score:
            best, best_score = delimiter, score
    return best


def _is_header(first: list[str], second: list[str]) -> bool:
    """Text in the first line where the second line holds a number."""
    return any(not _is_number(a) and _is_number(b) for a, b in zip(first, second, strict=False))


def _numeric_column(rows: list[tuple[int, list[str]]], c: int) -> bool:
    cells = [cells[c] for _, cells in rows if c < len(cells)]
    return bool(cells) and sum(map(_is_number, cells)) * 2 > len(rows) and _is_number(cells[0])


def _pick(
    columns: Sequence[str] | None,
    header: list[str] | None,
    numeric: list[int],
    width: int,
    name: str,
) -> list[int]:
    """0-based indices of the coordinate columns (one index: vertex values)."""
    if columns is not None:
        return [_column_index(c, header, width, name) for c in columns]
    if header is not None:
        for x, y, z in _NAMED:
            if x in header and y in header:
                found = [header.index(x), header.index(y)]
                if z in header and header.index(z) in numeric:
                    found.append(header.index(z))
                return found
    if width == 1 and numeric == [0]:
        return [0]
    if len(numeric) < 2:
        known = f" (columns: {', '.join(header)})" if header else ""
        raise InvalidPolygonError(
            f"{name}: needs two numeric columns (x, y){known}; name them with --columns x,y"
        )
    if len(numeric) == 3 == width:
        return numeric
    return numeric[:2]


def _column_index(column: str, header: list[str] | None, width: int, name: str) -> int:
    if column.isdigit() and 1 <= int(column) <= width:
        return int(column) - 1
    if header is not None and column.lower() in header:
        return header.index(column.lower())
    choices = ", ".join(header) if header else f"numbers 1 to {width}"
    raise InvalidPolygonError(f"{name}: no column {column!r} (columns: {choices})")


def _gather(
    rows: list[tuple[int, list[str]]], picked: list[int], header: list[str] | None, name: str
) -> NDArray[np.float64]:
    out = np.empty((len(rows), len(picked)), dtype=np.float64)
    for r, (lineno, cells) in enumerate(rows):
        for k, c in enumerate(picked):
            cell = cells[c] if c < len(cells) else ""
            try:
                out[r, k] = float(cell)
            except ValueError:
                label = f" ({header[c]})" if header and c < len(header) else ""
                raise InvalidPolygonError(
                    f"{name}:{lineno}: not a number {cell!r} in column {c + 1}{label}"
                ) from None
    return out[:, 0] if len(picked) == 1 else out
