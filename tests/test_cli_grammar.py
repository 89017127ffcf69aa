"""One CLI grammar (the command line in ``tetherheli.cli``, one module per command): the
shared flags come from one parent parser each, with one help text, wherever they apply;
every option's default is stated in its help; no help names an issue; a closed pipe
(``tetherheli scenarios | head -1``) ends quietly with exit 0 (it was "internal error
(BrokenPipeError)", exit 70); ``--help`` and ``trim`` build no compiled engine."""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from tetherheli import cli
from tetherheli.cli import _common
from tetherheli.shipped import shipped_scenarios

SRC = Path(__file__).resolve().parents[1] / "src"
ENV = {**os.environ, "PYTHONPATH": str(SRC)}

#: The shared flags each command takes (``--debug`` and ``--quiet``: every command).
SHARED_FLAGS = {
    "trim": (),
    "derive": (),
    "paper": ("--out", "--format", "--figure-format", "--force"),
    "simulate": ("--out", "--format", "--figure-format", "--force"),
    "animate": (),
    "view": (),
    "sweep": ("--out", "--metric", "--workers", "--format", "--figure-format", "--force"),
    "montecarlo": (
        "--out", "--runs", "--seed", "--metric", "--workers", "--format", "--figure-format",
        "--force",
    ),
    "sensing": ("--out", "--format", "--figure-format", "--force"),
    "compare": (
        "--out", "--runs", "--seed", "--workers", "--format", "--figure-format", "--force",
    ),
    "tether-study": ("--out", "--workers", "--format", "--figure-format", "--force"),
    "scenarios": (),
}  # fmt: skip
#: A command's own flags that share a shared flag's name but not its meaning: the ``--out``
#: FILE of derive, animate, view and scenarios; animate's and view's ``--runs`` (run names,
#: not draws).
OWN = {
    "derive": {"--out"},
    "animate": {"--out", "--runs"},
    "view": {"--out", "--runs"},
    "scenarios": {"--out"},
}


def _subcommands() -> dict[str, argparse.ArgumentParser]:
    parser = cli.build_parser()
    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(action.choices)


def _flags(parser: argparse.ArgumentParser) -> dict[str, argparse.Action]:
    return {s: a for a in parser._actions for s in a.option_strings}


def _words(text: str) -> str:
    return " ".join(text.split())


def test_every_command_has_a_module_and_the_listed_shared_flags():
    commands = _subcommands()
    assert set(commands) == set(SHARED_FLAGS)
    for module in cli.COMMANDS:  # one file per command, each with register and run
        path = Path(module.__file__)
        assert path.parent == SRC / "tetherheli" / "cli", path
        assert callable(module.register) and callable(module.run)
    for name, sub in commands.items():
        shared = {f for f in _flags(sub) if f in _common.HELP}
        expected = {*SHARED_FLAGS[name], "--debug", "--quiet", *OWN.get(name, ())}
        assert shared == expected, name


def test_each_shared_flag_has_one_help_text_shown_in_every_help():
    """The raw help of a shared flag is ``_common.HELP``'s, in every command that takes it
    (``OWN`` apart), and the rendered ``--help`` shows it."""
    for name, sub in _subcommands().items():
        rendered = _words(sub.format_help())
        for flag, action in _flags(sub).items():
            if flag not in _common.HELP or flag in OWN.get(name, ()):
                continue
            text = _common.HELP[flag].format(dpi=300)
            assert action.help == text, (name, flag)
            assert _words(text) in rendered, (name, flag)


def test_every_default_is_stated():
    """Each option with a default (not None or False) says it in its rendered help."""
    formatter = _common.Formatter("tetherheli")
    for name, sub in _subcommands().items():
        for action in sub._actions:
            if not action.option_strings or action.help == argparse.SUPPRESS:
                continue
            shown = formatter._get_help_string(action) % {"default": action.default}
            if action.required:
                assert "(required)" in shown, (name, action.option_strings)
            elif action.default not in (None, False, argparse.SUPPRESS):
                assert "default" in shown, (name, action.option_strings, shown)


def test_every_option_states_its_default_or_that_it_is_required():
    """Every option that takes a value says its default in its rendered help (argparse's
    %(default)s, the formatter's " (default: X)", or the text's own "default: ..."), or that
    it is required; only --help, flags (no value) and hidden deprecated spellings are exempt.
    (``trim --params``, ``montecarlo --scheduler`` and ``--max-chunks`` said neither.)"""
    formatter = _common.Formatter("tetherheli")
    silent = []
    for name, sub in _subcommands().items():
        for action in sub._actions:
            if not action.option_strings or isinstance(action, argparse._HelpAction):
                continue
            if action.help == argparse.SUPPRESS or action.nargs == 0:  # hidden, or a flag
                continue
            shown = formatter._get_help_string(action) % {"default": action.default}
            if "default" not in shown and "required" not in shown:
                silent.append(f"{name} {'/'.join(action.option_strings)}")
    assert silent == []


def test_one_default_metric_for_every_command():
    """``sweep``, ``sweep --find-min`` and ``montecarlo`` report ``names.DEFAULT_METRIC``
    (peak_q1, the paper's first claim) without --metric; sweep's was rms_q1."""
    from tetherheli.names import DEFAULT_METRIC

    assert DEFAULT_METRIC == "peak_q1"
    parser = cli.build_parser()
    for argv in (
        ["sweep", "s.toml", "--param", "q9", "--values", "9,10", "--out", "o"],
        ["sweep", "s.toml", "--find-min", "actuators.cyclic_limit", "--values", "1:2:2",
         "--out", "o"],
        ["montecarlo", "mc.toml", "--out", "o"],
    ):  # fmt: skip
        assert parser.parse_args(argv).metric == DEFAULT_METRIC, argv[0]
    for name in ("sweep", "montecarlo"):
        assert _flags(_subcommands()[name])["--metric"].help == _common.HELP["--metric"]


def test_the_formatter_states_a_default_once():
    p = _common.Parser(prog="x")
    p.add_argument("--n", type=int, default=3, help="a count")
    p.add_argument("--m", type=int, default=4, help="a count (default 4)")
    p.add_argument("--grid", type=float, nargs="+", default=[0.5, 2.0], help="a grid")
    p.add_argument("--must", required=True, help="needed")
    text = _words(p.format_help())
    assert "a count (default: 3)" in text and "(default 4)" in text
    assert "(default 4) (default" not in text
    assert "a grid (default: 0.5,2)" in text and "needed (required)" in text


def test_no_help_names_an_issue():
    pattern = re.compile(r"\bissues?\b", re.IGNORECASE)
    assert pattern.search("see (issue 13)") and not pattern.search("tissue")
    parser = cli.build_parser()
    for name, sub in {"tetherheli": parser, **_subcommands()}.items():
        found = pattern.search(sub.format_help())
        assert found is None, (name, found)


@pytest.mark.parametrize(
    "argv", [["scenarios"], ["trim", "--json"], ["--help"], ["montecarlo", "--help"]]
)
def test_a_closed_pipe_ends_quietly_with_exit_0(argv):
    """The reader of stdout is gone before the command writes: no message, exit 0."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "tetherheli", *argv],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        env=ENV,
    )
    proc.stdout.close()  # as ``| head -1`` does after its line
    _, err = proc.communicate(timeout=300)
    assert proc.returncode == 0, err.decode()
    assert err.decode() == ""


def test_a_pipe_that_reads_one_line_gets_it():
    """``tetherheli scenarios | head -1``: the first line arrives, the command ends quietly."""
    cmd = f"{sys.executable} -m tetherheli scenarios | head -1"
    done = subprocess.run(cmd, shell=True, env=ENV, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0 and done.stderr == ""
    first = min(shipped_scenarios())  # the listing is sorted by name
    assert len(done.stdout.splitlines()) == 1 and done.stdout.split()[0] == first


_PROBE = textwrap.dedent(
    """
    import contextlib, io, sys
    from tetherheli.cli import main
    with contextlib.suppress(SystemExit), contextlib.redirect_stdout(io.StringIO()):
        code = main(sys.argv[1:])
    heavy = ("numba", "llvmlite", "matplotlib", "tetherheli.engine.loop",
             "tetherheli.runs.closed_loop", "tetherheli.model.kernels", "tetherheli.tether.lumped",
             "tetherheli.studies.tether_study")
    print(code, " ".join(m for m in heavy if m in sys.modules) or "-")
    """
)


@pytest.mark.parametrize(
    "argv",
    [
        ["--help"],
        ["trim", "--help"],
        ["tether-study", "--help"],
        # the trim solves the generated model code as plain Python (model/trim.py)
        ["trim"],
        ["trim", "--tension", "25", "--json"],
    ],
)
def test_help_and_trim_import_no_numba(argv):
    """Issue 24, item 5: the parser and the trim run without the compiled stack (no Numba,
    no llvmlite, no compiled kernels, no engine, no Matplotlib); a fresh interpreter, so the
    order of the tests does not matter."""
    done = subprocess.run(
        [sys.executable, "-c", _PROBE, *argv], env=ENV, capture_output=True, text=True,
        timeout=300, check=True,
    )  # fmt: skip
    assert done.stdout.split() == ["0", "-"], done.stdout  # exit code, heavy modules


def test_python_dash_m_is_the_console_script():
    done = subprocess.run(
        [sys.executable, "-m", "tetherheli", "--version"], env=ENV, capture_output=True,
        text=True, timeout=300,
    )  # fmt: skip
    assert done.returncode == 0 and done.stdout.startswith("tetherheli ")
    pyproject = (SRC.parent / "pyproject.toml").read_text(encoding="utf-8")
    assert 'tetherheli = "tetherheli.cli:main"' in pyproject


def test_the_command_lines_choices_are_the_studys():
    """The light names the parser reads (``names``) are those the commands run with."""
    from tetherheli import names
    from tetherheli.studies import tether_study as ts

    assert tuple(c.key for c in ts.STUDY_CABLES) == names.TETHER_STUDY_CABLES
    subs = _subcommands()
    study = _flags(subs["tether-study"])
    assert tuple(study["--model"].choices) == ts.TETHER_MODELS
    assert tuple(study["--winch-gain"].choices) == ts.WINCH_GAINS
    assert tuple(study["--lengths"].default) == ts.DEFAULT_LENGTHS_M


@pytest.mark.parametrize("command", ["montecarlo", "compare"])
def test_runs_above_the_limit_is_one_line_naming_the_flag(command, tmp_path, capsys):
    from tetherheli.studies.montecarlo.config import MAX_RUNS

    argv = [command, "--runs", str(MAX_RUNS + 1), "--out", str(tmp_path / "o")]
    argv += ["--montecarlo"] if command == "compare" else []
    argv += ["missing.toml"]
    assert cli.main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and f"--runs = {MAX_RUNS + 1}" in err, err
    assert not (tmp_path / "o").exists()
