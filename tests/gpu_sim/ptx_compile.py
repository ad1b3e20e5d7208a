"""Compile every GPU kernel for sm_90 without a GPU, and check what a real launch needs.

The CUDA simulator runs the kernels as Python: it never types them, never
allocates registers and never overflows an index. This script does numba-cuda's
real compilation (typing, lowering, NVVM) to PTX for sm_90 (H100), at the default
settings in both table dtypes and at 1024 threads a block in float64, and checks:

1. every kernel is declared with launch bounds equal to the block it is launched
   with (ptxas then caps its registers so that such a block fits one SM);
2. no integer variable is 16- or 32-bit except thread and block indices, so no
   index into a 50,000-vertex table (2.5e9 cells, more than 2**31) can overflow
   (the only 8-bit values are chord-mask entries);
3. the min-plus product keeps its accumulators in registers (no local memory);
4. where ptxas is found (PATH or $CUDA_HOME/bin): registers x block threads fit
   the 65,536 registers of one SM (otherwise CUDA refuses the launch), static
   shared memory fits 48 KB, and the min-plus product neither spills nor has a
   stack frame. It prints each kernel's registers, shared memory and resident
   blocks per SM on an H100.

Exit status: 0 all checks pass, 1 a check failed, 77 this machine cannot compile
PTX at all (no libnvvm / libdevice, or numba internals moved).
Run: ``PYTHONPATH=src python tests/gpu_sim/ptx_compile.py``.
"""

from __future__ import annotations

import glob
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import traceback

SKIP = 77

#: sm_90 (H100) limits per SM: registers, register allocation unit (per warp),
#: threads, resident blocks, shared memory and the share each block reserves.
SM_REGISTERS, REG_UNIT, SM_THREADS, SM_BLOCKS = 65536, 256, 2048, 32
SM_SHARED, BLOCK_RESERVED_SHARED, STATIC_SHARED = 228 * 1024, 1024, 48 * 1024

#: 32-bit integers allowed in a kernel: the thread index and the block size
#: (and numba's temporaries that read them), never a table index.
SMALL_INT_OK = re.compile(r"^(tid|nth|\$\w*load_attr[\w.]*)$")


def _patch_for_offline_compile() -> None:
    """Let numba-cuda compile for a fixed compute capability without a driver."""
    import numba.cuda.cudadrv.libs as libs
    import numba.cuda.cudadrv.nvrtc as nvrtc
    import numba.cuda.cudadrv.nvvm as nvvm
    import numba.cuda.dispatcher as dispatcher

    class Device:
        compute_capability = (9, 0)

    dispatcher.get_current_device = lambda: Device()  # device functions ask for one
    nvrtc.get_supported_ccs = lambda: ((8, 0), (9, 0))  # nvrtc may be absent
    try:
        found = libs.get_libdevice()
    except Exception:  # any failure: look for it ourselves
        found = None
    if not found or not os.path.exists(str(found)):
        roots = [os.environ.get("CUDA_HOME", ""), *sorted(glob.glob("/usr/local/cuda*"))]
        hits = [h for r in roots if r for h in glob.glob(f"{r}/nvvm/libdevice/libdevice*.bc")]
        if not hits:
            raise RuntimeError("libdevice not found")
        found = hits[0]

    def read() -> bytes:
        with open(found, "rb") as fh:
            return fh.read()

    libs.get_libdevice = nvvm.get_libdevice = lambda: found
    libs.open_libdevice = nvvm.open_libdevice = read


def _ptxas() -> str | None:
    found = shutil.which("ptxas")
    if found:
        return found
    home = os.environ.get("CUDA_HOME", "")
    candidates = [f"{home}/bin/ptxas"] if home else []
    candidates += sorted(glob.glob("/usr/local/cuda*/bin/ptxas"))
    return next((c for c in candidates if os.access(c, os.X_OK)), None)


def ptxas_usage(ptxas: str, ptx: str) -> dict[str, int]:
    """Registers, spill bytes, stack frame and static shared memory from ``ptxas -v``."""
    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.join(tmp, "kernel.ptx")
        with open(src, "w") as fh:
            fh.write(ptx)
        proc = subprocess.run(
            [ptxas, "-arch=sm_90", "-v", src, "-o", os.path.join(tmp, "kernel.cubin")],
            capture_output=True,
            text=True,
            check=True,
        )
    text = proc.stderr + proc.stdout

    def number(pattern: str) -> int:
        hit = re.search(pattern, text)
        return int(hit.group(1)) if hit else 0

    return {
        "registers": number(r"Used (\d+) registers"),
        "spill": number(r"(\d+) bytes spill stores") + number(r"(\d+) bytes spill loads"),
        "stack": number(r"(\d+) bytes stack frame"),
        "smem": number(r"(\d+) bytes smem"),
    }


def blocks_per_sm(registers: int, smem: int, threads: int) -> int:
    """Resident blocks of ``threads`` threads on one sm_90 SM (0: cannot launch)."""
    warps = math.ceil(threads / 32)
    per_warp = math.ceil(max(registers, 1) * 32 / REG_UNIT) * REG_UNIT
    by_regs = (SM_REGISTERS // per_warp) // warps
    by_smem = SM_SHARED // (smem + BLOCK_RESERVED_SHARED)
    return min(by_regs, by_smem, SM_THREADS // (warps * 32), SM_BLOCKS)


def signatures(nt, dtype: str) -> dict[str, tuple]:
    i64, u8 = nt.int64, nt.uint8[:, :]
    tab, pts = getattr(nt, dtype)[:, :], nt.float64[:, :]
    return {
        "init": (tab, pts) + (i64,) * 4,
        "product_minplus": (tab, pts) + (i64,) * 7,
        "product": (tab, pts) + (i64,) * 7,
        "finish": (tab, pts, u8) + (i64,) * 8,
        "rebuild": (tab, pts) + (i64,) * 5 + (nt.int64[:, :], nt.int64[:, :], nt.float64[:]),
        "export": (tab, pts, u8) + (i64,) * 6 + (nt.float64[:, :],),
    }


def compile_kernel(kernel, sig) -> tuple[str, list[str]]:
    """PTX of ``kernel`` for sm_90 with its own launch bounds, and its narrow integers.

    One compilation gives both: numba-cuda's ``compile_cuda`` result (whose type
    map lists every variable's type) is caught on its way to ``compile_ptx``.
    Narrow integers are variables typed as 16- or 32-bit integers, other than
    thread indices.
    """
    from numba import cuda
    from numba import types as nt
    from numba.cuda import compiler

    caught = []
    real = compiler.compile_cuda

    def catching(*args, **kwargs):
        cres = real(*args, **kwargs)
        caught.append(cres)  # device functions first, the kernel last
        return cres

    compiler.compile_cuda = catching
    try:
        bounds = kernel.targetoptions.get("launch_bounds")
        ptx, _ = cuda.compile_ptx(kernel.py_func, sig, cc=(9, 0), launch_bounds=bounds)
    finally:
        compiler.compile_cuda = real
    typemap = caught[-1].type_annotation.typemap
    narrow = sorted(
        f"{name}: {ty}"
        for name, ty in typemap.items()
        if isinstance(ty, nt.Integer) and 16 <= ty.bitwidth < 64 and not SMALL_INT_OK.match(name)
    )
    return ptx, narrow


def check(what: str, name: str, ptx: str, narrow: list[str], block: int, ptxas) -> list[str]:
    """The failures of one compiled kernel; prints its resource line."""
    failed = []
    if narrow:
        failed.append(f"{what}: 32-bit integers may overflow an index: {narrow}")
    local = ptx.count("ld.local") + ptx.count("st.local")
    if name == "product_minplus" and local:
        failed.append(f"{what}: the min-plus accumulators spill to local memory")
    line = f"ok   {what:40s} ptx {len(ptx):7d} chars, local-memory ops {local:3d}"
    if ptxas:
        use = ptxas_usage(ptxas, ptx)
        fits = blocks_per_sm(use["registers"], use["smem"], block)
        line += (
            f" | {use['registers']:3d} regs x {block:4d} threads, smem {use['smem']:5d} B,"
            f" spill {use['spill']} B, stack {use['stack']} B, {fits} blocks/SM"
        )
        if fits < 1:
            failed.append(f"{what}: a block of {block} threads cannot launch ({use})")
        if use["smem"] > STATIC_SHARED:
            failed.append(f"{what}: {use['smem']} B of static shared memory")
        if name == "product_minplus" and (use["spill"] or use["stack"]):
            failed.append(f"{what}: the min-plus product spills ({use})")
    print(line)
    return failed


def main() -> int:
    try:
        from numba import cuda
        from numba import types as nt

        _patch_for_offline_compile()

        def probe(a):
            a[0] = 1.0

        cuda.compile_ptx(probe, (nt.float64[:],), cc=(9, 0))
    except Exception as exc:  # whatever stops a trivial compile: skip
        print(f"cannot compile PTX on this machine: {exc!r}")
        return SKIP

    from optri import config
    from optri.engines._gpu_kernels import build_kernels

    ptxas = _ptxas()
    print(f"ptxas: {ptxas or 'not found (register checks skipped)'}")
    default = config.GPU_THREADS_PER_BLOCK
    settings = [(default, "float64"), (default, "float32"), (1024, "float64")]
    failed: list[str] = []
    done: dict[tuple, str] = {}  # a kernel shared by two settings is compiled once
    for threads, dtype in settings:
        k = build_kernels(config.GPU_TILE, config.GPU_K_CHUNK, threads, dtype)
        for name, sig in signatures(nt, dtype).items():
            what = f"{dtype} {threads:4d} threads {name}"
            kernel = getattr(k, name)
            block = k.finish_threads if name == "finish" else threads
            bounds = kernel.targetoptions.get("launch_bounds")
            if bounds != block:
                failed.append(f"{what}: launch bounds {bounds!r}, launched with {block}")
            if (id(kernel), sig) in done:
                print(f"same {what:40s} as {done[id(kernel), sig]}")
                continue
            done[id(kernel), sig] = what.strip()
            try:
                ptx, narrow = compile_kernel(kernel, sig)
            except Exception:  # report every kernel, not just the first failure
                failed.append(f"{what}: does not compile\n{traceback.format_exc()}")
                continue
            failed += check(what, name, ptx, narrow, block, ptxas)
    for message in failed:
        print(f"FAIL {message}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
