"""Engine registry and the ``method="auto"`` choice.

An engine is a module with ``solve(problem) -> Solution`` and, optionally,
``unavailable() -> str | None`` (why it cannot run here),
``unsupported(problem) -> str | None`` (why it cannot take this problem),
``auto_accepts(problem) -> bool`` (whether ``"auto"`` should use it),
``SUPPORTS_GATES = True`` when it honours :attr:`Problem.gates` and
``EXACT_INTS = True`` when it computes integer costs exactly at any size
(:attr:`Problem.needs_big_ints`).
Modules load on first use, so importing optri never imports numba or CUDA.
"""

from __future__ import annotations

import importlib
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from types import ModuleType

from ..errors import EngineUnavailableError
from .problem import Problem, Solution

__all__ = [
    "ENGINES",
    "AUTO_ORDER",
    "EngineSpec",
    "check_method",
    "register_engine",
    "select_engine",
]


@dataclass(frozen=True)
class EngineSpec:
    """Where an engine lives and what it is."""

    name: str
    module: str
    description: str

    def load(self) -> ModuleType:
        """Import the engine module."""
        return importlib.import_module(self.module)


ENGINES: dict[str, EngineSpec] = {}

#: Engines tried in turn by ``method="auto"``; the first that can take the problem wins.
AUTO_ORDER = ("integer", "gpu", "fast", "table")


def register_engine(spec: EngineSpec) -> None:
    """Add or replace an engine in the registry."""
    ENGINES[spec.name] = spec


for _spec in (
    EngineSpec("memo", "optri.engines.memo", "top-down memoization (paper Alg. 3.1), pure Python"),
    EngineSpec("table", "optri.engines.table", "bottom-up square-matrix tabulation, pure Python"),
    EngineSpec(
        "brute", "optri.engines.brute", "exhaustive search over all triangulations (oracle)"
    ),
    EngineSpec("naive", "optri.engines.naive", "un-memoized recursion, 3^(n-2) calls (teaching)"),
    EngineSpec("fast", "optri.engines.jit", "compiled core (C++), parallel, one n x n table"),
    EngineSpec("gpu", "optri.engines.gpu", "numba-cuda tiled wavefront on one GPU"),
    EngineSpec(
        "integer", "optri.engines.integer", "exact integer DP for 'product' on integer values"
    ),
):
    register_engine(_spec)


def _reason_unavailable(spec: EngineSpec) -> tuple[ModuleType | None, str | None]:
    try:
        module = spec.load()
    except ImportError as exc:
        return None, f"engine {spec.name!r} cannot be loaded ({exc})"
    check = getattr(module, "unavailable", None)
    reason = check() if check is not None else None
    return module, reason


def _reason_unsupported(module: ModuleType, problem: Problem) -> str | None:
    # gated problems (second phase of a max-led lexicographic objective) must never
    # reach an engine that would silently ignore the gate
    if problem.gates and not getattr(module, "SUPPORTS_GATES", False):
        return "it does not support lexicographic objectives led by 'max' (triangle gates)"
    if problem.needs_big_ints and not getattr(module, "EXACT_INTS", False):
        return (
            "its float tables cannot hold this problem's integer costs exactly (above "
            "2**53); use method='integer', 'memo' or 'table' (exact integers)"
        )
    check = getattr(module, "unsupported", None)
    return check(problem) if check is not None else None


def check_method(method: object) -> str:
    """``method`` if it names an engine or is ``"auto"``; checked before any work.

    >>> check_method("fasst")
    Traceback (most recent call last):
    ...
    optri.errors.EngineUnavailableError: unknown method 'fasst'; choose one of: auto, ...
    """
    if not isinstance(method, str) or (method != "auto" and method not in ENGINES):
        known = ", ".join(["auto", *ENGINES])
        raise EngineUnavailableError(f"unknown method {method!r}; choose one of: {known}")
    return method


def select_engine(method: str, problem: Problem) -> tuple[str, Callable[[Problem], Solution]]:
    """Return ``(name, solve)`` for ``method`` on ``problem``.

    ``"auto"`` tries :data:`AUTO_ORDER`; an engine that declines a problem it
    would normally take (a plain Python weight for the compiled engine) is
    skipped with a warning that says why.

    Raises
    ------
    EngineUnavailableError
        Unknown method, or the named engine cannot run here or take the problem.
    """
    if isinstance(method, str) and method == "auto":
        for name in AUTO_ORDER:
            spec = ENGINES.get(name)
            if spec is None:
                continue
            module, reason = _reason_unavailable(spec)
            if module is None or reason is not None:
                continue
            auto_ok = getattr(module, "auto_accepts", None)
            if auto_ok is not None and not auto_ok(problem):
                continue
            reason = _reason_unsupported(module, problem)
            if reason is not None:
                if name == "fast" and not problem.needs_big_ints:
                    warnings.warn(
                        f"{reason}; falling back to the pure-Python engine",
                        RuntimeWarning,
                        stacklevel=3,
                    )
                continue
            return name, module.solve
        raise EngineUnavailableError("no engine can take this problem")  # pragma: no cover
    spec = ENGINES[check_method(method)]
    module, reason = _reason_unavailable(spec)
    if module is None or reason is not None:
        raise EngineUnavailableError(reason or f"engine {method!r} is unavailable")
    reason = _reason_unsupported(module, problem)
    if reason is not None:
        raise EngineUnavailableError(f"method={method!r} cannot take this problem: {reason}")
    return method, module.solve
