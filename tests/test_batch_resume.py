"""Interrupt (SIGINT / SIGTERM) and rerun gives the bytes of a clean run; resume rules."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import pytest

import optri
from batch_polys import mixed_polygons, write_ndjson
from cli_run import run_optri, run_python
from optri.batch import BatchInputError, iter_records

HELPER = Path(__file__).resolve().parent / "batch_interrupt.py"
TIMING = re.compile(rb'"seconds":[0-9.eE+-]+')


def _snapshot(directory: Path) -> dict[str, Any]:
    """Every file's bytes with the timing fields blanked; the parts ledger by its entries.

    The ledger lists parts in the order they were finished, which varies with the
    workers and the interruptions, and hashes bytes that hold timings: its entries
    are compared sorted, without the hashes.
    """
    out = {p.name: TIMING.sub(b'"seconds":0', p.read_bytes()) for p in sorted(directory.iterdir())}
    ledger = out.pop("_parts.ndjson", b"")
    # each part's hash covers its timings: the entries are compared without it
    entries = [json.loads(line) for line in ledger.splitlines()]
    out["_parts.ndjson"] = sorted(json.dumps({**e, "sha256": None}) for e in entries)
    return out


N_POLYGONS, CHUNK = 200, 16
PARTS = -(-N_POLYGONS // CHUNK)


def _interrupted(args, out: Path, sig: str, part: int) -> int:
    """Run ``optri batch`` signalled ``sig`` while it writes its ``part``-th part; parts then."""
    r = run_python(HELPER, sig, part, "--", "batch", *args, "-q")
    code, word = {"INT": (130, "interrupted"), "TERM": (143, "terminated")}[sig]
    assert r.returncode == code, r.stderr  # as every command: 128 + the signal's number
    assert r.stderr == f"optri: {word}\n"
    assert not (out / "_SUCCESS").exists()
    assert not list(out.glob(".part-*"))  # the part being written was removed, not left half
    return len(list(out.glob("part-*.ndjson")))


def test_sigint_then_sigterm_then_rerun_equals_clean_run(tmp_path):
    src = write_ndjson(tmp_path / "in.ndjson", mixed_polygons(N_POLYGONS, seed=11, lo=4, hi=6))
    optri.batch(src, tmp_path / "clean", workers=1, chunk_size=CHUNK)
    expected = _snapshot(tmp_path / "clean")
    out = tmp_path / "out"
    args = (src, "-o", out, "--workers", "2", "--chunk-size", CHUNK)
    assert _interrupted(args, out, "INT", part=3) == 2  # Ctrl-C in the third part
    assert _interrupted(args, out, "TERM", part=4) == 2 + 3  # resumed, killed in its fourth
    rerun = run_optri("batch", *args, "-q")
    assert rerun.returncode == 0, rerun.stderr
    assert len(list(out.glob("part-*.ndjson"))) == PARTS
    assert _snapshot(out) == expected  # two processes or one, interrupted or not: same bytes


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
