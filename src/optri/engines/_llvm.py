"""LLVM building blocks of the compiled kernels, as numba intrinsics.

* ``fmin``: ``llvm.minnum`` (no NaN); unlike ``a if a < b else b`` LLVM
  vectorizes its reductions.
* ``outer_4x16`` / ``outer_4x8`` / ``outer_8x16``: the min-plus register
  block ``C = min(C, A (+) B)`` on 4 (8) rows of a table, written as explicit
  vector code so that its accumulators stay in registers (the shape of the
  peak microbenchmark's kernels, ``optri/bench/yardsticks/minplus_peak.c``);
  ``register_plan`` picks its vector width and minimum for this CPU. Where the
  plan is 32-byte vectors with the integer minimum on float64 (AMD Zen 4), the
  4 x 16 block's loop is inline assembly with fixed registers instead
  (``outer_4x16_compact``): the same operations, with the sums in the
  registers that take 4-byte VEX additions.
* ``copy_8``: eight values of a table row in one vector load and store, with
  which the far product copies its ``B`` operand into a contiguous buffer.
* ``transpose_8x8``: an 8 x 8 transpose in vector registers, with which an
  exported table is copied to its lower half.
* ``load_at`` / ``store_at``: a cell of a 2-D table without numba's
  negative-index wraparound, for the near splits' straight-line leaves.
* atomics and ``yield_cpu`` for the tile queue of the min-plus fill.
"""

from __future__ import annotations

import sys

import llvmlite.binding as llvm
from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.core import config as numba_config
from numba.extending import intrinsic

from .compiled import kernel

__all__ = [
    "block_rows",
    "claim_at",
    "copy_8",
    "describe_plan",
    "fetch_add",
    "fmin",
    "load_acquire",
    "load_at",
    "outer_4x4",
    "outer_4x8",
    "outer_4x16",
    "outer_4x16_compact",
    "outer_4x16_fresh",
    "outer_8x16",
    "outer_8x16_fresh",
    "register_plan",
    "store_at",
    "store_release",
    "transpose_8x8",
    "wait_done",
    "yield_cpu",
]


def _asm_parser() -> bool:
    """Whether LLVM can parse inline assembly here (``outer_4x16``'s compact block needs it).

    llvmlite leaves the native assembly parser uninitialized; without it, LLVM
    aborts the process on the first inline assembly it meets. Versions that set
    it up themselves, or refuse the call, get the plain vector code instead.
    """
    try:
        llvm.initialize_native_asmparser()
    except Exception:  # pragma: no cover - depends on the llvmlite version
        return False
    return True


_ASM = _asm_parser()
_ADD_FLAGS = ("nnan", "nsz", "arcp", "contract", "reassoc")
_MIN_FLAGS = ("nnan", "nsz")


@intrinsic
def fmin(typingctx, a, b):
    """``llvm.minnum`` of two scalars of one type (no NaN)."""
    sig = a(a, a)

    def codegen(context, builder, signature, args):
        t = args[0].type
        fn = builder.module.declare_intrinsic("llvm.minnum", [t], ir.FunctionType(t, [t, t]))
        return builder.call(fn, args, fastmath=_MIN_FLAGS)

    return sig, codegen


def _c_table(arr) -> bool:  # type: ignore[no-untyped-def]
    """Whether a numba type is a C-contiguous 2-D array: a table the intrinsics address."""
    return isinstance(arr, types.Array) and arr.ndim == 2 and arr.layout == "C"


def _table(context, builder, ty, value):  # type: ignore[no-untyped-def]
    """Data pointer and row length of a C-contiguous 2-D array argument of type ``ty``."""
    ary = context.make_array(ty)(context, builder, value=value)
    return ary.data, cgutils.unpack_tuple(builder, ary.shape, 2)[1]


def _cell(builder, data, ld, i, j):  # type: ignore[no-untyped-def]
    """Pointer to cell ``(i, j)`` of a table (``data``, row length ``ld``); no wraparound."""
    return builder.gep(data, [builder.add(builder.mul(i, ld), j)], inbounds=True)


def _cpu() -> tuple[str, list[str]]:
    """The CPU numba compiles for: its LLVM name and feature flags."""
    name = getattr(numba_config, "CPU_NAME", None) or "host"
    if name == "host":
        name = llvm.get_host_cpu_name()
    features = getattr(numba_config, "CPU_FEATURES", None) or llvm.get_host_cpu_features().flatten()
    return name, features.split(",")


_AMD = ("znver", "bdver", "btver", "amdfam", "athlon", "opteron", "barcelona", "k8")


def register_plan(itemsize: int) -> tuple[int, bool]:
    """``(vector bytes, integer minimum)`` of the register block on this CPU.

    * AVX-512 on Intel (any CPU with AVX-512F that LLVM does not name as
      AMD): 64-byte vectors, whose two 512-bit ports do twice the work of a
      256-bit instruction; measured on a 2-core Xeon (AVX-512, LLVM name
      ``rocketlake``): 2.4e10 candidates/s per core in cache against 2.0e10
      with 32-byte float minima and 1.4e10 with 32-byte integer minima.
    * AVX-512VL on AMD (Zen 4 executes 512-bit instructions as two 256-bit
      halves): 32-byte vectors with the integer minimum, which runs on
      vector ports the floating-point minimum cannot use (1.2-1.45x the
      float kernel's rate on Zen 4). The Intel plan's 8 x 16 blocks of
      64-byte vectors made whole calls 1.03-1.10x slower there at n = 1000
      and 2000 (``docs/fast-engine.md``).
    * AVX2: 32-byte vectors; the integer minimum for 32-bit values.
    * Anything else: 32-byte vectors of float minima, split by LLVM as the
      target needs.

    The integer minimum is exact here: non-negative floats (+inf included)
    order as their bit patterns do as signed integers, so ``min`` of them as
    integers is the same value, bit for bit, and table values of the
    min-plus path are sums of lengths, never negative, never NaN.
    """
    name, features = _cpu()
    if "+avx512f" in features and not name.startswith(_AMD):
        return 64, "+avx512vl" in features
    return 32, ("+avx512vl" if itemsize == 8 else "+avx2") in features


def block_rows() -> int:
    """Rows of the dense products' register block on this CPU: 8 with 64-byte vectors, else 4.

    8 x 16 cells fill the 32 vector registers of AVX-512; with 32-byte vectors
    4 x 16 fill the 16 of AVX2 (``register_plan``; the width does not depend on
    the table's item size).
    """
    return 8 if register_plan(8)[0] == 64 else 4


def describe_plan(itemsize: int = 8) -> str:
    """The far products' register block on this CPU, in words (for benchmark reports).

    >>> "16 cells" in describe_plan()
    True
    """
    width, as_int = register_plan(itemsize)
    block = f"{block_rows()} x 16 cells in {width}-byte vectors"
    return f"{block}, {'integer' if as_int else 'float'} minimum (LLVM CPU {_cpu()[0]})"


def _outer(rows: int, cols: int, compact: bool = False, fresh: bool = False):  # type: ignore[no-untyped-def]
    """An intrinsic ``outer(C, ci, cj, A, ai, ak, B, bk, bj, kn)``: one register block.

    On C-contiguous 2-D tables (``C``, ``A`` and ``B`` may be one array), for
    ``r < rows`` and ``q < cols``, ``C[ci + r, cj + q]`` becomes the minimum of
    itself and of ``A[ai + r, ak + t] + B[bk + t, bj + q]`` over ``t < kn``.
    The ``rows x cols`` block is loaded once into vector registers; each step
    ``t`` loads row ``B[bk + t, bj:bj + cols]`` and broadcasts ``A[ai + r, ak + t]``.
    Every candidate is the same single addition as in any other order, and
    the minimum is exact, so the result does not depend on the order of
    evaluation.

    ``fresh``: the block starts from +inf instead of from ``C``, which it then
    only writes: the cells' first stores need not wait for their lines to be
    read (or taken from another CPU) before the block's work.
    """

    @intrinsic
    def outer(typingctx, C, ci, cj, A, ai, ak, B, bk, bj, kn):
        if not all(_c_table(arr) for arr in (C, A, B)):
            return None
        if not (C.dtype == A.dtype == B.dtype):
            return None
        if compact and C.dtype != types.float64:  # the compact loop is float64 only
            return None
        i = types.intp
        sig = types.none(C, i, i, A, i, i, B, i, i, i)

        def codegen(context, builder, signature, args):
            def table(k):  # data pointer and row length of argument k
                return _table(context, builder, signature.args[k], args[k])

            (c_data, c_ld), (a_data, a_ld), (b_data, b_ld) = table(0), table(3), table(6)
            ci, cj, ai, ak, bk, bj, kn = (args[k] for k in (1, 2, 4, 5, 7, 8, 9))
            elt = context.get_data_type(signature.args[0].dtype)
            size = context.get_abi_sizeof(elt)
            vector_bytes, as_int = register_plan(size)
            if compact or _compact_here(rows, cols, size, (vector_bytes, as_int)):
                tables = (c_data, c_ld), (a_data, a_ld), (b_data, b_ld)
                _compact_4x16(builder, *tables, (ci, cj, ai, ak, bk, bj, kn), fresh)
                return context.get_dummy_value()
            lanes = max(1, min(cols, vector_bytes // size))
            vty = ir.VectorType(elt, lanes)
            mty = ir.VectorType(ir.IntType(8 * size), lanes) if as_int else vty
            name = (
                f"llvm.smin.v{lanes}i{8 * size}" if as_int else f"llvm.minnum.v{lanes}f{8 * size}"
            )
            vmin = cgutils.get_or_insert_function(
                builder.module, ir.FunctionType(mty, [mty, mty]), name
            )
            flags = () if as_int else _MIN_FLAGS
            intp = ci.type

            def const(v):
                return ir.Constant(intp, v)

            def vec_at(data, ld, r, c, v):  # pointer to the v-th vector from table[r, c]
                p = _cell(builder, data, ld, r, builder.add(c, const(v * lanes)))
                return builder.bitcast(p, vty.as_pointer())

            vecs = cols // lanes
            c_rows = [builder.add(ci, const(r)) for r in range(rows)]
            a_rows = [builder.add(ai, const(r)) for r in range(rows)]
            slots = []
            inf = builder.bitcast(ir.Constant(vty, [float("inf")] * lanes), mty)
            for r in range(rows):
                for v in range(vecs):
                    slot = cgutils.alloca_once(builder, mty)  # promoted to a register
                    ptr = vec_at(c_data, c_ld, c_rows[r], cj, v)
                    start = inf if fresh else builder.load(ptr, align=size)
                    builder.store(builder.bitcast(start, mty), slot)
                    slots.append(slot)
            undef = ir.Constant(vty, ir.Undefined)
            splat = ir.Constant(ir.VectorType(ir.IntType(32), lanes), [0] * lanes)
            with cgutils.for_range(builder, kn) as loop:
                t = loop.index
                brow = builder.add(bk, t)
                b = [
                    builder.load(vec_at(b_data, b_ld, brow, bj, v), align=size) for v in range(vecs)
                ]
                for r in range(rows):
                    a = builder.load(_cell(builder, a_data, a_ld, a_rows[r], builder.add(ak, t)))
                    a = builder.insert_element(undef, a, ir.Constant(ir.IntType(32), 0))
                    a = builder.shuffle_vector(a, undef, splat)
                    for v in range(vecs):
                        slot = slots[r * vecs + v]
                        s = builder.bitcast(builder.fadd(a, b[v], flags=_ADD_FLAGS), mty)
                        m = builder.call(vmin, [builder.load(slot), s], fastmath=flags)
                        builder.store(m, slot)
            for r in range(rows):
                for v in range(vecs):
                    ptr = vec_at(c_data, c_ld, c_rows[r], cj, v)
                    value = builder.bitcast(builder.load(slots[r * vecs + v]), vty)
                    builder.store(value, ptr, align=size)
            return context.get_dummy_value()

        return sig, codegen

    return outer


# The compact 4 x 16 block (AVX-512VL, float64, integer minimum): its loop over the
# splits as inline assembly with fixed registers, chosen as follows. The 16
# accumulators live in ymm16-31, whose integer minimum (vpminsq) needs the EVEX
# encoding anyway; the row of B, the four broadcasts of A and the sums use ymm0-15, so
# that every addition has the 4-byte VEX encoding. On the 2-core AMD EPYC (Zen 4) of
# docs/fast-engine.md the loop LLVM writes from the vector code of ``_outer`` puts the
# sums in ymm16-31 (6-byte EVEX additions) and runs at 2.2e10 candidates/s a core; the
# same instructions as inline assembly ran at 2.2e10 with LLVM's registers and at 2.5e10
# with the sums in ymm0-15, as did GCC's kernel (262 bytes a split, against 224 here and
# 262 for LLVM's loop, so not the length alone: no performance counters there to say
# more). The additions come ahead of the minima, in the order GCC's
# scheduled kernel of ``minplus_peak.c`` uses; the sums and the minima are the same
# operations as ``_outer``'s, so the result is the same, bit for bit.
_B, _A = ["%ymm0", "%ymm1", "%ymm2", "%ymm3"], ["%ymm4", "%ymm5", "%ymm6", "%ymm7"]
_T = [f"%ymm{x}" for x in range(8, 16)]
_C = [f"%ymm{x}" for x in range(16, 32)]


def _compact_here(rows: int, cols: int, itemsize: int, plan: tuple[int, bool]) -> bool:
    """Whether ``_outer``'s block is the compact loop here.

    A float64 4 x 16 block, a plan of 32-byte vectors with the integer minimum, and
    a target it can run on (``_compact_runs``).
    """
    return (rows, cols, itemsize, plan) == (4, 16, 8, (32, True)) and _compact_runs()


def _compact_runs() -> bool:
    """Whether the compact loop can run here: AVX-512VL, and LLVM can assemble for it."""
    return _ASM and "+avx512vl" in _cpu()[1]


def _compact_text() -> str:
    """The compact block's loop over the splits, in AT&T syntax.

    Operands: $0-$15 the accumulators, $16 the byte count (negative, up to 0), $17
    the row of B, $18-$21 the rows of A (8 bytes a split), $44 B's row length in bytes.
    """
    pb, pa, count, ldb = "$17", [f"${18 + r}" for r in range(4)], "$16", "$44"

    def add(r: int, v: int, dst: str) -> str:
        return f"vaddpd {_B[v]}, {_A[r]}, {dst}"

    def low(r: int, v: int, src: str) -> str:
        return f"vpminsq {src}, {_C[4 * r + v]}, {_C[4 * r + v]}"

    lines = [".p2align 6", "1:"]
    lines += [f"vmovupd {32 * v}({pb}), {_B[v]}" for v in range(4)]
    lines += [f"vbroadcastsd ({pa[r]}), {_A[r]}" for r in range(4)]
    first = [(0, 1, _T[0]), (0, 0, _T[1]), (0, 2, _T[2]), (1, 0, _T[3]), (1, 1, _T[4])]
    first += [(1, 2, _T[5]), (2, 0, _T[6]), (2, 1, _T[7]), (3, 0, _B[0]), (3, 1, _B[1])]
    first += [(0, 3, _A[0]), (1, 3, _A[1])]
    lines += [add(r, v, d) for r, v, d in first]
    lines += [low(0, 1, _T[0]), low(0, 0, _T[1])]
    lines += [add(2, 2, _T[0]), add(3, 2, _B[2]), add(2, 3, _A[2]), add(3, 3, _A[3])]
    last = [(0, 2, _T[2]), (0, 3, _A[0]), (1, 0, _T[3]), (1, 1, _T[4]), (1, 2, _T[5])]
    last += [(1, 3, _A[1]), (2, 0, _T[6]), (2, 1, _T[7]), (2, 2, _T[0]), (2, 3, _A[2])]
    last += [(3, 0, _B[0]), (3, 1, _B[1]), (3, 2, _B[2]), (3, 3, _A[3])]
    lines += [low(r, v, src) for r, v, src in last]
    lines += [f"add {ldb}, {pb}"] + [f"add $$8, {p}" for p in pa]
    lines += [f"add $$8, {count}", "jnz 1b"]
    return "\n".join(lines)


def _compact_4x16(builder, c, a, b, places, fresh=False):  # type: ignore[no-untyped-def]
    """``_outer(4, 16)``'s block as the compact loop.

    ``c``, ``a``, ``b``: each table's data pointer and row length; ``places``:
    ``_outer``'s ``(ci, cj, ai, ak, bk, bj, kn)``; ``fresh``: start from +inf, not
    from ``C``.
    """
    (c_data, c_ld), (a_data, a_ld), (b_data, b_ld) = c, a, b
    ci, cj, ai, ak, bk, bj, kn = places
    intp = ci.type
    vty = ir.VectorType(ir.DoubleType(), 4)
    ptr = c_data.type

    def const(v):  # type: ignore[no-untyped-def]
        return ir.Constant(intp, v)

    cells = []
    for r in range(4):
        row = builder.add(ci, const(r))
        for v in range(4):
            p = _cell(builder, c_data, c_ld, row, builder.add(cj, const(4 * v)))
            cells.append(builder.bitcast(p, vty.as_pointer()))
    inf = ir.Constant(vty, [float("inf")] * 4)
    if fresh:  # no splits: the block is +inf
        with builder.if_then(builder.icmp_signed("<=", kn, const(0))):
            for p in cells:
                builder.store(inf, p, align=8)
    with builder.if_then(builder.icmp_signed(">", kn, const(0))):
        acc = [inf] * 16 if fresh else [builder.load(p, align=8) for p in cells]
        rows = [_cell(builder, a_data, a_ld, builder.add(ai, const(r)), ak) for r in range(4)]
        brow = _cell(builder, b_data, b_ld, bk, bj)
        count = builder.mul(kn, const(-8))
        ldb = builder.mul(b_ld, const(8))
        out = ir.LiteralStructType([vty] * 16 + [intp, ptr] + [ptr] * 4)
        fty = ir.FunctionType(out, [vty] * 16 + [intp, ptr] + [ptr] * 4 + [intp])
        constraints = [f"={{ymm{x}}}" for x in range(16, 32)] + ["=r"] * 6
        constraints += [str(x) for x in range(22)] + ["r"]
        constraints += [f"~{{ymm{x}}}" for x in range(16)] + ["~{cc}", "~{memory}"]
        loop = ir.InlineAsm(fty, _compact_text(), ",".join(constraints), side_effect=True)
        res = builder.call(loop, [*acc, count, brow, *rows, ldb])
        for x, p in enumerate(cells):
            builder.store(builder.extract_value(res, x), p, align=8)


def _transpose_masks() -> list[list[tuple[int, int, list[int]]]]:
    """Shuffles of an 8 x 8 transpose: per stage, ``(a, b, mask)`` building each output.

    Stage 1 interleaves single elements of row pairs, stage 2 pairs of
    elements, stage 3 halves: after it, vector ``t`` holds element ``t`` of
    every input row.
    """
    lo, hi = [0, 8, 2, 10, 4, 12, 6, 14], [1, 9, 3, 11, 5, 13, 7, 15]
    stage1 = [(2 * (v // 2), 2 * (v // 2) + 1, lo if v % 2 == 0 else hi) for v in range(8)]
    pair_lo, pair_hi = [0, 1, 8, 9, 4, 5, 12, 13], [2, 3, 10, 11, 6, 7, 14, 15]
    stage2 = []
    for half in (0, 4):  # rows 0-3, rows 4-7
        for v in range(4):  # element (mod 4) v
            a = half + v % 2
            stage2.append((a, a + 2, pair_lo if v < 2 else pair_hi))
    quad_lo, quad_hi = [0, 1, 2, 3, 8, 9, 10, 11], [4, 5, 6, 7, 12, 13, 14, 15]
    stage3 = [(t % 4, t % 4 + 4, quad_lo if t < 4 else quad_hi) for t in range(8)]
    return [stage1, stage2, stage3]


@intrinsic
def transpose_8x8(typingctx, src, si, sj, dst, di, dj):
    """``dst[di + t, dj + q] = src[si + q, sj + t]`` for ``q, t < 8``: an 8 x 8 transpose.

    Eight row loads, 24 vector shuffles and eight row stores (on C-contiguous
    2-D arrays of one float type) instead of 64 scalar loads and stores.
    """
    if not (_c_table(src) and _c_table(dst)):
        return None
    if src.dtype != dst.dtype:
        return None
    i = types.intp
    sig = types.none(src, i, i, dst, i, i)

    def codegen(context, builder, signature, args):
        def rows(k, r0, c0):  # pointers to the 8 rows' first elements
            data, ld = _table(context, builder, signature.args[k], args[k])
            out = []
            for r in range(8):
                row = builder.add(r0, ir.Constant(r0.type, r))
                ptr = _cell(builder, data, ld, row, c0)
                out.append(builder.bitcast(ptr, vty.as_pointer()))
            return out

        elt = context.get_data_type(signature.args[0].dtype)
        size = context.get_abi_sizeof(elt)
        vty = ir.VectorType(elt, 8)
        mty = ir.VectorType(ir.IntType(32), 8)
        vecs = [builder.load(p, align=size) for p in rows(0, args[1], args[2])]
        for stage in _transpose_masks():
            vecs = [
                builder.shuffle_vector(vecs[a], vecs[b], ir.Constant(mty, mask))
                for a, b, mask in stage
            ]
        for p, v in zip(rows(3, args[4], args[5]), vecs):
            builder.store(v, p, align=size)
        return context.get_dummy_value()

    return sig, codegen


@intrinsic
def copy_8(typingctx, src, si, sj, dst, di, dj):
    """``dst[di, dj + q] = src[si, sj + q]`` for ``q < 8``: one vector load and store.

    On C-contiguous 2-D arrays of one float type, without numba's wraparound.
    """
    if not (_c_table(src) and _c_table(dst)) or src.dtype != dst.dtype:
        return None
    i = types.intp
    sig = types.none(src, i, i, dst, i, i)

    def codegen(context, builder, signature, args):
        elt = context.get_data_type(signature.args[0].dtype)
        size = context.get_abi_sizeof(elt)
        vty = ir.VectorType(elt, 8).as_pointer()
        s_data, s_ld = _table(context, builder, signature.args[0], args[0])
        d_data, d_ld = _table(context, builder, signature.args[3], args[3])
        value = builder.load(
            builder.bitcast(_cell(builder, s_data, s_ld, args[1], args[2]), vty), align=size
        )
        ptr = builder.bitcast(_cell(builder, d_data, d_ld, args[4], args[5]), vty)
        builder.store(value, ptr, align=size)
        return context.get_dummy_value()

    return sig, codegen


@intrinsic
def load_at(typingctx, arr, i, j):
    """``arr[i, j]`` of a C-contiguous 2-D array; ``0 <= i, j`` (no wraparound, no check).

    numba indexes with a signed integer it cannot prove non-negative through
    a wraparound (``i + n`` where ``i < 0``): in the leaves of the near
    splits, whose cells are all indices computed at run time, that took
    over a quarter of their instructions (119 of about 434 in a leaf, as
    compiled on the Xeon of ``docs/fast-engine.md``).
    """
    if not _c_table(arr):
        return None

    def codegen(context, builder, signature, args):
        arr, i, j = args
        return builder.load(_cell(builder, *_table(context, builder, signature.args[0], arr), i, j))

    return arr.dtype(arr, types.intp, types.intp), codegen


@intrinsic
def store_at(typingctx, arr, i, j, value):
    """``arr[i, j] = value`` (of ``arr``'s type) with the bounds of ``load_at``."""
    if not _c_table(arr) or value != arr.dtype:
        return None

    def codegen(context, builder, signature, args):
        arr, i, j, value = args
        data, ld = _table(context, builder, signature.args[0], arr)
        builder.store(value, _cell(builder, data, ld, i, j))
        return context.get_dummy_value()

    return types.none(arr, types.intp, types.intp, arr.dtype), codegen


@intrinsic
def claim_at(typingctx, arr, i, j):
    """Ask for the cache line of ``arr[i, j]`` to be written (``llvm.prefetch``, write).

    ``prefetchw`` where the CPU has it: the line comes for writing and every
    other CPU's copy is invalidated, while this thread goes on; nothing waits for
    it and nothing changes but timing. On the EPYC of ``docs/fast-engine.md``, in
    its spells, the first store to a line the other CPU had read cost 12.7 ns a
    line in a sweep, against 3.6 outside them and 0.6 for a line no other CPU
    had read (``crosscore.c rewrite``, 64 KB): the fill rewrites lines both
    threads read in the solve before.
    """
    if not _c_table(arr):
        return None

    def codegen(context, builder, signature, args):
        arr, i, j = args
        i8p = ir.IntType(8).as_pointer()
        i32 = ir.IntType(32)
        data, ld = _table(context, builder, signature.args[0], arr)
        ptr = builder.bitcast(_cell(builder, data, ld, i, j), i8p)
        fnty = ir.FunctionType(ir.VoidType(), [i8p, i32, i32, i32])
        fn = cgutils.get_or_insert_function(builder.module, fnty, "llvm.prefetch.p0i8")
        # write, keep in every cache level, data
        builder.call(fn, [ptr, ir.Constant(i32, 1), ir.Constant(i32, 3), ir.Constant(i32, 1)])
        return context.get_dummy_value()

    return types.none(arr, types.intp, types.intp), codegen


outer_4x16 = _outer(4, 16)
outer_4x16_compact = _outer(4, 16, compact=True)  # always the compact loop (AVX-512VL only)
outer_4x8 = _outer(4, 8)
outer_4x4 = _outer(4, 4)
outer_8x16 = _outer(8, 16)  # the far product's block where vectors are 64 bytes wide
# the far products' first blocks of splits, which write a tile's cells without reading them
outer_4x16_fresh = _outer(4, 16, fresh=True)
outer_8x16_fresh = _outer(8, 16, fresh=True)


def _item_pointer(context, builder, signature, args):  # type: ignore[no-untyped-def]
    ty = signature.args[0]
    ary = context.make_array(ty)(context, builder, value=args[0])
    return cgutils.get_item_pointer(context, builder, ty, ary, [args[1]], wraparound=False)


@intrinsic
def fetch_add(typingctx, arr, idx):
    """``arr[idx] += 1`` atomically; the old value (1-D int64 ``arr``)."""

    def codegen(context, builder, signature, args):
        ptr = _item_pointer(context, builder, signature, args)
        return builder.atomic_rmw("add", ptr, ir.Constant(ir.IntType(64), 1), "seq_cst")

    return types.int64(arr, idx), codegen


@intrinsic
def load_acquire(typingctx, arr, idx):
    """``arr[idx]``, an atomic load: writes released before it was set are visible."""

    def codegen(context, builder, signature, args):
        ptr = _item_pointer(context, builder, signature, args)
        return builder.load_atomic(ptr, "acquire", 8)

    return types.int64(arr, idx), codegen


@intrinsic
def store_release(typingctx, arr, idx, val):
    """``arr[idx] = val`` after every earlier write of this thread (atomic store)."""

    def codegen(context, builder, signature, args):
        ptr = _item_pointer(context, builder, signature, args)
        builder.store_atomic(args[2], ptr, "release", 8)
        return context.get_dummy_value()

    return types.none(arr, idx, val), codegen


# sched_yield (POSIX) or SwitchToThread (Windows): both take nothing, return an int
_YIELD_SYMBOL = "SwitchToThread" if sys.platform == "win32" else "sched_yield"
_SPINS = 2000  # polls of a tile's flag before a waiting thread gives up its CPU


@intrinsic
def yield_cpu(typingctx):
    """Let the OS run another thread now: a waiter must not starve the thread it waits on."""

    def codegen(context, builder, signature, args):
        fnty = ir.FunctionType(ir.IntType(32), [])
        builder.call(cgutils.get_or_insert_function(builder.module, fnty, _YIELD_SYMBOL), [])
        return context.get_dummy_value()

    return types.none(), codegen


@kernel(inline="always")
def wait_done(done, idx):
    """Wait until ``done[idx]`` is set: spin briefly, then yield between polls.

    On a machine with more runnable threads than cores, the tile waited on may
    belong to a thread the OS has descheduled; spinning would burn the very CPU
    time it needs.
    """
    spins = 0
    while load_acquire(done, idx) == 0:
        spins += 1
        if spins >= _SPINS:
            yield_cpu()
