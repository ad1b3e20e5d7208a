"""Reading stacks of planar contours: JSON/GeoJSON, CSV and DICOM RTSTRUCT.

Every reader returns a list of ``(k, 3)`` float arrays, one closed contour
each (x, y, z), ready for :func:`optri.contours_to_mesh`.
"""

from __future__ import annotations

import csv
import json
import os
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._optional import import_optional
from ..errors import InvalidPolygonError

__all__ = ["CONTOUR_FORMATS", "read_contours", "rtstruct_rois"]

#: Suffixes read by :func:`read_contours`.
CONTOUR_FORMATS = ("json", "geojson", "csv", "dcm")

Contours = list[NDArray[np.float64]]


def read_contours(path: str | os.PathLike[str], roi: str | None = None) -> Contours:
    r"""Read the closed contours of a file as ``(k, 3)`` arrays.

    Parameters
    ----------
    path : path
        ``.json`` / ``.geojson``: a GeoJSON FeatureCollection (or Feature, or
        geometry) of Polygons / MultiPolygons whose coordinates carry z, or
        whose feature has a numeric property ``z`` (every ring, holes included,
        is a contour); or ``{"slices": [{"z": z, "contours": [[[x, y], ...],
        ...]}, ...]}``. ``.csv``: a header with ``x,y,z,contour`` (rows of one
        contour in order, contours named by any label). ``.dcm``: a DICOM
        RTSTRUCT (extra ``optri[contours]``, pydicom).
    roi : str, optional
        RTSTRUCT only: the structure's name or number; default the first one
        holding closed contours.

    Raises
    ------
    InvalidPolygonError
        Unknown suffix, unreadable file, a contour that is open (RTSTRUCT
        ``OPEN_PLANAR`` / ``POINT``), fewer than 3 points, missing columns.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "c.csv"
    >>> rows = ["x,y,z,contour", "0,0,0,a", "1,0,0,a", "0,1,0,a", "0,0,1,b", "1,0,1,b", "0,1,1,b"]
    >>> _ = f.write_text("\n".join(rows))
    >>> [c.shape for c in read_contours(f)]
    [(3, 3), (3, 3)]
    """
    p = Path(path)
    ext = p.suffix.lower().lstrip(".")
    if ext not in CONTOUR_FORMATS:
        raise InvalidPolygonError(
            f"{str(path)!r}: unsupported contour format {ext or '(none)'!r}; use one of "
            f"{', '.join('.' + f for f in CONTOUR_FORMATS)}"
        )
    if not p.is_file():
        raise InvalidPolygonError(f"cannot read {path}: no such file")
    if ext == "dcm":
        return _read_rtstruct(p, roi)
    if roi is not None:
        raise InvalidPolygonError("--roi applies to DICOM RTSTRUCT files only")
    if ext == "csv":
        return _read_csv(p)
    try:
        data = json.loads(p.read_text(encoding="utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InvalidPolygonError(f"{path}: not valid JSON ({exc})") from exc
    return _from_json(data, str(path))


def _ring(coords: Any, z: float | None, where: str) -> NDArray[np.float64]:
    try:
        arr = np.array(coords, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidPolygonError(f"{where}: coordinates are not numbers ({exc})") from exc
    if arr.ndim != 2 or arr.shape[1] not in (2, 3):
        raise InvalidPolygonError(f"{where}: expected a list of [x, y] or [x, y, z] points")
    if z is not None:
        arr = np.column_stack([arr[:, :2], np.full(len(arr), float(z))])
    elif arr.shape[1] != 3:
        raise InvalidPolygonError(f"{where}: no z: give [x, y, z] points or a 'z' property")
    if len(arr) < 3:
        raise InvalidPolygonError(f"{where}: a closed contour needs at least 3 points")
    return arr


def _from_json(data: Any, name: str) -> Contours:
    if isinstance(data, dict) and "slices" in data:
        out = []
        for s, sl in enumerate(data["slices"]):
            if not isinstance(sl, dict) or "z" not in sl or "contours" not in sl:
                raise InvalidPolygonError(f"{name}: slice {s} needs 'z' and 'contours'")
            for c, ring in enumerate(sl["contours"]):
                out.append(_ring(ring, float(sl["z"]), f"{name}: slice {s}, contour {c}"))
        return out
    features: list[Any]
    if isinstance(data, dict) and data.get("type") == "FeatureCollection":
        features = list(data.get("features") or [])
    elif isinstance(data, dict) and data.get("type") == "Feature":
        features = [data]
    elif isinstance(data, dict) and "coordinates" in data:
        features = [{"type": "Feature", "geometry": data, "properties": {}}]
    else:
        raise InvalidPolygonError(
            f"{name}: expected GeoJSON polygons or {{'slices': [{{'z': .., 'contours': ..}}]}}"
        )
    out = []
    for f, feat in enumerate(features):
        geom = (feat or {}).get("geometry") or {}
        props = (feat or {}).get("properties") or {}
        z = props.get("z")
        kind = geom.get("type")
        polys = [geom.get("coordinates")] if kind == "Polygon" else geom.get("coordinates")
        if kind not in ("Polygon", "MultiPolygon") or not isinstance(polys, list):
            raise InvalidPolygonError(f"{name}: feature {f} is a {kind}, not a (Multi)Polygon")
        for poly in polys:
            for ring in poly:
                out.append(_ring(ring, z, f"{name}: feature {f}"))
    if not out:
        raise InvalidPolygonError(f"{name}: no contours found")
    return out


def _read_csv(path: Path) -> Contours:
    with open(path, newline="", encoding="utf-8") as fh:
        reader = csv.DictReader(fh)
        fields = [f.strip().lower() for f in reader.fieldnames or []]
        need = {"x", "y", "z", "contour"}
        if not need <= set(fields):
            raise InvalidPolygonError(
                f"{path}: the header must name x, y, z and contour; got {', '.join(fields)}"
            )
        groups: dict[str, list[list[float]]] = {}
        for line, row in enumerate(reader, start=2):
            row = {(k or "").strip().lower(): v for k, v in row.items()}
            try:
                pt = [float(row["x"]), float(row["y"]), float(row["z"])]
            except (TypeError, ValueError) as exc:
                raise InvalidPolygonError(f"{path}, line {line}: not a number ({exc})") from exc
            groups.setdefault(str(row["contour"]).strip(), []).append(pt)
    if not groups:
        raise InvalidPolygonError(f"{path}: no rows")
    return [_ring(pts, None, f"{path}: contour {key!r}") for key, pts in groups.items()]


def rtstruct_rois(path: str | os.PathLike[str]) -> list[tuple[int, str, int]]:
    """``(number, name, contour count)`` of each structure of an RTSTRUCT file."""
    ds = _dataset(Path(path))
    names = {int(r.ROINumber): str(r.ROIName) for r in getattr(ds, "StructureSetROISequence", [])}
    out = []
    for rc in getattr(ds, "ROIContourSequence", []):
        num = int(rc.ReferencedROINumber)
        out.append((num, names.get(num, str(num)), len(getattr(rc, "ContourSequence", []))))
    return out


def _dataset(path: Path) -> Any:
    pydicom = import_optional("pydicom", "contours")
    try:
        ds = pydicom.dcmread(str(path))
    except Exception as exc:  # noqa: BLE001  (pydicom raises many kinds on bad bytes)
        raise InvalidPolygonError(f"cannot read DICOM {path}: {exc}") from exc
    if str(getattr(ds, "Modality", "")) != "RTSTRUCT" or "ROIContourSequence" not in ds:
        raise InvalidPolygonError(f"{path}: not a DICOM RTSTRUCT (no ROI contours)")
    return ds


def _read_rtstruct(path: Path, roi: str | None) -> Contours:
    ds = _dataset(path)
    rois = rtstruct_rois(path)
    pick = [r for r in rois if roi is None and r[2] > 0 or roi in (r[1], str(r[0]))]
    if not pick:
        listed = ", ".join(f"{num} {name!r} ({k} contours)" for num, name, k in rois)
        raise InvalidPolygonError(f"{path}: no structure {roi!r}; it holds {listed}")
    number = pick[0][0]
    rc = next(r for r in ds.ROIContourSequence if int(r.ReferencedROINumber) == number)
    out = []
    for c, item in enumerate(getattr(rc, "ContourSequence", [])):
        kind = str(getattr(item, "ContourGeometricType", "CLOSED_PLANAR"))
        if kind != "CLOSED_PLANAR":
            raise InvalidPolygonError(
                f"{path}: structure {pick[0][1]!r}, contour {c} is {kind}; only closed "
                f"planar contours bound a surface"
            )
        pts = np.array([float(v) for v in item.ContourData]).reshape(-1, 3)
        out.append(_ring(pts, None, f"{path}: structure {pick[0][1]!r}, contour {c}"))
    if not out:
        raise InvalidPolygonError(f"{path}: structure {pick[0][1]!r} has no contours")
    return out
