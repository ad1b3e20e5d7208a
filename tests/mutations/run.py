"""Mutation run: apply each deliberate bug of ``catalog.py`` and check the tests catch it.

    python tests/mutations/run.py                 # every mutation
    python tests/mutations/run.py NAME ...        # some of them
    python tests/mutations/run.py --list          # which still apply (no tests run)

(run with the project's Python: the mutants' tests run under ``sys.executable``)

The repository is copied once to a temporary directory; each mutation edits
that copy's file, runs ``python -m pytest -x -q`` on its tests there, and puts
the file back (bytes and modification time). The checkout itself is never
written, so stopping the run at any point (Ctrl-C) leaves it as it was.

A mutation is *killed* when pytest fails (exit 1, or 2/3 when the mutant
breaks an import), *survived* when it passes, *timeout* when it runs past
``--timeout`` (counted as killed: a hang is caught too), *stale* when its old
text is not found exactly once (update the catalog), *error* when pytest
could not run the named tests (exit 4/5). First the unmutated tests of every
selected mutation run once: a failure there stops the run, since no mutant
could then be judged.

A mutant of the compiled core (a file under ``src/core/``) is built in the
copy: the core is configured once in a build folder of the run's own (CMake,
Ninja), rebuilt after the edit and copied over the copy's ``src/optri/_core*``;
after the tests the file is put back and the core rebuilt again (the file then
keeps a new modification time, so the build sees it changed). A mutant that
does not compile counts as killed.

numba caches compiled kernels on disk by source file and modification time,
but not by the files whose functions a kernel inlines. Mutants of files that
compiled code reads (any file mentioning numba, and the plain-Python formulas
in ``COMPILED_ELSEWHERE``) therefore run with an empty cache of their own;
the others share one cache warmed by the unmutated run. Hypothesis runs with
a fixed seed, so a run is repeatable.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from catalog import MUTATIONS, Mutation  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
#: Plain-Python files whose functions numba compiles into kernels elsewhere.
COMPILED_ELSEWHERE = (
    "src/optri/weights.py",
    "src/optri/objective.py",  # lex_better
)
SKIP = shutil.ignore_patterns(
    ".git",
    ".venv",
    ".numba-cache",
    "__pycache__",
    ".hypothesis",
    ".pytest_cache",
    ".ruff_cache",
    ".mypy_cache",
    "*.egg-info",
    "build",
    "dist",
    "demo-output",
)
PYTEST = ("-m", "pytest", "-x", "-q", "-p", "no:cacheprovider", "--hypothesis-seed=0")


def main(argv: list[str] | None = None) -> int:
    args = _parse(argv)
    # started with Ctrl-C ignored (a background job), the tests' children would inherit it
    # and the Ctrl-C tests could not pass: a handler of our own resets it for them on exec
    signal.signal(signal.SIGINT, signal.default_int_handler)
    chosen = [m for m in MUTATIONS if not args.names or m.name in args.names]
    unknown = set(args.names) - {m.name for m in MUTATIONS}
    if unknown:
        print(f"unknown mutation(s): {', '.join(sorted(unknown))}", file=sys.stderr)
        return 2
    repo = Path(args.repo).resolve()
    status = {m.name: _applicability(repo, m) for m in chosen}
    if args.list:
        for m in chosen:
            print(f"{status[m.name]:<10} {m.name:<36} {m.file}")
        return 0
    results = _run_all(repo, chosen, status, args)
    _report(results)
    if args.json:
        Path(args.json).write_text(json.dumps(results, indent=1) + "\n")
    return 0 if all(r["status"] in ("killed", "timeout") for r in results) else 1


def _parse(argv: list[str] | None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("names", nargs="*", help="mutations to run (default: all)")
    p.add_argument("--list", action="store_true", help="show which mutations apply, run none")
    p.add_argument("--repo", default=str(ROOT), help="checkout to mutate (default: this one)")
    p.add_argument("--timeout", type=float, default=600, help="seconds per mutant (600)")
    p.add_argument("--json", help="also write the results to this file")
    p.add_argument("--keep", action="store_true", help="keep the temporary copy")
    return p.parse_args(argv)


def _applicability(repo: Path, m: Mutation) -> str:
    path = repo / m.file
    if not path.is_file():
        return "stale"
    count = path.read_text().count(m.old)
    return "applies" if count == 1 else "stale" if count == 0 else "ambiguous"


def _run_all(
    repo: Path, chosen: list[Mutation], status: dict[str, str], args: argparse.Namespace
) -> list[dict]:
    work = Path(tempfile.mkdtemp(prefix="optri-mutants-"))
    try:
        copy = work / "repo"
        shutil.copytree(repo, copy, ignore=SKIP)
        shared_cache = work / "numba-cache"
        live = [m for m in chosen if status[m.name] == "applies"]
        print(f"copied {repo} to {copy}; {len(live)} of {len(chosen)} mutations apply")
        baseline = sorted({t for m in live for t in _test_files(m)})
        rc, out, seconds = _pytest(copy, baseline, shared_cache, args.timeout * 4)
        print(f"unmutated tests: exit {rc} in {seconds:.0f} s")
        if rc != 0:
            print(out[-4000:])
            raise SystemExit("the unmutated tests fail: fix them before judging mutants")
        results = []
        for m in chosen:
            if status[m.name] != "applies":
                results.append(_result(m, status[m.name], 0.0, ""))
            else:
                results.append(_mutant(copy, m, work, shared_cache, args.timeout))
            r = results[-1]
            print(f"{r['status']:<9} {r['seconds']:6.1f} s  {m.name}", flush=True)
        return results
    finally:
        if args.keep:
            print(f"kept {work}")
        else:
            shutil.rmtree(work, ignore_errors=True)


def _test_files(m: Mutation) -> list[str]:
    """The test paths of ``m`` (its arguments without options such as ``-k expr``)."""
    files, skip = [], False
    for a in m.tests:
        if skip:
            skip = False
        elif a.startswith("-"):
            skip = a in ("-k", "-m")
        else:
            files.append(a)
    return files


def _mutant(copy: Path, m: Mutation, work: Path, shared_cache: Path, timeout: float) -> dict:
    path = copy / m.file
    original, stat = path.read_bytes(), path.stat()
    text = original.decode()
    cache = shared_cache
    if "numba" in text or m.file in COMPILED_ELSEWHERE:
        cache = work / f"numba-cache-{m.name}"  # see the module docstring
    core = m.file.startswith("src/core/")
    try:
        path.write_text(text.replace(m.old, m.new, 1))
        built, log = _build_core(copy, work) if core else (True, "")
        if built:
            rc, out, seconds = _pytest(copy, list(m.tests), cache, timeout)
        else:
            rc, out, seconds = 1, log, 0.0  # a mutant the compiler refuses is caught too
    finally:
        path.write_bytes(original)
        if core:
            built, log = _build_core(copy, work)  # the next mutant runs on the real core
            if not built:
                raise SystemExit(f"the core no longer builds after undoing {m.name}:\n{log}")
        else:
            os.utime(path, ns=(stat.st_atime_ns, stat.st_mtime_ns))
        if cache != shared_cache:
            shutil.rmtree(cache, ignore_errors=True)
    if rc is None:
        state = "timeout"
    elif rc == 0:
        state = "survived"
    elif rc in (1, 2, 3):
        state = "killed"
    else:
        state = "error"
    return _result(m, state, seconds, _summary_line(out) if state != "survived" else "")


def _build_core(copy: Path, work: Path) -> tuple[bool, str]:
    """Build the copy's compiled core (configured on first use) and put it in its src/optri."""
    build = work / "core-build"
    cmake = _tool("cmake")
    steps = [[cmake, "--build", str(build)]]
    if not (build / "CMakeCache.txt").is_file():
        configure = [cmake, "-S", str(copy), "-B", str(build), "-G", "Ninja"]
        configure += [f"-DCMAKE_MAKE_PROGRAM={_tool('ninja')}", "-DCMAKE_BUILD_TYPE=Release"]
        configure += [f"-DPython_EXECUTABLE={sys.executable}"]
        steps.insert(0, configure)
    for step in steps:
        proc = subprocess.run(step, capture_output=True, text=True)
        if proc.returncode:
            return False, proc.stdout + proc.stderr
    for old in (copy / "src" / "optri").glob("_core*"):
        old.unlink()
    for lib in build.glob("_core*"):
        shutil.copy2(lib, copy / "src" / "optri" / lib.name)
    return True, ""


def _tool(name: str) -> str:
    """``name`` from the running Python's environment (as make installs it), else from PATH."""
    beside = Path(sys.executable).with_name(name)
    return str(beside) if beside.is_file() else shutil.which(name) or name


def _pytest(
    copy: Path, args: list[str], cache: Path, timeout: float
) -> tuple[int | None, str, float]:
    env = dict(os.environ, PYTHONPATH=str(copy / "src"), NUMBA_CACHE_DIR=str(cache))
    env.pop("NUMBA_DISABLE_JIT", None)
    start = time.perf_counter()
    try:
        proc = subprocess.run(
            [sys.executable, *PYTEST, *args],
            cwd=copy,
            env=env,
            capture_output=True,
            text=True,
            timeout=timeout,
        )
    except subprocess.TimeoutExpired as exc:
        out = exc.stdout.decode() if isinstance(exc.stdout, bytes) else exc.stdout or ""
        return None, out, time.perf_counter() - start
    return proc.returncode, proc.stdout + proc.stderr, time.perf_counter() - start


def _summary_line(out: str) -> str:
    lines = [ln for ln in out.splitlines() if ln.startswith(("FAILED", "ERROR"))]
    return lines[0][:200] if lines else (out.strip().splitlines() or [""])[-1][:200]


def _result(m: Mutation, status: str, seconds: float, detail: str) -> dict:
    return {
        "name": m.name,
        "file": m.file,
        "status": status,
        "seconds": round(seconds, 1),
        "detail": detail,
        "why": m.why,
    }


def _report(results: list[dict]) -> None:
    counts = {
        s: sum(r["status"] == s for r in results)
        for s in ("killed", "timeout", "survived", "stale", "ambiguous", "error")
    }
    judged = counts["killed"] + counts["timeout"] + counts["survived"]
    rate = 100.0 * (counts["killed"] + counts["timeout"]) / judged if judged else 0.0
    print()
    for r in results:
        if r["status"] not in ("killed", "timeout"):
            print(f"{r['status'].upper()}: {r['name']} ({r['file']}) {r['why']} {r['detail']}")
    print(
        f"kill rate {rate:.1f} % ({counts['killed'] + counts['timeout']} of {judged} judged; "
        + ", ".join(f"{k} {v}" for k, v in counts.items() if v)
        + ")"
    )


if __name__ == "__main__":
    raise SystemExit(main())
