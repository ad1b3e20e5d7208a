"""Seeded polygon generators and file writers shared by the batch tests."""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

import numpy as np


def convex_polygon(rng: np.random.Generator, n: int) -> list[list[float]]:
    """n points on a jittered circle, sorted by angle: strictly convex."""
    angles = np.sort(rng.uniform(0, 2 * math.pi, n))
    angles = np.unique(np.round(angles, 6))
    while len(angles) < n:  # rare duplicate angles: fall back to a regular polygon
        angles = np.linspace(0, 2 * math.pi, n, endpoint=False)
    r = rng.uniform(1, 10)
    x, y = rng.uniform(-100, 100, 2)
    return np.column_stack((x + r * np.cos(angles), y + r * np.sin(angles))).round(6).tolist()


def star_polygon(rng: np.random.Generator, n: int) -> list[list[float]]:
    """A star-shaped (so simple) polygon: angles sorted, radii random."""
    angles = np.linspace(0, 2 * math.pi, n, endpoint=False) + rng.uniform(0, 0.3, n)
    radii = rng.uniform(0.4, 1.0, n)
    return np.column_stack((radii * np.cos(angles), radii * np.sin(angles))).round(6).tolist()


def mixed_polygons(count: int, seed: int = 0, lo: int = 4, hi: int = 10) -> list[dict]:
    """Records ``{"id", "coordinates"}``: two thirds convex, one third star-shaped."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(count):
        n = int(rng.integers(lo, hi + 1))
        coords = star_polygon(rng, n) if i % 3 == 2 else convex_polygon(rng, n)
        out.append({"id": f"p{i}", "coordinates": coords})
    return out


def write_ndjson(path: Path, rows: list) -> Path:
    path.write_text("".join(json.dumps(r) + "\n" for r in rows))
    return path


def write_feature_collection(path: Path, rows: list[dict]) -> Path:
    feats = [
        {
            "type": "Feature",
            "id": r["id"],
            "geometry": {"type": "Polygon", "coordinates": [r["coordinates"]]},
            "properties": {"name": str(r["id"])},
        }
        for r in rows
    ]
    path.write_text(json.dumps({"type": "FeatureCollection", "features": feats}, indent=1))
    return path


def killer(vertices, i, k, j):
    """A user weight whose process dies (as by the OOM killer) on any heptagon."""
    if len(vertices) == 7:
        import signal

        os.kill(os.getpid(), signal.SIGKILL)
    return 1.0


def write_arrow_layer(path: Path, table, row_group_size: int | None = None) -> Path:
    """An Arrow table with a WKB ``geometry`` column as GeoParquet, GeoPackage or FlatGeobuf.

    The CRS is EPSG:32633; FlatGeobuf is written without a spatial index (rows stay in order).
    """
    import pyarrow.parquet as pq
    import pyogrio

    if path.suffix == ".parquet":
        column = {"encoding": "WKB", "geometry_types": [], "crs": "EPSG:32633"}
        geo = {"version": "1.1.0", "primary_column": "geometry", "columns": {"geometry": column}}
        meta = {b"geo": json.dumps(geo)}
        pq.write_table(table.replace_schema_metadata(meta), path, row_group_size=row_group_size)
        return path
    driver = {".gpkg": "GPKG", ".fgb": "FlatGeobuf"}[path.suffix]
    pyogrio.write_arrow(
        table,
        path,
        driver=driver,
        geometry_name="geometry",
        geometry_type="Unknown",
        crs="EPSG:32633",
        layer_options={"SPATIAL_INDEX": "NO"} if driver == "FlatGeobuf" else None,
    )
    return path
