"""Compile the engine's hot functions into the Numba cache once, before the test workers start.

``tests/conftest.py`` runs this module in a subprocess on the pytest-xdist controller, so that
the workers load the engine from the cache instead of both compiling the same functions at the
same time (issue 24: the suite from an empty cache was ~70 % compilation). Each job below
flies a short run through one of the engine's entry points with the argument types the tests
use; the jobs run in two processes, one per core. ``TETHERHELI_NO_WARM=1`` skips the warm-up.

Run: python -m tests.warm_cache [JOB ...] (no job: all of them, two at a time).
"""

from __future__ import annotations

import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor


def _single() -> None:
    from tetherheli import simulate
    from tetherheli.report.paper import sensing_scenario
    from tetherheli.shipped import shipped_scenario

    for name in ("paper_sim1_tethered", "paper_sim1_free", "paper_sim1_drum"):
        simulate(shipped_scenario(name).replace(duration=0.2))
    simulate(sensing_scenario("tether").replace(duration=0.2))


def _lumped() -> None:
    from tetherheli import simulate
    from tetherheli.shipped import shipped_scenario

    simulate(shipped_scenario("paper_sim1_lumped").replace(duration=0.2))


def _unlaned() -> None:
    from tetherheli.runs.batch import run_batch
    from tetherheli.shipped import shipped_scenario

    run_batch([shipped_scenario("paper_sim1_tethered").replace(duration=0.2)] * 2, lanes=False)


def _lanes() -> None:
    from tetherheli.runs.batch import run_batch
    from tetherheli.shipped import shipped_scenario

    run_batch([shipped_scenario("paper_sim1_tethered").replace(duration=0.2)] * 2)


def _python_loop() -> None:
    import dataclasses

    from tetherheli import simulate
    from tetherheli.shipped import shipped_scenario

    s = shipped_scenario("paper_sim1_tethered").replace(duration=0.2)
    simulate(s.replace(control=dataclasses.replace(s.control, controller="mpc")))
    simulate(s, method="adaptive")


def _env() -> None:
    import gymnasium as gym

    import tetherheli.envs.env  # noqa: F401 (registers the ids)

    env = gym.make("tetherheli/TetheredHover-v0")
    env.reset(seed=0)
    env.step(env.action_space.sample())


def _vector_env() -> None:
    from tetherheli.envs.vector import TetheredHoverVectorEnv

    vector = TetheredHoverVectorEnv(4)
    vector.reset(seed=0)
    vector.step(vector.action_space.sample())


#: the warm-up's jobs, one process each, split so that no compiled function is compiled in
#: both (a callee compiles with its first caller in each process, unless the other process has
#: cached it by then). The first starts with the Python loop, whose phases (``step_sense``,
#: ``step_command``: the sample's phases, ``rk4_interval``, the lumped chain's
#: ``lumped_interval``) the lumped run then reuses, and ends with the vector environment, whose
#: largest callee ``rk4_lanes`` the second has cached by then. The second compiles the lanes
#: (``rk4_lanes`` through ``run_lanes``), then flies the Gymnasium environment and the single
#: runs on the phases the first has cached. From an empty cache on the 2-core AMD EPYC, in
#: parallel: about 70 and 60 s (this VM's speed varies by 15 %)
JOBS = {
    "phases_lumped_and_vector_env": (_python_loop, _lumped, _unlaned, _vector_env),
    "lanes_env_and_single_runs": (_lanes, _env, _single),
}


def warm(jobs: list[str] | None = None, processes: int = 2) -> None:
    """Run each job in its own Python process, ``processes`` at a time.

    Parameters
    ----------
    jobs : list of str, optional
        Keys of ``JOBS`` (default: all).
    processes : int
        Processes at a time.
    """
    names = list(JOBS) if not jobs else jobs
    command = [sys.executable, "-m", "tests.warm_cache"]
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

    def run(name: str) -> None:
        subprocess.run([*command, name], cwd=root, check=False, capture_output=True)

    with ThreadPoolExecutor(processes) as pool:
        list(pool.map(run, names))


def dispatchers():
    """(name, dispatcher) of every compiled function of the package imported so far: a
    module's dispatcher, or one in a module's table such as ``engine.CLOSED_LOOPS``."""
    import numba

    for modname, mod in list(sys.modules.items()):
        if not modname.startswith("tetherheli"):
            continue
        for key, value in vars(mod).items():
            items = value.items() if isinstance(value, dict) else [("", value)]
            for sub, f in items:
                if isinstance(f, numba.core.registry.CPUDispatcher) and f.__module__ == modname:
                    yield f"{modname}.{key}" + (f"[{sub}]" if sub != "" else ""), f


def duplicate_signatures() -> dict[str, list[str]]:
    """Each compiled function of the package (``dispatchers``) that holds more than one
    signature in this process: name -> its signatures (``tests/test_signatures.py``)."""
    return {
        name: [str(sig) for sig in f.signatures]
        for name, f in dispatchers()
        if len(f.signatures) > 1
    }


def compiled_here() -> bool:
    """Whether this process compiled any of the package's functions (a cache miss): then
    its signatures are those the calls needed, not those a warm cache happened to load."""
    return any(sum(f.stats.cache_misses.values()) for _, f in dispatchers())


#: where a job writes its report (``report``), set by ``tests/conftest.py`` for the suite
REPORT_FOLDER = "TETHERHELI_WARM_REPORT"


def report(name: str) -> None:
    """Write job ``name``'s ``{"compiled": ..., "duplicates": ...}`` to the folder
    ``$TETHERHELI_WARM_REPORT`` (when set), for ``tests/test_signatures.py``."""
    import json

    folder = os.environ.get(REPORT_FOLDER)
    if folder and os.path.isdir(folder):
        data = {"compiled": compiled_here(), "duplicates": duplicate_signatures()}
        with open(os.path.join(folder, f"{name}.json"), "w", encoding="utf-8") as out:
            json.dump(data, out)


if __name__ == "__main__":
    if len(sys.argv) == 2:
        for part in JOBS[sys.argv[1]]:
            part()
        report(sys.argv[1])
    else:
        warm(sys.argv[1:] or None)
