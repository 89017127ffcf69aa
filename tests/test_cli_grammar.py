"""Issue 25, item 6: one CLI grammar. A closed pipe (``tetherheli scenarios | head -1``) ends
quietly with exit 0 (it was "internal error (BrokenPipeError)", exit 70); the shared flags
have one help text, wherever they apply."""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
from pathlib import Path

import pytest

from tetherheli.cli import build_parser

SRC = Path(__file__).resolve().parents[1] / "src"


@pytest.mark.parametrize("argv", [["scenarios"], ["trim", "--json"]])
def test_a_closed_pipe_ends_quietly_with_exit_0(argv):
    """The reader of stdout is gone before the command writes: no message, exit 0."""
    env = {**os.environ, "PYTHONPATH": str(SRC)}
    proc = subprocess.Popen(
        [sys.executable, "-m", "tetherheli", *argv],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        env=env,
    )
    proc.stdout.close()  # as ``| head -1`` does after its line
    _, err = proc.communicate(timeout=300)
    assert proc.returncode == 0, err.decode()
    assert err.decode() == ""


def _subcommands() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(action.choices)


SHARED = ("--force", "--workers", "--figure-format", "--quiet", "--debug")


def test_each_shared_flag_has_one_help_text():
    """``--force``, ``--workers``, ``--figure-format``, ``--quiet``, ``--debug``: the same help
    in every command that has them; ``compare`` and ``tether-study`` have ``--figure-format``;
    no help says "(issue 13)"."""
    helps: dict[str, set[str]] = {flag: set() for flag in SHARED}
    commands = _subcommands()
    for name, sub in commands.items():
        for action in sub._actions:
            for flag in action.option_strings:
                if flag in helps:
                    helps[flag].add(action.help)
            assert "issue 13" not in (action.help or ""), (name, action.option_strings)
        assert "issue 13" not in (sub.description or "")
    for flag, texts in helps.items():
        assert len(texts) == 1, (flag, texts)
    for name in ("compare", "tether-study"):
        flags = {f for a in commands[name]._actions for f in a.option_strings}
        assert "--figure-format" in flags, name
        assert "--force" in flags, name
    assert "--workers" in {f for a in commands["tether-study"]._actions for f in a.option_strings}
