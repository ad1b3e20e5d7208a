"""Run ``optri batch`` and interrupt it at a fixed point (a script the resume tests run).

    python batch_interrupt.py SIGNAL PART -- batch ARGS...

runs the command line ``optri batch ARGS`` in this process and, while the run
writes its PART-th part file (counting from 1) and has written that file's
first record, sends itself SIGNAL (``INT`` or ``TERM``). The signal lands with a
temporary part file open, at the same point in every run: no sleeps, no races.
Python runs signal handlers in the main thread, which alone writes parts.
"""

from __future__ import annotations

import os
import signal
import sys
from collections.abc import Iterator, Sequence
from typing import Any

from optri.batch import driver
from optri.cli import main


class _SignalAfterFirst(list):
    """The records of one part; iterating past the first sends ``sig`` to this process."""

    def __init__(self, records: Sequence[dict], sig: int) -> None:
        super().__init__(records)
        self.sig = sig

    def __iter__(self) -> Iterator[dict]:
        for index, record in enumerate(list.__iter__(self)):
            if index == 1:
                os.kill(os.getpid(), self.sig)
            yield record


def interrupt_part(part: int, sig: int) -> None:
    """Make the driver's ``part``-th ``write_part`` call of this run signal ``sig`` midway."""
    real = driver.write_part
    calls = 0

    def write_part(path: Any, fmt: str, records: Sequence[dict], *args: Any, **kw: Any) -> None:
        nonlocal calls
        calls += 1
        if calls == part:
            records = _SignalAfterFirst(records, sig)
        real(path, fmt, records, *args, **kw)

    driver.write_part = write_part  # type: ignore[assignment]


if __name__ == "__main__":
    name, part, dashes, *args = sys.argv[1:]
    assert dashes == "--", __doc__
    # Python's own Ctrl-C handler even where this process started with SIGINT ignored (a
    # background job of a shell without job control): else SIGINT would not stop the run
    signal.signal(signal.SIGINT, signal.default_int_handler)
    interrupt_part(int(part), getattr(signal, "SIG" + name))
    main(args, prog_name="optri")
