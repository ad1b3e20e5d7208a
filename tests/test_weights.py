"""Every built-in weight three ways, on the same random and degenerate triangles.

For each :class:`~optri.weights.WeightCode` (but ``CUSTOM``) the weight is
evaluated by

(a) the Python formula of :mod:`optri.weights` (what the Python engines call),
(b) its C++ twin in the compiled core (``src/core/weights.hpp``, what
    ``method="fast"`` calls), through ``optri._core.generic``, and
(c) its CUDA twin, the device functions of :mod:`optri.engines._gpu_device`,
    run under numba's CUDA simulator in a subprocess (``NUMBA_ENABLE_CUDASIM``
    must be set before numba is imported).

(a) and (b) must agree bit for bit, here and on triangles whose coordinates
span float64's whole range (the scaled paths of the formulas). (c) must agree
within :data:`ULPS` units in the last place: it is a second text of the
formulas, kept term by term in the same order (under the simulator it runs as
Python, so it agrees to the bit today), and on a GPU libdevice's ``acos`` may
differ by an ulp or two. The test
iterates over ``WeightCode``, so a weight added without its GPU twin fails here
(the device ``weight`` returns +inf for a code it does not know).
"""

from __future__ import annotations

import itertools
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from optri._core import generic as core

from gpu_env import subprocess_env
from optri.weights import WEIGHTS, WeightCode, edge_weight, edge_weight_row, triangle_weight

#: Units in the last place the CUDA twin may differ by.
ULPS = 4
CODES = [code for code in WeightCode if code != WeightCode.CUSTOM]
TWIN = Path(__file__).parent / "gpu_sim" / "weights_twin.py"


def planar_or_spatial(dim: int, seed: int, n: int = 12) -> np.ndarray:
    """Random points with degenerate and near-degenerate triangles among them."""
    rng = np.random.default_rng(seed)
    p = rng.uniform(-5.0, 5.0, (n, dim))
    # (0, 1, 2) exactly collinear (eighths, |u| = 5/8 or 3/4): zero area, an angle of pi
    u = np.array([0.375, 0.5]) if dim == 2 else np.array([0.25, 0.5, 0.5])
    p[0] = np.round(p[0] * 8.0) / 8.0
    p[1] = p[0] + u
    p[2] = p[0] + 2.0 * u
    p[3] = p[1]  # a repeated vertex: zero-length sides
    side = rng.normal(size=dim)
    side -= side @ u / (u @ u) * u  # perpendicular to u
    p[4] = p[0] + 3.0 * u + 1e-5 * side  # (0, 1, 4) nearly collinear: aspect ~1e10
    p[5] = p[6] + 1e-7 * rng.normal(size=dim)  # tiny sides next to long ones
    p[7] = 1e6 * rng.uniform(-1.0, 1.0, dim)  # large coordinates
    return p


def values(seed: int, n: int = 12) -> np.ndarray:
    """1-D vertex values: matrix dimensions, zero, negatives, a large one."""
    rng = np.random.default_rng(seed)
    v = rng.uniform(-3.0, 40.0, n)
    v[:4] = [30.0, 35.0, 0.0, 1e8]
    return v


#: Vertex data by what a weight reads (Weight.needs).
DATA = {
    "points": {"2-D": planar_or_spatial(2, seed=1), "3-D": planar_or_spatial(3, seed=2)},
    "values": {"1-D": values(seed=3)},
}


def registered(code: WeightCode):
    """The registry's weight for ``code`` (its ``needs`` picks the data), or None."""
    return next((w for w in WEIGHTS.values() if w.code == code), None)


def jobs():
    """``(kind, code, dataset name, data, index rows)`` for every comparison."""
    out = []
    for code in CODES:
        weight = registered(code)
        for name, data in DATA[weight.needs].items() if weight else ():
            n = len(data)
            out.append(("triangle", code, name, data, list(itertools.combinations(range(n), 3))))
            if weight.edge_decomposable:
                out.append(("edge", code, name, data, list(itertools.combinations(range(n), 2))))
    return out


JOBS = jobs()


def python_values(kind, code, data, rows):
    p = [tuple(r) for r in data.reshape(len(data), -1).tolist()]  # as the Python engines
    if kind == "triangle":
        return np.array([triangle_weight(code, p, *t) for t in rows])
    return np.array([edge_weight(code, p, *e) for e in rows])


def compiled_values(kind, code, data, rows):
    p = np.ascontiguousarray(data.reshape(len(data), -1), dtype=np.float64)  # as jit.py
    if kind == "triangle":
        return np.array([core.triangle_weight(int(code), p, *t) for t in rows])
    return np.array([core.edge_weight(int(code), p, *e) for e in rows])


def extreme(dim: int, seed: int) -> dict[str, np.ndarray]:
    """Points whose sides, squares or cubes leave float64's range: the scaled paths."""
    rng = np.random.default_rng(seed)
    out = {}
    for scale in (1e300, 1e154, 1e-155, 1e-300, 1e-310, 2.0**-1070):
        p = rng.uniform(-1.0, 1.0, (8, dim)) * scale
        p[7] = p[6] * 1e-3
        out[f"{dim}-D x {scale:g}"] = p
    mixed = rng.uniform(-1.0, 1.0, (8, dim))
    mixed[0] *= 1e300
    mixed[1] *= 1e-300
    mixed[2] = -mixed[0]
    mixed[3], mixed[4] = 1.7e308, -1.7e308  # differences overflow to infinity
    out[f"{dim}-D mixed"] = mixed
    return out


EXTREME = {**extreme(2, seed=4), **extreme(3, seed=5)}


@pytest.fixture(scope="module")
def cuda_values(tmp_path_factory):
    """Every job's values from the CUDA device functions, in one simulator process."""
    pytest.importorskip("numba_cuda", reason="the CUDA simulator comes with numba-cuda")
    folder = tmp_path_factory.mktemp("weights_twin")
    arrays = {}
    for j, (kind, code, _, data, rows) in enumerate(JOBS):
        arrays |= {f"kind_{j}": kind, f"code_{j}": int(code), f"data_{j}": data}
        arrays[f"idx_{j}"] = np.array(rows, dtype=np.int64)
    np.savez(folder / "jobs.npz", **arrays)
    cmd = [sys.executable, str(TWIN), str(folder / "jobs.npz"), str(folder / "out.npz")]
    proc = subprocess.run(
        cmd, env=subprocess_env(simulator=True), capture_output=True, text=True, timeout=300
    )
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    out = np.load(folder / "out.npz")
    return [out[f"out_{j}"] for j in range(len(JOBS))]


def ulps_apart(got, want, ulps):
    """Rows where ``got`` and ``want`` differ by more than ``ulps`` units in the last place."""
    same = (got == want) | (np.isnan(got) & np.isnan(want))
    finite = np.isfinite(got) & np.isfinite(want)
    with np.errstate(invalid="ignore"):  # inf - inf where one side is finite
        scale = np.spacing(np.maximum(np.abs(got), np.abs(want)))
        close = finite & (np.abs(got - want) <= ulps * scale)
    return np.flatnonzero(~(same | close))


def disagreements(other, ulps):
    """One line per weight code and data set where ``other`` differs from the formula.

    ``other(j, kind, code, data, rows)`` gives job ``j``'s values. One test over
    every code, not one per code: the simulator then runs once.
    """
    problems = []
    for code in CODES:
        if registered(code) is None:
            problems.append(f"{code!r} has no registered weight (optri.weights registry)")
        for j, (kind, job_code, name, data, rows) in enumerate(JOBS):
            if job_code != code:
                continue
            want = python_values(kind, code, data, rows)
            got = other(j, kind, code, data, rows)
            bad = ulps_apart(got, want, ulps)
            if np.isnan(want).any():
                problems.append(f"{code.name}: the Python formula does not know the code")
            elif bad.size:
                first = bad[0]
                problems.append(
                    f"{code.name} {kind} on {name}: {bad.size} of {len(rows)} differ, e.g. "
                    f"{rows[first]}: {got[first]!r} != {want[first]!r}"
                )
    return problems


def bits(values):
    return np.asarray(values, dtype=np.float64).view(np.int64)


def test_python_and_core_weights_agree_bit_for_bit():
    problems = disagreements(lambda j, *job: compiled_values(*job), ulps=0)
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("name", sorted(EXTREME))
def test_python_and_core_weights_agree_bit_for_bit_over_the_whole_range(name):
    data = EXTREME[name]
    rows = [tuple(r) for r in data.tolist()]
    triples = list(itertools.combinations(range(len(data)), 3))
    for code in CODES:
        if registered(code).needs == "values":
            continue
        want = [triangle_weight(code, rows, *t) for t in triples]
        got = compiled_values("triangle", code, data, triples)
        assert np.array_equal(bits(got), bits(want)), (code.name, name)
        pairs = list(itertools.combinations(range(len(data)), 2))
        want = [edge_weight(code, rows, *e) for e in pairs]
        got = compiled_values("edge", code, data, pairs)
        assert np.array_equal(bits(got), bits(want)), (code.name, name)
    # the scaled paths were taken: sides outside [2**-250, 2**250], where cubes leave the range
    sides = [math.dist(rows[a], rows[b]) for a, b in itertools.combinations(range(len(rows)), 2)]
    assert any(not 2.0**-250 < s < 2.0**250 for s in sides), name


@pytest.mark.parametrize("name", sorted(EXTREME) + ["2-D", "3-D"])
@pytest.mark.parametrize("code", [WeightCode.PERIMETER, WeightCode.DIAGONAL])
def test_edge_weight_rows_agree_bit_for_bit(name, code):
    data = EXTREME.get(name)
    if data is None:
        data = DATA["points"][name]
    p = np.ascontiguousarray(data, dtype=np.float64)
    n = len(p)
    for a in range(n):
        for b0 in range(n):
            want = np.empty(n - b0)
            edge_weight_row(code, p, a, b0, want)
            got = core.edge_weight_row(int(code), p, a, b0, n - b0)
            assert np.array_equal(bits(got), bits(want)), (a, b0)


def test_cuda_twin_agrees_with_the_python_formula(cuda_values):
    problems = disagreements(lambda j, *job: cuda_values[j], ulps=ULPS)
    assert not problems, "\n".join(problems)


def test_the_data_hold_degenerate_triangles():
    # the degenerate cases the data were built with really are there
    for name, data in DATA["points"].items():
        p = [tuple(r) for r in data.tolist()]
        ratio = [triangle_weight(WeightCode.ASPECT_RATIO, p, *t) for t in [(0, 1, 2), (1, 3, 5)]]
        assert ratio == [math.inf, math.inf], name
        assert triangle_weight(WeightCode.MAX_ANGLE, p, 0, 1, 2) == math.pi, name
        assert 1e6 < triangle_weight(WeightCode.ASPECT_RATIO, p, 0, 1, 4) < math.inf, name
