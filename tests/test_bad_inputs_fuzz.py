"""Random bytes and random JSON into every file reader: only optri's own errors come out.

The batch reader's line-by-line fuzzing lives in test_batch_records.py; here the
single-polygon readers (CSV, JSON, GeoJSON, WKT), the mesh reader, the batch
reader on whole files, and ``optri solve`` on the same files.
"""

from __future__ import annotations

import json

import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from optri.batch import readers
from optri.cli import main
from optri.errors import OptriError
from optri.io import read_rings

JSON = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=4),
    lambda inner: (
        st.lists(inner, max_size=5)
        | st.dictionaries(
            st.sampled_from(
                ["type", "coordinates", "geometry", "features", "exterior", "holes", "x"]
            ),
            inner,
            max_size=4,
        )
    ),
    max_leaves=25,
)
GEO = st.fixed_dictionaries(
    {"type": st.sampled_from(["Polygon", "MultiPolygon", "Feature", "FeatureCollection"])},
    optional={"coordinates": JSON, "geometry": JSON, "features": JSON},
)
CONTENT = (
    st.binary(max_size=300)
    | JSON.map(lambda v: json.dumps(v).encode())
    | GEO.map(lambda v: json.dumps(v).encode())
    | st.lists(
        st.lists(st.floats() | st.integers() | st.text(max_size=3), max_size=4), max_size=6
    ).map(lambda rows: "\n".join(",".join(map(str, r)) for r in rows).encode())
    | st.text(max_size=60).map(lambda t: f"POLYGON (({t}))".encode())
)
SUFFIXES = st.sampled_from([".csv", ".json", ".geojson", ".wkt", ".txt"])
FUZZ = settings(
    max_examples=200, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)


@FUZZ
@given(data=CONTENT, suffix=SUFFIXES)
def test_read_rings_raises_only_own_errors(tmp_path, data, suffix):
    path = tmp_path / f"fuzz{suffix}"
    path.write_bytes(data)
    try:
        rings = read_rings(path)
    except OptriError as exc:
        assert str(exc)
    else:
        assert isinstance(rings, list) and rings


@FUZZ
@given(data=CONTENT, suffix=SUFFIXES)
def test_cli_solve_on_any_file_exits_cleanly(tmp_path, data, suffix):
    path = tmp_path / f"fuzz{suffix}"
    path.write_bytes(data)
    result = CliRunner().invoke(main, ["solve", str(path), "-q"])
    assert isinstance(result.exception, (SystemExit, type(None))), repr(result.exception)
    assert result.exit_code in (0, 2)
    if result.exit_code == 2:
        lines = [ln for ln in result.stderr.splitlines() if ln.strip()]
        assert len(lines) == 1 and lines[0].startswith("optri: error:"), lines
        assert "a bug in optri" not in lines[0]  # the CLI's catch-all: not a clean error


@settings(
    max_examples=100, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(data=CONTENT, suffix=st.sampled_from([".geojson", ".ndjson", ".json"]))
def test_batch_reader_on_any_file_gives_items_or_own_error(tmp_path, data, suffix):
    path = tmp_path / f"fuzz{suffix}"
    path.write_bytes(data)
    try:
        items = list(readers.read_items(path))
    except OptriError as exc:
        assert "\n" not in str(exc)
    else:
        for item in items:  # a polygon to solve, or a one-line reason why not
            assert item.coords is not None if item.reason is None else "\n" not in item.reason
            json.dumps(item.id, allow_nan=False)


@settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    data=st.binary(max_size=300)
    | st.lists(
        st.sampled_from(["v 0 0 0", "v 1 0 0", "v 0 1 0", "f 1 2 3", "f 1 2 9", "v x y z", "f"]),
        max_size=10,
    ).map(lambda ls: "\n".join(ls).encode()),
    suffix=st.sampled_from([".obj", ".stl", ".off", ".ply"]),
)
def test_read_mesh_raises_only_own_errors(tmp_path, data, suffix):
    pytest.importorskip("trimesh")
    from optri.io.meshes import read_mesh

    path = tmp_path / f"fuzz{suffix}"
    path.write_bytes(data)
    try:
        read_mesh(path)
    except OptriError as exc:
        assert str(exc)
