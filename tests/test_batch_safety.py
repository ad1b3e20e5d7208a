"""Batch under abuse: options checked first, a locked output, workers that die with their
parent, no temporary files left, duplicate ids reported, a user weight's error kept to its row."""

from __future__ import annotations

import collections
import itertools
import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st

import optri
from batch_polys import mixed_polygons, write_ndjson
from optri import config
from optri.batch import BatchLockedError, DuplicateIdWarning, iter_records, summary
from optri.batch.layout import output_lock
from optri.batch.summary import IdHashes
from optri.cli import main

SRC = str(Path(__file__).resolve().parents[1] / "src")
TESTS = str(Path(__file__).resolve().parent)
SQUARE = [[0, 0], [1, 0], [1, 1], [0, 1]]


def _env():
    path = os.pathsep.join([SRC, TESTS, os.environ.get("PYTHONPATH", "")])
    return dict(os.environ, PYTHONPATH=path)


def _popen(*args):
    cmd = [sys.executable, "-m", "optri", "batch", *map(str, args)]
    return subprocess.Popen(
        cmd, env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )


@pytest.mark.parametrize(
    "args, words",
    [
        (["-w", "nope"], "unknown weight 'nope'"),
        (["--objective", "median"], "objective must be"),
        (["-w", "perimeter,area"], "1 component(s) but 2 weight(s)"),
    ],
)
def test_unknown_options_are_refused_before_anything_is_read(tmp_path, args, words):
    src = write_ndjson(tmp_path / "in.ndjson", [{"id": 1, "coordinates": SQUARE}])
    res = CliRunner().invoke(main, ["batch", str(src), "-o", str(tmp_path / "out"), *args])
    assert res.exit_code == 2 and res.output.count("\n") == 1 and words in res.output
    assert not (tmp_path / "out").exists()
    with pytest.raises(optri.OptriError):  # the API refuses even before opening the file
        optri.batch(tmp_path / "missing.ndjson", tmp_path / "o", method="nope")


def test_a_locked_output_is_refused_with_the_holders_pid(tmp_path):
    src = write_ndjson(tmp_path / "in.ndjson", [{"id": 1, "coordinates": SQUARE}])
    out = tmp_path / "out.ndjson"
    with output_lock(tmp_path / ".out.ndjson.lock", out):
        with pytest.raises(BatchLockedError, match=f"pid {os.getpid()}"):
            optri.batch(src, out, workers=1)
        res = CliRunner().invoke(main, ["batch", str(src), "-o", str(out)])
        assert res.exit_code == 2 and "being written by another optri batch" in res.output
    assert not out.exists()
    optri.batch(src, out, workers=1)  # free again, and the lock file is gone
    assert [r["id"] for r in iter_records(out)] == [1]
    assert not (tmp_path / ".out.ndjson.lock").exists()


def test_a_lock_left_by_a_dead_process_does_not_block(tmp_path):
    (tmp_path / ".o.ndjson.lock").write_text("999999999\n")  # a file, but nobody holds it
    src = write_ndjson(tmp_path / "in.ndjson", [{"id": 1, "coordinates": SQUARE}])
    assert optri.batch(src, tmp_path / "o.ndjson", workers=1).ok == 1


@pytest.mark.parametrize("out_name", ["out.ndjson", "out/"])
def test_two_concurrent_runs_never_lose_or_repeat_records(tmp_path, out_name):
    rows = mixed_polygons(1500, seed=3, lo=4, hi=6)
    src = write_ndjson(tmp_path / "in.ndjson", rows)
    out = tmp_path / out_name
    args = (src, "-o", out, "-j", "1", "--chunk-size", "50")
    procs = [_popen(*args), _popen(*args)]
    codes = [p.wait(300) for p in procs]
    errs = [p.stderr.read() for p in procs]
    assert sorted(codes) in ([0, 0], [0, 2]), errs
    for code, err in zip(codes, errs):
        if code == 2:
            assert "being written by another optri batch" in err and "Traceback" not in err
    ids = [r["id"] for r in iter_records(out)]
    assert ids == [r["id"] for r in rows]  # every record, once, in input order


def test_workers_die_with_a_parent_killed_by_sigkill(tmp_path):
    psutil = pytest.importorskip("psutil")
    src = write_ndjson(tmp_path / "in.ndjson", mixed_polygons(20000, seed=4, lo=8, hi=12))
    proc = _popen(src, "-o", tmp_path / "out", "-j", "2", "--chunk-size", "20", "-q")
    parent = psutil.Process(proc.pid)
    deadline = time.monotonic() + 120
    kids: list = []
    while time.monotonic() < deadline and not (tmp_path / "out" / "part-00001.ndjson").exists():
        kids = parent.children(recursive=True) or kids
        time.sleep(0.05)
    kids = parent.children(recursive=True) or kids
    assert len(kids) >= 2, "the pool never started"
    proc.send_signal(signal.SIGKILL)
    proc.wait(30)
    gone, alive = psutil.wait_procs(kids, timeout=20)
    assert alive == [], f"left running: {alive}"


def test_sigterm_leaves_no_temporary_file(tmp_path):
    src = write_ndjson(tmp_path / "in.ndjson", mixed_polygons(3000, seed=6, lo=4, hi=6))
    out = tmp_path / "o.ndjson"
    proc = _popen(src, "-o", out, "-j", "2", "--chunk-size", "16", "-q")
    parts = tmp_path / ".o.ndjson.parts"
    deadline = time.monotonic() + 120
    while len(list(parts.glob("part-*"))) < 3 and time.monotonic() < deadline:
        time.sleep(0.01)
    proc.send_signal(signal.SIGTERM)
    assert proc.wait(60) == 143
    assert proc.stderr.read().splitlines()[-1] == "optri: terminated"
    assert [
        p.name for p in tmp_path.rglob("*") if ".tmp" in p.name or p.name.endswith(".lock")
    ] == []
    res = _popen(src, "-o", out, "-j", "2", "--chunk-size", "16", "-q")  # resumes, then tidies
    assert res.wait(300) == 0, res.stderr.read()
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        ".o.ndjson.optri.json",
        "in.ndjson",
        "o.ndjson",
    ]
    assert len(list(iter_records(out))) == 3000


def test_duplicate_ids_are_warned_about_and_counted(tmp_path):
    rows = [{"id": i % 3, "coordinates": SQUARE} for i in range(7)] + [{"coordinates": SQUARE}]
    src = write_ndjson(tmp_path / "in.ndjson", rows)
    with pytest.warns(DuplicateIdWarning, match=r"4 record\(s\) repeat an earlier id \('0' x3"):
        summary = optri.batch(src, tmp_path / "o.gpkg" if _geo() else tmp_path / "o", workers=1)
    assert summary.duplicates == 4 and "4 duplicate ids" in str(summary)
    res = CliRunner().invoke(main, ["batch", str(src), "-o", str(tmp_path / "c.ndjson"), "-j", "1"])
    assert res.exit_code == 0
    assert res.output.count("optri: warning: 4 record(s) repeat an earlier id") == 1
    unique = write_ndjson(
        tmp_path / "u.ndjson", [{"id": i, "coordinates": SQUARE} for i in range(5)]
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error", DuplicateIdWarning)  # unique ids: no warning at all
        assert optri.batch(unique, tmp_path / "v.ndjson", workers=1).duplicates == 0


def test_duplicate_ids_are_found_when_the_hashes_spill_to_disk(tmp_path, monkeypatch):
    # a few hashes in memory: the rest go to bucket files, counted and removed at the end
    monkeypatch.setattr(config, "BATCH_ID_HASHES_IN_MEMORY", 3)
    spill = tmp_path / "tmp"
    spill.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(spill))
    rows = [{"id": i % 40, "coordinates": SQUARE} for i in range(100)]
    src = write_ndjson(tmp_path / "in.ndjson", rows)
    with pytest.warns(DuplicateIdWarning, match=r"60 record\(s\) repeat an earlier id"):
        summary = optri.batch(src, tmp_path / "o.ndjson", workers=1, chunk_size=8)
    assert summary.duplicates == 60 and summary.partitions > 3
    assert list(spill.iterdir()) == []


def test_id_hash_spill_files_go_when_counted(tmp_path, monkeypatch):
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    hashes = IdHashes(limit=1)
    hashes.add(np.array([1, 2, 2], dtype=np.int64))
    assert len(list(tmp_path.rglob("*.bin"))) > 0  # spilled
    assert hashes.repeated() == (1, {2})
    assert list(tmp_path.iterdir()) == []  # gone at once, not when collected


def test_id_hashes_a_full_disk_neither_loses_nor_doubles_a_hash(tmp_path, monkeypatch):
    # every other append fails halfway: its rows stay in memory, the file is cut back
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    calls = itertools.count()

    def flaky(fh, rows):
        if next(calls) % 2:
            fh.write(rows.tobytes()[: len(rows.tobytes()) // 2 + 1])
            raise OSError(28, "No space left on device")
        rows.tofile(fh)

    monkeypatch.setattr(summary, "_write", flaky)
    rng = np.random.default_rng(7)
    pool = rng.integers(-(2**63), 2**63 - 1, 300, dtype=np.int64)
    parts = [rng.choice(pool, 50) for _ in range(12)]
    hashes = IdHashes(limit=60)
    for p in parts:
        hashes.add(p)
    assert next(calls) > 20  # spilled, and some appends failed
    flat = np.concatenate(parts).tolist()
    seen = collections.Counter(flat)
    assert hashes.repeated() == (len(flat) - len(seen), {h for h, c in seen.items() if c > 1})
    assert list(tmp_path.iterdir()) == []


@given(st.lists(st.lists(st.integers(-(2**63), 2**63 - 1) | st.integers(0, 5), max_size=6)))
@settings(max_examples=60, deadline=None)
def test_id_hashes_count_repeats_as_a_sort_does(parts):
    hashes = IdHashes(limit=4)
    for p in parts:
        hashes.add(np.array(p, dtype=np.int64))
    flat = [h for p in parts for h in p]
    seen = collections.Counter(flat)
    assert hashes.repeated() == (len(flat) - len(seen), {h for h, c in seen.items() if c > 1})


def _geo():
    try:
        import pyogrio  # noqa: F401
    except ImportError:
        return False
    return True


def fragile(vertices, i, k, j):
    """A user weight that fails on pentagons (a module-level function: picklable)."""
    if len(vertices) == 5:
        raise ZeroDivisionError("the user's weight divided by zero")
    return 1.0


def noisy(vertices, i, k, j):
    """A user weight that warns (as numpy overflow would) and still answers."""
    warnings.warn("overflow encountered in the user's weight", RuntimeWarning, stacklevel=1)
    return 1.0


@pytest.mark.parametrize("workers", [1, 2])
def test_a_user_weight_that_raises_fails_its_record_only(tmp_path, workers, capfd):
    pent = [[0, 0], [4, 0], [5, 3], [2, 5], [-1, 3]]
    rows = [{"id": "sq", "coordinates": SQUARE}, {"id": "pent", "coordinates": pent}] * 3
    src = write_ndjson(tmp_path / "in.ndjson", rows)
    s = optri.batch(src, tmp_path / "o.ndjson", weight=fragile, workers=workers, chunk_size=2)
    recs = list(iter_records(tmp_path / "o.ndjson"))
    assert (s.ok, s.errors) == (3, 3)
    for rec in recs:
        if rec["id"] == "pent":
            assert rec["status"] == "error"
            assert re.fullmatch(
                r"weight 'custom' raised ZeroDivisionError on triangle \(\d, \d, \d\): "
                r"the user's weight divided by zero",
                rec["reason"],
            ), rec["reason"]
        else:
            assert rec["status"] == "ok" and rec["cost"] == 2.0
    out = optri.batch(src, tmp_path / "n.ndjson", weight=noisy, workers=workers, chunk_size=2)
    assert out.ok == 6
    notes = {r["reason"] for r in iter_records(tmp_path / "n.ndjson")}
    assert notes == {"warning: overflow encountered in the user's weight"}
    assert "overflow" not in capfd.readouterr().err  # not on stderr, from any process


def test_overflowing_coordinates_warn_into_the_record_not_stderr(tmp_path):
    rows = [
        {"id": "big", "coordinates": [[0, 0], [1e200, 0], [0, 1e200]]},
        {"id": "ok", "coordinates": SQUARE},
    ]
    src = write_ndjson(tmp_path / "in.ndjson", rows)
    res = subprocess.run(
        [
            sys.executable,
            "-m",
            "optri",
            "batch",
            str(src),
            "-o",
            str(tmp_path / "o.ndjson"),
            "-j",
            "2",
        ],
        env=_env(),
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert res.returncode == 0 and "RuntimeWarning" not in res.stderr, res.stderr
    assert res.stderr.count("\n") == 1  # the summary line only
    recs = {r["id"]: r for r in iter_records(tmp_path / "o.ndjson")}
    assert recs["ok"]["status"] == "ok" and recs["big"]["status"] in ("ok", "error")
    assert "\n" not in json.dumps(recs["big"]["reason"])
