"""The compiled core as a user meets it: no JIT, no numba, one instruction-set level at a time.

A base install has no numba: every built-in weight and objective, simple polygons, many
polygons at once and polygons with holes run on ``optri._core``. These tests run a fresh
interpreter (empty caches, this checkout's ``src`` first) and look at ``sys.modules``
after the work.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

import optri
from optri import _core

SRC = Path(__file__).resolve().parents[1] / "src"

SOLVE_EVERYTHING = r"""
import json, math, sys
import numpy as np
import optri
from optri.weights import WeightCode

t = np.linspace(0, 2 * math.pi, 60, endpoint=False)
convex = np.column_stack([np.cos(t), np.sin(t) * 0.7])
r = 1 + 0.4 * np.cos(5 * t)
star = np.column_stack([r * np.cos(t), r * np.sin(t)])
values = [30.0, 35.0, 15.0, 5.0, 10.0, 20.0, 25.0]
done = []
weights = [w.name.lower() for w in WeightCode if w != WeightCode.CUSTOM]
for name in weights:
    data = values if name == "product" else convex
    for objective in ("sum", "max"):
        for method in ("fast", "auto"):
            optri.triangulate(data, name, objective=objective, method=method)
            done.append((name, objective, method))
    if name != "product":
        optri.triangulate(star, name, method="fast")
        optri.triangulate(convex, [name, "perimeter"], objective=("max", "sum"), method="fast")
        optri.triangulate(convex, [name, "area"], objective=("sum", "sum"), method="fast")
optri.triangulate(convex, "perimeter", method="fast", dtype="float32")
optri.triangulate_many([convex, star, convex[::2]])
print(json.dumps({"numba": sorted(m for m in sys.modules if m.split(".")[0] == "numba"),
                  "done": len(done)}))
"""


def _fresh(code: str, tmp_path: Path, **extra: str) -> subprocess.CompletedProcess[str]:
    env = dict(os.environ)
    env.update(
        PYTHONPATH=str(SRC),
        HOME=str(tmp_path),
        NUMBA_CACHE_DIR=str(tmp_path / "numba"),
        MPLBACKEND="Agg",
        **extra,
    )
    return subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=600
    )


def test_built_in_weights_and_objectives_never_import_numba(tmp_path):
    res = _fresh(SOLVE_EVERYTHING, tmp_path)
    assert res.returncode == 0, res.stderr[-2000:]
    out = json.loads(res.stdout.strip().splitlines()[-1])
    assert out["done"] >= 24
    assert out["numba"] == []


def test_the_core_names_its_levels_and_runs_at_the_best():
    levels = _core.simd_levels()
    assert levels[0] == "portable"
    assert _core.simd_level() in levels
    assert len(set(levels)) == len(levels)


def test_an_unknown_or_missing_level_is_refused(tmp_path):
    res = _fresh("import optri; optri.triangulate([(0,0),(1,0),(0,1)], method='fast')",
                 tmp_path, OPTRI_SIMD="sse9")
    assert res.returncode != 0
    last = res.stderr.strip().splitlines()[-1]
    assert "OPTRI_SIMD" in last and "portable" in last


@pytest.mark.parametrize("level", ["portable", "baseline", "avx2", "avx512"])
def test_each_level_the_cpu_has_gives_the_same_weight(level, tmp_path):
    if level not in _core.simd_levels():
        pytest.skip(f"this CPU has no {level}")
    code = (
        "import hashlib, math, numpy as np, optri\n"
        "t = np.linspace(0, 2 * math.pi, 301, endpoint=False)\n"
        "P = np.column_stack([np.cos(t), np.sin(t) * 0.6 + 0.01 * np.cos(7 * t)])\n"
        "s = optri.triangulate(P, 'perimeter', method='fast', keep_table=True)\n"
        "h = lambda a: hashlib.sha256(a.tobytes()).hexdigest()\n"
        "print(s.weight.hex(), h(s.table), h(s.triangles))\n"
    )
    here = _fresh(code, tmp_path, OPTRI_SIMD=level)
    best = _fresh(code, tmp_path)
    assert here.returncode == 0 and best.returncode == 0, here.stderr[-2000:] + best.stderr[-2000:]
    assert here.stdout == best.stdout


def test_thread_count_follows_optri_num_threads(tmp_path):
    code = (
        "import math, numpy as np, optri\n"
        "t = np.linspace(0, 2 * math.pi, 900, endpoint=False)\n"
        "P = np.column_stack([np.cos(t), np.sin(t)])\n"
        "print(optri.triangulate(P, method='fast').stats['threads'])\n"
    )
    res = _fresh(code, tmp_path, OPTRI_NUM_THREADS="1")
    assert res.returncode == 0, res.stderr[-2000:]
    assert res.stdout.strip() == "1"


def test_version_of_the_core_matches_the_package():
    assert optri.__version__
