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

ROOT = Path(__file__).resolve().parents[1]

_TYPICAL = """
import json, sys
import numba
from tests.warm_cache import JOBS

for job in JOBS.values():
    for part in job:
        part()
many = {}
for modname, mod in list(sys.modules.items()):
    if not modname.startswith("tetherheli"):
        continue
    for key, value in vars(mod).items():
        # a dispatcher, or a table of them (``engine.CLOSED_LOOPS``: the loop's variants)
        items = value.items() if isinstance(value, dict) else [("", value)]
        for sub, f in items:
            if isinstance(f, numba.core.registry.CPUDispatcher) and f.__module__ == modname:
                if len(f.signatures) > 1:
                    name = f"{modname}.{key}" + (f"[{sub}]" if sub != "" else "")
                    many[name] = [str(sig) for sig in f.signatures]
print(json.dumps(many))
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
