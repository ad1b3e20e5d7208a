"""Kernel settings on the command line of the GPU scripts (bench_gpu.py, gpu_check.py).

``--tile``, ``--k-chunk``, ``--threads`` and ``--min-blocks`` override
``optri.config.GPU_*`` for one run, so a tuning sweep on a GPU machine needs no
edit of the package; a setting the kernels cannot take is refused up front.
"""

from __future__ import annotations

import argparse

from optri import config
from optri.engines import gpu

#: option name -> the optri.config setting it overrides
SETTINGS = {
    "tile": "GPU_TILE",
    "k_chunk": "GPU_K_CHUNK",
    "threads": "GPU_THREADS_PER_BLOCK",
    "min_blocks": "GPU_MIN_BLOCKS",
}


def add_arguments(ap: argparse.ArgumentParser) -> None:
    """Add one optional integer option per kernel setting."""
    for option, name in SETTINGS.items():
        ap.add_argument(
            f"--{option.replace('_', '-')}",
            type=int,
            help=f"override config.{name} (default {getattr(config, name)})",
        )


def apply(args: argparse.Namespace, dtype: str = "float64") -> str | None:
    """Set the overridden settings; return why no GPU run can follow, or None.

    The reason is either settings the kernels cannot take or no usable GPU.
    """
    for option, name in SETTINGS.items():
        value = getattr(args, option)
        if value is not None:
            setattr(config, name, value)
    bad = gpu.bad_settings(dtype)
    if bad:
        return f"bad kernel settings: {bad}"
    reason = gpu.unavailable()
    return f"no GPU run possible: {reason}" if reason else None


def describe() -> str:
    """The settings in force, for the report's header."""
    return (
        f"tile {config.GPU_TILE}, k-slice {config.GPU_K_CHUNK}, "
        f"{config.GPU_THREADS_PER_BLOCK} threads/block, min blocks {config.GPU_MIN_BLOCKS}"
    )
