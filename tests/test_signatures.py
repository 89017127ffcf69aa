"""One compiled signature per hot function (issue 24 item 3).

The typical runs (every shipped kind of single run, a batch with and without lanes, the MPC's
Python loop, the Gymnasium environment and the vector environment) are flown in a process of
their own; afterwards each compiled function of the package must hold exactly one signature.
A second one means a second compilation of the same code (a read-only gain, a literal
``True``, an 'A'-layout slice), which costs the first run and the suite tens of seconds each:
``setup.EngineSetup.engine_args`` normalises the engine's inputs (``_read_only``) and compiled
callers pass constants through ``_compile.plain``."""

from __future__ import annotations

import json
import os
import subprocess
import sys

_TYPICAL = """
import dataclasses, json, sys
import numba
from tetherheli import simulate
from tetherheli.report import sensing_scenario
from tetherheli.shipped import shipped_scenario
from tetherheli.sim.batch import run_batch

for name in ("paper_sim1_tethered", "paper_sim1_free", "paper_sim1_drum", "paper_sim1_lumped"):
    simulate(shipped_scenario(name).replace(duration=0.2))
simulate(sensing_scenario("tether").replace(duration=0.2))
s = shipped_scenario("paper_sim1_tethered").replace(duration=0.2)
run_batch([s] * 2)
run_batch([s] * 2, lanes=False)
simulate(s.replace(control=dataclasses.replace(s.control, controller="mpc")))
import gymnasium as gym
import tetherheli.envs  # noqa: F401
env = gym.make("tetherheli/TetheredHover-v0")
env.reset(seed=0)
env.step(env.action_space.sample())
from tetherheli.vector_env import TetheredHoverVectorEnv
v = TetheredHoverVectorEnv(4)
v.reset(seed=0)
v.step(v.action_space.sample())
many = {}
for modname, mod in list(sys.modules.items()):
    if not modname.startswith("tetherheli"):
        continue
    for key, f in vars(mod).items():
        if isinstance(f, numba.core.registry.CPUDispatcher) and f.__module__ == modname:
            if len(f.signatures) > 1:
                many[f"{modname}.{key}"] = [str(sig) for sig in f.signatures]
print(json.dumps(many))
"""


def test_each_compiled_function_has_one_signature_after_the_typical_runs():
    done = subprocess.run(
        [sys.executable, "-c", _TYPICAL],
        env=dict(os.environ),
        capture_output=True,
        text=True,
        check=True,
    )
    many = json.loads(done.stdout.strip().splitlines()[-1])
    assert many == {}, many
