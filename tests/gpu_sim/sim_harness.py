"""Two fixes to numba's CUDA simulator for our tests (harness only, never the library).

The simulator runs each CUDA thread of a block as a Python thread.

1. Shared arrays. A block's threads get one shared array per source line: the
   first thread to reach the line allocates it, the others look it up. That
   look-up and the insert are not locked, so two threads preempted between them
   each allocate their own array. The block then works on two "shared" arrays:
   a 10-line kernel that checks every thread's value after each barrier read
   stale values in 3 of 4 runs on a busy 2-core machine (6 per step: one thread
   alone against three), and the GPU engine's ``finish`` kernel returned costs
   that were too low, at random. :func:`install` makes the allocation atomic.
2. Barriers. numba's block manager finds the threads waiting in
   ``syncthreads`` by polling them all in a busy loop, which holds the GIL
   against the very threads it waits for; it needed a short thread switch
   interval (1e-4 s) and still cost 50 to 150 us a thread per barrier on a
   2-core machine. :func:`install` makes ``syncthreads`` a condition-variable
   barrier with the same rule (it opens when every thread still running waits
   at it; a thread that ends leaves it) and the same abort on an exception:
   8 to 30 us a thread per barrier (4 to 256 threads a block), with Python's
   default switch interval.

Everything else stays numba's; written against numba-cuda 0.30.
"""

from __future__ import annotations

import sys
import threading


def install() -> None:
    """Patch the simulator's shared-array allocation and barrier (idempotent)."""
    from numba.cuda.simulator import kernel, kernelapi

    if getattr(kernel.BlockManager, "_optri_patched", False):
        return
    _lock_shared_arrays(kernelapi.FakeCUDAShared)
    kernel.BlockManager.run = _run_block
    kernel.BlockThread.syncthreads = _syncthreads
    kernel.BlockManager._optri_patched = True


def _lock_shared_arrays(shared) -> None:
    import numpy as np
    from numba.core import types
    from numba.np import numpy_support

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


class _Barrier:
    """The block's ``syncthreads``: opens when all threads still running wait."""

    def __init__(self, threads: int) -> None:
        self.cond = threading.Condition()
        self.running = threads
        self.waiting = 0
        self.generation = 0
        self.failed = None  # the first thread that raised

    def _open_if_full(self) -> None:  # holding self.cond
        if self.waiting and self.waiting == self.running:
            self.waiting = 0
            self.generation += 1
            self.cond.notify_all()

    def wait(self) -> None:
        with self.cond:
            if self.failed is not None:
                raise RuntimeError("abort flag set on syncthreads call")
            generation = self.generation
            self.waiting += 1
            self._open_if_full()
            while self.generation == generation and self.failed is None:
                self.cond.wait()
            if self.failed is not None:
                raise RuntimeError("abort flag set on syncthreads clear")

    def leave(self, failed: bool) -> None:
        with self.cond:
            self.running -= 1
            if failed and self.failed is None:
                self.failed = threading.current_thread()
                self.cond.notify_all()
            self._open_if_full()


def _run_block(self, grid_point, *args):
    """``BlockManager.run``: start the block's threads, join them, re-raise a failure."""
    import numpy as np
    from numba.cuda.simulator.kernel import BlockThread

    points = list(np.ndindex(*self._block_dim))
    barrier = self._optri_barrier = _Barrier(len(points))

    def target():
        failed = True
        try:
            self._f(*args)
            failed = False
        finally:
            barrier.leave(failed)

    threads = [BlockThread(target, self, grid_point, p, self._debug) for p in points]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    first = [barrier.failed] if barrier.failed is not None else []
    for t in first + threads:  # the original error first, not an "abort" it caused
        if t.exception:
            raise t.exception[0].with_traceback(t.exception[1])


def _syncthreads(self):
    self._manager._optri_barrier.wait()
