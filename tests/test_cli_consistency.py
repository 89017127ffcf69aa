"""The command line's flags are consistent: help text on every flag, no reStructuredText in
--help, --out / --quiet / --workers / --seed / --figure-format spelled the same everywhere,
and derive's old --output gone (no external users: refused, exit 2)."""

from __future__ import annotations

import argparse
import re

import pytest

from tetherheli import cli
from tetherheli.results.result import RESULT_FORMATS, TABLE_FORMATS
from tetherheli.viz.plots import FIGURE_FORMATS

#: reStructuredText markup that must not reach --help: ``literal``, `interpreted`, roles
_RST = re.compile(r"``|`[^`]+`|:(func|class|mod|meth|attr|data|ref|doc|math):")


def _subparsers(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    (action,) = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    return dict(action.choices)


def _flags(parser: argparse.ArgumentParser) -> dict[str, argparse.Action]:
    return {s: a for a in parser._actions for s in a.option_strings}


def test_every_flag_and_argument_has_help():
    parser = cli.build_parser()
    missing = []
    for name, sub in {"": parser, **_subparsers(parser)}.items():
        for a in sub._actions:
            if isinstance(a, (argparse._SubParsersAction, argparse._HelpAction)):
                continue
            if a.help == argparse.SUPPRESS:  # a hidden deprecated alias
                continue
            if not (a.help and a.help.strip()):
                missing.append(f"{name} {'/'.join(a.option_strings) or a.dest}")
    assert missing == []


def test_help_has_no_restructuredtext():
    parser = cli.build_parser()
    for name, sub in {"tetherheli": parser, **_subparsers(parser)}.items():
        text = sub.format_help()
        assert _RST.search(text) is None, (name, _RST.search(text).group(0))


def test_the_rst_check_can_fail():
    assert _RST.search("see ``--out``") and _RST.search(":func:`x`") and _RST.search("`a`")
    assert _RST.search("output directory (default paper_out)") is None


def test_the_same_things_are_spelled_the_same():
    subs = _subparsers(cli.build_parser())
    for name, sub in subs.items():
        flags = _flags(sub)
        assert "--quiet" in flags, name
        assert "--output" not in flags or flags["--output"].help == argparse.SUPPRESS, name
    for name in ("trim",):
        assert "--out" not in _flags(subs[name])  # prints, writes nothing
    for name in (
        "derive", "paper", "simulate", "animate", "sweep", "montecarlo", "sensing", "compare",
    ):  # fmt: skip
        assert "--out" in _flags(subs[name]), name
    for name in ("paper", "simulate", "sweep", "montecarlo", "sensing"):
        fmt = _flags(subs[name])["--figure-format"]
        assert fmt.choices == FIGURE_FORMATS and fmt.default == "png", name
    for name, sub in subs.items():  # --format is always the tables' data format
        if "--format" in _flags(sub):
            data = _flags(sub)["--format"]
            tables = ("montecarlo", "sweep", "compare", "tether-study")  # no MCAP table
            formats = TABLE_FORMATS if name in tables else RESULT_FORMATS
            assert tuple(data.choices) == formats and data.default == "csv", name
    for name in ("paper", "simulate", "montecarlo"):
        assert "--format" in _flags(subs[name]), name
    for name in ("sweep", "montecarlo"):
        assert _flags(subs[name])["--workers"].help == _flags(subs["montecarlo"])["--workers"].help
    assert "--seed" in _flags(subs["montecarlo"])


def test_derive_output_is_removed(tmp_path, capsys, monkeypatch):
    """``derive --out`` writes; the removed alias ``--output`` is refused (exit 2) and
    writes nothing."""
    from tetherheli.model import codegen

    monkeypatch.setattr(codegen, "generate_source", lambda: "# generated\n")
    new, old = tmp_path / "new.py", tmp_path / "old.py"
    assert cli.main(["derive", "--out", str(new)]) == 0
    assert new.read_text() == "# generated\n" and capsys.readouterr().err == ""
    other = tmp_path / "other.py"
    assert cli.main(["derive", "--output", str(old), "--out", str(other)]) == 2
    assert not old.exists() and not other.exists() and "--output" in capsys.readouterr().err
    help_text = _subparsers(cli.build_parser())["derive"].format_help()
    assert "--out " in help_text and "--output" not in help_text


@pytest.mark.parametrize("flag", ["--format", "--output-format"])
def test_figure_format_has_one_spelling(flag, capsys):
    assert cli.main(["paper", flag, "pdf", "--out", "x"]) == 2
    capsys.readouterr()
