"""The compiled core's min-plus fill, piece by piece, against plain numpy and each other.

* the micro-kernels (``optri._core.minplus._block``) of every SIMD level this CPU
  has: every entry equals the numpy minimum of the same sums, float64 and float32,
  ``B`` from the table or from a packed buffer, "fresh" blocks from +inf;
* the plan each level picks, as documented (``optri._core.minplus.plan``);
* the framework's products (``_product``, ``_far``), the fill's upper half, the
  mirror and the split, against numpy;
* the whole fill: every tiling (tile 4 to 256) and every SIMD level gives the same
  table bit for bit, since the minimum does not depend on the order the splits
  are taken in; every cell equals the Python engine's table; the edge weights
  are ``optri.weights.edge_weight``'s bits;
* ``OPTRI_SIMD``: a level the CPU has is used, one it lacks is a clear error.
"""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import optri
from cli_run import checkout_env
from optri import config
from optri.bench.compare import convex_polygon
from optri.engines import core
from optri.engines.core import minplus as M
from optri.weights import edge_weight, edge_weight_row

LEVELS = core.simd_levels()
KINDS = {"main": None, "main_fresh": None, "4x16": (4, 16), "4x16_fresh": (4, 16),
         "4x8": (4, 8), "4x4": (4, 4)}  # fmt: skip


@contextmanager
def simd(level: str) -> Iterator[None]:
    """Run the kernels at ``level`` inside the block."""
    before = core.simd_level()
    core.set_simd(level)
    try:
        yield
    finally:
        core.set_simd(before)


def _table(rng: np.random.Generator, n: int, dtype: type) -> np.ndarray:
    """Non-negative values, with zeros and +inf (unusable chords) among them."""
    T = rng.uniform(0.0, 100.0, (n, n))
    T[rng.random((n, n)) < 0.1] = 0.0
    T[rng.random((n, n)) < 0.1] = np.inf
    return T.astype(dtype)


def _block_want(T, ci, cj, A, ai, ak, B, bk, bj, kn, shape, fresh):  # type: ignore[no-untyped-def]
    """What a register block leaves in ``T``: numpy's minimum of the same sums.

    ``fresh``: the block's cells start from +inf, so whatever they held is gone
    (+inf where there are no splits).
    """
    rows, cols = shape
    want = T.copy()
    block = want[ci : ci + rows, cj : cj + cols]
    start = np.full_like(block, np.inf) if fresh else block
    if kn:
        sums = A[ai : ai + rows, ak : ak + kn, None] + B[None, bk : bk + kn, bj : bj + cols]
        start = np.minimum(start, sums.min(axis=1))
    want[ci : ci + rows, cj : cj + cols] = start
    return want


@pytest.mark.parametrize("packed", [False, True])
@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("kind", list(KINDS))
@pytest.mark.parametrize("level", LEVELS)
def test_micro_kernel_equals_numpy(level: str, kind: str, dtype: type, packed: bool) -> None:
    """Random places in tables of random sizes; only the block's cells may change.

    ``B`` is read from the table itself (the near products, where the block's cells,
    its ``A`` rows and its ``B`` rows share one array) or from a packed buffer (the
    far products); 0 to 40 splits.
    """
    with simd(level):
        shape = KINDS[kind] or (M.plan()["rows"], 16)
        rows, cols = shape
        rng = np.random.default_rng(len(kind) + 10 * packed + 100 * rows)
        for _ in range(25):
            n = int(rng.integers(24, 120))
            T = _table(rng, n, dtype)
            kn = int(rng.integers(0, min(40, n - rows)))
            if rng.random() < 0.15:
                kn = 0  # no splits: only a fresh block writes (+inf)
            ci, cj = int(rng.integers(0, n - rows + 1)), int(rng.integers(0, n - cols + 1))
            ai, ak = int(rng.integers(0, n - rows + 1)), int(rng.integers(0, n - kn + 1))
            P = _table(rng, kn + cols + 3, dtype)[: kn + 3, :cols].copy() if packed else T
            bk = int(rng.integers(0, len(P) - kn + 1))
            bj = 0 if packed else int(rng.integers(0, n - cols + 1))
            want = _block_want(T, ci, cj, T, ai, ak, P, bk, bj, kn, shape, kind.endswith("fresh"))
            M._block(kind, T, ci, cj, T, ai, ak, P, bk, bj, kn)
            assert np.array_equal(T, want), (n, ci, cj, ai, ak, bk, bj, kn)


def test_micro_kernel_refuses_a_block_out_of_bounds() -> None:
    T = np.zeros((20, 20))
    with pytest.raises(ValueError, match="out of bounds"):
        M._block("4x16", T, 0, 10, T, 0, 0, T, 0, 10, 3)
    with pytest.raises(ValueError, match="unknown block"):
        M._block("3x3", T, 0, 0, T, 0, 0, T, 0, 0, 3)


def test_each_level_has_its_plan() -> None:
    # the block shape, vector bytes and minima each level's micro-kernels use
    want = {
        "portable": ("portable", 4, 0, "float", "float"),
        "baseline": ("sse2", 4, 16, "float", "float"),
        "avx2": ("avx2", 4, 32, "float", "integer"),
    }
    for level in LEVELS:
        with simd(level):
            plan = M.plan()
        assert plan["level"] == level and plan["cols"] == 16 and plan["kblock"] == 256
        got = (plan["isa"], plan["rows"], plan["vector_width"])
        got += (plan["min_float64"], plan["min_float32"])
        if level == "avx512":  # 8 x 16 in zmm, or 4 x 16 in ymm where 512 bits run as halves
            assert got in {("avx512-zmm", 8, 64, "integer", "integer"),
                           ("avx512-ymm", 4, 32, "integer", "integer")}  # fmt: skip
        elif level == "baseline" and "avx2" not in LEVELS and plan["isa"] == "portable":
            assert got == want["portable"][:1] + got[1:]  # ARM64: the portable kernels
        else:
            assert got == want[level], level


@pytest.mark.parametrize("level", LEVELS)
@pytest.mark.parametrize("fresh", [False, True])
@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_far_product_equals_numpy(level: str, dtype: type, fresh: bool) -> None:
    # the far product packs B from the table's rows above the diagonal: rows and columns
    # past whole blocks and strips, and more than one block of splits (> 256);
    # fresh (a tile's first far product), the cells' old values take no part
    rng = np.random.default_rng(3 + fresh)
    T = _table(rng, 420, dtype)
    T[np.tril_indices(420)] = np.nan  # never read: the fill leaves the lower half unwritten
    ia, ib, ja, jb = 5, 30, 380, 417
    k0, k1 = ib, ja
    assert k1 - k0 > 256 and (ib - ia) % 8 and (jb - ja) % 16
    if fresh:  # old values far below any sum: a cell that kept one shows it
        T[ia:ib, ja:jb] = np.where(rng.random((ib - ia, jb - ja)) < 0.5, 0.0, -1.0)
    want = T.copy()
    a, b = T[ia:ib, k0:k1], T[k0:k1, ja:jb]
    sums = (a[:, :, None] + b[None, :, :]).min(axis=1)
    want[ia:ib, ja:jb] = sums if fresh else np.minimum(want[ia:ib, ja:jb], sums)
    with simd(level):
        M._far(T, ia, ib, ja, jb, k0, k1, fresh)
    assert np.array_equal(T, want, equal_nan=True)


@pytest.mark.parametrize("level", LEVELS)
@pytest.mark.parametrize("with_mask", [False, True])
def test_dense_product_equals_numpy(level: str, with_mask: bool) -> None:
    # the near part's products: rows and columns past whole blocks, and a chord mask
    # that skips blocks
    rng = np.random.default_rng(10 * with_mask)
    T = _table(rng, 120, np.float64)
    T = np.minimum(T, T.T)
    ia, ib, ja, jb, k0, k1 = 3, 30, 60, 97, 30, 60
    assert (ib - ia) % 8 and (jb - ja) % 16
    mask = rng.random((120, 120)) < 0.05 if with_mask else None
    if mask is not None:  # a block whose only allowed chord lies in its lower four rows
        mask[ia : ia + 8, ja : ja + 16] = False
        mask[ia + 6, ja + 2] = True
        T[ia + 6, ja + 2] = 1e6
    want = T.copy()
    sums = (T[ia:ib, k0:k1, None] + T[None, k0:k1, ja:jb]).min(axis=1)
    block = np.minimum(want[ia:ib, ja:jb], sums)
    with simd(level):
        M._product(T, mask, ia, ib, ja, jb, k0, k1)
    got = T[ia:ib, ja:jb]
    if mask is not None:  # blocks with no allowed cell are skipped: only allowed cells count
        allowed = mask[ia:ib, ja:jb]
        assert allowed.any() and not allowed.all()
        assert np.array_equal(got[allowed], block[allowed])
    else:
        assert np.array_equal(got, block)
    outside = np.ones(T.shape, dtype=bool)
    outside[ia:ib, ja:jb] = False
    assert np.array_equal(T[outside], want[outside])


def _star(n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    a = np.sort(rng.uniform(0, 2 * np.pi, n))
    r = rng.uniform(0.5, 1.0, n)
    return np.column_stack((r * np.cos(a), r * np.sin(a)))


def _mask(rng: np.random.Generator, n: int) -> np.ndarray:
    """Random allowed chords, the polygon's sides among them."""
    mask = rng.random((n, n)) < 0.7
    idx = np.arange(n - 1)
    mask[idx, idx + 1] = True
    mask[0, n - 1] = True
    return mask


def _fill(pts, code, mask, tile, threads, dtype=np.float64):  # type: ignore[no-untyped-def]
    n = len(pts)
    T = np.full((n, n), np.nan, dtype=dtype)
    done, stop = M.tile_flags(n, tile)
    M.fill(T, np.ascontiguousarray(pts, dtype=np.float64), code, mask, tile, threads, done, stop)
    nt = -(-n // tile)
    assert done.reshape(nt, nt)[np.triu_indices(nt)].all()  # every tile reported done
    return T


def _oracle(pts: np.ndarray, code: int, mask, dtype) -> np.ndarray:  # type: ignore[no-untyped-def]
    """The recurrence cell by cell, e from optri.weights.edge_weight (the Python engine's)."""
    n = len(pts)
    E = np.full((n, n), np.nan, dtype=dtype)
    p = pts.tolist()
    for d in range(1, n):
        for i in range(n - d):
            j = i + d
            e = edge_weight(code, p, i, j)
            if d == 1:
                E[i, j] = e
                continue
            best = (E[i, i + 1 : j] + E[i + 1 : j, j]).min()
            E[i, j] = np.inf if mask is not None and not mask[i, j] else float(best) + 2.0 * e
    return E


@pytest.mark.parametrize(
    "n, tile, code, use_mask, dtype",
    [(131, 128, 0, False, np.float64), (203, 50, 1, True, np.float64), (45, 8, 0, True, np.float32),
     (100, 12, 1, False, np.float32), (70, 64, 0, False, np.float64)],
)  # fmt: skip
def test_fill_equals_the_recurrence_and_writes_only_the_upper_half(
    n: int, tile: int, code: int, use_mask: bool, dtype: type
) -> None:
    # every cell above the diagonal is the recurrence's, bit for bit; nothing on or below
    # the diagonal is read or written (a NaN read there would spread)
    rng = np.random.default_rng(n)
    pts = _star(n, n) if use_mask else convex_polygon(n, tile)
    mask = _mask(rng, n) if use_mask else None
    T = _fill(pts, code, mask, tile, 2, dtype)
    upper = np.triu_indices(n, 1)
    assert np.array_equal(T[upper], _oracle(pts, code, mask, dtype)[upper])
    assert np.isnan(T[np.tril_indices(n)]).all()


def test_every_level_gives_the_same_tables() -> None:
    # each SIMD level this CPU has: the same tables bit for bit, n = 5..600 (sizes around
    # tile boundaries), with and without chord masks, float64 and float32, 1 and 2 threads
    rng = np.random.default_rng(51)
    cases = []
    for n in (5, 6, 17, 63, 64, 65, 127, 129, 200, 255, 257, 600):
        tile = 64 if n < 300 else 128
        for dtype in (np.float64, np.float32):
            masked = bool(rng.integers(0, 2))
            cases.append((n, tile, dtype, _mask(rng, n) if masked else None,
                          rng.random((n, 2)), int(rng.integers(0, 2))))  # fmt: skip
    for n, tile, dtype, mask, pts, code in cases:
        first = None
        for level in LEVELS:
            for threads in (1, 2):
                with simd(level):
                    T = _fill(pts, code, mask, tile, threads, dtype)
                if first is None:
                    first = T
                assert np.array_equal(T, first, equal_nan=True), (n, level, threads)


@pytest.mark.parametrize(
    "pts, weight, dtype",
    [
        (convex_polygon(301, 3), "perimeter", "float64"),
        (convex_polygon(150, 4), "diagonal", "float32"),
        (_star(203, 5), "perimeter", "float64"),  # a simple polygon: chord mask
    ],
    ids=["convex-301", "convex-150-float32", "star-203"],
)
def test_every_tiling_gives_the_same_table(
    monkeypatch: pytest.MonkeyPatch, pts: np.ndarray, weight: str, dtype: str
) -> None:
    results = []
    for tile in (256, 128, 64, 50, 48, 16, 8, 4):  # 50: rows and columns past whole blocks
        monkeypatch.setattr(config, "FAST_TILE", tile)
        t = optri.triangulate(pts, weight, method="fast", dtype=dtype, keep_table=True)
        results.append((tile, t))
    _, first = results[0]
    for tile, t in results[1:]:
        assert t.weight == first.weight, tile
        assert np.array_equal(t.triangles, first.triangles), tile
        assert np.array_equal(t.table, first.table), tile
    first.check(rtol=1e-5 if dtype == "float32" else 1e-9)


@pytest.mark.parametrize("n, tile", [(131, 128), (260, 128), (203, 50), (45, 8), (41, 4)])
def test_every_cell_equals_the_python_table(
    monkeypatch: pytest.MonkeyPatch, n: int, tile: int
) -> None:
    # the paper's table holds the cost of every chord, not only of the optimal ones: a
    # split forgotten anywhere (a leaf, a 16 x 16 block, a product) shows up here; tile
    # (0, 1) of n = 260 packs the B of its largest near products (64 x 64 cells) as the
    # far products do
    monkeypatch.setattr(config, "FAST_TILE", tile)
    pts = convex_polygon(n, tile)
    for weight in ("perimeter", "diagonal"):
        a = optri.triangulate(pts, weight, method="fast", keep_table=True)
        b = optri.triangulate(pts, weight, method="table", keep_table=True)
        upper = np.triu_indices(n, 1)
        assert np.allclose(a.table[upper], b.table[upper], rtol=1e-12, atol=0), weight
        assert abs(a.weight - b.weight) <= 1e-9 * abs(b.weight)


@settings(max_examples=30, deadline=None)
@given(
    dims=st.sampled_from([1, 2, 3]),
    scale=st.sampled_from([1e-300, 1e-160, 1e-5, 1.0, 7e3, 1e150, 1e300]),
    code=st.sampled_from([0, 1]),  # perimeter, diagonal
    seed=st.integers(0, 2**32 - 1),
)
def test_the_core_edge_weights_are_the_python_ones(
    dims: int, scale: float, code: int, seed: int
) -> None:
    # subtract_edges takes e(i, j) off every cell: from zeros, -e, bit for bit the Python
    # formula's (no fused multiply-add), lengths outside the plain formula's range included
    rng = np.random.default_rng(seed)
    n = 23
    p = rng.normal(size=(n, dims)) * scale
    p[5] = p[6]  # a zero length
    p[9, 0] = np.nextafter(p[8, 0], np.inf)  # a tiny one
    out = np.zeros((n, n))
    M.subtract_edges(out, p, code)
    rows = p.tolist()
    want = np.zeros((n, n))
    for i in range(n - 1):
        for j in range(i + 1, n):
            want[i, j] = 0.0 - edge_weight(code, rows, i, j)
    assert out.tobytes() == want.tobytes()
    for a in (0, 5, 8, 20):  # the Python engine's rows: the same bits
        row = np.empty(n - a - 1)
        edge_weight_row(code, p, a, a + 1, row)
        assert (0.0 - row).tobytes() == out[a, a + 1 :].tobytes(), a
    # and the fill's edge rows: a two-vertex table holds the side e(0, 1)
    for a, b in ((0, 1), (5, 6), (8, 9), (3, 17)):
        T = _fill(p[[a, b]], code, None, 64, 1)
        assert T[0, 1] == edge_weight(code, [rows[a], rows[b]], 0, 1)


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("n", [2, 9, 64, 131])
def test_mirror_table_fills_both_halves(n: int, dtype: type) -> None:
    # an exported table's splits read the lower half: every cell below the diagonal,
    # the sides (j = i + 1) included, becomes its mirror; the diagonal is left alone
    T = _table(np.random.default_rng(n), n, dtype)
    T[np.tril_indices(n)] = np.nan
    upper = T[np.triu_indices(n, 1)].copy()
    M.mirror_table(T)
    assert np.array_equal(T[np.triu_indices(n, 1)], upper)
    assert np.array_equal(T.T[np.triu_indices(n, 1)], upper)
    assert np.isnan(np.diag(T)).all()


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("n", [5, 40, 97])
def test_split_reads_the_upper_half_or_the_mirror(n: int, dtype: type) -> None:
    # the split of chord (i, j) from row i and column j, with nothing written below the
    # diagonal, equals the first minimizer by numpy and the mirrored table's
    T = _table(np.random.default_rng(n), n, dtype)
    T[np.tril_indices(n)] = np.nan
    T[1, 3] = T[2, 3] = T[1, 2] = 0.0  # a tie: the first split wins
    Tm = T.copy()
    M.mirror_table(Tm)
    for i in range(n - 2):
        for j in range(i + 2, n):
            sums = T[i, i + 1 : j] + T[i + 1 : j, j]
            want = -1 if np.isinf(sums.min()) else i + 1 + int(np.argmin(sums))
            assert M.split(T, i, j, False) == want, (i, j)
            assert M.split(Tm, i, j, True) == want, (i, j)


def test_bad_arguments_are_clear_errors() -> None:
    T = np.zeros((10, 10))
    done, stop = M.tile_flags(10, 4)
    pts = np.zeros((10, 2))
    with pytest.raises(ValueError, match="one row per vertex"):
        M.fill(T, np.zeros((9, 2)), 0, None, 4, 1, done, stop)
    with pytest.raises(ValueError, match="code"):
        M.fill(T, pts, 2, None, 4, 1, done, stop)
    with pytest.raises(ValueError, match="too few flags"):
        M.fill(T, pts, 0, None, 2, 1, done, stop)
    with pytest.raises(ValueError, match="n x n"):
        M.fill(T, pts, 0, np.ones((9, 9), dtype=bool), 4, 1, done, stop)
    with pytest.raises(ValueError, match="square"):
        M.mirror_table(np.zeros((3, 4)))
    with pytest.raises(ValueError, match="i < j"):
        M.split(T, 4, 4, False)
    with pytest.raises(TypeError):  # the table is written in place: never a converted copy
        M.fill(np.zeros((10, 10), dtype=np.int64), pts, 0, None, 4, 1, done, stop)


def test_worker_bytes_and_flags() -> None:
    # a tile of float64 edge weights and the packed rows (257 x 16 values a strip)
    assert M.worker_bytes(64, 8) == 64 * 64 * 8 + 257 * 4 * 16 * 8
    assert M.worker_bytes(256, 4) == 256 * 256 * 8 + 257 * 16 * 16 * 4
    done, stop = M.tile_flags(130, 64)
    assert done.shape == (9,) and stop.shape == (1,)
    assert done.dtype == stop.dtype == np.int64 and not done.any() and not stop.any()
    assert [M.default_tile(n) for n in (500, 1000, 4000)] == [64, 128, 256]


_LEVEL = "from optri.engines import core; print(core.simd_level())"


def test_optri_simd_picks_the_level_or_names_those_there_are() -> None:
    for level in LEVELS:
        got = subprocess.run([sys.executable, "-c", _LEVEL], capture_output=True, text=True,
                             env=checkout_env(OPTRI_SIMD=level.upper()), timeout=120)  # fmt: skip
        assert got.returncode == 0 and got.stdout.strip() == level, got.stderr
    missing = [x for x in core.LEVELS if x not in LEVELS] + ["sse9"]
    for level in missing:
        got = subprocess.run([sys.executable, "-c", _LEVEL], capture_output=True, text=True,
                             env=checkout_env(OPTRI_SIMD=level), timeout=120)  # fmt: skip
        assert got.returncode != 0
        assert "SimdUnavailableError" in got.stderr and "OPTRI_SIMD" in got.stderr
        assert ", ".join(LEVELS) in got.stderr
    with pytest.raises(core.SimdUnavailableError, match="one of portable"):
        core.set_simd("sse9")
