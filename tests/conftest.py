"""Shared fixtures: the paper's parameters and models; the compile cache warmed once.

Before anything imports Matplotlib, its config and cache go to a temporary folder of this
test process (``MPLCONFIGDIR``, ``XDG_CONFIG_HOME``, ``XDG_CACHE_HOME``; Stable-Baselines3's
logger folders, ``SB3_LOGDIR``), removed when it ends: no test then
depends on the user's HOME, on what an earlier test left there, or on test order (a test
that points HOME at a scratch folder would otherwise find Matplotlib's font cache in it).
"""

from __future__ import annotations

import atexit
import functools
import os
import shutil
import sys
import tempfile
import time

# The compiled engine's cache stays where the package would put it (``_compile._cache_base``),
# so isolating XDG_CACHE_HOME below does not make every test process compile afresh.
os.environ.setdefault(
    "NUMBA_CACHE_DIR",
    os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"),
)
# One thread for the BLAS (OpenBLAS, MKL) and OpenMP (PyTorch) pools of a test process and
# of the processes it starts, unless set: under ``-n 2`` each core already runs a test, and a
# pool's second thread only competes with the other worker (waiting threads spin), about 7 %
# of the suite's CPU time. A test's results are then those of one path (docs/testing.md).
for _var in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "OMP_NUM_THREADS"):
    os.environ.setdefault(_var, "1")
_ISOLATED = tempfile.mkdtemp(prefix="tetherheli-tests-")
atexit.register(shutil.rmtree, _ISOLATED, ignore_errors=True)
# Stable-Baselines3's default logger makes a folder per ``learn`` (``$SB3_LOGDIR``, else a new
# ``SB3-<date>`` in the system's temporary folder, never removed): the tests' go here too.
for _var, _sub in (
    ("MPLCONFIGDIR", "mpl"),
    ("XDG_CONFIG_HOME", "config"),
    ("XDG_CACHE_HOME", "cache"),
    ("SB3_LOGDIR", "sb3"),
):
    os.makedirs(os.path.join(_ISOLATED, _sub))
    os.environ[_var] = os.path.join(_ISOLATED, _sub)
# The figures the tests write are PNGs at 100 dpi, not the 300 of print (``viz.formats.
# PRINT_DPI``), through Matplotlib's own setting, which ``viz.figure.save_figure`` follows
# (``figure_dpi``) and the processes a test starts read too: the same drawing, a ninth of the
# pixels to render and encode (the suite writes some 700 PNGs). ``tests/test_plots.py``
# checks the 300 dpi default and the setting.
with open(os.path.join(_ISOLATED, "mpl", "matplotlibrc"), "w", encoding="utf-8") as _rc:
    _rc.write("savefig.dpi: 100\n")

from typing import TYPE_CHECKING  # noqa: E402

import numpy as np  # noqa: E402
import pytest  # noqa: E402

if TYPE_CHECKING:  # imported by the fixtures: the xdist controller starts the warm-up sooner
    from tetherheli import FreeHelicopter, Params, TetheredHelicopter


#: set by the xdist controller for its workers: a file that exists once the warm-up ended
WARM_DONE = "TETHERHELI_WARM_DONE"


def pytest_configure(config: pytest.Config) -> None:
    """On the pytest-xdist controller (``-n N``), fill the Numba cache before the workers
    run a test (``tests/warm_cache.py``): the workers then load the engine instead of each
    compiling it at once. The warm-up runs beside the workers' start and collection (about
    10 s of imports each, no compilation), which use the cores its shorter job leaves idle;
    each worker waits for it before its first test (``pytest_runtestloop``). Nothing happens
    without xdist, in a worker, or with ``TETHERHELI_NO_WARM=1``; with a warm cache it costs
    the cache's loading only."""
    workers = getattr(config.option, "numprocesses", None)
    if hasattr(config, "workerinput") or not workers or os.environ.get("TETHERHELI_NO_WARM"):
        return
    import threading

    from tests.warm_cache import REPORT_FOLDER, warm

    # the jobs' signature reports (``tests/test_signatures.py``); the workers inherit the path
    os.environ[REPORT_FOLDER] = os.path.join(_ISOLATED, "warm-signatures")
    os.makedirs(os.environ[REPORT_FOLDER], exist_ok=True)
    done = os.environ[WARM_DONE] = os.path.join(_ISOLATED, "warm-done")

    def warm_then_say_so() -> None:
        try:
            warm()
        finally:
            with open(done, "w", encoding="utf-8"):
                pass

    threading.Thread(target=warm_then_say_so, name="tetherheli-warm-up").start()


@pytest.hookimpl(tryfirst=True)
def pytest_runtestloop(session: pytest.Session) -> None:
    """A worker of a warming controller (``pytest_configure``) runs no test before the
    warm-up has ended (its file exists)."""
    done = os.environ.get(WARM_DONE)
    if done and hasattr(session.config, "workerinput"):
        while not os.path.exists(done):
            time.sleep(0.05)


_COMPILE_LOG = None
if os.environ.get("TETHERHELI_COMPILE_LOG"):
    from numba.core import event as _event

    class _CompileLog(_event.Listener):
        """Opt-in (``TETHERHELI_COMPILE_LOG=FILE``): one line per outermost Numba compilation,
        "seconds function test", appended to FILE by every process; it tells which tests
        compile what, and for how long (issue 24: the suite's time from an empty cache)."""

        def __init__(self, path: str) -> None:
            self.path, self.depth, self.test, self.started = path, 0, "(collection)", 0.0

        def on_start(self, event) -> None:
            if self.depth == 0:
                self.started = time.perf_counter()
            self.depth += 1

        def on_end(self, event) -> None:
            self.depth -= 1
            if self.depth == 0:
                name = getattr(event.data["dispatcher"], "__qualname__", "?")
                seconds = time.perf_counter() - self.started
                with open(self.path, "a", encoding="utf-8") as log:
                    log.write(f"{seconds:8.2f} {name} {self.test}\n")

    _COMPILE_LOG = _CompileLog(os.environ["TETHERHELI_COMPILE_LOG"])
    _event.register("numba:compile", _COMPILE_LOG)


def pytest_sessionfinish(session: pytest.Session) -> None:
    """With the compile log: each compiled function of the package with more than one
    signature, and where its signatures differ."""
    if _COMPILE_LOG is None:
        return
    from tests.warm_cache import dispatchers

    lines = []
    for name, f in dispatchers():
        first, *others = f.signatures or [()]
        for other in others:
            diff = [
                (i, str(a), str(b))
                for i, (a, b) in enumerate(zip(first, other, strict=False))
                if a != b
            ]
            lines.append(f"signature {name}: {diff}\n")
    with open(_COMPILE_LOG.path, "a", encoding="utf-8") as log:
        log.writelines(lines)


#: The optional extras the suite has tests for, each with the modules that tell it is
#: installed: a test marked ``@pytest.mark.extra(NAME)`` skips, with the reason, without any
#: of them; ``@pytest.mark.extra(NAME, MODULE)`` needs only that one of the extra's modules.
#: The README's install (``.[test]``) has none of them; ``.ci/run`` runs the README's test
#: command, then installs the extras and runs the marked tests (``--extras-only``).
EXTRAS = {
    "rl": ("stable_baselines3",),
    "validation": ("moordyn", "rotorpy"),
    "ship": ("capytaine",),
}


def extra_missing(extra: str, module: str | None = None) -> str | None:
    """Why a test of the optional ``extra`` (of its ``module`` only, if given) cannot run
    here (a module is not installed), or None when it can."""
    import importlib.util

    if module is not None and module not in EXTRAS[extra]:
        raise pytest.UsageError(f"{module!r} is not a module of the extra {extra!r}")
    for name in EXTRAS[extra] if module is None else (module,):
        if importlib.util.find_spec(name) is None:
            return f'{name} is not installed: the optional extra, pip install -e ".[{extra}]"'
    return None


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption(
        "--extras-only",
        action="store_true",
        help="run only the tests of optional extras (marked extra): CI's second pass",
    )


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """With ``--extras-only``, keep the tests marked ``extra``; an unknown extra is an error."""
    for item in items:
        for mark in item.iter_markers("extra"):
            if mark.args[0] not in EXTRAS:
                raise pytest.UsageError(f"{item.nodeid}: unknown extra {mark.args[0]!r}")
    if config.getoption("--extras-only"):
        keep = [item for item in items if item.get_closest_marker("extra")]
        config.hook.pytest_deselected(items=[i for i in items if i not in keep])
        items[:] = keep


@pytest.hookimpl(tryfirst=True)
def pytest_runtest_setup(item: pytest.Item) -> None:
    if _COMPILE_LOG is not None:
        _COMPILE_LOG.test = item.nodeid
    for mark in item.iter_markers("extra"):
        why = extra_missing(*mark.args)
        if why is not None:
            pytest.skip(why)


@pytest.fixture(name="blank_figures")
def blank_figures_fixture(monkeypatch):
    """The commands' figures drawn blank for this test (``tests/blank_figures.py``)."""
    from tests.blank_figures import blank_figures

    blank_figures(monkeypatch)


@pytest.fixture(scope="session")
def uninterrupted(tmp_path_factory) -> bytes:
    """results.csv of ``test_montecarlo``'s short job (``SHORT``) run whole, once per test
    process: what every stopped, resumed or repaired job's table must equal
    (``test_montecarlo``, ``test_output_safety_2``). Its figures are drawn blank: only the
    table is used, and it does not depend on where the scenario file lies."""
    from tests.blank_figures import blank_figures
    from tests.test_montecarlo import SHORT, _run

    folder = tmp_path_factory.mktemp("montecarlo")
    (folder / "mc.toml").write_text(SHORT)
    with pytest.MonkeyPatch.context() as m:
        blank_figures(m)
        _run(folder / "mc.toml", folder / "full")
    return (folder / "full" / "results.csv").read_bytes()


@pytest.fixture
def local_cluster():
    """``dask.distributed.LocalCluster`` (the test skips without it) on free ports: with
    ``dashboard_address=None`` its scheduler still binds 8787, which another test's cluster
    (the workers run tests at once) or a Dask dashboard on this machine may hold."""
    distributed = pytest.importorskip("distributed")
    return functools.partial(distributed.LocalCluster, dashboard_address=":0")


@pytest.fixture(autouse=True)
def _no_pyplot_figures_left():
    """Once a test process has imported pyplot (a library of a test may), the package's
    figures get pyplot's figure manager (``viz.figure.new_figure``), as in a user's notebook;
    they are closed after each test, so none outlives its test and pyplot's warning at 20
    open figures (an error here) never depends on the order of the tests."""
    yield
    pyplot = sys.modules.get("matplotlib.pyplot")
    if pyplot is not None:
        pyplot.close("all")


@pytest.fixture(scope="session", autouse=True)
def _one_derivation_per_process():
    """``codegen.generate_source`` (Kane's method for both models, then the code's printing:
    about 8 s) depends on the source and SymPy only: a test process derives once, and every
    later call (``test_derive``'s, ``tetherheli derive`` in the output tests) gets that text."""
    from tetherheli.model import codegen

    original = codegen.generate_source
    codegen.generate_source = functools.cache(original)
    yield
    codegen.generate_source = original


@pytest.fixture(scope="session")
def paper() -> Params:
    from tetherheli import Params

    return Params.paper()


@pytest.fixture(scope="session")
def tethered(paper: Params) -> TetheredHelicopter:
    from tetherheli import TetheredHelicopter

    return TetheredHelicopter(paper)


@pytest.fixture(scope="session")
def free(paper: Params) -> FreeHelicopter:
    from tetherheli import FreeHelicopter

    return FreeHelicopter(paper)


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20261122)
