"""``manifest.json`` records what decides a run's numbers (issue 12, item 3): the versions of
numpy, scipy, numba and python-control, and the git commit when there is one."""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import control
import numba
import numpy
import pytest
import scipy

from tetherheli import _version
from tetherheli.report.paper import _manifest
from tetherheli.scenario.core import Scenario


def test_manifest_records_dependency_versions():
    """The recorded versions (package metadata) are those the modules report themselves."""
    m = _manifest("test", {"run": Scenario(name="run", duration=0.1)})
    assert m["versions"] == {
        "numpy": numpy.__version__,
        "scipy": scipy.__version__,
        "numba": numba.__version__,
        "control": control.__version__,
    }
    assert m["scenarios"]["run"]["name"] == "run"
    assert "git_commit" in m


@pytest.mark.skipif(shutil.which("git") is None, reason="git is not installed")
def test_git_commit_is_the_source_tree_head():
    src = _version.__file__
    inside = subprocess.run(
        ["git", "ls-files", "--error-unmatch", src], capture_output=True, check=False
    )
    if inside.returncode != 0:
        pytest.skip("tetherheli is not imported from a git work tree")
    head = subprocess.run(
        ["git", "-C", str(Path(src).parent), "rev-parse", "HEAD"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.strip()
    commit = _version.git_commit()
    assert re.fullmatch(r"[0-9a-f]{40}(\+dirty)?", commit)
    assert commit.removesuffix("+dirty") == head


def test_git_commit_without_git_is_none(monkeypatch):
    def no_git(*args, **kwargs):
        raise FileNotFoundError("git")

    monkeypatch.setattr(subprocess, "run", no_git)
    assert _version.git_commit() is None
