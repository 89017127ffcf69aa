"""Issue 10, item 2: Numba's on-disk cache cannot go stale. Numba keys a cached function on
its own file only; tetherheli keys its whole cache on a fingerprint of the source files the
compiled code depends on (issue 24, item 5: an edit elsewhere keeps the cache)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

from tetherheli import _compile

PACKAGE = Path(_compile.__file__).resolve().parent

# engine.check_state (engine/loop.py) inlines kernels.angle_trig (model/kernels.py): the pair
# whose cache went stale before, since editing kernels.py left engine.py's cache key alone.
PROBE = """
import numpy as np
from tetherheli.engine import loop as engine
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
    assert len([p for p in (cache / "tetherheli-numba").iterdir() if p.is_dir()]) == 1
    with (copy_root / "tetherheli" / "model" / "kernels.py").open("a") as fh:
        fh.write(EDIT)
    assert _probe(copy_root, cache) != "0"  # the edit took effect: no stale machine code
    assert len([p for p in (cache / "tetherheli-numba").iterdir() if p.is_dir()]) == 2


def test_fingerprint_covers_the_compiled_code_and_what_it_reads(tmp_path: Path):
    """Issue 24, item 5: the cache is keyed on the files compiled code depends on. In a
    small package: a compiled function, the constant it reads (through an import and a
    module-level expression), the function it calls in a third file; a command-line file
    beside them that no compiled code uses."""
    root = tmp_path / "pkg"
    (root / "sub").mkdir(parents=True)
    (root / "__init__.py").write_text("")
    (root / "sub" / "__init__.py").write_text("")
    (root / "_compile.py").write_text("def compiled(**kw):\n    return lambda f: f\n")
    (root / "layout.py").write_text("BASE = 2\nSIZE = BASE + 1\n")
    (root / "sub" / "helper.py").write_text(
        "from .._compile import compiled\n@compiled()\ndef twice(x):\n    return 2 * x\n"
    )
    (root / "kernel.py").write_text(
        "from ._compile import compiled\nfrom .layout import SIZE\nfrom .sub import helper\n"
        "_jit = compiled()\n\n@_jit\ndef f(x):\n    return helper.twice(x) + SIZE\n"
    )
    (root / "cli.py").write_text("from .kernel import f\n\ndef main():\n    print(f(1))\n")
    rel = sorted(p.relative_to(root).as_posix() for p in _compile.compiled_sources(root))
    assert rel == ["_compile.py", "kernel.py", "layout.py", "sub/helper.py"]
    first = _compile.source_fingerprint(root)
    assert _compile.source_fingerprint(root) == first
    (root / "cli.py").write_text("from .kernel import f\n\ndef main():\n    print(f(2))\n")
    assert _compile.source_fingerprint(root) == first  # no compiled code changed
    (root / "layout.py").write_text("BASE = 3\nSIZE = BASE + 1\n")
    second = _compile.source_fingerprint(root)
    assert second != first  # a constant the compiled code reads
    (root / "sub" / "helper.py").write_text(
        "from .._compile import compiled\n@compiled()\ndef twice(x):\n    return 3 * x\n"
    )
    assert _compile.source_fingerprint(root) not in (first, second)
    (root / "kernel.py").write_text(  # a star import: the walk cannot tell, so every file
        "from ._compile import compiled\nfrom .layout import *\n\n"
        "@compiled()\ndef f(x):\n    return x + SIZE\n"
    )
    assert len(_compile.compiled_sources(root)) == len(list(root.rglob("*.py")))


def test_every_compiled_function_and_what_it_calls_is_in_the_key():
    """A second route to ``compiled_sources``: the package's Numba dispatchers themselves,
    imported. Each one's own file, and the file of every package function, dispatcher or
    module that its code names, are in the key."""
    import importlib
    import inspect
    import types

    from numba.core.registry import CPUDispatcher

    keyed = {p.resolve() for p in _compile.compiled_sources()}
    assert len(keyed) < len(list(PACKAGE.rglob("*.py")))  # the CLI and studies are not
    for mod in ("engine.loop", "runs.batch", "envs.vector", "envs.env", "model.kernels",
                "sensing.sensors", "tether.lumped", "tether.coupling", "tether.winch",
                "control.paper"):  # fmt: skip
        importlib.import_module(f"tetherheli.{mod}")
    dispatchers = {
        id(v): v
        for name, m in list(sys.modules.items())
        if name.startswith("tetherheli") and m is not None
        for v in vars(m).values()
        if isinstance(v, CPUDispatcher)
    }
    assert len(dispatchers) > 50

    def names(code: types.CodeType):
        yield from code.co_names
        for c in code.co_consts:
            if isinstance(c, types.CodeType):
                yield from names(c)

    def source(obj) -> Path | None:
        if isinstance(obj, CPUDispatcher):
            obj = obj.py_func
        if isinstance(obj, types.ModuleType):
            path = getattr(obj, "__file__", None)
        elif inspect.isfunction(obj):
            path = inspect.getsourcefile(obj)
        else:
            return None
        if path is None or not Path(path).resolve().is_relative_to(PACKAGE):
            return None
        return Path(path).resolve()

    for d in dispatchers.values():
        assert source(d) in keyed, d.py_func.__qualname__
        for n in names(d.py_func.__code__):
            value = d.py_func.__globals__.get(n)
            path = source(value) if value is not None else None
            assert path is None or path in keyed, (d.py_func.__qualname__, n, path)


def test_warm_up_jobs_fly_their_runs():
    """Issue 24, item 6: each job of the suite's cache warm-up (``tests/warm_cache.py``, run
    by conftest on the xdist controller) flies its short runs without error."""
    from tests import warm_cache

    assert set(warm_cache.JOBS) == {"phases_lumped_and_vector_env", "lanes_env_and_single_runs"}
    for job in warm_cache.JOBS.values():
        for part in job:
            part()


def test_help_builds_no_compiled_engine():
    """Issue 24, item 5: ``tetherheli --help`` and ``trim --help`` import neither the compiled
    engine nor Matplotlib (the parser needs names only)."""
    probe = (
        "import sys, contextlib, io\n"
        "from tetherheli import cli\n"
        "for argv in (['--help'], ['trim', '--help']):\n"
        "    with contextlib.suppress(SystemExit), contextlib.redirect_stdout(io.StringIO()):\n"
        "        cli.main(argv)\n"
        "heavy = ('tetherheli.engine.loop', 'tetherheli.runs.closed_loop', 'matplotlib')\n"
        "print(sorted(m for m in heavy if m in sys.modules))\n"
    )
    env = {**os.environ, "PYTHONPATH": str(PACKAGE.parent)}
    done = subprocess.run(
        [sys.executable, "-c", probe], env=env, capture_output=True, text=True, check=True
    )
    assert done.stdout.strip() == "[]"
