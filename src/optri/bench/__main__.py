"""``python -m optri.bench CSV DTYPE WARMUP``: the fresh-process worker of a benchmark.

Reads ``SECONDS CALLS`` lines from stdin, answers JSON lines (see
:func:`optri.bench.compare.serve`).
"""

import sys

from .compare import serve

serve(sys.argv[1:], sys.stdin, sys.stdout)
