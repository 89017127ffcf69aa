"""A one-line progress bar on stderr that knows whether its line is open, so that a note, an
error or "interrupted" printed after it starts on a line of its own."""

from __future__ import annotations

import sys

__all__ = ["ProgressLine"]


class ProgressLine:
    """``label [#####     ] done/total unit  pct%`` redrawn in place on stderr (nothing when
    not ``enabled``). Used as a context manager: leaving the block, normally or by an
    exception, ends an open line."""

    def __init__(self, label: str, unit: str, *, enabled: bool = True) -> None:
        self.label = label
        self.unit = unit
        self.enabled = enabled
        self._open = False

    def __enter__(self) -> ProgressLine:
        return self

    def __exit__(self, *exc: object) -> None:
        self.end_line()

    def update(self, done: int, total: int) -> None:
        if not self.enabled:
            return
        frac = done / total if total else 1.0
        bar = "#" * int(30 * frac)
        print(
            f"\r{self.label} [{bar:<30}] {done}/{total} {self.unit} {100 * frac:5.1f}%",
            end="",
            file=sys.stderr,
        )
        self._open = True
        if done >= total:
            self.end_line()
        sys.stderr.flush()

    def end_line(self) -> None:
        if self._open:
            self._open = False
            print(file=sys.stderr)
            sys.stderr.flush()

    def note(self, message: str) -> None:
        """One line on stderr (progress or not)."""
        self.end_line()
        print(message, file=sys.stderr)
        sys.stderr.flush()
