"""``python -m optri.bench CSV REPEATS DTYPE [WARMUP]``: the fresh-process worker of a benchmark."""

import json
import sys

from .compare import worker

warmup = float(sys.argv[4]) if len(sys.argv) > 4 else 0.0
print(json.dumps(worker(sys.argv[1], int(sys.argv[2]), sys.argv[3], warmup)))
