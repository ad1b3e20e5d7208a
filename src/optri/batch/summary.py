"""What a batch run reports: :class:`BatchSummary`, the running counts, duplicate ids."""

from __future__ import annotations

import collections
import hashlib
import warnings
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import DuplicateIdWarning

__all__ = ["BatchSummary", "Counter", "id_hash"]

#: Duplicate ids named in the warning.
_NAMED = 5


@dataclass(frozen=True)
class BatchSummary:
    """Counts of a batch run.

    Attributes
    ----------
    total, ok, errors : int
        Polygons read, triangulated, and given error records.
    partitions, reused : int
        Part files in the output, and how many an earlier run had already written.
    seconds : float
        Wall time of this run.
    output : Path
        The output directory or file.
    duplicates : int
        Records whose id an earlier record of the same output already has.

    Examples
    --------
    >>> import optri, tempfile, pathlib
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "footprints.ndjson"
    >>> s = optri.batch(optri.data.path("footprints.ndjson"), out, workers=1)
    >>> s.total, s.ok, s.errors       # one bow-tie among the 31 footprints
    (31, 30, 1)
    """

    total: int
    ok: int
    errors: int
    partitions: int
    reused: int
    seconds: float
    output: Path
    duplicates: int = 0

    def __str__(self) -> str:
        rate = self.total / self.seconds if self.seconds > 0 else 0.0
        dup = f", {self.duplicates} duplicate ids" if self.duplicates else ""
        return (
            f"{self.total} polygons: {self.ok} ok, {self.errors} errors{dup} in "
            f"{self.seconds:.2f} s ({rate:.0f}/s; {self.partitions} partitions, "
            f"{self.reused} reused) -> {self.output}"
        )


class Counter:
    """Running totals, reported to ``progress`` after each chunk, and the ids seen.

    Ids are kept as 64-bit hashes (8 bytes a record), so a run of ten million
    features holds 80 MB of them; the ids themselves are looked up again in
    the output only when some hashes repeat.
    """

    def __init__(self, progress: Callable[[int, int], None] | None, total: int) -> None:
        self.progress, self.total = progress, total
        self.n = self.ok = self.errors = self.parts = self.reused = 0
        self.hashes: list[np.ndarray] = []
        if progress is not None:
            progress(0, total)

    def add(self, records: Iterable[dict], reused: bool) -> None:
        """Count one part's records."""
        ids = []
        ok = 0
        for rec in records:
            ok += rec["status"] == "ok"
            ids.append(id_hash(rec["id"]))
        self.add_counts(np.array(ids, dtype=np.int64), ok, reused)

    def add_counts(self, hashes: np.ndarray, ok: int, reused: bool = False) -> None:
        """Count one part given as its ids' hashes (:func:`id_hash`) and its ok records."""
        self.n += len(hashes)
        self.ok += ok
        self.hashes.append(hashes)
        self.errors = self.n - self.ok
        self.parts += 1
        self.reused += reused
        if self.progress is not None:
            self.progress(self.n, max(self.total, self.n))

    def add_rows(self, ids: list[Any], statuses: list[str]) -> None:
        """Count one part's rows, given as columns."""
        self.add(({"id": i, "status": st} for i, st in zip(ids, statuses)), reused=False)

    def repeated_hashes(self) -> tuple[int, set[int]]:
        """How many records repeat an earlier id hash, and which hashes repeat."""
        if not self.hashes:
            return 0, set()
        all_ = np.sort(np.concatenate(self.hashes))
        same = all_[1:] == all_[:-1]
        return int(np.count_nonzero(same)), {int(h) for h in all_[1:][same]}

    def summary(self, output: Path, seconds: float, duplicates: int = 0) -> BatchSummary:
        """The summary of this run."""
        return BatchSummary(
            self.n, self.ok, self.errors, self.parts, self.reused, seconds, output, duplicates
        )


def id_hash(value: Any) -> int:
    """A 64-bit hash of an id, the same in every process (worker processes hash their parts).

    By text: table formats may store the ids of a file mixing numbers and text as text.

    >>> id_hash(7) == id_hash("7"), id_hash("a") == id_hash("b")
    (True, False)
    """
    digest = hashlib.blake2b(str(value).encode("utf-8", "surrogatepass"), digest_size=8)
    return int.from_bytes(digest.digest(), "little", signed=True)


def report_duplicates(count: int, hashes: set[int], records: Iterator[dict]) -> None:
    """Warn about duplicate ids, naming a few (looked up in ``records``, the output)."""
    if not count:
        return
    seen: collections.Counter[Any] = collections.Counter()
    for rec in records:
        rid = rec["id"]
        if id_hash(rid) in hashes:
            seen[str(rid)] += 1
    named = [f"{k!r} x{v}" for k, v in seen.most_common() if v > 1][:_NAMED]
    warnings.warn(
        f"{count} record(s) repeat an earlier id ({', '.join(named)}); ids should be unique",
        DuplicateIdWarning,
        stacklevel=3,
    )
