"""A user weight whose Dask worker dies the first time it sees a heptagon (marker file)."""

from __future__ import annotations

import os
from pathlib import Path

#: The environment variable naming the marker file (set before the cluster starts,
#: so its worker processes inherit it).
MARKER_ENV = "OPTRI_TEST_DIE_ONCE"


def dies_once(vertices, i, k, j):
    """Weight 1 per triangle; the first heptagon any worker meets ends that worker's process.

    The marker file is created before the process ends, so the rerun of the
    task (on the restarted or the other worker) and the in-memory oracle solve it.
    """
    marker = os.environ.get(MARKER_ENV)
    if marker and len(vertices) == 7 and not Path(marker).exists():
        Path(marker).write_text(str(os.getpid()))
        os._exit(1)
    return 1.0
