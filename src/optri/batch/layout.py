"""Where a batch writes: part files, the manifest, ``_SUCCESS``, and resume checks.

Two layouts, chosen by the output path:

* a directory (no known suffix, or an existing directory): ``OUT/part-00000.ndjson``,
  ``OUT/part-00001.ndjson``, ... plus ``OUT/_manifest.json`` (the options and input
  the parts were made from) and, once every part is written, ``OUT/_SUCCESS``;
* a single file (``OUT.ndjson``, ``.jsonl``, ``.geojson``, ``.json``, ``.parquet``):
  the same parts are made in a hidden directory ``.OUT.parts`` beside it, joined
  into ``OUT`` atomically at the end, and the hidden directory removed.

Part ``k`` always holds input polygons ``k*chunk_size`` to ``(k+1)*chunk_size - 1``,
so a part that exists is the same whichever run wrote it.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import BatchInputError
from ..io.atomic import write_json
from .writers import OUTPUT_FORMATS, SINGLE_FILE_SUFFIXES

__all__ = ["Layout", "plan_layout"]

MANIFEST = "_manifest.json"
SUCCESS = "_SUCCESS"


@dataclass(frozen=True)
class Layout:
    """Paths of one batch output."""

    target: Path
    parts_dir: Path
    fmt: str
    single: bool

    def part(self, index: int) -> Path:
        """Path of part ``index``."""
        return self.parts_dir / f"part-{index:05d}{OUTPUT_FORMATS[self.fmt]}"

    def parts(self) -> list[Path]:
        """Existing complete part files, in order."""
        return sorted(self.parts_dir.glob(f"part-*{OUTPUT_FORMATS[self.fmt]}"))

    @property
    def manifest(self) -> Path:
        """The ``_manifest.json`` path."""
        return self.parts_dir / MANIFEST

    @property
    def success(self) -> Path:
        """The ``_SUCCESS`` marker path."""
        return self.parts_dir / SUCCESS

    def started(self) -> bool:
        """True when an earlier run left output here."""
        if self.single and self.target.exists():
            return True
        return self.manifest.exists() or bool(self.parts())

    def clear(self) -> None:
        """Remove earlier output (``overwrite``): only files a batch writes."""
        if self.single:
            with contextlib.suppress(FileNotFoundError):
                self.target.unlink()
            shutil.rmtree(self.parts_dir, ignore_errors=True)
            return
        if not self.parts_dir.is_dir():
            return
        for p in self.parts_dir.iterdir():
            if p.name in (MANIFEST, SUCCESS) or _is_ours(p.name):
                p.unlink()

    def remove_stale_temporaries(self) -> None:
        """Delete half-written parts left by a run killed with SIGKILL."""
        if self.parts_dir.is_dir():
            for p in self.parts_dir.glob(".part-*.tmp"):
                with contextlib.suppress(FileNotFoundError):
                    p.unlink()

    def check_manifest(self, manifest: dict[str, Any]) -> None:
        """Write the manifest, or check it matches the one of the run being resumed."""
        if self.manifest.exists():
            try:
                old = json.loads(self.manifest.read_text())
            except (OSError, ValueError) as exc:
                raise BatchInputError(f"{self.manifest}: unreadable ({exc})") from None
            diff = sorted(k for k in manifest.keys() | old.keys() if manifest.get(k) != old.get(k))
            if diff:
                raise BatchInputError(
                    f"{self.target} was written from a different input or options "
                    f"(changed: {', '.join(diff)}); pass --overwrite to redo it"
                )
            return
        write_json(self.manifest, manifest)


def plan_layout(out: str | os.PathLike[str], out_fmt: str | None) -> Layout:
    """Pick the layout and format for output path ``out``.

    >>> plan_layout("results.geojson", None).single
    True
    >>> plan_layout("results", None).part(3).name
    'part-00003.ndjson'
    """
    target = Path(out)
    if out_fmt is not None and out_fmt not in OUTPUT_FORMATS:
        raise BatchInputError(
            f"unknown output format {out_fmt!r}; choose one of {list(OUTPUT_FORMATS)}"
        )
    suffix_fmt = SINGLE_FILE_SUFFIXES.get(target.suffix.lower())
    if suffix_fmt is not None and not target.is_dir():
        if out_fmt is not None and out_fmt != suffix_fmt:
            raise BatchInputError(
                f"{target}: the suffix says {suffix_fmt} but --out-format is {out_fmt}"
            )
        hidden = target.parent / f".{target.name}.parts"
        return Layout(target, hidden, suffix_fmt, True)
    if target.exists() and not target.is_dir():
        raise BatchInputError(f"{target}: exists and is not a directory or a known output file")
    return Layout(target, target, out_fmt or "ndjson", False)


def _is_ours(name: str) -> bool:
    return name.startswith(("part-", ".part-")) and name.split(".")[-1] in (
        "ndjson",
        "geojson",
        "parquet",
        "tmp",
    )
