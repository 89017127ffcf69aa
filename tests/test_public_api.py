"""The curated top-level API (issue 44 item 5): the run's entry points, the batch, the
paper's scenarios, the controller protocol, the cable, the shipped scenarios, the multirotor
and its SE(3) controller (issue 45) are reachable from ``tetherheli``; every public name
resolves, lazily (``import tetherheli`` loads no Numba)."""

from __future__ import annotations

import subprocess
import sys

import tetherheli


def test_every_public_name_resolves():
    for name in tetherheli.__all__:
        assert getattr(tetherheli, name) is not None, name


def test_the_entry_points_are_top_level():
    from tetherheli.control.base import Controller
    from tetherheli.control.se3 import SE3Controller
    from tetherheli.model.multirotor import Multirotor
    from tetherheli.runs.batch import run_batch
    from tetherheli.tether import Cable

    assert tetherheli.run_batch is run_batch
    assert tetherheli.Controller is Controller
    assert tetherheli.Cable is Cable
    assert tetherheli.Multirotor is Multirotor
    assert tetherheli.SE3Controller is SE3Controller
    assert tetherheli.paper_scenario(1, "tethered").name == "paper_sim1_tethered"


def test_importing_the_package_loads_no_engine():
    code = "import sys, tetherheli; print('numba' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0 and out.stdout.strip() == "False", out.stderr
