import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
# this checkout's optri, whatever else is installed; helper modules beside the tests
sys.path[:0] = [os.path.join(os.path.dirname(HERE), "src"), HERE]

# the mutation runner (tests/mutations/run.py) is a script, not tests
collect_ignore = ["mutations"]

import matplotlib  # noqa: E402  (a core dependency of optri)

matplotlib.use("Agg")
