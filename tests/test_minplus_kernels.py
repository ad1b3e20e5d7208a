"""The min-plus path's building blocks, against plain numpy and against each other.

* the register blocks (``optri.engines._llvm``): every entry equals the numpy
  minimum of the same sums, for float64 and float32, with 32- and 64-byte
  vectors and the minimum taken as integers and as floats (LLVM emulates what
  this CPU lacks), and ``register_plan`` picks them by CPU as documented;
* ``edge_weight_row``: the same bits as ``edge_weight`` at every point, in
  compiled code with the kernels' flags, including lengths outside the range
  of the plain formula;
* the whole fill: every tiling (tile 4 to 128: leaves, 8 x 8 and 16 x 16
  blocks, products, partial tiles) gives the same table bit for bit, since the
  minimum does not depend on the order the splits are taken in.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import optri
from cli_run import checkout_env
from optri import config
from optri.bench.compare import convex_polygon

numba = pytest.importorskip("numba")

from optri.engines import _llvm  # noqa: E402
from optri.engines._jit_weights import edge_weight, edge_weight_row  # noqa: E402
from optri.engines._minplus import FASTMATH  # noqa: E402
from optri.engines._minplus import tile_flags as _flags  # noqa: E402

SHAPES = [(4, 4), (4, 8), (4, 16), (8, 16)]


def _block_runner(rows: int, cols: int, fresh: bool = False):  # type: ignore[no-untyped-def]
    block = _llvm._outer(rows, cols, fresh=fresh)

    @numba.njit(fastmath=FASTMATH)
    def run(T, i, j, k0, kn):  # type: ignore[no-untyped-def]
        block(T, i, j, T, i, k0, T, k0, j, kn)

    return run


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


@pytest.mark.parametrize("fresh", [False, True])
@pytest.mark.parametrize("vector_bytes", [32, 64])
@pytest.mark.parametrize("as_int", [True, False])
@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("shape", SHAPES)
def test_register_block_equals_numpy(
    monkeypatch: pytest.MonkeyPatch,
    shape: tuple[int, int],
    dtype: type,
    as_int: bool,
    vector_bytes: int,
    fresh: bool,
) -> None:
    # fresh: the far products' first block of splits, which writes its cells unread
    monkeypatch.setattr(_llvm, "register_plan", lambda itemsize: (vector_bytes, as_int))
    rows, cols = shape
    run = _block_runner(rows, cols, fresh)
    rng = np.random.default_rng(rows * cols)
    for i, j, k0, kn in [(0, 40, 10, 30), (3, 33, 7, 1), (10, 50, 20, 0), (5, 44, 9, 25)]:
        T = _table(rng, 70, dtype)
        want = _block_want(T, i, j, T, i, k0, T, k0, j, kn, shape, fresh)
        run(T, i, j, k0, kn)
        assert np.array_equal(T, want), (i, j, k0, kn)


needs_avx512vl = pytest.mark.skipif(not _llvm._compact_runs(), reason="needs AVX-512VL")


@numba.njit(fastmath=FASTMATH)
def _compact(C, ci, cj, A, ai, ak, B, bk, bj, kn):  # type: ignore[no-untyped-def]
    _llvm.outer_4x16_compact(C, ci, cj, A, ai, ak, B, bk, bj, kn)


_compact_fresh_block = _llvm._outer(4, 16, compact=True, fresh=True)


@numba.njit(fastmath=FASTMATH)
def _compact_fresh(C, ci, cj, A, ai, ak, B, bk, bj, kn):  # type: ignore[no-untyped-def]
    _compact_fresh_block(C, ci, cj, A, ai, ak, B, bk, bj, kn)


@needs_avx512vl
@pytest.mark.parametrize("fresh", [False, True])
@pytest.mark.parametrize("packed", [False, True])
def test_compact_block_equals_numpy(packed: bool, fresh: bool) -> None:
    """The 4 x 16 block as inline assembly: the same cells as numpy's minimum of the sums.

    Random places in tables of random sizes, ``B`` read from the table itself (the near
    products, where the block's cells, its ``A`` rows and its ``B`` rows share one
    array) or from a packed 16-column buffer (the far products), 0 to 40 splits; only
    the block's 64 cells may change. ``fresh``: the cells start from +inf, not from
    the table (+inf with no splits).
    """
    block = _compact_fresh if fresh else _compact
    rng = np.random.default_rng(7 + packed)
    for _ in range(60):
        n = int(rng.integers(24, 200))
        T = _table(rng, n, np.float64)
        kn = int(rng.integers(0, min(40, n - 4)))
        ci, cj = int(rng.integers(0, n - 3)), int(rng.integers(0, n - 15))
        ai, ak = int(rng.integers(0, n - 3)), int(rng.integers(0, n - kn + 1))
        P = _table(rng, kn + 16, np.float64)[: kn + 3, :16].copy() if packed else T
        bk = int(rng.integers(0, len(P) - kn + 1))
        bj = 0 if packed else int(rng.integers(0, n - 15))
        if rng.random() < 0.15:
            kn = 0  # no splits: only a fresh block writes (+inf)
        want = _block_want(T, ci, cj, T, ai, ak, P, bk, bj, kn, (4, 16), fresh)
        block(T, ci, cj, T, ai, ak, P, bk, bj, kn)
        assert np.array_equal(T, want), (n, ci, cj, ai, ak, bk, bj, kn)


def test_compact_block_is_the_plan_only_with_avx512vl(monkeypatch: pytest.MonkeyPatch) -> None:
    """The plan's 4 x 16 float64 block is the assembly one only where the CPU runs it."""
    text = _llvm._compact_text()
    assert text.count("vaddpd") == 16 and text.count("vpminsq") == 16
    assert all(f"%ymm{x}" not in text.split("vpminsq")[0] for x in range(16, 32))  # sums low
    monkeypatch.setattr(_llvm.numba_config, "CPU_FEATURES", "+avx2,-avx512f", raising=False)
    monkeypatch.setattr(_llvm, "register_plan", lambda itemsize: (32, True))
    run = _block_runner(4, 16)  # compiled for a CPU without AVX-512VL: the vector code
    rng = np.random.default_rng(3)
    T = _table(rng, 60, np.float64)
    want = T.copy()
    sums = (T[2:6, 5:25, None] + T[None, 5:25, 30:46]).min(axis=1)
    want[2:6, 30:46] = np.minimum(want[2:6, 30:46], sums)
    run(T, 2, 30, 5, 20)
    assert np.array_equal(T, want)
    assert "#APP" not in run.inspect_asm(run.signatures[0])  # no inline assembly
    if "+avx512vl" in _llvm.llvm.get_host_cpu_features().flatten():
        compact = _compact.inspect_asm(_compact.signatures[0]) if _compact.signatures else ""
        assert not compact or "#APP" in compact


@pytest.mark.parametrize(
    ("name", "features", "plan8", "plan4"),
    [
        ("znver4", "+avx2,+avx512f,+avx512vl", (32, True), (32, True)),  # AMD: 256-bit halves
        ("znver3", "+avx2,-avx512f,-avx512vl", (32, False), (32, True)),
        ("sapphirerapids", "+avx2,+avx512f,+avx512vl", (64, True), (64, True)),
        ("rocketlake", "+avx2,+avx512f,+avx512vl", (64, True), (64, True)),
        ("knl", "+avx2,+avx512f,-avx512vl", (64, False), (64, False)),
        ("haswell", "+avx2,-avx512f", (32, False), (32, True)),
        ("x86-64", "+sse2", (32, False), (32, False)),
    ],
)
def test_register_plan_follows_the_cpu(
    monkeypatch: pytest.MonkeyPatch,
    name: str,
    features: str,
    plan8: tuple[int, bool],
    plan4: tuple[int, bool],
) -> None:
    monkeypatch.setattr(_llvm.numba_config, "CPU_NAME", name, raising=False)
    monkeypatch.setattr(_llvm.numba_config, "CPU_FEATURES", features, raising=False)
    assert _llvm.register_plan(8) == plan8 and _llvm.register_plan(4) == plan4
    rows = 8 if plan8[0] == 64 else 4
    assert _llvm.block_rows() == rows
    assert _llvm.describe_plan().startswith(f"{rows} x 16 cells in {plan8[0]}-byte vectors")


@numba.njit(fastmath=FASTMATH)
def _edge_rows(code, p, a, b0, out):  # type: ignore[no-untyped-def]
    edge_weight_row(code, p, a, b0, out)


@numba.njit(fastmath=FASTMATH)
def _edges_one_by_one(code, p, a, b0, out):  # type: ignore[no-untyped-def]
    for q in range(len(out)):
        out[q] = edge_weight(code, p, a, b0 + q)


@settings(max_examples=40, deadline=None)
@given(
    dims=st.sampled_from([1, 2, 3]),
    scale=st.sampled_from([1e-300, 1e-160, 1e-5, 1.0, 7e3, 1e150, 1e300]),
    code=st.sampled_from([0, 1]),  # perimeter, diagonal
    order=st.sampled_from("CF"),  # the fill passes coordinates column by column
    seed=st.integers(0, 2**32 - 1),
)
def test_edge_weight_row_is_edge_weight_bit_for_bit(
    dims: int, scale: float, code: int, order: str, seed: int
) -> None:
    rng = np.random.default_rng(seed)
    n = 37
    p = rng.normal(size=(n, dims)) * scale
    p[5] = p[6]  # a zero length
    p[9, 0] = np.nextafter(p[8, 0], np.inf)  # a tiny one
    p = np.asarray(p, order=order)
    for a in (0, 5, 9, 20):
        got, want = np.empty(n - 1), np.empty(n - 1)
        _edge_rows(code, p, a, 1, got)
        _edges_one_by_one(code, p, a, 1, want)
        assert got.tobytes() == want.tobytes(), (a, dims, scale, code)


def _star(n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    a = np.sort(rng.uniform(0, 2 * np.pi, n))
    r = rng.uniform(0.5, 1.0, n)
    return np.column_stack((r * np.cos(a), r * np.sin(a)))


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


@pytest.mark.parametrize("fresh", [False, True])
@pytest.mark.parametrize("rows", [4, 8])
@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_far_product_equals_numpy(rows: int, dtype: type, fresh: bool) -> None:
    # the far product packs B from the table's rows above the diagonal: rows and columns
    # past whole blocks and strips, and more than one block of splits (> _KBLOCK);
    # fresh (a tile's first far product), the cells' old values take no part
    from optri.engines import _minplus

    rng = np.random.default_rng(rows)
    T = _table(rng, 420, dtype)
    T[np.tril_indices(420)] = np.nan  # never read: the fill leaves the lower half unwritten
    ia, ib, ja, jb = 5, 30, 380, 417
    k0, k1 = ib, ja
    assert k1 - k0 > _minplus._KBLOCK and (ib - ia) % rows and (jb - ja) % 16
    if fresh:  # old values far below any sum: a cell that kept one shows it
        T[ia:ib, ja:jb] = np.where(rng.random((ib - ia, jb - ja)) < 0.5, 0.0, -1.0)
    want = T.copy()
    a, b = T[ia:ib, k0:k1], T[k0:k1, ja:jb]
    sums = (a[:, :, None] + b[None, :, :]).min(axis=1)
    want[ia:ib, ja:jb] = sums if fresh else np.minimum(want[ia:ib, ja:jb], sums)
    P = np.full((_minplus._STRIP * 128 // 16, 16), np.nan, dtype=dtype)
    _minplus._far(T, P, rows, ia, ib, ja, jb, k0, k1, fresh)
    assert np.array_equal(T, want, equal_nan=True)


@pytest.mark.parametrize("with_mask", [False, True])
@pytest.mark.parametrize("rows", [4, 8])
def test_dense_product_equals_numpy(rows: int, with_mask: bool) -> None:
    # the near part's products, in 8 x 16 blocks (64-byte vectors) or 4 x 16 ones, on any
    # CPU: rows and columns past whole blocks, and a chord mask that skips blocks
    from optri.engines import _minplus

    rng = np.random.default_rng(rows + 10 * with_mask)
    T = _table(rng, 120, np.float64)
    T = np.minimum(T, T.T)  # both halves hold a chord's value: cells at the edges read B's
    ia, ib, ja, jb, k0, k1 = 3, 30, 60, 97, 30, 60
    assert (ib - ia) % rows and (jb - ja) % 16
    mask = rng.random((120, 120)) < 0.05 if with_mask else None
    if with_mask:  # a block whose only allowed chord lies in its lower four rows
        mask[ia : ia + 8, ja : ja + 16] = False
        mask[ia + 6, ja + 2] = True
        T[ia + 6, ja + 2] = 1e6
    want = T.copy()
    sums = (T[ia:ib, k0:k1, None] + T[None, k0:k1, ja:jb]).min(axis=1)
    block = np.minimum(want[ia:ib, ja:jb], sums)
    _minplus._product(T, mask, rows, ia, ib, ja, jb, k0, k1)
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


@pytest.mark.parametrize(
    "n, tile, use_mask",
    [(203, 64, False), (203, 50, True), (100, 12, False), (131, 16, False), (45, 8, True)],
)
def test_fill_writes_only_the_upper_half(n: int, tile: int, use_mask: bool) -> None:
    # the fill reads and writes only above the diagonal (a NaN read below would spread)
    from optri.engines import _jit_kernels
    from optri.weights import WeightCode

    pts = np.asfortranarray(_star(n, n) if use_mask else convex_polygon(n, tile))
    rng = np.random.default_rng(n)
    mask = None
    if use_mask:
        mask = rng.random((n, n)) < 0.7
        mask |= mask.T
    T = np.full((n, n), np.nan)
    code = int(WeightCode.PERIMETER)
    _jit_kernels.minplus_tiles(T, pts, code, mask, tile, 2, *_flags(n, tile))
    upper = np.triu_indices(n, 1)
    assert not np.isnan(T[upper]).any()
    assert np.isnan(T[np.tril_indices(n)]).all()
    # and the same upper half as with 4 x 4 tiles, all leaves
    T4 = np.full((n, n), np.nan)
    _jit_kernels.minplus_tiles(T4, pts, code, mask, 4, 1, *_flags(n, 4))
    assert np.array_equal(T[upper], T4[upper])


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("name", ["transpose_8x8", "copy_8"])
def test_copy_intrinsics_equal_numpy(name: str, dtype: type) -> None:
    # transpose_8x8, mirror_table's blocks: 8 row loads, 24 shuffles, 8 row stores;
    # copy_8, the far product's copy of B: 64 bytes of a table row at a time
    copy = getattr(_llvm, name)

    @numba.njit
    def run(S, si, sj, D, di, dj):  # type: ignore[no-untyped-def]
        copy(S, si, sj, D, di, dj)

    rng = np.random.default_rng(8)
    S = rng.uniform(0, 1, (20, 21)).astype(dtype)
    for si, sj, di, dj in [(0, 0, 0, 0), (3, 5, 7, 2), (12, 13, 22, 9)]:
        D = np.full((30, 17), -1.0, dtype=dtype)
        want = D.copy()
        if name == "copy_8":
            want[di, dj : dj + 8] = S[si, sj : sj + 8]
        else:
            want[di : di + 8, dj : dj + 8] = S[si : si + 8, sj : sj + 8].T
        run(S, si, sj, D, di, dj)
        assert np.array_equal(D, want), (si, sj, di, dj)


@pytest.mark.parametrize("n", [2, 9, 64, 131])
def test_mirror_table_fills_both_halves(n: int) -> None:
    # an exported table's splits read the lower half: every cell below the diagonal,
    # the sides (j = i + 1) included, becomes its mirror; the diagonal is left alone
    from optri.engines import _jit_kernels

    T = _table(np.random.default_rng(n), n, np.float64)
    T[np.tril_indices(n)] = np.nan
    upper = T[np.triu_indices(n, 1)].copy()
    _jit_kernels.mirror_table(T)
    assert np.array_equal(T[np.triu_indices(n, 1)], upper)
    assert np.array_equal(T.T[np.triu_indices(n, 1)], upper)
    assert np.isnan(np.diag(T)).all()


@pytest.mark.parametrize("n", [5, 40, 97])
def test_trace_reads_the_upper_half_splits(n: int) -> None:
    # the trace's split of chord (i, j) from row i and column j, with nothing written
    # below the diagonal, equals the first minimizer by numpy and the mirrored table's
    from optri.engines import _jit_kernels

    T = _table(np.random.default_rng(n), n, np.float64)
    T[np.tril_indices(n)] = np.nan
    M = T.copy()
    _jit_kernels.mirror_table(M)
    for i in range(n - 2):
        for j in range(i + 2, n):
            sums = T[i, i + 1 : j] + T[i + 1 : j, j]
            want = -1 if np.isinf(sums.min()) else i + 1 + int(np.argmin(sums))
            assert _jit_kernels.minplus_split(T, i, j, False) == want, (i, j)
            assert _jit_kernels.minplus_split(M, i, j, True) == want, (i, j)


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_tile_edges_claims_the_tile_lines_and_changes_nothing(dtype: type) -> None:
    """With the table, ``tile_edges`` asks for the tile's lines to be written, nothing more.

    The claims are prefetches for writing (``claim_at``): the same edge weights,
    the table untouched, and on an x86-64 CPU with ``prfchw`` the compiled
    kernel holds ``prefetchw`` instructions, which it lacks without the table.
    """
    from optri.engines._minplus import tile_edges

    pts = np.asfortranarray(convex_polygon(70, 2))
    T = np.random.default_rng(3).uniform(0, 1, (70, 70)).astype(dtype)
    before = T.copy()
    for i0, i1, j0, j1, above in [(0, 16, 0, 16, 0), (16, 32, 48, 70, 16), (32, 48, 50, 70, 0)]:
        plain, claimed = np.full((16, 22), -1.0), np.full((16, 22), -1.0)
        tile_edges(plain, pts, 0, i0, i1, j0, j1)
        tile_edges(claimed, pts, 0, i0, i1, j0, j1, T, above)
        assert plain.tobytes() == claimed.tobytes()
    assert T.tobytes() == before.tobytes()
    import llvmlite.binding as ll

    if ll.get_process_triple().startswith("x86_64") and ll.get_host_cpu_features().get("prfchw"):
        fresh = numba.njit(fastmath=FASTMATH)(tile_edges.py_func)  # the cached one hides its code
        fresh(plain, pts, 0, 0, 16, 0, 16)
        fresh(plain, pts, 0, 0, 16, 0, 16, T, 0)
        asm = {
            isinstance(sig[7], numba.types.Array): fresh.inspect_asm(sig)
            for sig in fresh.signatures
        }
        assert "prefetchw" in asm[True] and "prefetchw" not in asm[False]


_FRESH_TILE = """
import sys
import numpy as np
from optri.engines import _minplus as M

n, tile = 70, 16
nt = (n + tile - 1) // tile
T = np.zeros((n, n))
W, P = np.empty((tile, tile)), np.empty((M._STRIP, 16))
done = np.ones(nt * nt, dtype=np.int64)
pts = np.asfortranarray(np.random.default_rng(1).uniform(0, 1, (n, 2)))
M._tile(T, pts, 0, W, P, None, tile, 0, 1, done, nt)
print(M._tile.inspect_asm(M._tile.signatures[0]).count("prefetchw"))
"""


def test_the_fill_claims_its_tile_lines(tmp_path) -> None:
    """A tile's compiled code holds the claims of ``tile_edges``: the fill really makes them.

    The cached kernels hide their code, so a fresh process compiles ``_tile``
    (and what it calls) into an empty cache directory, about 11 s here. Without
    the table passed on to ``tile_edges``, the code holds no ``prefetchw``.
    """
    import llvmlite.binding as ll

    if not (
        ll.get_process_triple().startswith("x86_64") and ll.get_host_cpu_features().get("prfchw")
    ):
        pytest.skip("prefetch for writing is an x86-64 instruction (prfchw)")
    env = checkout_env(NUMBA_CACHE_DIR=str(tmp_path / "cache"))  # fresh: numba must compile
    got = subprocess.run(
        [sys.executable, "-c", _FRESH_TILE], capture_output=True, text=True, env=env, timeout=600
    )
    assert got.returncode == 0, got.stderr
    assert int(got.stdout) > 0
