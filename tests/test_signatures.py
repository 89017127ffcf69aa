"""One compiled signature per hot function (issue 24 item 3).

The typical runs are the suite's warm-up jobs (``tests/warm_cache.py``: every shipped kind of
single run, a batch with and without lanes, the MPC's Python loop and the adaptive method, the
Gymnasium environment and the vector environment), flown in a process of their own;
afterwards each compiled function of the package must hold exactly one signature.
A second one means a second compilation of the same code (a read-only gain, a literal
``True``, an 'A'-layout slice), which costs the first run and the suite tens of seconds each:
``setup.EngineSetup.engine_args`` normalises the engine's inputs (``read_only``) and compiled
callers pass constants through ``_compile.plain``."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.warm_cache import REPORT_FOLDER

ROOT = Path(__file__).resolve().parents[1]

_TYPICAL = """
import json
from tests.warm_cache import JOBS, duplicate_signatures

for job in JOBS.values():
    for part in job:
        part()
print(json.dumps(duplicate_signatures()))
"""


def test_each_compiled_function_has_one_signature_after_the_typical_runs():
    done = subprocess.run(
        [sys.executable, "-c", _TYPICAL],
        cwd=ROOT,
        env=dict(os.environ),
        capture_output=True,
        text=True,
        check=True,
    )
    many = json.loads(done.stdout.strip().splitlines()[-1])
    assert many == {}, many


def test_the_warm_up_compiled_one_signature_each():
    """The same rule where it is decided: a warm cache serves a writable array from a
    read-only signature it loaded, but a process compiling from an empty cache compiles a
    second one. The suite's warm-up (``tests/conftest.py``) flies the typical runs first; a
    job that compiled (an empty or stale cache, as in CI) reports its signatures here."""
    folder = os.environ.get(REPORT_FOLDER)
    reports = sorted(Path(folder).glob("*.json")) if folder and os.path.isdir(folder) else []
    compiled = {p.stem: json.loads(p.read_text()) for p in reports}
    compiled = {k: v for k, v in compiled.items() if v["compiled"]}
    if not compiled:
        pytest.skip("no warm-up job compiled here (a warm cache, or no pytest-xdist)")
    assert {k: v["duplicates"] for k, v in compiled.items() if v["duplicates"]} == {}
