"""A small reader of numpydoc sections, for the scenario reference (which prints the keys'
descriptions from the classes' own ``Parameters``) and for the docstring test.

Only what those two need: section titles underlined with dashes, and in ``Parameters``
entries of the form ``name[, name...] : type`` followed by an indented description.
"""

from __future__ import annotations

import inspect
import re

__all__ = ["parameter_docs", "sections"]

_UNDERLINE = re.compile(r"^-{3,}$")


def sections(doc: str | None) -> dict[str, list[str]]:
    """The numpydoc sections of a docstring.

    Parameters
    ----------
    doc : str or None
        A docstring (raw, as ``__doc__`` holds it).

    Returns
    -------
    dict of str to list of str
        Section title (e.g. ``"Parameters"``) -> its lines, dedented; the text before the
        first section is under ``""``.
    """
    lines = inspect.cleandoc(doc or "").splitlines()
    out: dict[str, list[str]] = {"": []}
    title = ""
    i = 0
    while i < len(lines):
        if i + 1 < len(lines) and lines[i].strip() and _UNDERLINE.match(lines[i + 1].strip()):
            title = lines[i].strip()
            out[title] = []
            i += 2
            continue
        out[title].append(lines[i])
        i += 1
    return out


def parameter_docs(doc: str | None, section: str = "Parameters") -> dict[str, tuple[str, str]]:
    """The entries of a ``Parameters``-style section.

    Parameters
    ----------
    doc : str or None
        A docstring.
    section : str, optional
        The section to read (default ``"Parameters"``).

    Returns
    -------
    dict of str to (str, str)
        Each documented name -> (its type text, its description joined into one line). A
        line ``a, b : float`` documents both ``a`` and ``b``.
    """
    out: dict[str, tuple[str, str]] = {}
    names: list[str] = []
    kind = ""
    text: list[str] = []

    def flush() -> None:
        for name in names:
            out[name] = (kind, " ".join(text))

    for line in sections(doc).get(section, []):
        if line and not line[0].isspace():
            flush()
            head, _, kind = line.partition(" : ")
            names = [n.strip() for n in head.split(",") if n.strip()]
            kind = kind.strip()
            text = []
        elif line.strip():
            text.append(line.strip())
    flush()
    return out
