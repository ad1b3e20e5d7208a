"""Compile every GPU kernel to PTX for sm_90 without a GPU (needs libnvvm + libdevice).

The CUDA simulator runs the kernels as Python and never type-checks them; this
script does numba's real CUDA compilation (typing, lowering, NVVM) for both
table dtypes at the default tile / threads settings, and reports each kernel's
local-memory use (the min-plus product must keep its accumulators in registers).

Exit status: 0 all compiled, 1 a kernel failed to compile, 77 this machine cannot
compile PTX at all (no libnvvm / libdevice, or numba internals moved).
Run: ``PYTHONPATH=src python tests/gpu_sim/ptx_compile.py``.
"""

from __future__ import annotations

import glob
import os
import sys
import traceback

SKIP = 77


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
    from optri.engines.gpu_kernels import build_kernels

    i64, u8 = nt.int64, nt.uint8[:, :]
    failed = 0
    for dtype in ("float64", "float32"):
        k = build_kernels(config.GPU_TILE, config.GPU_K_CHUNK, config.GPU_THREADS_PER_BLOCK, dtype)
        tab, pts = getattr(nt, dtype)[:, :], nt.float64[:, :]
        sigs = {
            "init": (tab, pts, i64, i64, i64, i64),
            "product_minplus": (tab, pts) + (i64,) * 7,
            "product": (tab, pts) + (i64,) * 7,
            "finish": (tab, pts, u8) + (i64,) * 8,
            "rebuild": (tab, pts) + (i64,) * 5 + (nt.int64[:, :], nt.int64[:, :], nt.float64[:]),
            "export": (tab, pts, u8) + (i64,) * 6 + (nt.float64[:, :],),
        }
        for name, sig in sigs.items():
            try:
                ptx, _ = cuda.compile_ptx(getattr(k, name).py_func, sig, cc=(9, 0))
            except Exception:  # report every kernel, not just the first failure
                failed += 1
                print(f"FAIL {dtype} {name}\n{traceback.format_exc()}")
                continue
            local = ptx.count("ld.local") + ptx.count("st.local")
            print(f"ok   {dtype:8s} {name:16s} ptx {len(ptx):7d} chars, local-memory ops {local}")
            if name == "product_minplus" and local:
                failed += 1
                print("FAIL the min-plus accumulators spilled to local memory")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
