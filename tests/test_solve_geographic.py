"""``optri solve`` says, as ``optri batch`` does, when a polygon's coordinates are degrees."""

from __future__ import annotations

import json
import warnings

import pytest
from click.testing import CliRunner

from optri.cli import main
from optri.errors import GeographicCRSWarning
from optri.io.files import read_rings_and_crs

RING = [[13.40, 52.50], [13.41, 52.50], [13.41, 52.51], [13.40, 52.51], [13.40, 52.50]]
UTM = {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::32633"}}


def _solve(path):
    return CliRunner().invoke(main, ["solve", str(path)])


def _polygon(tmp_path, crs=None):
    obj = {"type": "Polygon", "coordinates": [RING]}
    if crs is not None:
        obj["crs"] = crs
    path = tmp_path / "p.geojson"
    path.write_text(json.dumps(obj))
    return path


def test_lon_lat_geojson_warns_in_one_line(tmp_path):
    r = _solve(_polygon(tmp_path))
    assert r.exit_code == 0, r.output
    lines = [line for line in r.stderr.splitlines() if "warning" in line]
    assert len(lines) == 1
    assert lines[0].startswith("optri: warning: the polygon's CRS is geographic")
    assert "degrees, not metres" in lines[0]
    assert "optimal weight" in r.stdout


@pytest.mark.parametrize("kind", ["projected", "csv"])
def test_projected_or_unknown_crs_does_not_warn(tmp_path, kind):
    if kind == "csv":
        path = tmp_path / "p.csv"
        path.write_text("\n".join(f"{x},{y}" for x, y in RING[:-1]))
    else:
        path = _polygon(tmp_path, UTM)
    r = _solve(path)
    assert r.exit_code == 0 and "warning" not in r.stderr


def test_crs_of_each_input_kind(tmp_path):
    assert read_rings_and_crs(_polygon(tmp_path))[1] == "OGC:CRS84"
    assert read_rings_and_crs(_polygon(tmp_path, UTM))[1] == "urn:ogc:def:crs:EPSG::32633"
    (tmp_path / "p.wkt").write_text("POLYGON ((0 0, 2 0, 1 1, 0 0))")
    assert read_rings_and_crs(tmp_path / "p.wkt")[1] is None


def test_the_warning_is_a_geographic_crs_warning(tmp_path):
    from optri.batch.layer import warn_geographic

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        warn_geographic("OGC:CRS84", False, "the polygon's", "hint")
    assert [w.category for w in caught] == [GeographicCRSWarning]
