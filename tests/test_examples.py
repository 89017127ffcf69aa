"""The scripts in examples/ run and each writes its figure (STYLE: examples are tested).

A script whose first line is ``# not-for-ci`` (e.g. one that trains a policy for minutes) is
listed but skipped here.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
SCRIPTS = sorted(EXAMPLES.glob("*.py"))
NOT_FOR_CI = "# not-for-ci"


def test_there_are_examples():
    assert len([s for s in SCRIPTS if not _skipped(s)]) >= 3


def _skipped(script: Path) -> bool:
    with script.open(encoding="utf-8") as fh:
        return fh.readline().strip().lower().startswith(NOT_FOR_CI)


@pytest.mark.slow
@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.stem)
def test_example_runs_and_writes_a_figure(script: Path, tmp_path: Path):
    if _skipped(script):
        pytest.skip(f"{script.name} is marked {NOT_FOR_CI!r}")
    src = str(Path(__file__).resolve().parents[1] / "src")
    env = {
        **os.environ,
        "MPLBACKEND": "Agg",
        "PYTHONPATH": os.pathsep.join(filter(None, [src, os.environ.get("PYTHONPATH")])),
    }
    out = tmp_path / "out"  # OUT_DIR by the commands' rules: not the current directory
    # generous: the first process on a fresh machine compiles the engine (1-3 min)
    done = subprocess.run(
        [sys.executable, str(script), str(out)],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    figures = list(out.glob("*.png"))
    assert len(figures) == 1 and figures[0].stat().st_size > 10_000, done.stdout
    assert f"wrote {figures[0]}" in done.stdout
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]  # nothing else written
