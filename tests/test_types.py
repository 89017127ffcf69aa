"""The package's types check (issue 44 item 5): ``mypy`` with ``[tool.mypy]`` of
pyproject.toml (the default strictness, unused ignores and redundant casts reported, the
untyped third-party packages silenced one by one) finds no error in ``src/tetherheli``."""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow
def test_mypy_finds_no_error(tmp_path):
    """About 20 s of CPU from a cold cache; the cache goes to ``tmp_path`` (not HOME, not
    the clone)."""
    if importlib.util.find_spec("mypy") is None:
        pytest.skip("mypy is not installed (test extra)")
    env = {k: v for k, v in os.environ.items() if k != "MYPYPATH"}
    run = subprocess.run(
        [
            sys.executable,
            "-m",
            "mypy",
            "--config-file",
            str(ROOT / "pyproject.toml"),
            "--cache-dir",
            str(tmp_path / "mypy_cache"),
        ],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert run.returncode == 0, run.stdout + run.stderr
