"""A one-line progress bar on stderr that knows whether it left the terminal line open, so
that a later message (an interrupt, an error) starts on a line of its own."""

from __future__ import annotations

import sys

__all__ = ["line_open", "show_progress"]

_state = {"open": False}


def show_progress(label: str, done: int, total: int, unit: str) -> None:
    """Redraw ``label [#####     ] done/total unit  pct%``; the line closes at ``total``."""
    frac = done / total if total else 1.0
    bar = "#" * int(30 * frac)
    finished = done >= total
    print(
        f"\r{label} [{bar:<30}] {done}/{total} {unit} {100 * frac:5.1f}%",
        end="\n" if finished else "",
        file=sys.stderr,
    )
    sys.stderr.flush()
    _state["open"] = not finished


def line_open() -> bool:
    """True while a progress line is drawn and not finished."""
    return _state["open"]
