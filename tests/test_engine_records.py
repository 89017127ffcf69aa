"""The compiled engine's records (issue 44, item 1): phases take named records (``layout.Run``,
``LoopState``, ``Scratch``, ``WindPack``, ``Signals``) rather than long positional lists, the
state's slots and the enums are named in ``layout``, and the vehicle slot dispatches on the
vehicle's code."""

from __future__ import annotations

import importlib
import inspect
import pkgutil

import numpy as np
import pytest
from numba.core.registry import CPUDispatcher

import tetherheli
from tetherheli import layout

#: the most parameters a compiled function of the package may take
MAX_PARAMETERS = 10
#: modules that need an optional extra (not importable in every environment)
_OPTIONAL = {"tetherheli.envs.sb3", "tetherheli.__main__"}


def _dispatchers() -> dict[str, CPUDispatcher]:
    """Every compiled function of the package, by qualified name: Numba dispatchers found
    as module attributes (``compiled(...)``'s products among them) and in module-level
    dicts and tuples (``engine.loop.CLOSED_LOOPS``)."""
    found: dict[str, CPUDispatcher] = {}
    for info in pkgutil.walk_packages(tetherheli.__path__, "tetherheli."):
        if info.name in _OPTIONAL:
            continue
        module = importlib.import_module(info.name)
        for value in vars(module).values():
            members = value.values() if isinstance(value, dict) else [value]
            for member in members:
                if isinstance(member, CPUDispatcher):
                    f = member.py_func
                    found[f"{f.__module__}.{f.__qualname__}"] = member
    return found


def test_no_compiled_function_takes_more_than_ten_parameters():
    dispatchers = _dispatchers()
    assert len(dispatchers) > 100  # the walk found the package's compiled code
    counts = {n: len(inspect.signature(d.py_func).parameters) for n, d in dispatchers.items()}
    assert {n: c for n, c in counts.items() if c > MAX_PARAMETERS} == {}


def test_the_enums_are_chosen_by_name():
    assert layout.VEHICLES[layout.VEHICLE_HELICOPTER] == "helicopter"
    assert layout.VEHICLES[layout.VEHICLE_MULTIROTOR] == "multirotor"
    assert layout.VEHICLE_HELICOPTER == 0  # a zeroed cfg flies the helicopter
    assert layout.CONTROL_LAWS[layout.CONTROL_LAW_PAPER] == "paper"
    assert layout.CONTROL_LAWS[layout.CONTROL_LAW_TETHER_LQI] == "tether_lqi"


def test_the_state_slots_are_named():
    assert (layout.X_Q4, layout.X_Q9, layout.X_U1, layout.X_U4, layout.X_LN) == (0, 5, 6, 9, 12)
    assert layout.X_SIZE == 13 and layout.SC_COS + 5 == layout.SC_SIZE


def test_the_vehicle_slot_dispatches_on_the_vehicle():
    from tetherheli.engine import loop as engine
    from tetherheli.model.kernels import angle_trig, model_constants
    from tetherheli.params import Params

    c = model_constants("tethered", Params.paper().helicopter)
    x = np.zeros(13)
    x[layout.X_Q9], x[layout.X_LN] = 10.0, 10.0
    sc = np.empty(10)
    angle_trig(x, sc)
    cfg = np.zeros(layout.CFG_SIZE)
    cfg[layout.CFG_ATTACHED], cfg[layout.CFG_K_C] = 1.0, 1000.0
    out = np.empty(13)
    engine.vehicle_derivative(x, sc, np.zeros(4), 0.5, cfg, c, np.zeros(3), out, layout.no_gear())
    assert np.all(np.isfinite(out)) and out[layout.X_LN] == 0.5
    cfg[layout.CFG_VEHICLE] = layout.VEHICLE_MULTIROTOR  # reserved: no kernel in the slot yet
    engine.vehicle_derivative(x, sc, np.zeros(4), 0.5, cfg, c, np.zeros(3), out, layout.no_gear())
    assert np.all(np.isnan(out))


@pytest.mark.parametrize("record", [layout.Run, layout.Scratch, layout.WindPack])
def test_records_are_named_tuples(record):
    assert issubclass(record, tuple) and record._fields
