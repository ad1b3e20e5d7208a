"""Throw about 1,500 bad inputs at optri and count what happens, per category.

    PYTHONPATH=src python benchmarks/hostile_inputs.py [--quick] [--json]

Categories: API parameters, extreme coordinates, files given to the CLI, batch
lines, meshes at scales, processes, and outputs and faults (an output that is the
input, planted links and parts, a finished output reused for another job, "proven"
at three scales, exact ints near 2**63, killed workers, endless stdin, layers). Outcomes:

* ``own_error``: the library raised one of optri's exceptions;
* ``cli_error``: the CLI exited 2 with one ``optri: error:``/usage line;
* ``answer``: a valid answer (finite cost, ``check()`` passes), for input that is fine;
* ``traceback``: any other exception escaped (or the CLI printed a traceback);
* ``hang``: past the time limit (``HANG_SECONDS``);
* ``silent``: bad input accepted (a result for a bad parameter, ``inf``/NaN cost,
  a triangulation failing its own check);
* ``lost``: a batch record missing or duplicated.

Tracebacks, hangs and losses must be 0 (the script exits 1 otherwise).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import signal
import subprocess
import sys
import tempfile
from collections import Counter, defaultdict
from pathlib import Path

import numpy as np
from click.testing import CliRunner

import optri
from optri.batch import iter_records
from optri.cli import main

HANG_SECONDS = 30
SQ = [[0, 0], [1, 0], [1, 1], [0, 1]]
PENT = [[0, 0], [2, 0], [3, 2], [1, 3], [-1, 2]]
ARROW = [[0, 0], [4, 0], [1, 1], [0, 4]]
RESULTS: dict[str, Counter] = defaultdict(Counter)
EXAMPLES: dict[tuple[str, str], list[str]] = defaultdict(list)


class Hang(Exception):
    pass


def _alarm(signum, frame):
    raise Hang


def record(category: str, outcome: str, label: str) -> None:
    RESULTS[category][outcome] += 1
    EXAMPLES[(category, outcome)].append(label)


def run_api(category: str, label: str, call, bad: bool = True) -> None:
    """Call; classify. ``bad``: the input should be refused (else an answer is expected)."""
    signal.alarm(HANG_SECONDS)
    try:
        out = call()
        if isinstance(out, list) and out and isinstance(out[0], optri.Triangulation):
            out = out[0]
        if bad:
            record(category, "silent", label)
        elif isinstance(out, optri.Triangulation):
            weights = out.weight if isinstance(out.weight, tuple) else (out.weight,)
            ok = all(math.isfinite(w) for w in weights)
            try:
                out.check()
            except Exception:
                ok = False
            record(category, "answer" if ok else "silent", label)
        else:
            record(category, "answer", label)
    except Hang:
        record(category, "hang", label)
    except optri.OptriError:
        record(category, "own_error", label)
    except Exception as exc:
        record(category, "traceback", f"{label}: {type(exc).__name__}: {exc}"[:200])
    finally:
        signal.alarm(0)


def run_cli(category: str, label: str, argv: list[str]) -> None:
    signal.alarm(HANG_SECONDS)
    try:
        res = CliRunner().invoke(main, argv)
    except Hang:
        record(category, "hang", label)
        return
    finally:
        signal.alarm(0)
    err = [ln for ln in res.stderr.splitlines() if ln.strip()]
    escaped = "Traceback" in res.stderr or "a bug in optri" in res.stderr  # the catch-all
    if not isinstance(res.exception, (SystemExit, type(None))) or escaped:
        record(category, "traceback", f"{label}: {res.exception!r}"[:200])
    elif res.exit_code == 0:
        record(category, "answer", label)
    elif res.exit_code == 2 and len(err) == 1:
        record(category, "cli_error", label)
    elif res.exit_code == 2 and err and err[0].startswith(("Usage:", "Error:")):
        record(category, "cli_error", label)  # click usage message (several lines)
    else:
        record(category, "traceback", f"{label}: exit {res.exit_code} {err[-2:]}"[:200])


# --- categories -----------------------------------------------------------------------


def api_parameters() -> None:
    cat = "api_parameters"
    objectives = [None, 5, 1.5, "avg", "", ("sum", "avg"), (), [], ("sum", None), {"sum"}, b"sum"]
    weights = [None, 5, 1.5, "nope", "", b"perimeter", ("perimeter",) * 3, object(), [], {}]
    ks = [0, -1, "3", 1.5, None, True, np.float64(2.0), [3], -(10**30)]
    methods = [None, 5, "x", "FAST", "", ["fast"], b"memo", "gpu2"]
    dtypes = ["banana", int, np.int32, np.complex128, object, "float16", np.bool_, "f8x"]
    seconds = [-1, 0, math.nan, math.inf, "x", True, [1], -math.inf]
    flags = ["x", 1, 0, [], "True", 2.0]
    callbacks = [5, "print", lambda: None, lambda a: None, lambda a, b, c: None]
    seeds = ["x", 1.5, [1], b"seed", object(), 2.5]
    polys = [SQ, PENT, ARROW]
    for p in polys:
        for o in objectives:
            run_api(
                cat,
                f"triangulate objective={o!r}",
                lambda o=o, p=p: optri.triangulate(p, objective=o),
            )
            run_api(
                cat,
                f"best objective={o!r}",
                lambda o=o, p=p: optri.best_triangulations(p, k=2, objective=o),
            )
            run_api(
                cat,
                f"enumerate objective={o!r}",
                lambda o=o, p=p: list(optri.enumerate_triangulations(p, "area", o)),
            )
            run_api(
                cat,
                f"many objective={o!r}",
                lambda o=o, p=p: optri.triangulate_many([p], objective=o),
            )
        for w in weights:
            run_api(
                cat, f"triangulate weight={w!r}", lambda w=w, p=p: optri.triangulate(p, weight=w)
            )
            run_api(
                cat,
                f"best weight={w!r}",
                lambda w=w, p=p: optri.best_triangulations(p, weight=w, k=2),
            )
            if w is not None:  # None: no weight, a fine call
                run_api(
                    cat,
                    f"random weight={w!r}",
                    lambda w=w, p=p: optri.random_triangulation(p, 1, weight=w),
                )
        for k in ks:
            run_api(cat, f"best k={k!r}", lambda k=k, p=p: optri.best_triangulations(p, k=k))
        for m in methods:
            run_api(
                cat, f"triangulate method={m!r}", lambda m=m, p=p: optri.triangulate(p, method=m)
            )
            run_api(
                cat, f"chain method={m!r}", lambda m=m: optri.matrix_chain([2, 3, 4, 5], method=m)
            )
        for d in dtypes:
            run_api(cat, f"dtype={d!r}", lambda d=d, p=p: optri.triangulate(p, dtype=d))
        for s in seconds:
            run_api(cat, f"time_limit={s!r}", lambda s=s, p=p: optri.triangulate(p, time_limit=s))
        for f in flags:
            run_api(cat, f"keep_table={f!r}", lambda f=f, p=p: optri.triangulate(p, keep_table=f))
        for i, cb in enumerate(callbacks):
            run_api(cat, f"progress #{i}", lambda cb=cb, p=p: optri.triangulate(p, progress=cb))
        for s in seeds:
            run_api(cat, f"seed={s!r}", lambda s=s, p=p: optri.random_triangulation(p, seed=s))
    user = {
        "none": lambda i, k, j: None,
        "str": lambda i, k, j: "1",
        "array": lambda i, k, j: np.array([1.0]),
        "complex": lambda i, k, j: 1j,
        "bigint": lambda i, k, j: 10**400,
        "nan": lambda i, k, j: math.nan,
        "raise": lambda i, k, j: 1 / 0,
        "arity1": lambda i: 1.0,
        "arity2": lambda i, k: 1.0,
        "kwonly": lambda *, i, k, j: 1.0,
    }
    for name, w in user.items():
        for p in polys:
            for m in ("memo", "table", "brute", "naive", "auto"):
                run_api(
                    cat,
                    f"user weight {name} {m}",
                    lambda w=w, m=m, p=p: optri.triangulate(p, weight=w, method=m),
                )
            run_api(
                cat,
                f"user weight {name} best",
                lambda w=w, p=p: optri.best_triangulations(p, weight=w, k=3),
            )
            run_api(
                cat,
                f"user weight {name} enumerate",
                lambda w=w, p=p: list(optri.enumerate_triangulations(p, w)),
            )
    for v in [None, "x", 1.5, [], [[0, 0]], -5, 10**400, 10**7, [[0, 0], [1, 0], [math.nan, 1]]]:
        run_api(cat, f"count {v!r}"[:40], lambda v=v: optri.count_triangulations(v))
    for dims in [
        [],
        [1],
        [1, 2],
        [1, -2, 3],
        [1, 0, 3],
        ["a", "b", "c"],
        [1.5, 2, 3],
        None,
        [10**400, 2, 3],
    ]:
        run_api(cat, f"chain {dims!r}"[:40], lambda d=dims: optri.matrix_chain(d))


def extreme_coordinates() -> None:
    cat = "extreme_coordinates"
    shapes = {
        "square": np.array(SQ, float),
        "pent": np.array(PENT, float),
        "arrow": np.array(ARROW, float),
    }
    exps = list(range(-320, 310, 20)) + [307, 308, -308, -310]
    for name, shape in shapes.items():
        for e in exps:
            scale = 10.0**e
            pts = shape * scale
            fine = bool(np.all(np.isfinite(pts))) and len(np.unique(pts, axis=0)) == len(pts)
            for m in ("memo", "fast", "brute"):
                run_api(
                    cat,
                    f"{name} 1e{e} {m}",
                    lambda pts=pts, m=m: optri.triangulate(pts, method=m),
                    bad=False if fine else True,
                )
            run_api(
                cat,
                f"{name} 1e{e} best",
                lambda pts=pts: optri.best_triangulations(pts, k=2),
                bad=False if fine else True,
            )
            run_api(
                cat,
                f"{name} 1e{e} max_angle",
                lambda pts=pts: optri.triangulate(pts, "max_angle", "max"),
                bad=False if fine else True,
            )
    for label, value in [
        ("python int 10**400", [[0, 0], [10**400, 0], [0, 1]]),
        ("complex", np.array(SQ, float) + 1j),
        ("object", np.array([[0, 0], [1, 0], [None, 1]], dtype=object)),
        ("strings", [["0", "0"], ["1", "0"], ["1", "1"]]),
        ("3-D bow-tie", [[0, 0, 0], [2, 2, 0], [2, 0, 0], [0, 2, 0]]),
        ("inf", [[0, 0], [math.inf, 0], [0, 1]]),
        ("nan", [[0, 0], [math.nan, 0], [0, 1]]),
        ("1e308 polyline", np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0.1]]) * 1e308),
        ("ragged", [[0, 0], [1], [0, 1, 2]]),
        ("4-D", [[0, 0, 0, 0], [1, 0, 0, 0], [0, 1, 0, 0]]),
        ("empty", []),
        ("bool", [[True, False], [False, True], [True, True]]),
    ]:
        fn = optri.fill_polyline if "polyline" in label else optri.triangulate
        run_api(cat, label, lambda v=value, fn=fn: fn(v), bad=label != "strings")  # numbers as text


def cli_files(tmp: Path) -> None:
    cat = "cli_files"
    rng = np.random.default_rng(0)
    contents = {
        "binary": lambda i: rng.bytes(40 + i),
        "latin1": lambda i: f"0,0\n1,0\n1,1\n# caf\u00e9 {i}\n".encode("latin-1"),
        "utf16": lambda i: "0,0\n1,0\n1,1\n".encode("utf-16"),
        "bom": lambda i: b"\xef\xbb\xbf0,0\n1,0\n1,1\n0,1\n",
        "deep": lambda i: b"[" * (1000 * (i + 1)) + b"]" * (1000 * (i + 1)),
        "json_scalar": lambda i: json.dumps([None, 5, "x", True, 1.5][i % 5]).encode(),
        "geojson_bad": lambda i: json.dumps(
            {"type": "Polygon", "coordinates": [5, None, "x", [[1]], {}][i % 5]}
        ).encode(),
        "wkt_bad": lambda i: [
            "POLYGON ((0 0, 1 0",
            "POINT (1 2)",
            "POLYGON EMPTY",
            "POLYGON ((a b, c d, e f))",
            "((((",
        ][i % 5].encode(),
        "csv_bad": lambda i: [
            "a,b\nc,d\n",
            "0,0\n1\n",
            "nan,0\n1,0\n0,1\n",
            "0,0\n1e400,0\n1,1\n",
            "0,0\n1,0\n2,0\n",
        ][i % 5].encode(),
        "bowtie": lambda i: b"0,0\n2,2\n2,0\n0,2\n",
        "huge_int": lambda i: b"0,0\n" + b"9" * (300 * (i + 1)) + b",0\n1,1\n",
    }
    commands = [
        ["solve", "-q"],
        ["solve", "-m", "memo", "-q"],
        ["count"],
        ["best", "-k", "2"],
        ["enumerate", "-n", "2"],
        ["solve", "--json", "-q"],
    ]
    suffixes = [".csv", ".json", ".geojson", ".wkt", ".txt"]
    for kind, make in contents.items():
        for i in range(5):
            suffix = suffixes[i % len(suffixes)]
            path = tmp / f"{kind}{i}{suffix}"
            path.write_bytes(make(i))
            for cmd in commands:
                run_cli(cat, f"{' '.join(cmd)} {kind}{suffix}", [cmd[0], str(path), *cmd[1:]])
    ok = tmp / "ok.csv"
    ok.write_text("0,0\n1,0\n1,1\n0,1\n")
    for argv in (
        ["solve", "/nonexistent.csv"],
        ["solve", str(tmp)],
        ["solve", "-w", "nope", str(ok)],
        ["solve", "--objective", "avg", str(ok)],
        ["best", "-k", "0", str(ok)],
        ["best", "-k", "x", str(ok)],
        ["count", "-5"],
        ["count", "0"],
        ["count", "10000000"],
        ["chain", "1", "-2", "3"],
        ["chain", "x"],
        ["enumerate", "30", "--limit", "-1"],
        ["bench", "0"],
        ["fill", "/nonexistent.obj", "-o", str(tmp / "o.obj")],
        ["solve", "--time-limit", "-1", str(ok)],
        ["solve", "-m", "nope", str(ok)],
    ):
        run_cli(cat, " ".join(argv)[:60], argv)


def batch_lines(tmp: Path) -> None:
    cat = "batch_lines"
    rng = np.random.default_rng(1)
    lines = []
    templates = [
        b"[" * 100000 + b"]" * 100000,
        b"\x00\xff\xfe",
        b"{",
        b"[1, 2]",
        b"42",
        b"null",
        b'"x"',
        b"{}",
        b'{"id": NaN, "coordinates": [[0, 0], [1, 0]]}',
        b'{"id": Infinity}',
        b'{"id": 1e400}',
        b'{"coordinates": 5}',
        b'{"coordinates": [[0, 0], [1e400, 0], [1, 1]]}',
        b'{"coordinates": [["a", 0], [1, 0], [1, 1]]}',
        b'{"coordinates": [[0, 0], [2, 2], [2, 0], [0, 2]]}',
        b'{"type": "Feature", "geometry": {"type": "Polygon", "coordinates": 5}}',
        b'{"type": "Feature", "geometry": null}',
        b'{"coordinates": [[0, 0], [1, 0], [2, 0]]}',
        b'{"coordinates": [[0, 0], [' + b"9" * 500 + b", 0], [1, 1]]}",
    ]
    good = b'{"id": "good%d", "coordinates": [[0, 0], [4, 0], [5, 3], [2, 5], [-1, 3]]}'
    for i in range(420):
        bad = (
            templates[i % len(templates)]
            if i < 2 * len(templates)
            else rng.bytes(int(rng.integers(1, 80))).replace(b"\n", b" ")
        )
        lines += [bad, good % i]
    src = tmp / "batch.ndjson"
    src.write_bytes(b"\n".join(lines) + b"\n")
    expected = sum(1 for ln in lines if ln.strip() and ln.strip() != b"\xef\xbb\xbf")
    signal.alarm(HANG_SECONDS * 10)
    try:
        optri.batch(src, tmp / "batch_out.ndjson", workers=1)
        records = list(iter_records(tmp / "batch_out.ndjson"))
    except Hang:
        record(cat, "hang", "the batch run")
        return
    except Exception as exc:
        record(cat, "traceback", f"batch: {type(exc).__name__}: {exc}"[:200])
        return
    finally:
        signal.alarm(0)
    goods = {r["id"] for r in records if isinstance(r["id"], str) and r["id"].startswith("good")}
    for r in records:
        if isinstance(r["id"], str) and r["id"].startswith("good"):
            continue
        record(
            cat,
            "own_error" if r["status"] == "error" and "\n" not in r["reason"] else "silent",
            str(r["id"]),
        )
    for _ in range(expected - len(records)):
        record(cat, "lost", "record")
    for _ in range(len([ln for ln in lines if ln.startswith(b'{"id": "good')]) - len(goods)):
        record(cat, "lost", "good record")
    # unknown weight / method: refused before the run
    for kw in ({"weight": "nope"}, {"objective": "x"}, {"method": "nope"}, {"weight": None}):
        run_api(
            cat,
            f"batch {kw}",
            lambda kw=kw: optri.batch(src, tmp / "never.ndjson", workers=1, **kw),
        )


def meshes(tmp: Path) -> None:
    cat = "meshes_at_scales"
    try:
        import trimesh
    except ImportError:
        return
    sphere = trimesh.creation.icosphere(subdivisions=2)
    faces = np.delete(sphere.faces, [0, 40], axis=0)
    for e in (-12, -9, -8, -6, -3, 0, 3, 6, 9, 12, 15, 100, 150):
        mesh = (sphere.vertices * 10.0**e, faces)
        signal.alarm(HANG_SECONDS * 2)
        try:
            _, report = optri.fill_holes(mesh)
            filled = sum(1 for r in report if r.status == "filled")
            record(cat, "answer" if filled == 2 else "silent", f"scale 1e{e}: {filled} filled")
        except Hang:
            record(cat, "hang", f"scale 1e{e}")
        except optri.OptriError:
            record(cat, "own_error", f"scale 1e{e}")
        except Exception as exc:
            record(cat, "traceback", f"scale 1e{e}: {type(exc).__name__}: {exc}"[:200])
        finally:
            signal.alarm(0)
    for e in (-9, 0, 12):
        path = tmp / f"sphere{e}.obj"
        trimesh.Trimesh(sphere.vertices * 10.0**e, faces, process=False).export(path)
        run_cli(cat, f"fill scale 1e{e}", ["fill", str(path), "-o", str(tmp / f"out{e}.obj"), "-q"])
    for name, data in (
        ("garbage.obj", b"\x00\xff" * 50),
        ("garbage.stl", b"solid x\nfacet\n"),
        ("empty.off", b""),
    ):
        path = tmp / name
        path.write_bytes(data)
        run_cli(cat, f"fill {name}", ["fill", str(path), "-o", str(tmp / "o.obj"), "-q"])


def processes(tmp: Path) -> None:
    cat = "processes"
    env = {**os.environ}
    # Ctrl-C in the compiled mask kernel: a plain KeyboardInterrupt
    code = (
        "import numpy as np\nfrom optri.simple import valid_diagonals\n"
        "def star(n):\n a=2*np.pi*np.arange(n)/n; r=np.where(np.arange(n)%2==0,1.0,0.6)\n"
        " return np.column_stack((r*np.cos(a), r*np.sin(a)))\n"
        "valid_diagonals(star(200)); print('go', flush=True); valid_diagonals(star(14000))\n"
    )
    for delay in (0.5, 1.5):
        proc = subprocess.Popen(
            [sys.executable, "-c", code],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            env=env,
        )
        proc.stdout.readline()
        import time

        time.sleep(delay)
        proc.send_signal(signal.SIGINT)
        try:
            _, err = proc.communicate(timeout=120)
        except subprocess.TimeoutExpired:
            proc.kill()
            record(cat, "hang", f"SIGINT mask {delay}")
            continue
        last = err.strip().splitlines()[-1] if err.strip() else ""
        ok = last == "KeyboardInterrupt" and "SystemError:" not in err
        record(cat, "own_error" if ok else "traceback", f"SIGINT mask {delay}: {last}")
    # two batch runs into one output: one refuses or both finish; every record exactly once
    src = tmp / "many.ndjson"
    src.write_text("".join(json.dumps({"id": i, "coordinates": PENT}) + "\n" for i in range(3000)))
    out = tmp / "same.ndjson"
    cmd = [sys.executable, "-m", "optri", "batch", str(src), "-o", str(out), "-j", "1", "-q"]
    procs = [
        subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
        for _ in range(2)
    ]
    codes = [p.wait(timeout=600) for p in procs]
    ids = [r["id"] for r in iter_records(out)]
    lost = len(ids) != 3000 or len(set(ids)) != 3000
    record(cat, "lost" if lost else "own_error", f"concurrent batch exit codes {codes}")


def killer(vertices, i, k, j):
    """A user weight whose worker process dies (as by the OOM killer) on a heptagon."""
    if len(vertices) == 7:
        os.kill(os.getpid(), signal.SIGKILL)
    return 1.0


def _kept(cat: str, label: str, path: Path, before: bytes, argv: list[str]) -> None:
    """Run the CLI; ``path`` must still hold ``before`` (else the run lost a file)."""
    run_cli(cat, label, argv)
    if not path.exists() or path.read_bytes() != before:
        record(cat, "lost", f"{label}: {path.name} changed")


def _batch_ok(src: Path, out: Path, *args: str) -> None:
    CliRunner().invoke(main, ["batch", str(src), "-o", str(out), "-j", "1", "-q", *args])


def outputs_and_faults(tmp: Path) -> None:
    """Issue 55: outputs, work files, reuse, "proven", exact ints, faults and limits."""
    cat = "outputs_faults"
    base = tmp / "o55"
    base.mkdir()
    rows = "".join(json.dumps({"id": i, "coordinates": PENT}) + "\n" for i in range(6))
    for name in ("f.ndjson", "f.gpkg", "f.geojson"):
        src = base / name
        if name == "f.ndjson":
            src.write_text(rows)
        else:
            (base / "seed.ndjson").write_text(rows)
            _batch_ok(base / "seed.ndjson", src)
        before = src.read_bytes()
        for spelling in (src, base / "x" / ".." / name, base / f"link-{name}"):
            (base / "x").mkdir(exist_ok=True)
            if spelling.name.startswith("link") and not spelling.exists():
                spelling.symlink_to(src)
            for extra in ([], ["--overwrite"]):
                argv = ["batch", str(src), "-o", str(spelling), "-j", "1", *extra]
                _kept(cat, f"output is input {spelling.name} {extra}", src, before, argv)
    # an input named like a part inside the output directory
    d = base / "dir"
    d.mkdir()
    part = d / "part-00000.ndjson"
    part.write_text(rows)
    argv = ["batch", str(part), "-o", f"{d}/", "--overwrite", "-j", "1"]
    _kept(cat, "input inside output dir", part, rows.encode(), argv)
    # a user's file of a sample's name
    (base / "octagon.csv").write_text("x,y\n0,0\n")
    argv = ["data", "-o", str(base), "octagon.csv"]
    _kept(cat, "optri data -o over a user file", base / "octagon.csv", b"x,y\n0,0\n", argv)
    # a private output stays private
    src = base / "f.ndjson"
    private = base / "private.ndjson"
    private.write_text("secret\n")
    private.chmod(0o600)
    _batch_ok(src, private, "--overwrite")
    mode = private.stat().st_mode & 0o777
    record(cat, "answer" if mode == 0o600 else "silent", f"private output mode {oct(mode)}")
    # planted links and parts
    precious = base / "precious"
    precious.write_text("keep\n")
    (base / ".l.ndjson.lock").symlink_to(precious)
    _kept(
        cat, "lock symlink", precious, b"keep\n", ["batch", str(src), "-o", str(base / "l.ndjson")]
    )
    elsewhere = base / "elsewhere"
    elsewhere.mkdir()
    (base / ".p.ndjson.parts").symlink_to(elsewhere)
    run_cli(cat, "parts folder symlink", ["batch", str(src), "-o", str(base / "p.ndjson")])
    if list(elsewhere.iterdir()):
        record(cat, "lost", "parts written through a planted link")
    planted = base / "planted"
    planted.mkdir()
    fake = json.dumps({"id": 0, "status": "ok", "cost": -1.0, "triangles": [[0, 1, 2]]})
    (planted / "part-00000.ndjson").write_text(fake + "\n")
    _batch_ok(src, planted)
    costs = [r["cost"] for r in iter_records(planted)]
    record(cat, "silent" if -1.0 in costs else "answer", "planted part")
    # a finished output reused only for the same job
    other = base / "g.ndjson"
    other.write_text(rows.replace('"id": 5', '"id": 7'))
    for label, args in (
        ("other input", [str(other)]),
        ("-w area", [str(src), "-w", "area"]),
        ("-O max", [str(src), "-O", "max"]),
        ("--method memo", [str(src), "--method", "memo"]),
    ):
        out = base / "done.ndjson"
        _batch_ok(src, out, "--overwrite")
        before = out.read_bytes()
        res = CliRunner().invoke(main, ["batch", *args, "-o", str(out), "-j", "1", "-q"])
        reused = res.exit_code == 0 and out.read_bytes() == before
        record(cat, "silent" if reused else "cli_error", f"finished output, {label}")
    # exact integers near 2**63 (27 cases)
    from optri.engines.brute import all_index_triangulations

    for a in (-1, 5, 9):
        for b in (0, 3, 9):
            for c in (3, 7, -2):
                v = [2**63 + a, 3, 2**63 + b, 7 + c]
                want = min(
                    sum(v[i] * v[k] * v[j] for i, k, j in t) for t in all_index_triangulations(4)
                )
                got = optri.triangulate(v, "product").weight
                exact = type(got) is int and got == want
                record(cat, "answer" if exact else "silent", f"product {v}")
    # "proven" on martinez's issue96 at three scales
    ring = Path(__file__).parents[1] / "tests" / "data" / "rings" / "martinez_issue96.geojson"
    outer, hole = json.loads(ring.read_text())["features"][0]["geometry"]["coordinates"][0]
    for e in (-20, 0, 20):
        s = math.ldexp(1.0, e)
        poly = (np.array(outer[:-1]) * s, [np.array(hole[:-1]) * s])
        got = optri.triangulate(poly, "diagonal")
        tiling = optri.triangulate(poly, "diagonal", method="bridge")
        wrong = got.optimality == "proven" and got.weight > tiling.weight * (1 + 1e-9)
        record(cat, "silent" if wrong else "answer", f"issue96 at 2**{e}: {got.optimality}")
    # faults and limits
    heptagon = [[0, 0], [4, 0], [6, 2], [5, 5], [2, 6], [-1, 4], [-1, 1]]
    kill_in = base / "kill.ndjson"
    kill_in.write_text(
        "".join(
            json.dumps({"id": f"p{i}", "coordinates": heptagon if i == 2 else PENT}) + "\n"
            for i in range(6)
        )
    )
    run_api(
        cat,
        "a worker killed by the system",
        lambda: optri.batch(kill_in, base / "kill_out.ndjson", weight=killer, workers=2),
        bad=False,
    )
    reasons = [r["reason"] or "" for r in iter_records(base / "kill_out.ndjson")]
    if sum("worker process died" in r for r in reasons) != 1:
        record(cat, "lost", "killed worker: not one error record")
    t = 2 * np.pi * np.arange(6000) / 6000
    r = np.where(np.arange(6000) % 2 == 0, 1.0, 0.6)
    star = base / "star.csv"
    star.write_text(
        "x,y\n"
        + "".join(
            f"{x!r},{y!r}\n" for x, y in zip((r * np.cos(t)).tolist(), (r * np.sin(t)).tolist())
        )
    )
    run_cli(cat, "enumerate a 6000-vertex star", ["enumerate", str(star), "-n", "1"])
    os.environ["OPTRI_MAX_INPUT_BYTES"] = "4096"
    try:
        for cmd in (["solve", "-"], ["batch", "-", "-o", str(base / "s.ndjson")]):
            signal.alarm(HANG_SECONDS)
            try:
                res = CliRunner().invoke(main, cmd, input=rows.encode() * 200)
            finally:
                signal.alarm(0)
            limited = res.exit_code == 2 and "OPTRI_MAX_INPUT_BYTES" in res.output
            record(cat, "cli_error" if limited else "traceback", f"endless stdin {cmd[0]}")
    finally:
        del os.environ["OPTRI_MAX_INPUT_BYTES"]
    big = 2e306
    sq = np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float) * big
    hole_sq = np.array([[4, 4], [4, 6], [6, 6], [6, 4]], float) * big
    run_api(cat, "holes: weights sum past float64", lambda: optri.triangulate((sq, [hole_sq])))
    try:
        import pyogrio
    except ImportError:
        return
    layers = base / "layers.gpkg"
    _batch_ok(src, layers)
    gdf = pyogrio.read_dataframe(layers)[["geometry"]].iloc[:1]
    pyogrio.write_dataframe(gdf, layers, layer="roofs")
    run_cli(cat, "gpkg with two layers", ["batch", str(layers), "-o", str(base / "m.ndjson")])
    run_cli(
        cat,
        "gpkg --layer roofs",
        ["batch", str(layers), "-o", str(base / "m.ndjson"), "--layer", "roofs", "-j", "1"],
    )


def _warm_up() -> None:
    """Compile (or load) every kernel first: a first compile is not a hang."""
    ring = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0.1]])
    optri.fill_polyline(ring)
    optri.fill_polyline(ring, method="liepa")
    a = 2 * np.pi * np.arange(200) / 200
    circle = np.column_stack((np.cos(a), np.sin(a)))
    for w in ("perimeter", "max_angle", "area"):
        optri.triangulate(circle, w, method="fast")
    optri.triangulate(circle * np.where(np.arange(200) % 2, 1, 0.6)[:, None], method="fast")
    try:
        import trimesh
    except ImportError:
        return
    sphere = trimesh.creation.icosphere(subdivisions=2)
    optri.fill_holes((sphere.vertices, np.delete(sphere.faces, [0, 40], axis=0)))


def main_(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--json", action="store_true", help="print the table as JSON")
    parser.add_argument("--verbose", action="store_true", help="list every bad outcome")
    parser.add_argument("--skip", nargs="*", default=[], help="categories to skip")
    args = parser.parse_args(argv)
    signal.signal(signal.SIGALRM, _alarm)
    import warnings

    warnings.simplefilter("ignore")
    _warm_up()
    with tempfile.TemporaryDirectory() as folder:
        tmp = Path(folder)
        for name, fn in (
            ("api_parameters", api_parameters),
            ("extreme_coordinates", extreme_coordinates),
            ("cli_files", lambda: cli_files(tmp)),
            ("batch_lines", lambda: batch_lines(tmp)),
            ("meshes_at_scales", lambda: meshes(tmp)),
            ("processes", lambda: processes(tmp)),
            ("outputs_faults", lambda: outputs_and_faults(tmp)),
        ):
            if name not in args.skip:
                fn()
    outcomes = ["own_error", "cli_error", "answer", "traceback", "hang", "silent", "lost"]
    if args.json:
        print(json.dumps({c: dict(v) for c, v in RESULTS.items()}, indent=1))
    else:
        print(f"{'category':22s} {'tried':>6s} " + " ".join(f"{o:>9s}" for o in outcomes))
        for c, v in RESULTS.items():
            print(f"{c:22s} {sum(v.values()):6d} " + " ".join(f"{v[o]:9d}" for o in outcomes))
        total = sum((v for v in RESULTS.values()), Counter())
        print(
            f"{'total':22s} {sum(total.values()):6d} "
            + " ".join(f"{total[o]:9d}" for o in outcomes)
        )
    for (c, o), labels in sorted(EXAMPLES.items()):
        if o in ("traceback", "hang", "lost", "silent"):
            for label in labels[: None if args.verbose else 1]:
                print(f"  {c} {o}: {label}", file=sys.stderr)
    bad = sum(v[o] for v in RESULTS.values() for o in ("traceback", "hang", "lost"))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main_())
