"""Hostile input, table-driven: every row says what must happen.

Three tables:

* ``API``: a call and the exception it must raise, always one of optri's own
  (:class:`optri.OptriError`), with the built-in base a Python user would catch
  (``ValueError``/``TypeError``/``MemoryError``...), raised before any work;
* ``CLI``: arguments (and a file's content) and the exit status, with no
  traceback and, for library errors, exactly one ``optri: error:`` line;
* ``BATCH``: one NDJSON line each, all run through one batch: every line gives
  exactly one record (nothing lost), bad lines an error record with a one-line
  reason, good lines between them an ``ok`` record.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from click.testing import CliRunner

import optri
from optri import config
from optri.batch import iter_records
from optri.cli import main
from optri.errors import (
    EngineUnavailableError,
    InvalidParameterError,
    InvalidPolygonError,
    OptriError,
    ParameterTypeError,
    TableTooLargeError,
    WeightError,
)

SQ = [[0, 0], [1, 0], [1, 1], [0, 1]]
PENT = [[0, 0], [2, 0], [3, 2], [1, 3], [-1, 2]]
ARROW = [[0, 0], [4, 0], [1, 1], [0, 4]]  # one reflex vertex: a chord mask

# --- the API table ---------------------------------------------------------------------

BAD_OBJECTIVES = [None, 5, 1.5, "avg", "", ("sum", "avg"), (), [], ("sum", None), {"sum"}, b"sum"]
BAD_WEIGHTS = [None, 5, 1.5, "nope", "", b"perimeter", ("perimeter",) * 3, object()]
BAD_K = [0, -1, "3", 1.5, None, True, np.float64(2.0), [3]]
BAD_METHODS = [None, 5, "x", "FAST", "", ["fast"], b"memo"]
BAD_DTYPES = ["banana", int, np.int32, np.complex128, object, "float16", np.bool_]
BAD_SECONDS = [-1, 0, math.nan, math.inf, "x", True, [1]]
BAD_FLAGS = ["x", 1, 0, [], "True"]
BAD_CALLBACKS = [5, "print", (lambda: None), (lambda a: None), (lambda a, b, c: None)]
BAD_SEEDS = ["x", 1.5, [1], b"seed", object()]


def _id(value):
    """A test id without memory addresses (the same in every xdist worker)."""
    text = repr(value)
    return type(value).__name__ if " at 0x" in text else text[:30]


def _weight_returning(value):
    return lambda i, k, j: value


def _weight_raising(exc):
    def w(i, k, j):
        raise exc

    return w


BAD_USER_WEIGHTS = {
    "returns_none": _weight_returning(None),
    "returns_str": _weight_returning("1.0"),
    "returns_array1": _weight_returning(np.array([1.0])),
    "returns_list": _weight_returning([1.0]),
    "returns_complex": _weight_returning(1 + 2j),
    "returns_dict": _weight_returning({}),
    "returns_big_int": _weight_returning(10**400),
    "returns_nan": _weight_returning(math.nan),
    "raises_zero_division": lambda i, k, j: 1 / 0,
    "raises_key_error": lambda i, k, j: {}[i],
    "raises_value_error": _weight_raising(ValueError("bad")),
    "raises_type_error": _weight_raising(TypeError("bad")),
    "raises_recursion": _weight_raising(RecursionError("deep")),
    "arity_0": lambda: 1.0,
    "arity_1": lambda i: 1.0,
    "arity_2": lambda i, k: 1.0,
    "arity_5": lambda v, i, k, j, extra: 1.0,
    "keyword_only": lambda *, i, k, j: 1.0,
}
ARITY = {"arity_0", "arity_1", "arity_2", "arity_5", "keyword_only"}
ENGINES_FOR_WEIGHTS = ["memo", "table", "brute", "naive"]


def _api_rows():
    rows = []
    add = rows.append
    for obj in BAD_OBJECTIVES:
        add(
            (
                f"triangulate-objective-{_id(obj)}",
                lambda o=obj: optri.triangulate(SQ, objective=o),
                WeightError,
            )
        )
        add(
            (
                f"best-objective-{_id(obj)}",
                lambda o=obj: optri.best_triangulations(SQ, k=2, objective=o),
                WeightError,
            )
        )
        add(
            (
                f"many-objective-{_id(obj)}",
                lambda o=obj: optri.triangulate_many([SQ], objective=o),
                WeightError,
            )
        )
    for w in BAD_WEIGHTS:
        add(
            (
                f"triangulate-weight-{_id(w)}",
                lambda w=w: optri.triangulate(SQ, weight=w),
                WeightError,
            )
        )
        add(
            (
                f"best-weight-{_id(w)}",
                lambda w=w: optri.best_triangulations(SQ, weight=w, k=2),
                WeightError,
            )
        )
    for k in BAD_K:
        err = (
            ParameterTypeError
            if not isinstance(k, int) or isinstance(k, bool)
            else InvalidParameterError
        )
        add((f"best-k-{_id(k)}", lambda k=k: optri.best_triangulations(SQ, k=k), err))
    for m in BAD_METHODS:
        add(
            (
                f"triangulate-method-{_id(m)}",
                lambda m=m: optri.triangulate(SQ, method=m),
                EngineUnavailableError,
            )
        )
        add(
            (
                f"many-method-{_id(m)}",
                lambda m=m: optri.triangulate_many([SQ], method=m),
                EngineUnavailableError,
            )
        )
    for d in BAD_DTYPES:
        add(
            (
                f"triangulate-dtype-{_id(d)}",
                lambda d=d: optri.triangulate(SQ, dtype=d),
                InvalidParameterError,
            )
        )
        add(
            (
                f"fast-dtype-{_id(d)}",
                lambda d=d: optri.triangulate(SQ, dtype=d, method="fast"),
                InvalidParameterError,
            )
        )
    for s in BAD_SECONDS:
        add(
            (
                f"time_limit-{_id(s)}",
                lambda s=s: optri.triangulate(SQ, time_limit=s),
                InvalidParameterError,
            )
        )
    for f in BAD_FLAGS:
        add(
            (
                f"keep_table-{_id(f)}",
                lambda f=f: optri.triangulate(SQ, keep_table=f),
                ParameterTypeError,
            )
        )
    for i, cb in enumerate(BAD_CALLBACKS):
        add((f"progress-{i}", lambda cb=cb: optri.triangulate(SQ, progress=cb), ParameterTypeError))
    for s in BAD_SEEDS:
        add(
            (
                f"random-seed-{_id(s)}",
                lambda s=s: optri.random_triangulation(PENT, seed=s),
                ParameterTypeError,
            )
        )
    for name, func in BAD_USER_WEIGHTS.items():
        for method in ENGINES_FOR_WEIGHTS:
            add(
                (
                    f"user-weight-{name}-{method}",
                    lambda f=func, m=method: optri.triangulate(PENT, weight=f, method=m),
                    WeightError,
                )
            )
        add(
            (
                f"user-weight-{name}-mask",
                lambda f=func: optri.triangulate(ARROW, weight=f, method="table"),
                WeightError,
            )
        )
        add(
            (
                f"user-weight-{name}-best",
                lambda f=func: optri.best_triangulations(PENT, weight=f, k=3),
                WeightError,
            )
        )
        add(
            (
                f"user-weight-{name}-enumerate",
                lambda f=func: list(optri.enumerate_triangulations(PENT, weight=f)),
                WeightError,
            )
        )
        add(
            (
                f"user-weight-{name}-random",
                lambda f=func: optri.random_triangulation(PENT, seed=1, weight=f),
                WeightError,
            )
        )
    for v in [None, "x", 1.5, [], [[0, 0]], [[0, 0], [1, 1]], [[0, 0], [1, 0], [math.nan, 1]]]:
        add((f"count-{_id(v)}", lambda v=v: optri.count_triangulations(v), InvalidPolygonError))
    for v in [10**5000, 10**400, 10**7, config.COUNT_MAX_N + 1]:
        add(
            (
                f"count-huge-{v.bit_length()}",
                lambda v=v: optri.count_triangulations(v),
                InvalidParameterError,
            )
        )
    for dims in [[], [1], [1, 2], [1, -2, 3], [1, 0, 3], ["a", "b", "c"], [1.5, 2, 3], None]:
        add((f"chain-{_id(dims)}", lambda d=dims: optri.matrix_chain(d), InvalidPolygonError))
    for style in ["svg", None, 5]:
        add(
            (
                f"format_table-{_id(style)}",
                lambda s=style: optri.format_table(optri.triangulate(SQ, method="memo"), s),
                OptriError,
            )
        )
    return rows


API = _api_rows()


@pytest.mark.parametrize("call, expected", [r[1:] for r in API], ids=[r[0] for r in API])
def test_api_bad_input_raises_own_error(call, expected):
    with pytest.raises(OptriError) as info:
        call()
    assert isinstance(info.value, expected), repr(info.value)
    if isinstance(info.value, WeightError) and "triangle (" in str(info.value):
        assert (
            info.value.__cause__ is not None
            or "NaN" in str(info.value)
            or "returned" in str(info.value)
        )


def test_user_weight_error_names_triangle_and_chains_cause():
    with pytest.raises(
        WeightError, match=r"raised ZeroDivisionError on triangle \(\d, \d, \d\)"
    ) as info:
        optri.triangulate(PENT, weight=lambda i, k, j: 1 / 0, method="memo")
    assert isinstance(info.value.__cause__, ZeroDivisionError)


def test_user_weight_raising_on_one_triangle_is_named():
    def w(i, k, j):
        if (i, k, j) == (1, 2, 4):
            raise ValueError("not this one")
        return 1.0

    with pytest.raises(WeightError, match=r"triangle \(1, 2, 4\)"):
        optri.triangulate(PENT, weight=w, method="table")


def test_numba_weight_raising_in_compiled_engine_is_a_weight_error():
    numba = pytest.importorskip("numba")

    @numba.njit
    def w(v, i, k, j):
        if i == 0 and k == 2:
            raise ValueError("boom")
        return 1.0

    with pytest.raises(
        WeightError, match=r"inside the compiled engine on triangle \(0, 2, \d\)"
    ) as info:
        optri.triangulate(PENT, weight=w, method="fast")
    assert not isinstance(info.value, SystemError)
    assert isinstance(info.value.__cause__, ValueError)


# --- limits before work ------------------------------------------------------------------

LIMIT_ROWS = [
    ("triangulate-big-convex", lambda: optri.triangulate(_circle(20000), method="table")),
    # a convex polygon skips the floor check: the engine "auto" picks refuses
    ("triangulate-big-convex-auto", lambda: optri.triangulate(_circle(20000))),
    ("triangulate-big-mask", lambda: optri.triangulate(_star(20000))),
    ("mask", lambda: optri.valid_diagonals(_star(20000))),
    ("count-mask", lambda: optri.count_triangulations(_star(4000))),
    ("random-mask", lambda: optri.random_triangulation(_star(4000), seed=1)),
    ("best-k", lambda: optri.best_triangulations(_circle(3000), k=10)),
    ("fast", lambda: optri.triangulate(_circle(20000), method="fast")),
]


def _circle(n):
    a = 2 * np.pi * np.arange(n) / n
    return np.column_stack((np.cos(a), np.sin(a)))


def _star(n):
    r = np.where(np.arange(n) % 2 == 0, 1.0, 0.6)
    return _circle(n) * r[:, None]


@pytest.mark.parametrize("call", [r[1] for r in LIMIT_ROWS], ids=[r[0] for r in LIMIT_ROWS])
def test_memory_guard_refuses_before_allocating(monkeypatch, call):
    """A tiny monkeypatched ceiling: every large request is refused, naming limit and way out."""
    monkeypatch.setattr(config, "MEMORY_LIMIT_BYTES", 50 << 20)
    with pytest.raises(
        TableTooLargeError, match=r"needs .* MB but only 52.4 MB .*MEMORY_LIMIT_BYTES.*; \w+"
    ):
        call()


def test_memory_ceiling_reads_cgroup_limits(monkeypatch, tmp_path):
    from optri.engines import memory

    v2 = tmp_path / "cg"
    v2.mkdir()
    (v2 / "memory.max").write_text("1000000\n")
    (v2 / "memory.current").write_text("400000\n")
    (v2 / "memory.stat").write_text("anon 1\ninactive_file 100000\n")
    monkeypatch.setattr(
        memory, "_cgroup_files", lambda: ((v2 / "memory.max", v2 / "memory.current"),)
    )
    assert memory.cgroup_room() == 1000000 - 300000
    monkeypatch.setattr(config, "MEMORY_FRACTION", 0.5)
    assert memory.available_memory_bytes() == 350000
    (v2 / "memory.max").write_text("max\n")
    assert memory.cgroup_room() is None


def test_memory_ceiling_reads_meminfo(monkeypatch):
    from optri.engines import memory

    meminfo = b"MemTotal:       16000000 kB\nMemFree:  100 kB\nMemAvailable:   2500000 kB\n"
    monkeypatch.setattr(memory, "_read", lambda path: meminfo if path == "/proc/meminfo" else None)
    assert memory._meminfo_available() == 2500000 * 1024
    assert memory.cgroup_room() is None  # no cgroup file could be read
    monkeypatch.setattr(config, "MEMORY_FRACTION", 0.5)
    assert memory.available_memory_bytes() == 1250000 * 1024
    monkeypatch.setattr(memory, "_read", lambda path: b"MemTotal: 1 kB\n")
    assert memory._meminfo_available() is None


def test_memory_check_reads_the_os_only_for_large_requests(monkeypatch):
    """Below ``MEMORY_CHECK_MIN_BYTES`` no counter is read; from it, the OS's room decides."""
    from optri.engines import memory

    reads = []
    meminfo = b"MemAvailable:   1000 kB\n"  # 1 MB left: anything checked is refused

    def read(path):
        reads.append(path)
        return meminfo if path == "/proc/meminfo" else None

    monkeypatch.setattr(memory, "_read", read)
    floor = config.MEMORY_CHECK_MIN_BYTES
    memory.require_memory(floor - 1, "a small table")
    assert reads == []
    with pytest.raises(TableTooLargeError, match="a large table needs 33.6 MB but only 0.8 MB"):
        memory.require_memory(floor, "a large table")
    assert "/proc/meminfo" in reads
    monkeypatch.setattr(config, "MEMORY_LIMIT_BYTES", 1000)  # an explicit ceiling: every size
    with pytest.raises(TableTooLargeError, match="MEMORY_LIMIT_BYTES"):
        memory.require_memory(2000, "a tiny table")


def test_cgroup_files_found_from_proc_self_cgroup(monkeypatch, tmp_path):
    from optri.engines import memory

    root = tmp_path / "sys"
    (root / "memory" / "a" / "b").mkdir(parents=True)
    (root / "memory" / "a" / "b" / "memory.limit_in_bytes").write_text("5000\n")
    (root / "memory" / "a" / "memory.limit_in_bytes").write_text("9223372036854771712\n")
    (root / "memory" / "memory.limit_in_bytes").write_text("9223372036854771712\n")
    proc = tmp_path / "cgroup"
    proc.write_text("4:memory:/a/b\n0::/\n")
    monkeypatch.setattr(memory, "_ROOT", root)
    real_path = memory.Path
    monkeypatch.setattr(
        memory, "Path", lambda p: proc if p == "/proc/self/cgroup" else real_path(p)
    )
    memory._cgroup_files.cache_clear()
    try:
        files = memory._cgroup_files()
    finally:
        memory._cgroup_files.cache_clear()
    assert files[0][0] == root / "memory" / "a" / "b" / "memory.limit_in_bytes"
    assert len(files) == 3


def test_best_k1_is_the_plain_dp():
    poly = _star(40)
    (best,) = optri.best_triangulations(poly, k=1)
    assert best.method == "kbest"
    assert best.weight == pytest.approx(optri.triangulate(poly).weight, rel=1e-12)
    best.check()


# --- the CLI table -----------------------------------------------------------------------

CLI_FILES = {
    "binary.csv": b"\x00\xff\xfe\x89PNG\r\n\x1a\n" * 10,
    "empty.csv": b"",
    "one_line.csv": b"0,0\n",
    "two_points.csv": b"0,0\n1,1\n",
    "letters.csv": b"a,b\nc,d\ne,f\n",
    "nan.csv": b"0,0\n1,0\nnan,1\n",
    "inf.csv": b"0,0\n1,0\ninf,1\n",
    "huge.csv": b"0,0\n1e400,0\n1,1\n",
    "bowtie.csv": b"0,0\n2,2\n2,0\n0,2\n",
    "repeat.csv": b"0,0\n1,0\n1,0\n0,1\n",
    "ragged.csv": b"0,0\n1,0,5,6\n1\n",
    "collinear.csv": b"0,0\n1,0\n2,0\n",
    "bad.json": b"{not json",
    "list.json": b"[1, 2",
    "deep.json": b"[" * 100000 + b"]" * 100000,
    "obj.json": b'{"a": 1}',
    "coords5.geojson": b'{"type": "Polygon", "coordinates": 5}',
    "point.geojson": b'{"type": "Point", "coordinates": [1, 2]}',
    "nullgeom.geojson": b'{"type": "Feature", "geometry": null}',
    "bad.wkt": b"POLYGON ((0 0, 1 0",
    "point.wkt": b"POINT (1 2)",
    "latin1.csv": "0,0\n1,0\n1,1\n# caf\u00e9\n".encode("latin-1"),
    "dims.txt": b"1 2 x\n",
    "huge_ints.csv": b"0,0\n" + b"1" * 500 + b",0\n1,1\n",
}

CLI_ROWS = []
for _name in CLI_FILES:
    for _cmd in (
        ["solve"],
        ["solve", "-m", "memo"],
        ["count"],
        ["best", "-k", "2"],
        ["enumerate", "-n", "2"],
    ):
        CLI_ROWS.append((f"{'-'.join(_cmd)}-{_name}", [*_cmd, "{file}"], _name, 2))
CLI_ROWS += [
    ("solve-missing-file", ["solve", "/nonexistent/x.csv"], None, 2),
    ("solve-directory", ["solve", "{dir}"], None, 2),
    ("solve-bad-weight", ["solve", "-w", "nope", "{ok}"], None, 2),
    (
        "solve-bad-pair",
        ["solve", "-w", "perimeter,area,area", "--objective", "sum,max", "{ok}"],
        None,
        2,
    ),
    ("solve-bad-objective", ["solve", "--objective", "avg", "{ok}"], None, 2),
    ("best-k0", ["best", "-k", "0", "{ok}"], None, 2),
    ("best-k-neg", ["best", "-k", "-3", "{ok}"], None, 2),
    ("best-k-text", ["best", "-k", "abc", "{ok}"], None, 2),
    ("best-bad-weight", ["best", "-w", "nope", "{ok}"], None, 2),
    ("enumerate-bad-weight", ["enumerate", "-w", "nope", "{ok}"], None, 2),
    ("bench-zero", ["bench", "0"], None, 2),
    ("bench-two", ["bench", "2"], None, 2),
    ("bench-repeats-zero", ["bench", "5", "--repeats", "0"], None, 2),
    ("count-negative", ["count", "-5"], None, 2),
    ("count-zero", ["count", "0"], None, 2),
    ("chain-negative", ["chain", "1", "-2", "3"], None, 2),
    ("chain-one", ["chain", "1"], None, 2),
    ("chain-text", ["chain", "a", "b", "c"], None, 2),
    ("fill-missing", ["fill", "/nonexistent.obj", "-o", "{dir}/o.obj"], None, 2),
    ("fill-garbage", ["fill", "{file}", "-o", "{dir}/o.obj"], "binary.csv", 2),
    (
        "batch-bad-weight",
        ["batch", "{file}", "-o", "{dir}/out.ndjson", "-w", "nope", "-q"],
        "ok.ndjson",
        2,
    ),
    (
        "batch-bad-objective",
        ["batch", "{file}", "-o", "{dir}/out.ndjson", "--objective", "x", "-q"],
        "ok.ndjson",
        2,
    ),
    ("batch-missing", ["batch", "/nonexistent.ndjson", "-o", "{dir}/out.ndjson", "-q"], None, 2),
]
CLI_FILES["ok.ndjson"] = b'{"id": 1, "coordinates": [[0, 0], [1, 0], [1, 1]]}\n'


@pytest.mark.parametrize(
    "args, fname, code", [r[1:] for r in CLI_ROWS], ids=[r[0] for r in CLI_ROWS]
)
def test_cli_bad_input_is_one_line_and_exit_code(tmp_path, args, fname, code):
    ok = tmp_path / "ok.csv"
    ok.write_text("0,0\n1,0\n1,1\n0,1\n")
    path = tmp_path / (fname or "none")
    if fname:
        path.write_bytes(CLI_FILES[fname])
    argv = [a.format(file=path, dir=tmp_path, ok=ok) for a in args]
    result = CliRunner().invoke(main, argv)
    assert result.exit_code == code, (result.output, result.exception)
    assert isinstance(result.exception, SystemExit), repr(result.exception)  # no traceback
    err = [ln for ln in result.stderr.splitlines() if ln.strip()]
    assert "Traceback" not in result.stderr
    assert "a bug in optri" not in result.stderr  # the CLI's catch-all: not a clean error
    own = [ln for ln in err if ln.startswith("optri: error:")]
    if own:  # a library error: exactly one line
        assert len(own) == 1 and len(err) == 1, err
    else:  # a usage error from click: names the problem
        assert any(ln.startswith("Error:") or "optri: error" in ln for ln in err), err


# --- the batch table -----------------------------------------------------------------------

BATCH_LINES = [
    ("deep_nesting", b"[" * 100000 + b"]" * 100000),
    ("not_utf8", b'{"id": "x\xff", "coordinates": [[0, 0], [1, 0], [1, 1]]}'),
    ("truncated", b'{"id": 1, "coordinates": [[0, 0], [1, 0]'),
    ("number_id_nan", b'{"id": NaN, "coordinates": [[0, 0], [1, 0]]}'),
    ("id_infinity", b'{"id": Infinity, "coordinates": [[0, 0], [1, 0]]}'),
    ("id_1e400", b'{"id": 1e400, "coordinates": [[0, 0], [1, 0]]}'),
    ("coords_number", b'{"coordinates": 5}'),
    ("coords_null", b'{"coordinates": null}'),
    ("coords_strings", b'{"coordinates": [["a", "b"], ["c", "d"], ["e", "f"]]}'),
    ("coords_nested_deep", b'{"coordinates": ' + b"[" * 50 + b"]" * 50 + b"}"),
    ("coords_1e400", b'{"coordinates": [[0, 0], [1e400, 0], [1, 1]]}'),
    ("coords_nan", b'{"coordinates": [[0, 0], [NaN, 0], [1, 1]]}'),
    ("coords_bool", b'{"coordinates": [[true, false], [1, 0], [1, 1]]}'),
    ("coords_two", b'{"coordinates": [[0, 0], [1, 1]]}'),
    ("coords_bowtie", b'{"coordinates": [[0, 0], [2, 2], [2, 0], [0, 2]]}'),
    ("coords_repeat", b'{"coordinates": [[0, 0], [1, 0], [1, 0], [0, 1]]}'),
    ("coords_collinear", b'{"coordinates": [[0, 0], [1, 0], [2, 0]]}'),
    ("coords_ragged", b'{"coordinates": [[0, 0], [1], [1, 1, 1, 1]]}'),
    ("coords_huge_int", b'{"coordinates": [[0, 0], [' + b"9" * 400 + b", 0], [1, 1]]}"),
    (
        "geometry_point",
        b'{"type": "Feature", "geometry": {"type": "Point", "coordinates": [1, 2]}}',
    ),
    ("geometry_null", b'{"type": "Feature", "geometry": null}'),
    ("geometry_string", b'{"type": "Feature", "geometry": "POLYGON"}'),
    ("geometry_coords5", b'{"type": "Feature", "geometry": {"type": "Polygon", "coordinates": 5}}'),
    ("list_line", b"[1, 2, 3]"),
    ("number_line", b"42"),
    ("string_line", b'"polygon"'),
    ("null_line", b"null"),
    ("garbage", b"\x00\x01\x02\xff\xfe"),
    ("bom_in_middle", b"\xef\xbb\xbf{}"),
    ("empty_object", b"{}"),
    ("duplicate_keys", b'{"coordinates": [[0, 0]], "coordinates": 5}'),
    (
        "big_properties",
        b'{"coordinates": [[0, 0], [1, 0], [1, 1]], "properties": '
        + b"[" * 200
        + b"]" * 200
        + b"}",
    ),
]
GOOD_LINE = b'{"id": "good%d", "coordinates": [[0, 0], [4, 0], [5, 3], [2, 5], [-1, 3]]}'
# lines the reader takes as polygons (they are fine, or their oddity is only in attributes)
BATCH_OK = {"big_properties"}


@pytest.fixture(scope="module")
def batch_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("batch")
    lines = []
    for i, (_, raw) in enumerate(BATCH_LINES):
        lines += [raw, GOOD_LINE % i]
    src = folder / "in.ndjson"
    src.write_bytes(b"\n".join(lines) + b"\n")
    summary = optri.batch(src, folder / "out.ndjson", workers=1)
    return summary, list(iter_records(folder / "out.ndjson"))


@pytest.mark.parametrize("index", range(len(BATCH_LINES)), ids=[r[0] for r in BATCH_LINES])
def test_batch_bad_line_gives_one_error_record(batch_run, index):
    summary, records = batch_run
    assert summary.total == len(records) == 2 * len(BATCH_LINES)  # no record lost
    rec, after = records[2 * index], records[2 * index + 1]
    json.dumps(rec["id"], allow_nan=False)  # ids are valid JSON
    if BATCH_LINES[index][0] in BATCH_OK:
        assert rec["status"] == "ok"
    else:
        assert rec["status"] == "error" and rec["reason"] and "\n" not in rec["reason"], rec
    assert after["status"] == "ok" and after["id"] == f"good{index}"


def test_tables_have_at_least_200_rows():
    assert len(API) + len(CLI_ROWS) + len(BATCH_LINES) + len(LIMIT_ROWS) >= 200
