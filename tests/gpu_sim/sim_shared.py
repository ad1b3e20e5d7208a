"""Thread-safe ``cuda.shared.array`` for numba's CUDA simulator (test harness only).

The simulator runs each CUDA thread as a Python thread and gives a block's
threads one shared array per source line: the first thread to reach the line
allocates it, the others look it up. That look-up and the insert are not
locked, so two threads preempted between them each allocate their own array.
The block then works on two "shared" arrays: a 10-line kernel that checks every
thread's value after each barrier read stale values in 3 of 4 runs on a busy
2-core machine (6 per step: one thread alone against three), and the GPU
engine's ``finish`` kernel returned costs that were too low, at random.
:func:`install` makes the allocation atomic; everything else stays numba's.
"""

from __future__ import annotations

import sys
import threading


def install() -> None:
    """Patch the simulator's shared-array allocation (idempotent)."""
    import numpy as np
    from numba.core import types
    from numba.cuda.simulator import kernelapi
    from numba.np import numpy_support

    shared = kernelapi.FakeCUDAShared
    if getattr(shared, "_optri_locked", False):
        return
    lock = threading.Lock()

    def array(self, shape, dtype, alignment=None):
        if alignment is not None or shape == 0:
            raise NotImplementedError("the patched simulator allocates static shared arrays only")
        if isinstance(dtype, types.Type):
            dtype = numpy_support.as_dtype(dtype)
        caller = sys._getframe(1)  # one array per kernel source line, as numba keys them
        key = (caller.f_code.co_filename, caller.f_lineno)
        with lock:
            found = self._allocations.get(key)
            if found is None:
                found = self._allocations[key] = np.empty(shape, dtype)
        return found

    shared.array = array
    shared._optri_locked = True
