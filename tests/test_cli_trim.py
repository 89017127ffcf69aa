"""The trim and derive commands of the CLI."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from tetherheli.cli import main


def test_trim_table_iv_digits(capsys):
    """`tetherheli trim` prints Table IV's values to every printed digit."""
    assert main(["trim"]) == 0
    out = capsys.readouterr().out
    for row in (
        "q4                 5.29",
        "q2              -0.0189",
        "q3              10.2037",
        "fMR3           123.7633",
        "tMR1             1.0933",
        "fTR2            11.4596",
    ):
        assert row in out


def test_trim_table_v_json(capsys):
    """`tetherheli trim --tension 25 --json`: Table V in SI units."""
    assert main(["trim", "--tension", "25", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert round(data["trim"]["fMR3"], 4) == 148.6568
    assert round(data["trim"]["tMR1"], 4) == 1.3132
    assert round(data["trim"]["fTR2"], 4) == 13.7645
    assert data["trim"]["LN"] == pytest.approx(9.375)


@pytest.mark.parametrize(
    "argv",
    [
        ["trim", "--tension", "-1"],
        ["trim", "--q9", "abc"],
        ["trim", "--params", "missing.toml"],
        ["nosuchcommand"],
    ],
)
def test_cli_errors_one_line_exit_2(argv, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_python_dash_m_is_the_same_program():
    res = subprocess.run(
        [sys.executable, "-m", "tetherheli", "trim", "--tension", "25"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert res.returncode == 0 and "148.6568" in res.stdout
    res = subprocess.run(
        [sys.executable, "-m", "tetherheli", "trim", "--q9", "-1"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert res.returncode == 2 and "Traceback" not in res.stderr


def test_derive_needs_out_and_never_writes_the_package_by_default(monkeypatch, capsys):
    """``derive`` without ``--out`` is one usage line naming ``--out`` (exit 2), and the
    package's own _generated.py is not touched (it was the default target)."""
    from tetherheli.model import codegen

    calls = []
    monkeypatch.setattr(codegen, "generate_source", lambda: calls.append(1) or "# generated\n")
    before = codegen.GENERATED_PATH.stat()
    for argv in (["derive"], ["derive", "--check"]):
        assert main(argv) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "--out" in err[0] and "required" in err[0], err
    after = codegen.GENERATED_PATH.stat()
    assert calls == [] and (after.st_mtime_ns, after.st_size) == (
        before.st_mtime_ns,
        before.st_size,
    )
