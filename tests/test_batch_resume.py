"""Interrupt (SIGINT / SIGTERM) and rerun gives the bytes of a clean run; resume rules."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import optri
from batch_polys import mixed_polygons, write_ndjson
from optri.batch import BatchInputError, iter_records

SRC = str(Path(__file__).resolve().parents[1] / "src")
TIMING = re.compile(rb'"seconds":[0-9.eE+-]+')


def _cli(*args):
    env = dict(os.environ, PYTHONPATH=SRC + os.pathsep + os.environ.get("PYTHONPATH", ""))
    cmd = [sys.executable, "-m", "optri", "batch", *map(str, args), "-q"]
    return subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE)


def _snapshot(directory: Path) -> dict[str, bytes]:
    """Every file's bytes with the timing fields blanked."""
    return {p.name: TIMING.sub(b'"seconds":0', p.read_bytes()) for p in sorted(directory.iterdir())}


ARGS = ("--workers", "2", "--chunk-size", "16")
N_POLYGONS = 3000  # enough parts that a signal lands well before the end, even on a busy CI
PARTS = -(-N_POLYGONS // 16)


def _interrupt(args, out: Path, sig: int, after: int) -> int:
    """Start the CLI, send ``sig`` once ``after`` parts exist; return the parts then."""
    proc = _cli(*args)
    deadline = time.monotonic() + 60
    while len(list(out.glob("part-*"))) < after and time.monotonic() < deadline:
        time.sleep(0.01)
    proc.send_signal(sig)
    code = proc.wait(60)
    assert code == 130, proc.stderr.read()
    done = len(list(out.glob("part-*.ndjson")))
    assert not (out / "_SUCCESS").exists() and after <= done < PARTS
    assert not list(out.glob(".part-*"))  # no half-written part is left behind
    return done


def test_sigint_then_sigterm_then_rerun_equals_clean_run(tmp_path):
    src = write_ndjson(tmp_path / "in.ndjson", mixed_polygons(N_POLYGONS, seed=11, lo=4, hi=6))
    optri.batch(src, tmp_path / "clean", workers=2, chunk_size=16)
    expected = _snapshot(tmp_path / "clean")
    out = tmp_path / "out"
    args = (src, "-o", out, *ARGS)
    first = _interrupt(args, out, signal.SIGINT, after=3)
    _interrupt(args, out, signal.SIGTERM, after=first + 3)
    rerun = _cli(*args)
    assert rerun.wait(120) == 0, rerun.stderr.read()
    assert _snapshot(out) == expected


def test_killed_hard_leaves_only_temporaries_which_resume_removes(tmp_path):
    rows = mixed_polygons(30, seed=2)
    src = write_ndjson(tmp_path / "in.ndjson", rows)
    out = tmp_path / "out"
    optri.batch(src, out, workers=1, chunk_size=10)
    (out / "part-00001.ndjson").rename(out / ".part-00001.ndjson.abc.tmp")  # as after SIGKILL
    (out / "_SUCCESS").unlink()
    s = optri.batch(src, out, workers=1)  # chunk size comes from the manifest
    assert (s.reused, s.partitions, s.total) == (2, 3, 30)
    assert not list(out.glob(".part-*")) and (out / "_SUCCESS").exists()
    assert [r["id"] for r in iter_records(out)] == [r["id"] for r in rows]


def test_resume_overwrite_and_option_checks(tmp_path):
    src = write_ndjson(tmp_path / "in.ndjson", mixed_polygons(20, seed=4))
    out = tmp_path / "out"
    first = optri.batch(src, out, workers=1, chunk_size=6)
    again = optri.batch(src, out, workers=1)
    assert (again.reused, again.total, again.ok) == (4, 20, first.ok)
    with pytest.raises(BatchInputError, match="changed: weight"):
        optri.batch(src, out, workers=1, weight="area")
    with pytest.raises(BatchInputError, match="overwrite"):
        optri.batch(src, out, workers=1, resume=False)
    redo = optri.batch(src, out, workers=1, weight="area", overwrite=True)
    assert redo.reused == 0 and redo.total == 20


def test_single_file_output_is_assembled_and_not_redone(tmp_path):
    rows = mixed_polygons(25, seed=6)
    src = write_ndjson(tmp_path / "in.ndjson", rows)
    target = tmp_path / "res.ndjson"
    optri.batch(src, target, workers=2, chunk_size=4)
    assert not (tmp_path / ".res.ndjson.parts").exists()
    assert [r["id"] for r in iter_records(target)] == [r["id"] for r in rows]
    before = target.read_bytes()
    assert optri.batch(src, target, workers=1).reused == 1
    assert target.read_bytes() == before
