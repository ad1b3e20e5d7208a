"""``python -m optri.bench CSV REPEATS DTYPE``: the fresh-process worker of a benchmark."""

import json
import sys

from .compare import worker

print(json.dumps(worker(sys.argv[1], int(sys.argv[2]), sys.argv[3])))
