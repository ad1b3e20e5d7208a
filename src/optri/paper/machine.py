"""A one-paragraph description of the machine a report ran on."""

from __future__ import annotations

import os
import platform

__all__ = ["machine_info"]


def machine_info() -> dict[str, str]:
    """CPU model, cores, load, OS, Python and library versions.

    >>> sorted(machine_info())[:3]
    ['cores', 'cpu', 'load average (1, 5, 15 min)']
    """
    import matplotlib
    import numpy

    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    try:
        usable = len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        usable = os.cpu_count() or 1
    try:
        load = ", ".join(f"{v:.2f}" for v in os.getloadavg())
    except (AttributeError, OSError):
        load = "unknown"
    return {
        "cpu": cpu,
        "load average (1, 5, 15 min)": load,
        "cores": f"{usable} usable of {os.cpu_count()}",
        "os": platform.platform(),
        "python": platform.python_version(),
        "numpy": numpy.__version__,
        "matplotlib": matplotlib.__version__,
    }
