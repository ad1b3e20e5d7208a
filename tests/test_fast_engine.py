"""The compiled engine (method="fast") against the memo and brute-force oracles."""

from __future__ import annotations

import math
import threading
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import optri
from optri import config
from optri.engines import interrupts, jit, memo
from optri.engines.progress import tile_work
from optri.errors import (
    EngineUnavailableError,
    InvalidParameterError,
    TableTooLargeError,
    WeightError,
)
from optri.polygon import as_polygon
from optri.solve import build_problem
from strategies import MAX_LED_EDGE_PAIRS, TWO_PHASE_CASES
from strategies import ellipse_polygon as convex_polygon

THREADS = "OPTRI_NUM_THREADS"  # the compiled engines' thread count (optri.engines.threads)

WEIGHTS = ["perimeter", "diagonal", "area", "max_angle", "min_angle", "aspect_ratio"]
OBJECTIVES = ["sum", "max"]
LEX = [(("max_angle", "area"), ("max", "sum")), (("perimeter", "aspect_ratio"), ("sum", "max"))]
#: float32 tables: observed relative error of the optimum ~1e-7 (n <= 2000); allow 1e-5.
FLOAT32_RTOL = 1e-5


def close(a: object, b: object, rtol: float = 1e-9) -> bool:
    if isinstance(a, tuple):
        return all(close(x, y, rtol) for x, y in zip(a, b))  # type: ignore[arg-type]
    return math.isclose(a, b, rel_tol=rtol, abs_tol=rtol)  # type: ignore[arg-type]


polygons = st.tuples(st.integers(3, 32), st.integers(0, 2**32 - 1))


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(polygons)
def test_fast_equals_memo_every_weight_and_objective(spec: tuple[int, int]) -> None:
    pts = convex_polygon(*spec)
    for w in WEIGHTS:
        for obj in OBJECTIVES:
            a = optri.triangulate(pts, w, obj, method="fast")
            b = optri.triangulate(pts, w, obj, method="memo")
            assert close(a.weight, b.weight), (w, obj, a.weight, b.weight)
            a.check()
    for ws, obj in LEX:
        a = optri.triangulate(pts, ws, obj, method="fast")
        b = optri.triangulate(pts, ws, obj, method="memo")
        assert close(a.weight, b.weight), (ws, obj, a.weight, b.weight)
        a.check()


@settings(max_examples=3, deadline=None)
@given(st.integers(41, 60), st.integers(0, 2**32 - 1))
def test_fast_equals_memo_larger(n: int, seed: int) -> None:
    pts = convex_polygon(n, seed)
    for w, obj in (("perimeter", "sum"), ("diagonal", "sum"), ("max_angle", "max")):
        a = optri.triangulate(pts, w, obj, method="fast")
        b = optri.triangulate(pts, w, obj, method="memo")
        assert close(a.weight, b.weight)
        a.check()


@pytest.mark.parametrize("tile", [3, 5, 8])
def test_fast_small_tiles_equal_memo(monkeypatch: pytest.MonkeyPatch, tile: int) -> None:
    # tiny tiles: many tile-diagonals, far splits, partial tiles and odd row counts
    monkeypatch.setattr(config, "FAST_TILE", tile)
    monkeypatch.setattr(config, "FAST_GENERIC_TILE", tile)
    monkeypatch.setattr(config, "FAST_WATCH_WORK", 0)  # in a watched helper thread
    pts = convex_polygon(37, tile)
    for w, obj in (("perimeter", "sum"), ("diagonal", "sum"), ("max_angle", "max")):
        a = optri.triangulate(pts, w, obj, method="fast")
        b = optri.triangulate(pts, w, obj, method="memo")
        assert close(a.weight, b.weight), (w, obj)
    a = optri.triangulate(pts, LEX[0][0], LEX[0][1], method="fast")
    b = optri.triangulate(pts, LEX[0][0], LEX[0][1], method="memo")
    assert close(a.weight, b.weight)


@pytest.mark.parametrize("n", [3, 4, 7, 10])
def test_fast_equals_brute(n: int) -> None:
    pts = convex_polygon(n, n)
    for w in WEIGHTS:
        for obj in OBJECTIVES:
            a = optri.triangulate(pts, w, obj, method="fast")
            b = optri.triangulate(pts, w, obj, method="brute")
            assert close(a.weight, b.weight), (w, obj)
    for ws, obj in LEX:
        a = optri.triangulate(pts, ws, obj, method="fast")
        b = optri.triangulate(pts, ws, obj, method="brute")
        assert close(a.weight, b.weight), (ws, obj)


def test_fast_3d_planar_and_product_weight() -> None:
    pts = convex_polygon(25, 5, dims=3)
    for w in ("perimeter", "area", "aspect_ratio"):
        a = optri.triangulate(pts, w, "sum", method="fast")
        b = optri.triangulate(pts, w, "sum", method="memo")
        assert close(a.weight, b.weight)
    dims = [30, 35, 15, 5, 10, 20, 25]  # CLRS 15.2: 15125 scalar multiplications
    assert optri.triangulate(dims, "product", method="fast").weight == 15125.0


def test_fast_known_square() -> None:
    t = optri.triangulate([[0, 0], [1, 0], [1, 1], [0, 1]], method="fast")
    assert math.isclose(t.weight, 4 + 2 * math.sqrt(2))
    assert t.method == "fast"
    t.check()


@pytest.mark.parametrize("weight", ["perimeter", "max_angle"])
def test_fast_float32_within_tolerance(weight: str) -> None:
    pts = convex_polygon(300 if weight == "perimeter" else 120, 11)
    a = optri.triangulate(pts, weight, method="fast", dtype=np.float32)
    b = optri.triangulate(pts, weight, method="fast")
    assert close(a.weight, b.weight, FLOAT32_RTOL)
    assert a.weight != b.weight  # really ran in float32: its rounding shows
    if weight == "max_angle":  # the generic path reports the float32 table's cell as is
        assert a.weight == float(np.float32(a.weight))
    a.check(rtol=1e-4)


@pytest.mark.parametrize("n, seed", TWO_PHASE_CASES)
@pytest.mark.parametrize("pair", MAX_LED_EDGE_PAIRS)
def test_fast_max_led_pair_with_edge_weight_second(n: int, seed: int, pair: tuple) -> None:
    """("max", "sum") with a perimeter or diagonal second: the gated phase is not min-plus.

    The second phase sums an edge-decomposable weight, which alone would run on
    the min-plus kernel; that kernel has no gate, so it would return the
    unconstrained optimum. On these polygons that optimum breaks the bottleneck.
    """
    pts = convex_polygon(n, seed)
    fast = optri.triangulate(pts, pair, ("max", "sum"), method="fast")
    fast.check()
    for oracle in ("brute", "memo"):
        ref = optri.triangulate(pts, pair, ("max", "sum"), method=oracle)
        assert close(fast.weight, ref.weight), (oracle, fast.weight, ref.weight)
        assert sorted(map(tuple, fast.triangles.tolist())) == sorted(
            map(tuple, ref.triangles.tolist())
        )
    free = optri.triangulate(pts, pair[1], "sum", method="fast")
    assert free.weight < fast.weight[1] * (1 - 1e-9)  # the gate binds on this input
    assert fast.stats["minplus"] == 0


@pytest.mark.parametrize("values", [[3, 1, 4, 1, 5, 9, 2], [0, 5, 7, 3, 2], [4, 0, 6, 0, 5, 2]])
def test_fast_integer_max_led_pair_keeps_the_bottleneck(values: list) -> None:
    # a zero bottleneck (fans around a zero value): tie_ceiling(0.0) adds nothing, so the
    # compiled gate's threshold is the bottleneck itself and must let it through
    spec = (("product", "product"), ("max", "sum"))
    fast = optri.triangulate(values, *spec, method="fast")
    assert fast.weight == optri.triangulate(values, *spec, method="brute").weight
    assert fast.method == "fast"


def test_fast_float32_gate_admits_the_bottleneck() -> None:
    """The float32 phase-1 bottleneck is rounded; the gate widens it by one float32 ulp.

    Here float32 rounds the bottleneck M* down, so a gate at the rounded value
    would forbid the very triangle that attains M*.
    """
    pts = convex_polygon(8, 0)
    spec = (("max_angle", "perimeter"), ("max", "sum"))
    exact = optri.triangulate(pts, *spec, method="fast")
    assert float(np.float32(exact.weight[0])) < exact.weight[0]  # rounds down: the case
    single = optri.triangulate(pts, *spec, method="fast", dtype=np.float32)
    assert close(single.weight, exact.weight, FLOAT32_RTOL)
    assert np.array_equal(single.triangles, exact.triangles)


def test_fast_memory_check_counts_each_threads_buffers(monkeypatch: pytest.MonkeyPatch) -> None:
    # n = 5000: 256-tiles, 1 MB of buffers a thread; a limit with room for the table and
    # one thread's buffers, not two, is refused on two threads
    n = 5000
    per_thread = jit._worker_bytes(n, np.float64)
    assert per_thread == (1 << 20) + 16 * 16 * 8  # 1 MB and a spare packed row a strip
    monkeypatch.setattr(config, "MEMORY_LIMIT_BYTES", jit.estimate_bytes(n) + 3 * per_thread // 2)
    monkeypatch.setenv(THREADS, "2")
    with pytest.raises(TableTooLargeError, match="5000 x 5000"):
        optri.triangulate(convex_polygon(n, 1), method="fast")


def test_fast_memory_estimator_refuses(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(config, "MEMORY_LIMIT_BYTES", 50 << 20)
    with pytest.raises(TableTooLargeError, match="float32"):
        optri.triangulate(convex_polygon(3000, 1), method="fast")
    assert jit.estimate_bytes(3000, np.float32) < jit.estimate_bytes(3000)


def test_fast_threads_follow_the_setting(monkeypatch: pytest.MonkeyPatch) -> None:
    # OPTRI_NUM_THREADS (else the core's OpenMP limit) from the size thresholds on, one
    # thread below them (config.FAST_PARALLEL_MIN_N, FAST_GENERIC_PARALLEL_MIN_N); a
    # problem's options["threads"] wins
    for setting in (2, 1, 3):
        monkeypatch.setenv(THREADS, str(setting))
        for n, threads in ((300, 1), (1000, setting)):
            got = optri.triangulate(convex_polygon(n, 3), method="fast")
            assert got.stats["threads"] == threads
        for n, threads in ((100, 1), (260, setting)):
            got = optri.triangulate(convex_polygon(n, 3), "max_angle", "max", method="fast")
            assert got.stats["threads"] == threads
    monkeypatch.delenv(THREADS)
    from optri import _core

    got = optri.triangulate(convex_polygon(260, 3), "area", "max", method="fast")
    assert got.stats["threads"] == _core.max_threads()
    problem = build_problem(as_polygon(convex_polygon(30, 1)), "area", "max", keep_table=False)
    problem.options["threads"] = 2
    assert jit.solve(problem).stats["threads"] == 2
    monkeypatch.setenv(THREADS, "two")
    with pytest.raises(InvalidParameterError, match=THREADS):
        optri.triangulate(convex_polygon(260, 3), "area", "max", method="fast")


def test_fast_reproducible_across_runs_and_threads(monkeypatch: pytest.MonkeyPatch) -> None:
    pts = convex_polygon(1000, 7)
    results = []
    for threads in (1, 2, 2):
        monkeypatch.setenv(THREADS, str(threads))
        results.append(optri.triangulate(pts, method="fast"))
        results.append(optri.triangulate(pts[:400], "max_angle", "max", method="fast"))
    for r, first in zip(results[2:], results[:-2]):  # each run against the one before
        assert r.weight == first.weight  # bit for bit: min is exact, sums are ordered
        assert np.array_equal(r.triangles, first.triangles)
    results[0].check()


@pytest.mark.parametrize("n, tile", [(400, 16), (523, 32)])
def test_two_threads_fill_the_one_thread_table(
    monkeypatch: pytest.MonkeyPatch, n: int, tile: int
) -> None:
    # small tiles: dozens of tile-diagonals and paired tiles, so that the threads meet
    # where a tile waits for rows or cells another one is still writing (a pair's shared
    # far splits, the tile below, the left neighbour); one started too early reads an
    # unfinished cell or loses a minimum to the other thread, and the table differs
    monkeypatch.setattr(config, "FAST_TILE", tile)
    monkeypatch.setattr(config, "FAST_PARALLEL_MIN_N", 0)
    pts = convex_polygon(n, 5)
    monkeypatch.setenv(THREADS, "1")
    want = optri.triangulate(pts, method="fast", keep_table=True).table
    monkeypatch.setenv(THREADS, "2")
    for run in range(40):  # a race shows in some runs only
        got = optri.triangulate(pts, method="fast", keep_table=True)
        assert got.stats["threads"] == 2
        assert np.array_equal(got.table, want), run


def test_fast_masked_chords_equal_memo() -> None:
    rng = np.random.default_rng(3)
    n = 14
    pg = as_polygon(convex_polygon(n, 2))
    allowed = rng.random((n, n)) < 0.6
    allowed = allowed | allowed.T
    # keep one fan triangulation possible so a solution always exists
    allowed[0, :] = allowed[:, 0] = True
    for w, obj in (
        ("perimeter", "sum"),
        ("max_angle", "max"),
        (("area", "perimeter"), ("max", "sum")),
    ):
        pf = build_problem(pg, w, obj, allowed=allowed, keep_table=False)
        pm = build_problem(pg, w, obj, allowed=allowed, keep_table=False)
        a, b = jit.solve(pf), memo.solve(pm)
        assert close(a.cost, b.cost), (w, obj)
        ok = pm.allowed_rows()
        assert all(ok[i][k] and ok[k][j] and ok[i][j] for i, k, j in a.triangles.tolist())


def test_fast_progress_and_table() -> None:
    calls: list[tuple[int, int]] = []
    pts = convex_polygon(12, 4)
    a = optri.triangulate(
        pts, method="fast", keep_table=True, progress=lambda d, t: calls.append((d, t))
    )
    b = optri.triangulate(pts, method="memo", keep_table=True)
    assert calls and calls[-1][0] == calls[-1][1] == 220  # C(12, 3) split evaluations
    assert [d for d, _ in calls] == sorted(d for d, _ in calls)
    np.testing.assert_allclose(np.triu(a.table), np.triu(b.table), rtol=1e-9, atol=1e-9)
    np.testing.assert_array_equal(np.tril(a.table), np.tril(b.table))


@pytest.mark.parametrize(
    "weight, objective, n, tile", [("perimeter", "sum", 1200, 16), ("max_angle", "max", 300, 4)]
)
def test_fast_watched_fill_reports_progress_and_equals_the_direct_one(
    monkeypatch: pytest.MonkeyPatch, weight: str, objective: str, n: int, tile: int
) -> None:
    # a long fill (min-plus; generic) runs in a helper thread while this one reports the
    # split evaluations of finished tiles (tile-diagonals): reports rise to the total,
    # more than once (fills of about 0.1 s, polled every millisecond), and the optimum is
    # the direct call's, bit for bit
    pts = convex_polygon(n, 3)
    monkeypatch.setattr(config, "FAST_TILE", tile)
    monkeypatch.setattr(config, "FAST_GENERIC_TILE", tile)
    direct = optri.triangulate(pts, weight, objective, method="fast")
    monkeypatch.setattr(config, "FAST_WATCH_WORK", 0)
    monkeypatch.setattr(config, "FAST_PROGRESS_SECONDS", 1e-3)
    calls: list[tuple[int, int]] = []
    got = optri.triangulate(
        pts, weight, objective, method="fast", progress=lambda d, t: calls.append((d, t))
    )
    assert got.weight == direct.weight
    assert np.array_equal(got.triangles, direct.triangles)
    total = n * (n - 1) * (n - 2) // 6
    assert len(calls) > 1 and calls[-1] == (total, total) and all(t == total for _, t in calls)
    assert all(a < b for (a, _), (b, _) in zip(calls, calls[1:]))
    # what the reports add up: each tile's split evaluations (j - i - 1 for chord (i, j)),
    # every chord in exactly one tile, in the closed form against the chords counted
    for n, tile in ((300, 8), (1000, 128), (10, 4), (9, 16), (4000, 256), (37, 5)):
        i, j = np.triu_indices(n, 2)
        nt = -(-n // tile)
        per_tile = np.bincount(i // tile * nt + j // tile, weights=j - i - 1, minlength=nt * nt)
        assert np.array_equal(tile_work(n, tile), per_tile.astype(np.int64)), (n, tile)


def test_fast_watched_fill_stops_when_the_caller_raises(monkeypatch: pytest.MonkeyPatch) -> None:
    # an exception in the watching thread (Ctrl-C arrives there too) sets the stop
    # flag: the helper takes no further tile and is waited for before the exception
    # goes on; a fill that was not stopped would have finished every tile
    from optri.engines import _jit_kernels

    made: list[tuple[np.ndarray, np.ndarray]] = []
    fresh = _jit_kernels.tile_flags

    def flags(n: int, tile: int) -> tuple[np.ndarray, np.ndarray]:
        made.append(fresh(n, tile))
        return made[-1]

    monkeypatch.setattr(_jit_kernels, "tile_flags", flags)
    monkeypatch.setattr(config, "FAST_TILE", 16)
    monkeypatch.setattr(config, "FAST_WATCH_WORK", 0)
    monkeypatch.setattr(config, "FAST_PROGRESS_SECONDS", 1e-3)

    def stop_now(done: int, total: int) -> None:
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        optri.triangulate(convex_polygon(1500, 2), method="fast", progress=stop_now)
    done, stop = made[-1]
    nt = -(-1500 // 16)
    assert stop[0] == 1 and not done.reshape(nt, nt)[np.triu_indices(nt)].all()
    assert not any(t.name == "optri-fill" and t.is_alive() for t in threading.enumerate())
    # a stopped kernel call takes no tile at all
    n = 100
    T = np.full((n, n), np.nan)
    stop = np.ones(1, dtype=np.int64)
    pts = np.asfortranarray(convex_polygon(n, 1))
    _jit_kernels.minplus_tiles(T, pts, 0, None, 8, 2, fresh(n, 8)[0], stop)
    assert np.isnan(T).all()


def test_watched_raises_a_real_sigint_only_once_the_fill_has_returned(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # the calling thread waits when SIGINT comes: it sets the stop flag and raises only
    # once the helper has returned (on Python 3.11 a Thread.join that Ctrl-C interrupts
    # marks the thread as stopped, and a second join returns at once while it still runs)
    import os
    import signal
    import time

    monkeypatch.setattr(config, "FAST_PROGRESS_SECONDS", 1.0)  # the signal finds it waiting
    # Python's Ctrl-C handler even where the test run started with SIGINT ignored (a
    # background job of a shell without job control)
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    stop = np.zeros(1, dtype=np.int64)
    returned: list[bool] = []

    def fill() -> None:  # a kernel: runs until stopped, then finishes the tiles it took
        start = time.monotonic()
        while not stop[0] and time.monotonic() - start < 20:
            time.sleep(0.001)
        time.sleep(0.05)
        returned.append(True)

    timer = threading.Timer(0.05, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            interrupts.watched(fill, 1, stop, lambda: None)
    finally:
        timer.join()
        signal.signal(signal.SIGINT, old)
    assert returned == [True] and stop[0] == 1


def test_a_kernels_first_call_is_watched(monkeypatch: pytest.MonkeyPatch) -> None:
    # the first call of a numba kernel compiles it or loads it from the disk cache, partly
    # in llvmlite callbacks that swallow Ctrl-C: it runs in the helper, whatever its size;
    # so does the first call for another table dtype (a new specialization). The core's
    # generic kernel has nothing to compile: it never asks
    numba = pytest.importorskip("numba")
    @numba.njit(cache=False)
    def never_called(x):  # type: ignore[no-untyped-def]
        return x + 1

    assert not interrupts.is_loaded(never_called)
    never_called(1)
    assert interrupts.is_loaded(never_called)

    @numba.njit(cache=False)
    def first_cell(tables):  # type: ignore[no-untyped-def]
        return tables[0][0, 0]

    first_cell((np.zeros((2, 2)), np.zeros((1, 1))))  # a tuple of tables, as generic_tiles
    assert interrupts.is_loaded(first_cell, np.float64)
    assert not interrupts.is_loaded(first_cell, np.float32)
    first_cell((np.zeros((2, 2), np.float32), np.zeros((1, 1), np.float32)))
    assert interrupts.is_loaded(first_cell, np.float32)

    @numba.njit(cache=False)
    def masked_cell(table, mask):  # type: ignore[no-untyped-def]
        return table[0, 0] if mask is None or mask[0, 0] else 0.0

    masked_cell(np.ones((2, 2)), None)  # without a mask: the masked version is not loaded
    assert interrupts.is_loaded(masked_cell, np.float64, False)
    assert not interrupts.is_loaded(masked_cell, np.float64, True)
    masked_cell(np.ones((2, 2)), np.ones((2, 2), dtype=np.bool_))
    assert interrupts.is_loaded(masked_cell, np.float64, True)

    watched: list[object] = []
    asked: list[tuple[np.dtype, bool]] = []
    monkeypatch.setattr(jit, "watched", lambda fill, *rest: (watched.append(fill), fill()))
    pts = convex_polygon(8, 1)
    for loaded in (False, True):

        def is_loaded(kernel: object, dtype: object, masked: bool, loaded: bool = loaded) -> bool:
            asked.append((np.dtype(dtype), masked))  # type: ignore[call-overload]
            return loaded

        monkeypatch.setattr(jit, "is_loaded", is_loaded)
        optri.triangulate(pts, method="fast")  # min-plus
        optri.triangulate(pts, "max_angle", "max", method="fast")  # generic: never asks
    assert len(watched) == 1 and len(asked) == 2  # the min-plus first call, not the later one
    a = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    star = np.column_stack((np.cos(a), np.sin(a))) * np.where(np.arange(12) % 2, 0.5, 1.0)[:, None]
    optri.triangulate(pts, method="fast", dtype=np.float32)  # asks for its table's dtype
    assert asked[-1] == (np.float32, False)
    optri.triangulate(star, method="fast")  # and for a chord mask
    assert asked[-1] == (np.float64, True)
    assert asked[:2] == [(np.float64, False)] * 2


def test_fast_watched_generic_fill_stops_when_the_caller_raises(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # the generic kernel checks the stop flag between tile-diagonals
    from optri.engines import jit

    seen: list[np.ndarray] = []
    fresh = np.zeros

    def zeros(shape: object, dtype: object = float) -> np.ndarray:
        a = fresh(shape, dtype=dtype)  # type: ignore[call-overload]
        seen.append(a)
        return a

    class _Numpy:  # numpy, except that the driver's zeros are kept for a look afterwards
        def __getattr__(self, name: str) -> object:
            return zeros if name == "zeros" else getattr(np, name)

    monkeypatch.setattr(jit, "np", _Numpy())
    monkeypatch.setattr(config, "FAST_GENERIC_TILE", 4)
    monkeypatch.setattr(config, "FAST_WATCH_WORK", 0)
    monkeypatch.setattr(config, "FAST_PROGRESS_SECONDS", 1e-3)

    def stop_now(done: int, total: int) -> None:
        raise KeyboardInterrupt

    n = 700
    with pytest.raises(KeyboardInterrupt):
        optri.triangulate(
            convex_polygon(n, 2), "max_angle", "max", method="fast", progress=stop_now
        )
    stop, reached = seen[-2], seen[-1]
    assert stop[0] == 1 and 0 < reached[0] < -(-n // 4)
    assert not any(t.name == "optri-fill" and t.is_alive() for t in threading.enumerate())


def _perimeter(v, i, k, j):  # type: ignore[no-untyped-def]
    if v.shape[0] == 13:  # a NaN for one polygon size, to test detection
        return math.nan
    a = math.hypot(v[i, 0] - v[k, 0], v[i, 1] - v[k, 1])
    b = math.hypot(v[k, 0] - v[j, 0], v[k, 1] - v[j, 1])
    c = math.hypot(v[j, 0] - v[i, 0], v[j, 1] - v[i, 1])
    return a + b + c


def test_fast_custom_njit_weight_and_nan(monkeypatch: pytest.MonkeyPatch) -> None:
    numba = pytest.importorskip("numba")
    njit_perimeter = numba.njit(cache=False)(_perimeter)
    pts = convex_polygon(30, 9)[::-1]  # clockwise input: indices are the caller's
    w = optri.custom_weight(njit_perimeter)
    assert w.compiled is njit_perimeter  # recognized as numba-compiled: runs in the kernel
    a = optri.triangulate(pts, w, method="fast")
    b = optri.triangulate(pts, "perimeter", method="fast")
    assert close(a.weight, b.weight)
    a.check()
    with pytest.raises(WeightError, match="NaN"):
        optri.triangulate(convex_polygon(13, 1), w, method="fast")
    # the same in the watched helper thread (one test: the user's kernel compiles once)
    monkeypatch.setattr(config, "FAST_WATCH_WORK", 0)
    assert optri.triangulate(pts, w, method="fast").weight == a.weight
    with pytest.raises(WeightError, match="NaN"):
        optri.triangulate(convex_polygon(13, 1), w, method="fast")


def test_fast_plain_python_weight_falls_back(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(config, "FAST_AUTO_MIN_N", 0)
    pts = convex_polygon(8, 1)

    def py_weight(i: int, k: int, j: int) -> float:
        return float(i * k + j)

    with pytest.warns(RuntimeWarning, match="plain Python callable"):
        t = optri.triangulate(pts, py_weight)
    assert t.method == "table"  # the pure-Python engine auto falls back to
    with pytest.raises(EngineUnavailableError, match="numba.njit"):
        optri.triangulate(pts, py_weight, method="fast")


def test_fast_is_auto_default_above_threshold() -> None:
    pts = convex_polygon(config.FAST_AUTO_MIN_N, 1)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert optri.triangulate(pts).method == "fast"


def test_fast_generic_path_needs_no_numba(monkeypatch: pytest.MonkeyPatch) -> None:
    # built-in weights run in the compiled core: numba is imported for a user's
    # numba.njit weight only
    import sys

    want = optri.triangulate(convex_polygon(30, 4), "max_angle", "max", method="fast")
    monkeypatch.setitem(sys.modules, "numba", None)  # import numba fails
    assert jit.unavailable() is None
    got = optri.triangulate(convex_polygon(30, 4), "max_angle", "max", method="fast")
    assert got.weight == want.weight
    assert np.array_equal(got.triangles, want.triangles)


def test_fast_tile_queue_waits_for_its_neighbours(monkeypatch: pytest.MonkeyPatch) -> None:
    # tiny tiles, every tile-diagonal in one kernel call, two threads: each tile must
    # wait for the tiles left of it and below it (done flags), else it reads unfinished
    # cells; the table must equal the one-thread, one-call-per-diagonal table bit for bit
    monkeypatch.setattr(config, "FAST_TILE", 4)
    monkeypatch.setattr(config, "FAST_PARALLEL_MIN_N", 0)
    pts = convex_polygon(400, 11)
    monkeypatch.setenv(THREADS, "1")
    ref = optri.triangulate(pts, method="fast", keep_table=True)
    monkeypatch.setenv(THREADS, "2")
    for watch in (0, 1e18, 0):  # in a helper thread, in this one
        monkeypatch.setattr(config, "FAST_WATCH_WORK", watch)
        got = optri.triangulate(pts, method="fast", keep_table=True)
        assert got.stats["threads"] == 2
        assert np.array_equal(got.table, ref.table, equal_nan=True)
        assert got.weight == ref.weight


class _SignalingEmpty:
    """numpy, except that ``empty`` float32 arrays hold signaling NaNs (as garbage may)."""

    def __getattr__(self, name: str) -> object:
        return getattr(np, name)

    @staticmethod
    def empty(shape: object, dtype: object = float) -> np.ndarray:
        a = np.empty(shape, dtype=dtype)  # type: ignore[call-overload]
        if a.dtype == np.float32:
            a.view(np.uint32)[...] = 0x7FA00000
        return a


def test_float32_table_export_ignores_the_unwritten_diagonal(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # the fill never writes T[i, i]; whatever the memory held there (a signaling NaN
    # warns when cast to float64) must neither warn nor reach the exported table
    monkeypatch.setattr(jit, "np", _SignalingEmpty())
    pts = convex_polygon(40, 0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        t = optri.triangulate(pts, method="fast", dtype="float32", keep_table=True)
    assert np.all(np.isfinite(t.table))
    assert np.all(np.diag(t.table) == 0.0)
