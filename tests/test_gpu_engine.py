"""The GPU engine in the normal (non-simulator) environment: errors, choices, sizes."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import optri
from optri import config
from optri.engines import gpu, select_engine
from optri.engines._gpu_kernels import thread_layout
from optri.errors import EngineUnavailableError
from optri.polygon import as_polygon
from optri.solve import build_problem

SQUARE = [[0, 0], [1, 0], [1, 1], [0, 1]]
no_gpu = pytest.mark.skipif(gpu.unavailable() is None, reason="a (simulated) GPU is present")


def problem(weight="perimeter", objective="sum", n=6):
    ang = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return build_problem(as_polygon(np.c_[np.cos(ang), np.sin(ang)]), weight, objective)


def test_import_optri_loads_no_cuda():
    code = "import sys, optri; assert 'numba.cuda' not in sys.modules"
    subprocess.run([sys.executable, "-c", code], check=True)


@no_gpu
def test_method_gpu_without_gpu_raises():
    with pytest.raises(EngineUnavailableError, match="GPU|numba"):
        optri.triangulate(SQUARE, method="gpu")


@no_gpu
def test_cli_method_gpu_exits_2_with_one_line(tmp_path):
    path = tmp_path / "square.csv"
    path.write_text("\n".join(f"{x},{y}" for x, y in SQUARE) + "\n")
    proc = subprocess.run(
        [sys.executable, "-m", "optri", "solve", str(path), "--method", "gpu"],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("optri: error:") and "gpu" in lines[0].lower()


@no_gpu
def test_auto_falls_back_without_gpu(monkeypatch):
    monkeypatch.setattr(config, "GPU_AUTO_MIN_N", 3)
    name, _ = select_engine("auto", problem())
    assert name != "gpu"


@pytest.fixture
def driver_without_nvvm(monkeypatch, tmp_path):
    """Pretend a GPU and its driver are present but libNVVM is not."""
    cuda = pytest.importorskip("numba.cuda")
    from numba.cuda.cudadrv import nvvm

    node = tmp_path / "nvidiactl"
    node.touch()
    monkeypatch.setattr(gpu, "_DRIVER_NODES", (str(node),))
    monkeypatch.setattr(cuda, "is_available", lambda: True)
    monkeypatch.setattr(nvvm, "is_available", lambda: False)
    gpu._probe.cache_clear()
    yield nvvm
    gpu._probe.cache_clear()


def test_gpu_without_libnvvm_names_the_toolkit_extras(driver_without_nvvm, monkeypatch):
    reason = gpu._probe(False)
    assert reason is not None and "libNVVM" in reason and "optri[gpu-cu13]" in reason
    monkeypatch.setattr(driver_without_nvvm, "is_available", lambda: True)
    gpu._probe.cache_clear()
    assert gpu._probe(False) is None  # driver and libNVVM: the engine may run


def test_unsupported_reasons():
    assert gpu.unsupported(problem()) is None
    assert gpu.unsupported(problem("max_angle", "max")) is None
    assert "Python callable" in gpu.unsupported(problem(lambda i, k, j: 1.0))
    lex = problem(("max_angle", "perimeter"), ("max", "sum"))
    assert "lexicographic" in gpu.unsupported(lex)


@pytest.mark.parametrize(
    ("name", "value", "match"),
    [("GPU_K_CHUNK", 24, "divide"), ("GPU_THREADS_PER_BLOCK", 2048, "1024"),
     ("GPU_TILE", 128, "shared memory")],
)  # fmt: skip
def test_unsupported_kernel_settings(monkeypatch, name, value, match):
    monkeypatch.setattr(config, name, value)
    assert match in gpu.unsupported(problem())


def test_auto_accepts_only_large_n(monkeypatch):
    monkeypatch.delenv("NUMBA_ENABLE_CUDASIM", raising=False)
    monkeypatch.setattr(config, "GPU_AUTO_MIN_N", 7)
    assert not gpu.auto_accepts(problem(n=6))
    assert gpu.auto_accepts(problem(n=7))
    monkeypatch.setenv("NUMBA_ENABLE_CUDASIM", "1")
    assert not gpu.auto_accepts(problem(n=7))


def test_device_bytes_grows_with_padded_table(monkeypatch):
    monkeypatch.setattr(config, "GPU_TILE", 8)
    p = problem(n=10)
    assert gpu.device_bytes(p) >= 16 * 16 * 8
    p.dtype = np.dtype(np.float32)
    assert gpu.device_bytes(p) < 16 * 16 * 8 + 16 * 24 + 10 * 40 + 100


@pytest.mark.parametrize(("tile", "threads"), [(64, 256), (32, 256), (4, 3), (8, 1), (6, 1024)])
def test_thread_layout_covers_the_tile(tile, threads):
    tx, ty, rh, cw = thread_layout(tile, threads)
    assert tx * ty <= max(threads, 1) and tx * cw == tile and ty * rh == tile
