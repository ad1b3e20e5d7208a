"""Batch outputs under hostile conditions: nothing lost, nothing run, nothing silently reused.

Every case here was a way to lose a file, write through a planted link, adopt planted
parts, reuse another job's results, or crash with an unexpected error.
"""

from __future__ import annotations

import errno
import json
import os
import stat

import pytest
from click.testing import CliRunner

import optri
from batch_polys import killer, write_ndjson
from optri.batch import iter_records
from optri.cli import main
from optri.errors import BatchInputError

SQUARE = [[0, 0], [1, 0], [1, 1], [0, 1]]
PENT = [[0, 0], [4, 0], [5, 3], [2, 5], [-1, 3]]
HEPT = [[0, 0], [4, 0], [6, 2], [5, 5], [2, 6], [-1, 4], [-1, 1]]


def _rows(k: int = 4) -> list[dict]:
    return [{"id": i, "coordinates": SQUARE if i % 2 else PENT} for i in range(k)]


def _cli(*args: object):
    return CliRunner().invoke(main, [str(a) for a in args])


def _one_error_line(res, *words: str) -> None:
    assert res.exit_code == 2, res.output
    assert res.output.count("\n") == 1 and res.output.startswith("optri: error:"), res.output
    for w in words:
        assert w in res.output, res.output


# --- outputs never destroy inputs ----------------------------------------------------


@pytest.mark.parametrize("name", ["f.ndjson", "f.geojson", "f.gpkg"])
@pytest.mark.parametrize("overwrite", [False, True])
def test_an_output_that_is_the_input_is_refused(tmp_path, name, overwrite):
    src = tmp_path / name
    if name.endswith(".gpkg"):
        optri.batch(write_ndjson(tmp_path / "in.ndjson", _rows()), src, workers=1)
    elif name.endswith(".geojson"):
        optri.batch(write_ndjson(tmp_path / "in.ndjson", _rows()), src, workers=1)
    else:
        write_ndjson(src, _rows())
    before = src.read_bytes()
    for out in (src, tmp_path / "sub" / ".." / name):
        (tmp_path / "sub").mkdir(exist_ok=True)
        res = _cli("batch", src, "-o", out, *(["--overwrite"] if overwrite else []))
        _one_error_line(res, "is the input")
    link = tmp_path / ("link" + src.suffix)
    link.symlink_to(src)
    with pytest.raises(BatchInputError, match="is the input"):
        optri.batch(src, link, overwrite=overwrite, workers=1)
    assert src.read_bytes() == before


def test_an_input_inside_the_output_directory_is_never_deleted(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    src = write_ndjson(out / "part-00000.ndjson", _rows())
    before = src.read_bytes()
    res = _cli("batch", src, "-o", str(out) + "/", "--overwrite")
    _one_error_line(res, "inside the output")
    assert src.read_bytes() == before


def test_data_copy_never_replaces_a_users_file(tmp_path):
    mine = tmp_path / "octagon.csv"
    mine.write_text("x,y\n0,0\n")
    res = _cli("data", "-o", tmp_path, "octagon.csv")
    _one_error_line(res, "octagon.csv", "--overwrite")
    assert mine.read_text() == "x,y\n0,0\n"
    with pytest.raises(FileExistsError):
        optri.data.copy_to(tmp_path, ["octagon.csv"])
    assert _cli("data", "-o", tmp_path, "octagon.csv", "--overwrite").exit_code == 0
    assert mine.read_bytes() == optri.data.path("octagon.csv").read_bytes()
    # the same bytes again: nothing to lose, no --overwrite needed
    assert _cli("data", "-o", tmp_path, "octagon.csv").exit_code == 0


def test_a_private_output_stays_private(tmp_path):
    src = write_ndjson(tmp_path / "in.ndjson", _rows())
    out = tmp_path / "out.ndjson"
    out.write_text("secret\n")
    out.chmod(0o600)
    optri.batch(src, out, overwrite=True, workers=1)
    assert stat.S_IMODE(out.stat().st_mode) == 0o600
    assert len(list(iter_records(out))) == 4


def test_a_temporary_left_by_a_killed_final_write_is_removed(tmp_path):
    src = write_ndjson(tmp_path / "in.ndjson", _rows())
    stale = tmp_path / ".out.ndjson.999999.0123456789ab.tmp"
    stale.write_bytes(b"x" * 4096)
    optri.batch(src, tmp_path / "out.ndjson", workers=1)
    assert not stale.exists()


# --- links, planted parts, foreign folders -------------------------------------------


def test_a_lock_file_that_is_a_link_is_refused_not_followed(tmp_path):
    src = write_ndjson(tmp_path / "in.ndjson", _rows())
    precious = tmp_path / "precious"
    precious.write_text("keep me\n")
    (tmp_path / ".out.ndjson.lock").symlink_to(precious)
    with pytest.raises(BatchInputError, match="link"):
        optri.batch(src, tmp_path / "out.ndjson", workers=1)
    assert precious.read_text() == "keep me\n"


def test_a_parts_folder_that_is_a_link_is_refused(tmp_path):
    src = write_ndjson(tmp_path / "in.ndjson", _rows())
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (tmp_path / ".out.ndjson.parts").symlink_to(elsewhere)
    with pytest.raises(BatchInputError, match="link"):
        optri.batch(src, tmp_path / "out.ndjson", workers=1)
    assert list(elsewhere.iterdir()) == []


@pytest.mark.skipif(os.geteuid() != 0, reason="making a folder another user owns needs root")
def test_a_work_folder_owned_by_another_user_is_refused(tmp_path):
    src = write_ndjson(tmp_path / "in.ndjson", _rows())
    parts = tmp_path / ".out.ndjson.parts"
    parts.mkdir()
    os.chown(parts, 4242, 4242)
    with pytest.raises(BatchInputError, match="owned by another user"):
        optri.batch(src, tmp_path / "out.ndjson", workers=1)


def _forged(rec: dict) -> dict:
    return {**rec, "cost": -1.0, "triangles": [[0, 1, 2]], "diagonals": []}


@pytest.mark.parametrize("out_name", ["out/", "out.ndjson"])
def test_planted_parts_are_never_adopted(tmp_path, out_name):
    src = write_ndjson(tmp_path / "in.ndjson", _rows())
    clean = list(iter_records(optri.batch(src, tmp_path / "clean/", workers=1).output))
    out = tmp_path / out_name
    parts = out if out_name.endswith("/") else tmp_path / ".out.ndjson.parts"
    parts.mkdir()
    forged = [_forged(r) for r in clean]
    (parts / "part-00000.ndjson").write_text("".join(json.dumps(r) + "\n" for r in forged))
    # and one past the input's end, which no run would redo
    (parts / "part-00099.ndjson").write_text(json.dumps({**forged[0], "id": "planted"}) + "\n")
    s = optri.batch(src, out, workers=1, chunk_size=len(clean))
    got = list(iter_records(s.output))
    assert [(r["id"], r["cost"]) for r in got] == [(r["id"], r["cost"]) for r in clean]


def test_a_part_changed_after_it_was_written_is_redone(tmp_path):
    src = write_ndjson(tmp_path / "in.ndjson", _rows())
    out = tmp_path / "out"
    optri.batch(src, str(out) + "/", workers=1, chunk_size=2)
    clean = [r["cost"] for r in iter_records(out)]
    part = out / "part-00000.ndjson"
    recs = [json.loads(line) for line in part.read_text().splitlines()]
    part.write_text("".join(json.dumps(_forged(r)) + "\n" for r in recs))
    (out / "_SUCCESS").unlink()
    optri.batch(src, str(out) + "/", workers=1, chunk_size=2)
    assert [r["cost"] for r in iter_records(out)] == clean


# --- a finished output is reused only for the same job --------------------------------


@pytest.mark.parametrize(
    "change",
    [["other"], ["-w", "area"], ["-O", "max"], ["--method", "memo"], ["edited"]],
)
def test_a_finished_file_is_reused_only_for_the_same_job(tmp_path, change):
    a = write_ndjson(tmp_path / "a.ndjson", _rows())
    b = write_ndjson(tmp_path / "b.ndjson", _rows(6))
    out = tmp_path / "out.ndjson"
    assert _cli("batch", a, "-o", out, "-j", "1").exit_code == 0
    first = out.read_bytes()
    res = _cli("batch", a, "-o", out, "-j", "1", "--json")
    assert res.exit_code == 0 and json.loads(res.output)["reused"] == 1  # the same job: reused
    if change == ["other"]:
        args = [b]
    elif change == ["edited"]:  # same size and time, other bytes: only the hash tells
        st = a.stat()
        a.write_bytes(a.read_bytes().replace(b'"id": 0', b'"id": 9'))
        os.utime(a, ns=(st.st_atime_ns, st.st_mtime_ns))
        args = [a]
    else:
        args = [a, *change]
    res = _cli("batch", *args, "-o", out, "-j", "1")
    _one_error_line(res, "--overwrite")
    assert out.read_bytes() == first
    assert _cli("batch", *args, "-o", out, "-j", "1", "--overwrite").exit_code == 0
    assert out.read_bytes() != first


def test_a_file_the_batch_did_not_write_is_not_reused_or_replaced(tmp_path):
    src = write_ndjson(tmp_path / "in.ndjson", _rows())
    out = tmp_path / "out.ndjson"
    out.write_text('{"id": 0, "status": "ok"}\n')
    res = _cli("batch", src, "-o", out, "-j", "1")
    _one_error_line(res, "not written by", "--overwrite")
    assert out.read_text() == '{"id": 0, "status": "ok"}\n'


# --- faults become records or one clear line -----------------------------------------


def test_a_killed_worker_gives_error_records_naming_the_polygon(tmp_path):
    rows = [{"id": f"p{i}", "coordinates": HEPT if i == 3 else PENT} for i in range(8)]
    src = write_ndjson(tmp_path / "in.ndjson", rows)
    s = optri.batch(src, tmp_path / "out.ndjson", weight=killer, workers=2, chunk_size=2)
    recs = {r["id"]: r for r in iter_records(tmp_path / "out.ndjson")}
    assert (s.ok, s.errors) == (7, 1)
    assert recs["p3"]["status"] == "error"
    assert "worker process died" in recs["p3"]["reason"] and "p3" in recs["p3"]["reason"]
    assert all(recs[f"p{i}"]["status"] == "ok" for i in range(8) if i != 3)


@pytest.mark.slow
def test_a_killed_dask_worker_gives_error_records_not_a_hang(tmp_path):
    pytest.importorskip("distributed")
    rows = [{"id": f"p{i}", "coordinates": HEPT if i == 1 else PENT} for i in range(4)]
    src = write_ndjson(tmp_path / "in.ndjson", rows)
    s = optri.batch(
        src, tmp_path / "out.ndjson", weight=killer, workers=2, chunk_size=2, scheduler="dask"
    )
    recs = {r["id"]: r for r in iter_records(tmp_path / "out.ndjson")}
    assert (s.ok, s.errors) == (3, 1)
    assert "worker process died" in recs["p1"]["reason"] and "p1" in recs["p1"]["reason"]


def test_a_full_disk_is_one_clear_line(tmp_path, monkeypatch):
    src = write_ndjson(tmp_path / "in.ndjson", _rows())
    import optri.io.atomic as atomic

    real = os.fdopen

    def full(fd, *args, **kwargs):
        fh = real(fd, *args, **kwargs)

        def no_space(*a, **k):
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

        fh.write = no_space
        return fh

    monkeypatch.setattr(atomic.os, "fdopen", full)
    res = _cli("batch", src, "-o", tmp_path / "out.ndjson", "-j", "1")
    _one_error_line(res, "No space left on device")
    assert not [p for p in tmp_path.rglob("*.tmp*")]


def test_a_full_disk_while_writing_a_geopackage_is_one_clear_line(tmp_path, monkeypatch):
    pyogrio = pytest.importorskip("pyogrio")
    src = write_ndjson(tmp_path / "in.ndjson", _rows())

    def full(*args, **kwargs):
        raise pyogrio.errors.DataLayerError("failed to write: No space left on device")

    monkeypatch.setattr(pyogrio, "write_arrow", full)
    res = _cli("batch", src, "-o", tmp_path / "out.gpkg", "-j", "1")
    _one_error_line(res, "out.gpkg", "No space left on device")


@pytest.mark.skipif(os.geteuid() != 0, reason="mounting a small tmpfs needs root")
def test_a_really_full_disk_is_one_clear_line(tmp_path):
    import subprocess

    disk = tmp_path / "disk"
    disk.mkdir()
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", disk]).returncode:
        pytest.skip("cannot mount a tmpfs here")
    try:
        rows = [
            {"id": i, "coordinates": PENT, "properties": {"pad": "x" * 2000}} for i in range(80)
        ]
        src = write_ndjson(tmp_path / "in.ndjson", rows)
        for name in ("out.ndjson", "out.gpkg"):
            res = _cli("batch", src, "-o", disk / name, "-j", "1")
            _one_error_line(res, "No space left on device")
    finally:
        subprocess.run(["umount", disk])


def test_several_layers_are_listed_and_one_is_chosen_by_name(tmp_path):
    pytest.importorskip("pyogrio")
    import pyogrio

    a = tmp_path / "a.gpkg"
    optri.batch(write_ndjson(tmp_path / "one.ndjson", _rows(2)), a, workers=1)
    gdf = pyogrio.read_dataframe(a)
    gdf = gdf[["geometry"]].iloc[:1]
    pyogrio.write_dataframe(gdf, a, layer="roofs")
    layers = [str(n) for n in pyogrio.list_layers(a)[:, 0]]
    assert len(layers) == 2
    res = _cli("batch", a, "-o", tmp_path / "o.ndjson", "-j", "1")
    _one_error_line(res, *layers, "--layer")
    res = _cli("batch", a, "-o", tmp_path / "o.ndjson", "-j", "1", "--layer", "roofs", "--json")
    assert res.exit_code == 0 and json.loads(res.output)["total"] == 1
    res = _cli("batch", a, "-o", tmp_path / "p.ndjson", "-j", "1", "--layer", "nope")
    _one_error_line(res, "nope", *layers)


def test_endless_standard_input_stops_at_the_size_limit(monkeypatch):
    monkeypatch.setenv("OPTRI_MAX_INPUT_BYTES", "1000")
    endless = b'{"id": 1, "coordinates": [[0, 0], [1, 0], [0, 1]]}\n' * 100
    for cmd in (["solve", "-"], ["batch", "-", "-o", "x.ndjson"], ["fill", "-", "-o", "x.obj"]):
        res = CliRunner().invoke(main, cmd, input=endless)
        _one_error_line(res, "OPTRI_MAX_INPUT_BYTES")
