"""The compiled engine's tables: reused between solves, never read before written.

A table of at least ``config.TABLE_CACHE_MIN_BYTES`` is kept after its solve
(``optri.engines.memory.release_table``) and the next solve fills it again, so the
kernels must write every cell before reading it: here each reused table is first
filled with garbage (NaN, negative numbers, random bytes), and the solve must still
equal, bit for bit, one on a table of its own. The threshold is lowered so that
small polygons take that path.
"""

from __future__ import annotations

import functools
import gc
import json
import threading
import time
import weakref
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

import optri
from optri import config
from optri.engines import jit, memory
from strategies import ellipse_polygon as convex_polygon

pytest.importorskip("numba")
pytestmark = pytest.mark.skipif(
    memory._MADV_FREE is None, reason="no MADV_FREE here: tables are never kept"
)

RINGS = Path(__file__).parent / "data" / "rings" / "natural_earth_countries_states.json"

#: bytes a reused table holds before its solve
GARBAGE = {
    "nan": lambda size, rng: np.full(size, 0xFF, np.uint8),  # NaN, sign bit set
    "minus-one": lambda size, rng: np.frombuffer(np.full(size // 8, -1.0).tobytes(), np.uint8),
    "random": lambda size, rng: rng.integers(0, 256, size, dtype=np.uint8),
}


@pytest.fixture(autouse=True)
def _kept_tables(monkeypatch: pytest.MonkeyPatch):  # type: ignore[no-untyped-def]
    """Every table goes through the cache; nothing kept before or after a test."""
    monkeypatch.setattr(config, "TABLE_CACHE_MIN_BYTES", 0)
    monkeypatch.setattr(config, "TABLE_CACHE_SECONDS", 30.0)
    memory.clear_table_cache()
    yield
    memory.clear_table_cache()


def _kept() -> memory._TableBuffer | None:
    return memory._CACHE.buffer


def _plant(n: int, dtype: type, garbage: str, seed: int = 0) -> memory._TableBuffer:
    """Keep a table buffer for ``n`` vertices whose every byte is ``garbage``."""
    table = memory.new_table(n, np.dtype(dtype))
    buffer = memory._buffer_of(table)
    assert buffer is not None
    raw = np.frombuffer(buffer, np.uint8)
    raw[:] = GARBAGE[garbage](len(raw), np.random.default_rng(seed))
    del raw
    memory.release_table(table)
    assert _kept() is buffer
    return buffer


def _solve_fresh(pts, *args, **kw):  # type: ignore[no-untyped-def]
    """The solve on a table of numpy's, no cache involved."""
    before = config.TABLE_CACHE_SECONDS
    config.TABLE_CACHE_SECONDS = 0
    try:
        return optri.triangulate(pts, *args, method="fast", **kw)
    finally:
        config.TABLE_CACHE_SECONDS = before


def _same(a: optri.Triangulation, b: optri.Triangulation) -> None:
    assert a.weight == b.weight
    assert np.array_equal(a.triangles, b.triangles)
    if a.table is not None:
        assert np.array_equal(a.table, b.table, equal_nan=True)


@functools.cache
def _simple_ring() -> np.ndarray:
    """A real non-convex ring of the corpus with 40-200 vertices (its closing vertex off)."""
    for r in json.loads(RINGS.read_text()):
        if r["expected"]["simple"] and 40 <= r["expected"]["n"] <= 200:
            pts = np.array(r["ring"], dtype=float)[:-1, :2]
            if not optri.as_polygon(pts).convex:
                return pts
    raise AssertionError("no such ring")


CASES = {  # name: (polygon, triangulate's arguments, its keywords, config.FAST_TILE)
    # min-plus fill: 5 tiles of 64 a side (a pair at tile-diagonal 4)
    "minplus-300": (lambda: convex_polygon(300, 1), ("perimeter",), {}, None),
    # 17 tiles of 32 a side: many pairs, a partial last tile
    "minplus-523-tile32": (lambda: convex_polygon(523, 2), ("perimeter",), {}, 32),
    "minplus-float32": (lambda: convex_polygon(200, 3), ("perimeter",), {"dtype": "float32"}, None),
    "generic-max": (lambda: convex_polygon(150, 4), ("max_angle", "max"), {}, None),
    "generic-lex": (
        lambda: convex_polygon(90, 5),
        (("max_angle", "area"), ("max", "sum")),
        {},
        None,
    ),
    "masked-ring": (_simple_ring, ("perimeter",), {}, None),
    "exported-table": (lambda: convex_polygon(60, 6), ("perimeter",), {"keep_table": True}, None),
}


@pytest.mark.parametrize("garbage", sorted(GARBAGE))
@pytest.mark.parametrize("case", sorted(CASES))
def test_a_reused_table_gives_the_same_solve(
    case: str, garbage: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    make, args, kw, tile = CASES[case]
    monkeypatch.setattr(config, "FAST_TILE", tile)
    pts = make()
    want = _solve_fresh(pts, *args, **kw)
    n = len(pts)
    buffer = _plant(n, np.float32 if kw.get("dtype") == "float32" else np.float64, garbage)
    got = optri.triangulate(pts, *args, method="fast", **kw)
    assert _kept() is buffer  # the planted buffer was filled, then kept again
    _same(got, want)


def test_the_cases_reach_their_paths() -> None:
    """The parametrized cases above take the paths they are named after."""
    pts = CASES["masked-ring"][0]()
    assert not optri.as_polygon(pts).convex
    stats = {
        case: optri.triangulate(make(), *args, method="fast", **kw).stats
        for case, (make, args, kw, tile) in CASES.items()
        if tile is None
    }
    assert stats["minplus-300"]["minplus"] == 1 and stats["minplus-300"]["tile"] == 64
    assert stats["generic-max"]["minplus"] == 0 and stats["generic-lex"]["minplus"] == 0


def test_one_table_is_kept_and_a_smaller_one_let_go_first() -> None:
    small = memory.new_table(100, np.float64)
    buffer = memory._buffer_of(small)
    gone = weakref.ref(buffer)
    memory.release_table(small)
    del small, buffer
    assert _kept() is not None
    larger = memory.new_table(1000, np.float64)  # 8 MB do not fit: the kept one is unmapped
    gc.collect()
    assert gone() is None and _kept() is None
    memory.release_table(larger)
    again = memory.new_table(900, np.float64)  # fits in the kept one: reused
    assert memory._buffer_of(again) is memory._buffer_of(larger) and _kept() is None
    assert again.ctypes.data % (2 << 20) == 0  # starts a huge page
    assert again.flags.writeable and again.flags.c_contiguous and again.shape == (900, 900)


def test_a_kept_table_is_let_go_after_its_seconds(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(config, "TABLE_CACHE_SECONDS", 0.05)
    table = memory.new_table(100, np.float64)
    gone = weakref.ref(memory._buffer_of(table))
    memory.release_table(table)
    del table
    assert gone() is not None
    deadline = time.monotonic() + 5
    while gone() is not None and time.monotonic() < deadline:
        time.sleep(0.02)
        gc.collect()
    assert gone() is None and _kept() is None


@pytest.mark.parametrize("setting", ["seconds", "size"])
def test_tables_from_numpy_when_not_kept(setting: str, monkeypatch: pytest.MonkeyPatch) -> None:
    if setting == "seconds":
        monkeypatch.setattr(config, "TABLE_CACHE_SECONDS", 0)
    else:
        monkeypatch.setattr(config, "TABLE_CACHE_MIN_BYTES", 100 * 100 * 8 + 1)
    table = memory.new_table(100, np.float64)
    assert memory._buffer_of(table) is None
    assert table.ctypes.data % 64 == 0
    memory.release_table(table)
    assert _kept() is None
    optri.triangulate(convex_polygon(90, 7), method="fast")  # 65 KB
    assert _kept() is None


def test_a_failed_solve_keeps_no_table(monkeypatch: pytest.MonkeyPatch) -> None:
    """On an error a kernel may still write the table (a second Ctrl-C): never kept."""

    def broken(*args, **kw):  # type: ignore[no-untyped-def]
        raise RuntimeError("export failed")

    monkeypatch.setattr(jit, "_export", broken)
    with pytest.raises(RuntimeError, match="export failed"):
        optri.triangulate(convex_polygon(80, 8), method="fast", keep_table=True)
    assert _kept() is None
    optri.triangulate(convex_polygon(80, 8), method="fast")
    assert _kept() is not None


def test_solves_on_several_threads_at_once() -> None:
    """Each solve takes the kept table or a new one, never one another solve holds."""
    polys = [convex_polygon(n, seed) for seed, n in enumerate((120, 200, 160, 240, 90, 300))]
    want = [_solve_fresh(p) for p in polys]
    with ThreadPoolExecutor(4) as pool:
        for _ in range(3):
            got = list(pool.map(lambda p: optri.triangulate(p, method="fast"), polys))
            for a, b in zip(got, want):
                _same(a, b)


def test_a_forked_child_starts_with_nothing_kept() -> None:
    memory.release_table(memory.new_table(100, np.float64))
    parent = memory._CACHE
    assert parent.buffer is not None
    assert parent.lock.acquire(timeout=1)  # as if another thread held it at the fork
    try:
        memory._reset_after_fork()
        assert memory._CACHE is not parent and _kept() is None
        memory.release_table(memory.new_table(100, np.float64))  # the new lock is free
        assert _kept() is not None
    finally:
        parent.lock.release()


def test_one_daemon_thread_lets_kept_tables_go() -> None:
    """Started once, with the first table kept; it never delays the interpreter's exit."""
    memory.release_table(memory.new_table(100, np.float64))
    thread = memory._CACHE.thread
    assert isinstance(thread, threading.Thread) and thread.daemon and thread.is_alive()
    for _ in range(3):
        memory.release_table(memory.new_table(100, np.float64))
    assert memory._CACHE.thread is thread
