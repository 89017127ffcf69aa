"""Issue 10, item 2: Numba's on-disk cache cannot go stale. Numba keys a cached function on
its own file only; tetherheli keys its whole cache on a fingerprint of every source file."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

from tetherheli import _compile

PACKAGE = Path(_compile.__file__).resolve().parent

# engine.check_state (sim/engine.py) inlines kernels.angle_trig (model/kernels.py): the pair
# whose cache went stale before, since editing kernels.py left engine.py's cache key alone.
PROBE = """
import numpy as np
from tetherheli.sim import engine
x = np.zeros(13); x[5] = 10.0; x[12] = 9.0
cfg = np.zeros(engine.CFG_SIZE)
cfg[engine.CFG_MAX_TENSION] = 1e9; cfg[engine.CFG_MAX_ANGLE] = 1.0
cfg[engine.CFG_MAX_DEVIATION] = 1e9
print(engine.check_state(x, np.array([0.0, 0.0, 10.0, 0.0]), np.zeros(4), 0.0, cfg))
"""

# Appended to the copy's kernels.py: every cosine 0, so the state looks singular.
EDIT = """

@_jit_inline
def angle_trig(x, sc):
    for i in range(10):
        sc[i] = 0.0
"""


def _probe(copy_root: Path, cache: Path) -> str:
    env = {**os.environ, "PYTHONPATH": str(copy_root), "NUMBA_CACHE_DIR": str(cache)}
    done = subprocess.run(
        [sys.executable, "-c", PROBE], env=env, capture_output=True, text=True, check=True
    )
    return done.stdout.strip()


def test_an_edit_to_a_compiled_dependency_takes_effect_with_no_manual_step(tmp_path: Path):
    copy_root = tmp_path / "src"
    shutil.copytree(PACKAGE, copy_root / "tetherheli", ignore=shutil.ignore_patterns("*.py[co]"))
    cache = tmp_path / "cache"
    assert _probe(copy_root, cache) == "0"  # STATUS_OK, compiled and cached
    assert _probe(copy_root, cache) == "0"  # ... loaded from the cache
    assert len(list((cache / "tetherheli-numba").iterdir())) == 1
    with (copy_root / "tetherheli" / "model" / "kernels.py").open("a") as fh:
        fh.write(EDIT)
    assert _probe(copy_root, cache) != "0"  # the edit took effect: no stale machine code
    assert len(list((cache / "tetherheli-numba").iterdir())) == 2


def test_fingerprint_covers_every_source_file(tmp_path: Path):
    root = tmp_path / "pkg"
    (root / "sub").mkdir(parents=True)
    (root / "a.py").write_text("x = 1\n")
    (root / "sub" / "b.py").write_text("y = 2\n")
    first = _compile.source_fingerprint(root)
    assert _compile.source_fingerprint(root) == first
    (root / "sub" / "b.py").write_text("y = 3\n")
    second = _compile.source_fingerprint(root)
    assert second != first
    (root / "sub" / "c.py").write_text("")
    assert _compile.source_fingerprint(root) not in (first, second)


def test_warm_up_jobs_fly_their_runs():
    """Issue 24, item 6: each job of the suite's cache warm-up (``tests/warm_cache.py``, run
    by conftest on the xdist controller) flies its short runs without error."""
    from tests import warm_cache

    assert set(warm_cache.JOBS) == {"single", "batch", "lumped"}
    for job in warm_cache.JOBS.values():
        job()


def test_help_builds_no_compiled_engine():
    """Issue 24, item 5: ``tetherheli --help`` and ``trim --help`` import neither the compiled
    engine nor Matplotlib (the parser needs names only)."""
    probe = (
        "import sys, contextlib, io\n"
        "from tetherheli import cli\n"
        "for argv in (['--help'], ['trim', '--help']):\n"
        "    with contextlib.suppress(SystemExit), contextlib.redirect_stdout(io.StringIO()):\n"
        "        cli.main(argv)\n"
        "heavy = ('tetherheli.sim.engine', 'tetherheli.sim.closed_loop', 'matplotlib')\n"
        "print(sorted(m for m in heavy if m in sys.modules))\n"
    )
    env = {**os.environ, "PYTHONPATH": str(PACKAGE.parent)}
    done = subprocess.run(
        [sys.executable, "-c", probe], env=env, capture_output=True, text=True, check=True
    )
    assert done.stdout.strip() == "[]"
