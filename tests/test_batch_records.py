"""Batches go record by record: every line that cannot be read is an error record, never a crash."""

from __future__ import annotations

import json

import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import optri
from batch_polys import write_feature_collection
from optri.batch import BatchInputError, iter_records, readers
from optri.cli import main

SQUARE = [[0, 0], [1, 0], [1, 1], [0, 1]]
PENTAGON = [[0, 0], [4, 0], [5, 3], [2, 5], [-1, 3]]


def _good(i):
    return json.dumps({"id": f"good{i}", "coordinates": SQUARE if i % 2 else PENTAGON}) + "\n"


# (line bytes, words in the reason, id the record must carry: None = its position)
BAD_LINES = {
    "truncated": (b'{"id": "cut", "coordinates": [[0, 0], [1,', "invalid JSON", "cut"),
    "not_json": (b"this is not json", "invalid JSON", None),
    "wrong_shape": (b'{"id": "shape", "coordinates": {"x": 1}}', "must be a list", "shape"),
    "a_list": (b"[1, 2, 3]", "expected a JSON object", None),
    "a_number": (b"42", "expected a JSON object", None),
    "deep": (b"[" * 100_000 + b"]" * 100_000, "nested too deeply", None),
    "deep_props": (
        b'{"id": "dp", "coordinates": [[0,0],[1,0],[0,1]], "properties": '
        + b'{"a": ' * 200
        + b"1"
        + b"}" * 200
        + b', "type": "Feature", '
        + b'"geometry": {"type": "Polygon", "coordinates": [[[0,0],[1,0],[0,1]]]}}',
        "nested deeper",
        "dp",
    ),
    "latin1": ('{"id": "caf\xe9", "coordinates": []}'.encode("latin-1"), "not UTF-8", None),
    "binary": (bytes(range(1, 10)) + b"\xff\xfe", "not UTF-8", None),
    "huge_int": (
        b'{"id": "big", "coordinates": [[' + b"9" * 5000 + b", 0], [1, 0], [0, 1]]}",
        "invalid JSON",
        "big",
    ),
    "overflow": (b'{"id": "ovf", "coordinates": [[1e400, 0], [1, 0], [0, 1]]}', "", "ovf"),
    "nan_coord": (b'{"id": "nanc", "coordinates": [[NaN, 0], [1, 0], [0, 1]]}', "", "nanc"),
    "point": (b'{"type": "Point", "id": "pt", "coordinates": [1, 2]}', "not a Polygon", "pt"),
    "null_geometry": (b'{"type": "Feature", "id": "ng", "geometry": null}', "no geometry", "ng"),
}


def _layer(tmp_path):
    """Good lines with every kind of bad line in the middle; returns path and expectations."""
    lines, expect = [], []
    for k, (key, (raw, words, rid)) in enumerate(BAD_LINES.items()):
        lines += [_good(k).encode(), raw + b"\n"]
        expect += [(f"good{k}", "ok", None, ""), (key, "error", rid, words)]
    lines.append(_good(99).encode())
    expect.append(("good99", "ok", None, ""))
    src = tmp_path / "mixed.ndjson"
    src.write_bytes(b"".join(lines))
    return src, expect


@pytest.mark.parametrize("out_name", ["out.ndjson", "out.geojson", "parts/"])
def test_bad_lines_in_the_middle_become_error_records_and_the_run_goes_on(tmp_path, out_name):
    src, expect = _layer(tmp_path)
    res = CliRunner().invoke(main, ["batch", str(src), "-o", str(tmp_path / out_name), "-j", "1"])
    assert res.exit_code == 0, res.output
    assert "Traceback" not in res.output
    recs = list(iter_records(tmp_path / out_name))
    assert len(recs) == len(expect)
    for position, (rec, (key, status, rid, words)) in enumerate(zip(recs, expect)):
        assert rec["status"] == status, (key, rec)
        if status == "ok":
            assert rec["id"] == key and rec["reason"] is None
            continue
        assert rec["id"] == (position if rid is None else rid), (key, rec)
        assert words in rec["reason"] and "\n" not in rec["reason"], (key, rec)
        if key not in ("overflow", "nan_coord"):
            # what the reader refuses names its line (1-based); the solver's reasons do not
            assert rec["reason"].startswith(f"line {position + 1}: "), (key, rec)


def test_strict_exits_1_after_writing_every_record(tmp_path):
    src, expect = _layer(tmp_path)
    res = CliRunner().invoke(
        main, ["batch", str(src), "-o", str(tmp_path / "o.ndjson"), "-j", "1", "--strict"]
    )
    assert res.exit_code == 1
    assert len(list(iter_records(tmp_path / "o.ndjson"))) == len(expect)


def test_unreadable_file_still_exits_2_with_one_line(tmp_path):
    for name, data in [("gone.ndjson", None), ("dir.ndjson", "dir")]:
        path = tmp_path / name
        if data == "dir":
            path.mkdir()
        res = CliRunner().invoke(main, ["batch", str(path), "-o", str(tmp_path / "o.ndjson")])
        assert res.exit_code == 2 and res.output.count("\n") == 1, res.output
        assert res.output.startswith("optri: error: ")


def test_ids_are_always_valid_json(tmp_path):
    src = tmp_path / "ids.ndjson"
    lines = [
        '{"id": NaN, "coordinates": [[0,0],[1,0],[0,1]]}',
        '{"id": Infinity, "coordinates": [[0,0],[1,0],[0,1]]}',
        '{"id": -Infinity, "coordinates": [[0,0],[1,0],[0,1]]}',
        '{"id": 1e400, "coordinates": [[0,0],[1,0],[0,1]]}',
        '{"id": {"nested": [1]}, "coordinates": [[0,0],[1,0],[0,1]]}',
        '{"id": 7, "coordinates": [[0,0],[1,0],[0,1]], "properties": {"v": NaN, "w": [Infinity]}}',
    ]
    src.write_text("\n".join(lines) + "\n")
    for out in ("o.ndjson", "o.geojson"):
        optri.batch(src, tmp_path / out, workers=1)
        text = (tmp_path / out).read_text()
        # strict JSON: this hook refuses the NaN/Infinity tokens Python would accept
        docs = text.splitlines() if out.endswith("ndjson") else [text]
        assert all(json.loads(t, parse_constant=_refuse) for t in docs)
    ids = [r["id"] for r in iter_records(tmp_path / "o.ndjson")]
    assert ids == ["NaN", "Infinity", "-Infinity", "Infinity", '{"nested":[1]}', 7]
    last = list(iter_records(tmp_path / "o.ndjson"))[-1]
    assert (last["v"], last["w"]) == ("NaN", ["Infinity"])


def _refuse(token):
    raise AssertionError(f"non-standard JSON token {token}")


@pytest.mark.parametrize("block", [1, 7, 1 << 20])  # line numbers across block edges
def test_feature_collection_skips_a_broken_feature_and_reads_on(tmp_path, monkeypatch, block):
    monkeypatch.setattr(optri.config, "BATCH_READ_BLOCK", block)
    src = tmp_path / "fc.geojson"
    good = json.dumps(
        {
            "type": "Feature",
            "id": "g",
            "properties": {},
            "geometry": {"type": "Polygon", "coordinates": [SQUARE]},
        }
    )
    deep = "[" * 5_000 + "]" * 5_000
    src.write_text(
        '{"type": "FeatureCollection",\n"features": [\n'
        + good
        + ',\n{"b": },\n'
        + deep
        + ",\n"
        + good.replace('"g"', '"h"')
        + "\n]}\n"
    )
    recs = list(_records(src, tmp_path / "o.ndjson"))
    assert [r["status"] for r in recs] == ["ok", "error", "error", "ok"]
    assert recs[1]["reason"].startswith("line 4: invalid JSON")
    assert recs[2]["reason"] == "line 5: invalid JSON (nested too deeply to read)"
    assert [recs[0]["id"], recs[3]["id"]] == ["g", "h"]


def _records(src, out):
    optri.batch(src, out, workers=1)
    return iter_records(out)


def test_feature_collection_cut_short_is_refused(tmp_path):
    src = tmp_path / "cut.geojson"
    src.write_text(
        '{"type": "FeatureCollection", "features": [\n{"type": "Feature", "geometry": [[['
    )
    with pytest.raises(BatchInputError, match=r"cut.geojson:2: unexpected end"):
        optri.batch(src, tmp_path / "o.ndjson", workers=1)


def test_attributes_of_geojson_features_survive_ndjson_and_geojson(tmp_path):
    rows = [{"id": i, "coordinates": SQUARE} for i in range(3)]
    src = write_feature_collection(tmp_path / "in.geojson", rows)
    data = json.loads(src.read_text())
    data["features"][1]["properties"] = {"name": "b", "status": "built", "h": None}
    src.write_text(json.dumps(data))
    optri.batch(src, tmp_path / "o.geojson", workers=1)
    optri.batch(src, tmp_path / "o.ndjson", workers=1)
    feat = json.loads((tmp_path / "o.geojson").read_text())["features"][1]
    assert feat["properties"]["name"] == "b" and feat["properties"]["h"] is None
    assert feat["properties"]["status_input"] == "built" and feat["properties"]["status"] == "ok"
    rec = list(iter_records(tmp_path / "o.ndjson"))[1]  # a Feature line, as in the collection
    assert rec == {"id": feat["id"], **feat["properties"], "seconds": rec["seconds"]}


JSON_VALUES = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=5),
    lambda inner: (
        st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=3), inner, max_size=4)
    ),
    max_leaves=20,
)


@settings(
    max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    lines=st.lists(
        st.binary(max_size=60) | JSON_VALUES.map(lambda v: json.dumps(v).encode()), max_size=8
    )
)
def test_any_bytes_or_json_lines_give_one_item_each(tmp_path, lines):
    src = tmp_path / "fuzz.ndjson"
    clean = [ln.replace(b"\n", b" ").replace(b"\r", b" ") for ln in lines]
    src.write_bytes(b"".join(ln + b"\n" for ln in clean))
    items = list(readers.read_items(src))  # never raises: every line is an item
    if clean and clean[0].startswith(b"\xef\xbb\xbf"):  # a byte-order mark is not content
        clean[0] = clean[0][3:]
    assert len(items) == sum(1 for ln in clean if ln.strip())
    for item in items:
        assert (item.reason is None) == (item.coords is not None)
        json.dumps(item.id, allow_nan=False)  # ids are valid JSON


@settings(
    max_examples=100, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(data=st.binary(max_size=200) | JSON_VALUES.map(lambda v: json.dumps(v).encode()))
def test_any_bytes_as_a_feature_collection_give_items_or_one_clear_error(tmp_path, data):
    src = tmp_path / "fuzz.geojson"
    src.write_bytes(data)
    try:
        list(readers.read_items(src))
    except BatchInputError as exc:
        assert str(exc).startswith(f"{src}:") and "\n" not in str(exc)
