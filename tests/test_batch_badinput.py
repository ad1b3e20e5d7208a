"""Bad polygons become error records; corrupt files give one clear error naming file and line."""

from __future__ import annotations

import json

import pytest
from click.testing import CliRunner

import optri
from batch_polys import write_feature_collection, write_ndjson
from optri.batch import BatchFailedError, BatchInputError, iter_records
from optri.cli import main

GOOD = [[0, 0], [4, 0], [5, 3], [2, 5], [-1, 3]]
SQUARE = [[0, 0], [1, 0], [1, 1], [0, 1]]
HOLE = [[0.2, 0.2], [0.4, 0.2], [0.3, 0.4]]

BAD = {
    "too_few": ({"id": "too_few", "coordinates": [[0, 0], [1, 1]]}, "at least 3 vertices"),
    "nan": ({"id": "nan", "coordinates": [[0, 0], [1, 0], [float("nan"), 1]]}, "non-finite"),
    "inf": ({"id": "inf", "coordinates": [[0, 0], [1, 0], [1e400, 1]]}, "non-finite"),
    "repeated": ({"id": "repeated", "coordinates": [[0, 0], [1, 0], [1, 0], [0, 1]]}, "repeats"),
    "bowtie": ({"id": "bowtie", "coordinates": [[0, 0], [2, 2], [2, 0], [0, 2]]}, ""),
    "not_numbers": ({"id": "not_numbers", "coordinates": [["a", "b"], [1, 0], [0, 1]]}, ""),
    "ragged": ({"id": "ragged", "coordinates": [[0, 0], [1], [0, 1, 2, 3]]}, ""),
    "coords_string": ({"id": "coords_string", "coordinates": "0,0 1,0 0,1"}, "must be a list"),
    "no_coords": ({"id": "no_coords", "points": [[0, 0], [1, 0], [0, 1]]}, "coordinates"),
    "hole": (
        {
            "type": "Feature",
            "id": "hole",
            "geometry": {
                "type": "Polygon",
                "coordinates": [SQUARE, [[2.2, 0.2], [2.4, 0.2], [2.3, 0.4]]],
            },
            "properties": {},
        },
        "outside the exterior ring",
    ),
    "multi": (
        {
            "type": "Feature",
            "id": "multi",
            "properties": {},
            "geometry": {"type": "MultiPolygon", "coordinates": [[SQUARE], [[[0, 0], [1, 1]]]]},
        },
        "MultiPolygon part 1: a polygon needs at least 3 vertices",
    ),
    "point": (
        {
            "type": "Feature",
            "id": "point",
            "properties": {},
            "geometry": {"type": "Point", "coordinates": [1, 2]},
        },
        "not a Polygon",
    ),
    "null_geometry": ({"type": "Feature", "id": "null_geometry", "geometry": None}, "no geometry"),
}


def _rows():
    rows = [{"id": "good0", "coordinates": GOOD}]
    for key, (obj, _) in BAD.items():
        rows += [obj, {"id": f"good_after_{key}", "coordinates": SQUARE}]
    rows.append([1, 2, 3])  # not an object at all: id is its position
    return rows


def test_each_bad_kind_gives_an_error_record_and_good_ones_survive(tmp_path):
    src = write_ndjson(tmp_path / "in.ndjson", _rows())
    s = optri.batch(src, tmp_path / "out", workers=1, chunk_size=4)
    recs = {r["id"]: r for r in iter_records(tmp_path / "out")}
    assert s.total == len(_rows()) == len(recs)
    for key, (_, words) in BAD.items():
        rec = recs[key]
        assert rec["status"] == "error", key
        assert rec["reason"] and "\n" not in rec["reason"] and words in rec["reason"], rec
        assert rec["triangles"] is None and rec["cost"] is None
        assert recs[f"good_after_{key}"]["status"] == "ok"
    assert recs[len(_rows()) - 1]["reason"] == "line 28: expected a JSON object, got list"
    assert recs["good0"]["status"] == "ok" and s.errors == len(BAD) + 1


def test_multi_line_error_becomes_a_one_line_reason(tmp_path):
    def weight(i, k, j):  # a user weight failing with a message of two lines
        raise ValueError("first line\n  second line")

    src = write_ndjson(tmp_path / "in.ndjson", [{"id": 1, "coordinates": SQUARE}])
    optri.batch(src, tmp_path / "o.ndjson", workers=1, weight=weight)
    rec = next(iter_records(tmp_path / "o.ndjson"))
    # a WeightError naming the triangle; the user's exception keeps its type name
    assert rec["status"] == "error"
    assert rec["reason"] == (
        "weight 'custom' raised ValueError on triangle (0, 1, 2): first line second line"
    )


def test_single_part_multipolygon_is_its_polygon(tmp_path):
    row = {
        "type": "Feature",
        "id": 1,
        "properties": {},
        "geometry": {"type": "MultiPolygon", "coordinates": [[GOOD + [GOOD[0]]]]},
    }
    src = write_ndjson(tmp_path / "in.ndjson", [row])
    optri.batch(src, tmp_path / "o.ndjson", workers=1)
    rec = next(iter_records(tmp_path / "o.ndjson"))
    assert rec["status"] == "ok" and rec["n"] == 5
    assert rec["cost"] == pytest.approx(optri.triangulate(GOOD).weight)


def test_strict_raises_after_writing_everything(tmp_path):
    src = write_ndjson(tmp_path / "in.ndjson", _rows())
    with pytest.raises(BatchFailedError) as info:
        optri.batch(src, tmp_path / "out", workers=1, strict=True)
    assert info.value.summary.errors == len(BAD) + 1
    assert (tmp_path / "out" / "_SUCCESS").exists()


def _cli(*args):
    return CliRunner().invoke(main, ["batch", *map(str, args), "-q"])


def test_cli_exit_codes(tmp_path):
    src = write_ndjson(tmp_path / "in.ndjson", _rows())
    assert _cli(src, "-o", tmp_path / "a", "-j", "1").exit_code == 0
    res = _cli(src, "-o", tmp_path / "b", "-j", "1", "--strict")
    assert res.exit_code == 1
    good = write_ndjson(tmp_path / "good.ndjson", [{"id": 1, "coordinates": GOOD}])
    assert _cli(good, "-o", tmp_path / "c", "-j", "1", "--strict").exit_code == 0


@pytest.mark.parametrize(
    "name, text, where, words",
    [
        (
            "trunc.geojson",
            '{"type": "FeatureCollection",\n "features": [\n {"type": "Feature", "geometry": nul',
            ":3:",
            "JSON",
        ),
        ("unclosed.geojson", '{"type": "FeatureCollection", "features": [\n', ":2:", "end of file"),
        (
            "garbage_tail.geojson",
            '{"type": "FeatureCollection",\n"features": [\n{"a": 1},\n{"b": }] x',
            ":4:",
            "invalid JSON",
        ),
        ("point.geojson", '{"type": "Point", "coordinates": [1, 2]}', ":1:", "not a polygon layer"),
        ("list.json", "[1, 2, 3]", ":1:", "expected '{'"),
        ("nofeatures.geojson", '{"type": "FeatureCollection"}', ":1:", "no 'features'"),
    ],
)
def test_corrupt_file_is_one_line_naming_file_and_line(tmp_path, name, text, where, words):
    src = tmp_path / name
    src.write_text(text)
    with pytest.raises(BatchInputError, match=words) as info:
        optri.batch(src, tmp_path / "out", workers=1)
    assert f"{src}{where}" in str(info.value)
    res = _cli(src, "-o", tmp_path / "out2", "-j", "1")
    assert res.exit_code == 2
    assert res.output.count("\n") == 1 and "Traceback" not in res.output
    assert f"{name}{where}" in res.output


def test_missing_file_and_unknown_suffix(tmp_path):
    assert "no such file" in _cli(tmp_path / "nope.ndjson", "-o", tmp_path / "o").output
    (tmp_path / "x.txt").write_text("{}")
    res = _cli(tmp_path / "x.txt", "-o", tmp_path / "o")
    assert res.exit_code == 2 and "--format" in res.output


def test_geojson_file_counts_and_ids(tmp_path):
    rows = [{"id": i * 10, "coordinates": SQUARE} for i in range(5)]
    src = write_feature_collection(tmp_path / "in.geojson", rows)
    data = json.loads(src.read_text())
    del data["features"][1]["id"]  # falls back to properties.id, then position
    data["features"][1]["properties"] = {"id": "from_props"}
    del data["features"][2]["id"]
    src.write_text(json.dumps(data))
    optri.batch(src, tmp_path / "o.ndjson", workers=1)
    assert [r["id"] for r in iter_records(tmp_path / "o.ndjson")] == [0, "from_props", 2, 30, 40]
