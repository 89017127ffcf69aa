"""Progress of the long commands (``montecarlo``, ``sweep``, ``animate``, ``paper``) on stderr:
the one place that decides how it looks.

On a terminal a tqdm bar with the count, rate and ETA, redrawn in place; when stderr is not a
terminal (a log file, a pipe, CI) nothing while the work runs and one summary line when it
ends, so a log never receives carriage-return frames; nothing at all when not ``enabled``
(the CLI's ``--quiet``).
"""

from __future__ import annotations

import sys
import time
from typing import TextIO

__all__ = ["Progress"]


def _is_terminal(stream: TextIO) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):  # no isatty, or a closed stream
        return False


class Progress:
    """Progress of ``total`` units of work labelled ``label``; a context manager (leaving the
    block, normally or by an exception, closes the bar and prints the summary line).

    Parameters
    ----------
    label : str
        What is being done (e.g. "montecarlo").
    total : int
        Units of work in all.
    unit : str
        Name of a unit, plural (e.g. "draws").
    enabled : bool
        False: print nothing (``--quiet``).
    stream : text stream, optional
        Where to write (default ``sys.stderr`` at creation).
    """

    def __init__(
        self,
        label: str,
        total: int,
        unit: str,
        *,
        enabled: bool = True,
        stream: TextIO | None = None,
    ) -> None:
        self.label = label
        self.total = int(total)
        self.unit = unit
        self.enabled = enabled
        self.done = 0
        self._stream = sys.stderr if stream is None else stream
        self._start = time.perf_counter()
        self._closed = False
        self._bar = None
        if enabled and _is_terminal(self._stream):
            from tqdm import tqdm

            self._bar = tqdm(
                total=self.total,
                desc=label,
                unit=f" {unit}",
                file=self._stream,
                dynamic_ncols=True,
                leave=True,
            )

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    @property
    def terminal(self) -> bool:
        """Whether a live bar is drawn (enabled, on a terminal)."""
        return self._bar is not None

    def set_total(self, total: int) -> None:
        """The units of work in all, when known only once the work has started.

        Parameters
        ----------
        total : int
            Units of work in all.
        """
        self.total = int(total)
        if self._bar is not None:
            self._bar.total = self.total
            self._bar.refresh()

    def update(self, n: int = 1) -> None:
        """``n`` more units done.

        Parameters
        ----------
        n : int
            Units just finished.
        """
        self.done += int(n)
        if self._bar is not None:
            self._bar.update(int(n))

    def update_to(self, done: int) -> None:
        """``done`` units done in all.

        Parameters
        ----------
        done : int
            Units finished so far, in all.
        """
        self.update(int(done) - self.done)

    def note(self, message: str) -> None:
        """One line on stderr (shown even when not ``enabled``: it is a message, not
        progress), above the bar on a terminal.

        Parameters
        ----------
        message : str
            The line, without a newline.
        """
        if self._bar is not None:
            self._bar.write(message, file=self._stream)
        else:
            print(message, file=self._stream)
            self._stream.flush()

    def summary(self) -> str:
        """The final line: ``label: done/total unit in s (rate unit/s)``.

        Returns
        -------
        str
            The line, e.g. "montecarlo: 200/200 draws in 12.3 s, 16.3 draws/s".
        """
        elapsed = time.perf_counter() - self._start
        rate = f", {self.done / elapsed:.3g} {self.unit}/s" if elapsed > 0 and self.done else ""
        return f"{self.label}: {self.done}/{self.total} {self.unit} in {elapsed:.1f} s{rate}"

    def close(self) -> None:
        """End the bar (terminal) or print the summary line (otherwise); idempotent."""
        if self._closed:
            return
        self._closed = True
        if self._bar is not None:
            self._bar.close()
        elif self.enabled:
            print(self.summary(), file=self._stream)
            self._stream.flush()
