"""``method="gpu"``: the DP on one CUDA GPU (numba-cuda), tiled min-plus wavefront.

The host side: availability, what the engine takes, device memory, launches.
The kernels live in :mod:`optri.engines._gpu_kernels`; both import numba.cuda
only when a problem is solved, so ``import optri`` never loads CUDA.

Under ``NUMBA_ENABLE_CUDASIM=1`` numba's CUDA simulator runs the same kernels on
the CPU (very slowly): the test suite checks the kernels that way, and
``method="auto"`` never picks the simulator.
"""

from __future__ import annotations

import functools
import importlib.util
import os
import sys
from typing import Any

import numpy as np

from .. import config
from .._optional import import_optional
from ..errors import MissingDependencyError, NoTriangulationError, TableTooLargeError
from ..weights import WeightCode
from ._gpu_device import OBJ_MAX, OBJ_SUM
from ._gpu_kernels import build_kernels
from .memory import require_memory
from .problem import Problem, Solution, with_sides
from .progress import diagonal_work, work_reporter

__all__ = [
    "auto_accepts",
    "bad_settings",
    "device_bytes",
    "simulated",
    "solve",
    "unavailable",
    "unsupported",
]

_DTYPES = ("float32", "float64")


def simulated() -> bool:
    """True when numba's CUDA simulator is switched on (``NUMBA_ENABLE_CUDASIM``)."""
    return os.environ.get("NUMBA_ENABLE_CUDASIM", "0").strip() not in ("", "0")


def unavailable() -> str | None:
    """Why the GPU engine cannot run here, or None (the simulator counts as a GPU)."""
    return _probe(simulated())


#: Device nodes of the NVIDIA driver (Linux, WSL).
_DRIVER_NODES = ("/dev/nvidiactl", "/dev/dxg")


@functools.cache
def _probe(simulate: bool) -> str | None:
    if importlib.util.find_spec("numba") is None:
        return "method='gpu' needs numba-cuda; install it with: pip install 'optri[gpu]'"
    # a cheap look for the driver's device nodes first: importing numba.cuda
    # costs ~0.4 s, too much for every method="auto" call on a machine without GPU
    drivers = map(os.path.exists, _DRIVER_NODES)
    if not simulate and sys.platform.startswith("linux") and not any(drivers):
        return "no CUDA GPU found (no NVIDIA driver device); method='gpu' needs an NVIDIA GPU"
    try:
        cuda = import_optional("numba.cuda")
    except MissingDependencyError as exc:
        return str(exc)
    try:
        ok = bool(cuda.is_available())
    except Exception as exc:  # any driver failure means "no usable GPU"
        return f"no usable CUDA GPU ({exc})"
    if not ok:
        return "no CUDA GPU found (numba.cuda.is_available() is False); method='gpu' needs one"
    if not simulate and not _nvvm_found():
        return (
            "numba-cuda found a GPU but not libNVVM, so it cannot compile kernels; install "
            f"the CUDA toolkit or the wheels: {_TOOLKIT_HINT}"
        )
    return None


#: How to get numba-cuda with the CUDA toolkit wheels (libNVVM) for the driver.
_TOOLKIT_HINT = "pip install 'optri[gpu-cu13]' (driver >= 580) or 'optri[gpu-cu12]'"


def _nvvm_found() -> bool:
    """True when numba-cuda can load libNVVM, which compiles the kernels (not simulated)."""
    from numba.cuda.cudadrv import nvvm

    return bool(nvvm.is_available())


def unsupported(problem: Problem) -> str | None:
    """Why the GPU engine cannot take ``problem``, or None."""
    if problem.objective.is_lex:
        return "the GPU engine does not do lexicographic objectives; use method='table'"
    w = problem.weights[0]
    if w.code == WeightCode.CUSTOM:
        return (
            f"weight {w.name!r} is a Python callable, which cannot run on the GPU; "
            f"the GPU engine computes the built-in weights only"
        )
    if np.dtype(problem.dtype).name not in _DTYPES:
        return f"dtype must be float32 or float64, got {np.dtype(problem.dtype)}"
    return bad_settings(problem.dtype)


#: Static shared memory a CUDA block may declare.
_SHARED_LIMIT = 48 * 1024


def bad_settings(dtype: str | np.dtype = "float64") -> str | None:
    """Why the ``config.GPU_*`` kernel settings cannot compile or launch, or None.

    Checked: the slice depth divides the tile, 1 to 1024 threads a block, and at
    most 48 KB of static shared memory for a table of ``dtype``.

    >>> bad_settings("float64") is None
    True
    """
    itemsize = np.dtype(dtype).itemsize
    tile, chunk, threads = config.GPU_TILE, config.GPU_K_CHUNK, config.GPU_THREADS_PER_BLOCK
    if tile < 1 or chunk < 1 or tile % chunk:
        return "config.GPU_K_CHUNK must divide config.GPU_TILE"
    if not 1 <= threads <= 1024:
        return "config.GPU_THREADS_PER_BLOCK must be between 1 and 1024"
    if max(tile * (tile + 1), 2 * tile * (chunk + 1)) * itemsize > _SHARED_LIMIT:
        return f"config.GPU_TILE = {tile} needs more than 48 KB of shared memory per block"
    return None


def auto_accepts(problem: Problem) -> bool:
    """``method="auto"`` takes the GPU from ``config.GPU_AUTO_MIN_N`` vertices, never simulated."""
    return problem.n >= config.GPU_AUTO_MIN_N and not simulated()


def device_bytes(problem: Problem) -> int:
    """Device memory ``solve`` allocates for ``problem``, in bytes.

    >>> from optri.solve import build_problem
    >>> from optri.polygon import as_polygon
    >>> p = build_problem(as_polygon([[0, 0], [1, 0], [0, 1]]), "perimeter", "sum")
    >>> device_bytes(p) >= 64 * 64 * 8
    True
    """
    n = problem.n
    size = _padded(n)
    need = size * size * np.dtype(problem.dtype).itemsize + size * 24 + n * 40 + 64
    if problem.allowed is not None:
        need += size * size  # uint8 chord mask
    if problem.keep_table:
        need += n * n * 8  # the exported paper table
    return need


def solve(problem: Problem) -> Solution:
    """Fill the table on the GPU, rebuild the triangles there, copy back the answer.

    ``Solution.stats``: ``tile``, ``tiles``, ``launches``, ``padded_n``.

    Raises
    ------
    TableTooLargeError
        The table does not fit in device memory (checked before allocating).
    NoTriangulationError
        No triangulation has a finite cost.
    """
    for w in problem.weights:
        w.evaluator(problem.polygon)  # weight fits the input (points or values)
    cuda = import_optional("numba.cuda")

    n, tile = problem.n, config.GPU_TILE
    threads = config.GPU_THREADS_PER_BLOCK
    dtype = np.dtype(problem.dtype)
    _require_device_memory(problem, cuda)
    size = _padded(n)
    nt = size // tile
    code, dim, pts = _coordinates(problem, size)
    obj = OBJ_SUM if problem.objective.components[0] == "sum" else OBJ_MAX
    eform = int(obj == OBJ_SUM and problem.weights[0].edge_decomposable)
    mask = _mask(problem, size)
    has_mask = int(problem.allowed is not None)
    k = build_kernels(tile, config.GPU_K_CHUNK, threads, dtype.name)

    tab = cuda.device_array((size, size), dtype=dtype)
    d_pts, d_mask = cuda.to_device(pts), cuda.to_device(mask)
    k.init[_blocks(-(-size * size // threads)), threads](tab, d_pts, n, code, obj, eform)
    launches = 1
    report = work_reporter(problem)
    if report is not None:  # splits of the table's tile-diagonals 0 .. d - 1, at [d]
        work = diagonal_work(n, tile)
    for d in range(nt):
        count = nt - d
        if d >= 2:
            splits = min(d - 1, max(1, -(-config.GPU_MIN_BLOCKS // count)))
            total = count * splits
            product = k.product_minplus if eform else k.product
            product[_blocks(total), threads](tab, d_pts, dim, n, code, obj, d, splits, total)
            launches += 1
        k.finish[_blocks(count), k.finish_threads](
            tab, d_pts, d_mask, has_mask, dim, n, code, obj, eform, d, count
        )
        launches += 1
        if report is not None:
            cuda.synchronize()
            report(int(work[min(d + 1, len(work) - 1)]))

    cost, tris = _rebuild(k, cuda, tab, d_pts, dim, n, code, obj, eform, threads)
    table = None
    if problem.keep_table:
        out = cuda.device_array((n, n), dtype=np.float64)
        k.export[_blocks(-(-n * n // threads)), threads](
            tab, d_pts, d_mask, has_mask, dim, n, code, obj, eform, out
        )
        table = out.copy_to_host()
    stats = {"tile": tile, "tiles": nt * (nt + 1) // 2, "launches": launches, "padded_n": size}
    return Solution(cost, tris, table, stats)


def _padded(n: int) -> int:
    tile = config.GPU_TILE
    return -(-n // tile) * tile


def _blocks(work: int) -> int:
    return max(1, min(config.GPU_MAX_BLOCKS, work))


def _coordinates(problem: Problem, size: int) -> tuple[int, int, np.ndarray]:
    """Weight code, input dimension and ``(size, 3)`` float64 coordinates.

    Padding rows repeat the last vertex: the cells they feed are never read.
    """
    data = problem.polygon.data
    n = problem.n
    pts = np.zeros((size, 3), dtype=np.float64)
    dim = 1 if data.ndim == 1 else data.shape[1]
    pts[:n, :dim] = data.reshape(n, dim)
    pts[n:] = pts[n - 1]
    return problem.weights[0].code, dim, pts


def _mask(problem: Problem, size: int) -> np.ndarray:
    if problem.allowed is None:
        return np.ones((1, 1), dtype=np.uint8)
    n = problem.n
    mask = np.ones((size, size), dtype=np.uint8)
    mask[:n, :n] = with_sides(problem.allowed)  # polygon sides are always usable
    return mask


def _rebuild(
    k: Any,
    cuda: Any,
    tab: Any,
    d_pts: Any,
    dim: int,
    n: int,
    code: int,
    obj: int,
    eform: int,
    threads: int,
) -> tuple[float, np.ndarray]:
    """Run the one-block re-scan kernel; return the cost and the n - 2 triangles."""
    stack = cuda.device_array((n, 2), dtype=np.int64)
    tris = cuda.device_array((max(n - 2, 1), 3), dtype=np.int64)
    out = cuda.to_device(np.zeros(4, dtype=np.float64))
    k.rebuild[1, threads](tab, d_pts, dim, n, code, obj, eform, stack, tris, out)
    res = out.copy_to_host()
    if res[1]:
        i, j = int(res[2]), int(res[3])
        raise NoTriangulationError(
            f"no valid triangulation of sub-polygon ({i}, {j}): every split has "
            f"an infinite or invalid cost",
            (i, j),
        )
    return float(res[0]), tris.copy_to_host()[: n - 2].astype(np.int64)


def _require_device_memory(problem: Problem, cuda: Any) -> None:
    need = device_bytes(problem)
    hint = "use dtype=float32 (halves the table) or a GPU with more memory"
    if np.dtype(problem.dtype) == np.float32:
        hint = "use a GPU with more memory or split the polygon"
    what = f"the GPU table for n = {problem.n}"
    if problem.keep_table:
        require_memory(problem.n * problem.n * 8, "the copied-back n x n table", "keep_table=False")
    if config.GPU_MEMORY_LIMIT_BYTES is not None:
        limit = int(config.GPU_MEMORY_LIMIT_BYTES)
    elif simulated():
        require_memory(need, f"{what} (CUDA simulator, host memory)", hint)
        return
    else:
        free, _total = cuda.current_context().get_memory_info()
        limit = int(free * config.GPU_MEMORY_FRACTION)
    if need > limit:
        raise TableTooLargeError(
            f"{what} needs {need / 1e6:.1f} MB of device memory but only "
            f"{limit / 1e6:.1f} MB may be used (config.GPU_MEMORY_FRACTION of the free "
            f"memory); {hint}"
        )
