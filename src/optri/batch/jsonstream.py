"""A GeoJSON FeatureCollection read feature by feature, in bounded memory.

:class:`JsonStream` is just enough of an incremental JSON reader to walk one
top-level object: values are decoded with :meth:`json.JSONDecoder.raw_decode`
from a buffer that grows from the file only while a value is incomplete, and
consumed text is dropped, so memory is bounded by the largest single feature.
A feature that is not JSON (or is nested too deeply for Python's decoder) but
whose brackets balance is skipped and reported as a :class:`BadValue`, so the
features after it are still read; a file that ends inside a value, or whose
top level is not a FeatureCollection, is refused with its file and line.
"""

from __future__ import annotations

import json
import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NoReturn

from .. import config
from ..errors import BatchInputError

__all__ = ["BadValue", "JsonStream", "read_feature_collection"]

# the characters that matter when skipping a value without decoding it
_STRUCTURE = re.compile(r'[\[\]{},"]')
_STRING = re.compile(r'"(?:[^"\\]|\\.)*"', re.DOTALL)


@dataclass(frozen=True)
class BadValue:
    """A value that could not be decoded: where it starts and why."""

    line: int
    reason: str


def read_feature_collection(
    path: Path, on_member: Callable[[str, Any], None]
) -> Iterator[tuple[Any, int]]:
    """Yield ``(feature or BadValue, line)`` for each element of ``features``.

    ``on_member(key, value)`` sees every other top-level member (``type``,
    ``crs``, ``name``...) as it is read.
    """
    stream = JsonStream(path)
    try:
        stream.expect("{")
        seen_features = False
        while stream.peek() != "}":
            key = stream.value()
            stream.expect(":")
            if key == "features":
                stream.expect("[")
                first = True
                while stream.peek() != "]":
                    if not first:
                        stream.expect(",")
                    first = False
                    line = stream.line()
                    yield stream.value(recover=True), line
                stream.expect("]")
                seen_features = True
            else:
                value = stream.value()
                if key == "type" and value != "FeatureCollection":
                    stream.fail(
                        f"not a polygon layer: type is {value!r}, expected FeatureCollection"
                    )
                on_member(str(key), value)
            if stream.peek() == ",":
                stream.expect(",")
        if not seen_features:
            stream.fail("not a polygon layer: no 'features' array")
    finally:
        stream.close()


class JsonStream:
    """Incremental reader of one JSON document, value by value."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.fh = path.open(encoding="utf-8-sig")  # tolerate a byte-order mark
        self.buf = ""
        self.pos = 0
        # a mark in buf and the newlines before it (dropped text included): line numbers
        # are counted from the mark on, so each feature costs its own length only
        self.mark_pos = 0
        self.mark_lines = 0
        self.eof = False
        self.decoder = json.JSONDecoder()

    def close(self) -> None:
        """Close the file (idempotent)."""
        self.fh.close()

    def _more(self) -> bool:
        if self.eof:
            return False
        try:
            block = self.fh.read(config.BATCH_READ_BLOCK)
        except UnicodeDecodeError as exc:
            self.fail(f"not UTF-8 text ({exc.reason})")
        if not block:  # keep buf as is: error positions still point into it
            self.eof = True
            return False
        self.line(self.pos)  # move the mark up to the text kept
        self.mark_pos -= self.pos
        self.buf = self.buf[self.pos :] + block
        self.pos = 0
        return True

    def _skip_space(self) -> None:
        while True:
            while self.pos < len(self.buf) and self.buf[self.pos] in " \t\r\n":
                self.pos += 1
            if self.pos < len(self.buf) or not self._more():
                return

    def line(self, at: int | None = None) -> int:
        """1-based line number of buffer position ``at`` (default: the current one)."""
        at = self.pos if at is None else at
        if at < self.mark_pos:
            return self.mark_lines - self.buf.count("\n", at, self.mark_pos) + 1
        self.mark_lines += self.buf.count("\n", self.mark_pos, at)
        self.mark_pos = at
        return self.mark_lines + 1

    def peek(self) -> str:
        """The next non-space character (not consumed)."""
        self._skip_space()
        if self.pos >= len(self.buf):
            self.fail("unexpected end of file (truncated JSON?)")
        return self.buf[self.pos]

    def expect(self, char: str) -> None:
        """Consume ``char`` or fail."""
        got = self.peek()
        if got != char:
            self.fail(f"invalid JSON: expected {char!r}, found {got!r}")
        self.pos += 1

    def value(self, recover: bool = False) -> Any:
        """Decode the next value; with ``recover`` a bad one is skipped as a :class:`BadValue`."""
        self.peek()
        while True:
            try:
                obj, end = self.decoder.raw_decode(self.buf, self.pos)
            except json.JSONDecodeError as exc:
                if _may_continue(exc, len(self.buf)) and self._more():
                    continue
                if recover and self.buf[exc.pos :].strip():
                    return self._skip_bad(f"invalid JSON ({exc.msg})")
                if not self.buf[exc.pos :].strip():
                    self.fail("unexpected end of file (truncated JSON?)", exc.pos)
                self.fail(f"invalid JSON ({exc.msg})", exc.pos)
            except RecursionError:
                if recover:
                    return self._skip_bad("invalid JSON (nested too deeply to read)")
                self.fail("invalid JSON (nested too deeply to read)")
            # a number could continue in the next block: only trust a value that ends early
            if end < len(self.buf) or not self._more():
                self.pos = end
                return obj

    def _skip_bad(self, reason: str) -> BadValue:
        """Skip the value at ``pos`` by matching brackets only; fail if the file ends inside it."""
        bad = BadValue(self.line(), reason)
        depth, i = 0, self.pos
        while True:
            m = _STRUCTURE.search(self.buf, i)
            if m is None:
                i = len(self.buf)
            elif m.group() == '"':
                s = _STRING.match(self.buf, m.start())
                if s is not None:
                    i = s.end()
                    continue
                i = m.start()  # an unterminated string: read on
            else:
                ch, i = m.group(), m.end()
                if ch in "[{":
                    depth += 1
                    continue
                if depth == 0:  # "," or a closing bracket of the enclosing array
                    self.pos = m.start()
                    return bad
                if ch in "]}":
                    depth -= 1
                    if depth == 0:
                        self.pos = i
                        return bad
                continue
            consumed = i - self.pos
            if not self._more():
                self.fail("unexpected end of file (truncated JSON?)")
            i = consumed  # _more moved buf so that it starts at the value

    def fail(self, message: str, at: int | None = None) -> NoReturn:
        """Raise BatchInputError naming the file and line of ``at``."""
        line = self.line(at)
        self.fh.close()
        raise BatchInputError(f"{self.path}:{line}: {message}")


def _may_continue(exc: json.JSONDecodeError, size: int) -> bool:
    # only an error at the end of the buffered text (or a string still open) can be
    # cured by reading on; anything earlier is a real syntax error
    return exc.pos >= size - 8 or exc.msg.startswith("Unterminated string")
