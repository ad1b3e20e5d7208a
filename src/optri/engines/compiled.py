"""Compiling optri's kernels with numba, with a disk cache that never goes stale.

numba's on-disk cache keys a compiled function on its own source file only, so
a kernel that inlines a helper from another file (the weight formulas of
:mod:`optri.weights`, the predicates of :mod:`optri.predicates`) would be
served from a cache built before that helper changed. :func:`kernel` is
``numba.njit(cache=True)`` with the cache placed in a directory named after a
hash of every source file kernels are compiled from (:data:`KERNEL_SOURCES`),
so any change to any of them compiles afresh.

Where the cache lives: ``$NUMBA_CACHE_DIR`` (or ``config.JIT_CACHE_DIR``) when
set, else ``__pycache__`` beside this package when writable, else
``~/.cache/optri``; always in a subdirectory ``numba-<hash>``.

Imported only by the kernel modules, which load on first use: ``import optri``
never imports numba.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import os
import shutil
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numba
from numba.core import event

from .. import config
from .progress import announce_compile

__all__ = ["KERNEL_SOURCES", "cache_dir", "kernel", "source_hash"]

_PACKAGE = Path(__file__).resolve().parents[1]

#: Folders and files (relative to the package) whose code numba compiles: every kernel
#: module and every module a kernel calls into (tests/test_architecture.py checks this).
KERNEL_SOURCES = ("engines", "weights.py", "objective.py")
#: Cache directories of other source versions kept beside the current one.
_KEEP_OLD = 3


@functools.cache
def source_hash(package: Path = _PACKAGE) -> str:
    """Hash of the kernel sources (:data:`KERNEL_SOURCES` under ``package``) and numba's version."""
    digest = hashlib.sha256(numba.__version__.encode())
    for entry in KERNEL_SOURCES:
        path = package / entry
        files = sorted(path.rglob("*.py")) if path.is_dir() else [path]
        for f in files:
            digest.update(str(f.relative_to(package)).encode())
            digest.update(f.read_bytes())
    return digest.hexdigest()[:16]


@functools.cache
def cache_dir() -> str:
    """The directory numba caches optri's kernels in (created on first use)."""
    base = os.environ.get("NUMBA_CACHE_DIR") or config.JIT_CACHE_DIR
    candidates = [Path(base)] if base else [_PACKAGE / "__pycache__", _user_cache()]
    for root in candidates:
        target = root / f"numba-{source_hash()}"
        with contextlib.suppress(OSError):
            target.mkdir(parents=True, exist_ok=True)
            if os.access(target, os.W_OK):
                _prune(root, target)
                return str(target)
    return str(_user_cache() / f"numba-{source_hash()}")


class _CompileListener(event.Listener):  # type: ignore[misc]
    """numba broadcasts "numba:compile" only on a cache miss: a real compile is starting."""

    def on_start(self, event: Any) -> None:
        announce_compile()

    def on_end(self, event: Any) -> None:
        pass


event.register("numba:compile", _CompileListener())


def kernel(**options: Any) -> Callable[[Callable[..., Any]], Any]:
    """``numba.njit(cache=True, **options)``, cached under :func:`cache_dir`.

    Used as ``@kernel(parallel=True)`` on the functions of the kernel modules
    (the GPU engine's modules).
    """

    def decorate(func: Callable[..., Any]) -> Any:
        dispatcher = numba.njit(**options)(func)
        with _numba_cache_dir(cache_dir()):
            dispatcher.enable_caching()  # the locator reads config.CACHE_DIR now, once
        return dispatcher

    return decorate


@contextlib.contextmanager
def _numba_cache_dir(path: str) -> Iterator[None]:
    settings: Any = numba.config
    old = settings.CACHE_DIR
    settings.CACHE_DIR = path
    try:
        yield
    finally:
        settings.CACHE_DIR = old


def _user_cache() -> Path:
    root = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(root) / "optri"


def _prune(root: Path, current: Path) -> None:
    """Remove all but the newest few caches of other source versions."""
    others = sorted(
        (p for p in root.glob("numba-*") if p.is_dir() and p != current),
        key=lambda p: p.stat().st_mtime,
        reverse=True,
    )
    for old in others[_KEEP_OLD:]:
        shutil.rmtree(old, ignore_errors=True)
