"""Validate once (issue 24, item 3): input is checked where it enters (a ``Scenario``, a
public function's or class's arguments); the set-up of a run trusts the scenario it is
handed, and loading a scenario checks each field once.

Traced with ``sys.setprofile``: (a) setting up and flying every shipped scenario (and the
MPC and the tethered LQI on a few) calls no check of ``tetherheli._validation`` and neither
``params.check_tether_length`` nor ``TetherParams.check_tension``, with the design caches
emptied first, so nothing is skipped for having been done before; (b) loading a shipped
scenario checks each field (the checks' ``field`` argument) at most once; (c) bad input
through the public routes the set-up now bypasses is still refused with the same one-line
message.
"""

from __future__ import annotations

import collections
import contextlib
import dataclasses
import functools
import math
import sys
import tomllib
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np
import pytest

from tetherheli import ParameterError, Params
from tetherheli.base.motion import FileBase, FixedBase, base_motion_from
from tetherheli.control.mpc_design import mpc_plant
from tetherheli.control.observer import measurement_covariance
from tetherheli.control.tether_lqi import tethered_design
from tetherheli.errors import InfeasibleError
from tetherheli.model import TetheredHelicopter
from tetherheli.model.trim import hover_trim
from tetherheli.params import (
    _PAPER_HELICOPTER,
    _PAPER_TENSION_CONTROL,
    _PAPER_TETHER,
    HelicopterParams,
    TensionControlParams,
    TetherParams,
)
from tetherheli.runs import simulate
from tetherheli.runs.start import lumped_tether
from tetherheli.scenario.core import BaseSettings, Scenario, scenario_from_dict
from tetherheli.sensing.config import SensorConfig
from tetherheli.sensing.noise import noise_table
from tetherheli.sensing.schedules import sample_schedule
from tetherheli.shipped import shipped_scenario_text, shipped_scenarios
from tetherheli.tether.chain import LumpedTether
from tetherheli.tether.lumped_trim import hover_trim_lumped

#: the checks of input: (module, function name); ``check`` is ``Key.check``
CHECKS = {
    ("tetherheli._validation", name)
    for name in ("check_number", "check_integer", "check_vector", "check_bool", "check")
} | {("tetherheli.params", "check_tether_length"), ("tetherheli.params", "check_tension")}


class _Calls:
    """What ``sys.setprofile`` saw: the checks called (with their callers), the ``field`` of
    every outermost check of ``_validation``, and every tetherheli function entered."""

    def __init__(self) -> None:
        self.checks: collections.Counter[str] = collections.Counter()
        self.fields: collections.Counter[str] = collections.Counter()
        self.entered: set[str] = set()

    def __call__(self, frame: Any, event: str, arg: Any) -> None:
        if event != "call":
            return
        module = frame.f_globals.get("__name__", "")
        if not module.startswith("tetherheli"):
            return
        name = frame.f_code.co_name
        self.entered.add(f"{module}:{name}")
        if (module, name) not in CHECKS:
            return
        caller = frame.f_back
        where = f"{caller.f_globals.get('__name__')}:{caller.f_code.co_name}"
        self.checks[f"{module}.{name} <- {where}"] += 1
        if module == "tetherheli._validation" and not where.startswith(module):
            self.fields[str(frame.f_locals.get("field"))] += 1


@contextlib.contextmanager
def _traced() -> Iterator[_Calls]:
    calls = _Calls()
    previous = sys.getprofile()
    sys.setprofile(calls)
    try:
        yield calls
    finally:
        sys.setprofile(previous)


def _empty_caches() -> None:
    """Empty every ``functools`` cache of tetherheli (trims, gains, designs), so that the
    traced set-up solves and designs everything anew."""
    for name, module in list(sys.modules.items()):
        if name.startswith("tetherheli"):
            for value in list(vars(module).values()):
                if isinstance(value, functools._lru_cache_wrapper):
                    value.cache_clear()


def _data(name: str) -> dict[str, Any]:
    """A shipped scenario's tables (a Monte Carlo file's scenario without its dispersions)."""
    data = tomllib.loads(shipped_scenario_text(name))
    data.pop("montecarlo", None)
    return data


def _short(name: str, controller: str | None = None) -> Scenario:
    """Shipped scenario ``name`` (flown by ``controller``), long enough to pass its metrics'
    start and its maneuver's (a landing starts its descent)."""
    s = scenario_from_dict(_data(name))
    if controller is not None:
        s = s.replace(control=dataclasses.replace(s.control, controller=controller))
    if s.maneuver.landing:  # its descent (and its trims at the scheduled tensions) soon
        s = s.replace(maneuver=dataclasses.replace(s.maneuver, start_time=0.5))
    dt = s.control.dt
    seconds = max(1.0, s.metrics_start + 0.5, s.maneuver.start_time + 1.0)
    return s.replace(duration=dt * math.ceil(seconds / dt - 1e-9))


SHIPPED = sorted(shipped_scenarios())
RUNS = [(name, None) for name in SHIPPED] + [
    ("paper_sim1_tethered", "mpc"),
    ("paper_sim1_free", "mpc"),
    ("sensing_gps", "mpc"),  # the MPC's Kalman filter on the sensors' noise
    ("paper_sim1_lumped", "mpc"),
    ("paper_sim1_tethered", "tether_lqi"),
    ("sensing_tether", "tether_lqi"),
]


def test_the_tracer_sees_checks():
    """The positive control: a public trim called under the tracer is seen checking."""
    with _traced() as calls:
        hover_trim(Params.paper(), 25.0, 10.0)
    assert calls.checks[
        "tetherheli.params.check_tension <- tetherheli.model.trim:check_trim_arguments"
    ]
    assert calls.fields["tension"] == 1 and calls.fields["q9"] == 1


@pytest.mark.parametrize(("name", "controller"), RUNS, ids=lambda v: str(v))
def test_a_built_scenario_is_set_up_and_flown_without_checks(name, controller):
    scenario = _short(name, controller)
    simulate(scenario)  # compiled (or loaded from the cache) outside the trace
    _empty_caches()
    with _traced() as calls:
        simulate(scenario)
    assert "tetherheli.runs.setup:engine_setup" in calls.entered  # the set-up was traced
    assert "tetherheli.runs.start:paper_gain" in calls.entered  # and designed anew
    assert not calls.checks, f"{name}: checks during the set-up: {dict(calls.checks)}"


@pytest.mark.parametrize("name", SHIPPED)
def test_loading_checks_each_field_once(name):
    data = _data(name)
    with _traced() as calls:
        scenario_from_dict(data)
    assert len(calls.fields) > 100  # every key of a scenario is checked ...
    twice = {field: n for field, n in calls.fields.items() if n > 1}
    assert not twice, f"{name}: fields checked more than once: {twice}"  # ... once


def test_the_paper_constants_pass_their_checks():
    """``Params.paper()`` builds its constants trusted: they are what the checks accept."""
    checked = Params(
        helicopter=HelicopterParams(**_PAPER_HELICOPTER),
        tether=TetherParams(**_PAPER_TETHER),
        tension_control=TensionControlParams(**_PAPER_TENSION_CONTROL),
    )
    paper = Params.paper()
    assert paper == checked
    for section in dataclasses.fields(paper):
        values = dataclasses.astuple(getattr(paper, section.name))
        assert all(type(v) is float for v in values), section.name


@pytest.mark.parametrize("name", SHIPPED)
def test_what_set_up_builds_trusted_is_what_the_checks_build(name):
    """A trusted build (``_validation.trusted``) equals the checked one, field types too."""
    s = scenario_from_dict(_data(name))
    built = [getattr(s.params, f.name) for f in dataclasses.fields(s.params)]
    if not isinstance(s.base_motion, FileBase):  # a file's track is read, not trusted
        built.append(s.base_motion)
    if s.tether.lumped:
        built.append(lumped_tether(s))
    for obj in built:
        again = dataclasses.replace(obj)  # through __post_init__'s checks
        assert again == obj
        assert [type(v) for v in dataclasses.astuple(again)] == [
            type(v) for v in dataclasses.astuple(obj)
        ]


def _toml(text: str) -> Callable[[], object]:
    return lambda: scenario_from_dict(tomllib.loads(text), source="bad.toml")


_GPS = SensorConfig(gps_rate=5.0)
#: bad input through the public routes, and the message refusing it (as before issue 24's
#: item 3: the set-up no longer repeats these checks, the entry points still make them)
REFUSED: list[tuple[str, Callable[[], object], type, str]] = [
    ("hover_trim tension", lambda: hover_trim(Params.paper(), -1.0),
     ParameterError, "tension = -1.0 is invalid; allowed: a finite number >= 0 [N]"),
    ("hover_trim q9", lambda: hover_trim(Params.paper(), 25.0, 0.1),
     ParameterError, "q9 = 0.1 is invalid; allowed: a tether length in [0.5, 1000] m"),
    ("hover_trim tension above the tether's", lambda: hover_trim(Params.paper(), 300.0),
     InfeasibleError, "tension = 300.0 is invalid; allowed: a tension <= 200 N, the most this "
     "tether (K_C = 40 N/m) gives at q9 = 10 m: above it the natural length LN = q9 - TC/K_C "
     "= 2.5 m would be below q9/2 (strain > 100%)"),
    ("hover_trim wind", lambda: hover_trim(Params.paper(), 25.0, N_F_wind=(1.0, 2.0)),
     ParameterError, "N_F_wind = (1.0, 2.0) is invalid; allowed: 3 finite numbers"),
    ("TetheredHelicopter.trim", lambda: TetheredHelicopter().trim(25.0, 2000.0),
     ParameterError, "q9 = 2000.0 is invalid; allowed: a tether length in [0.5, 1000] m"),
    ("lumped chain of 0 nodes", lambda: LumpedTether(segments=0),
     ParameterError, "tether.segments = 0 is invalid; allowed: an integer in [2, 1000]"),
    ("lumped chain's gravity", lambda: LumpedTether().packed(-9.81),
     ParameterError, "g = -9.81 is invalid; allowed: a finite number >= 0"),
    ("from_paper_stiffness", lambda: LumpedTether.from_paper_stiffness(40.0, 0.0),
     ParameterError, "tether.L_N0 = 0.0 is invalid; allowed: a finite number > 0"),
    ("hover_trim_lumped tension",
     lambda: hover_trim_lumped(Params.paper(), LumpedTether(), 0.0),
     ParameterError, "ground_tension_N = 0.0 is invalid; allowed: a finite number > 0 [N]"),
    ("hover_trim_lumped q9", lambda: hover_trim_lumped(Params.paper(), LumpedTether(), 25.0, 0.0),
     ParameterError, "q9 = 0.0 is invalid; allowed: a tether length in [0.5, 1000] m"),
    ("a sensor rate off the control grid", lambda: SensorConfig(gps_rate=3.0).group_timing(0.01),
     ParameterError, "sensors.gps_rate = 3.0 is invalid; allowed: 0, >= 1/dt = 100 Hz, or a "
     "rate r with 1/(r dt) an integer (dt = 0.01 s)"),
    ("group_timing dt", lambda: _GPS.group_timing(-0.01),
     ParameterError, "control.dt = -0.01 is invalid; allowed: a finite number > 0"),
    ("sample_schedule dt", lambda: sample_schedule(_GPS, 0.0, 10),
     ParameterError, "control.dt = 0.0 is invalid; allowed: a finite number > 0"),
    ("sample_schedule samples", lambda: sample_schedule(_GPS, 0.01, -1),
     ParameterError, "n_samples = -1 is invalid; allowed: an integer >= 0"),
    ("noise_table samples", lambda: noise_table(_GPS, 1.5, np.random.default_rng(0)),
     ParameterError, "n_samples = 1.5 is invalid; allowed: an integer >= 0"),
    ("measurement_covariance dt",
     lambda: measurement_covariance(_GPS, np.zeros(13), 25.0, 0.2, 0.0, states=13,
                                    load_cell=True),
     ParameterError, "control.dt = 0.0 is invalid; allowed: a finite number > 0"),
    ("tethered_design tension", lambda: tethered_design(Params.paper(), -5.0, 10.0, 0.01),
     ParameterError, "tension = -5.0 is invalid; allowed: a finite number >= 0 [N]"),
    ("mpc_plant q9", lambda: mpc_plant(Params.paper(), "free", 0.0, 0.2, 0.01),
     ParameterError, "q9 = 0.2 is invalid; allowed: a tether length in [0.5, 1000] m"),
    ("base_motion_from motion", lambda: base_motion_from(BaseSettings(motion="boat")),
     ParameterError, "base.motion = 'boat' is invalid; allowed: one of 'fixed', 'velocity', "
     "'harmonic', 'sea_state', 'file', 'ship'"),
    ("FixedBase position", lambda: FixedBase(position=(1.0, 2.0)),
     ParameterError, "base.position = (1.0, 2.0) is invalid; allowed: 3 finite numbers in "
     "[-1e+06, 1e+06] [m]"),
    ("Params.replace", lambda: Params.paper().replace(tether={"K_C": 0.0}),
     ParameterError, "tether.K_C = 0.0 is invalid; allowed: a finite number > 0 [N/m]"),
    ("Scenario duration", lambda: Scenario(duration=-1.0),
     ParameterError, "duration = -1.0 is invalid; allowed: a finite number > 0 [s]"),
    ("Scenario.replace q9", lambda: Scenario().replace(q9=0.1),
     ParameterError, "q9 = 0.1 is invalid; allowed: a tether length in [0.5, 1000] m"),
    ("Scenario base position",
     lambda: Scenario(base=BaseSettings(motion="velocity", position=(0.0, 0.0))),
     ParameterError, "base.position = (0.0, 0.0) is invalid; allowed: 3 finite numbers in "
     "[-1e+06, 1e+06] [m]"),
    ("TOML duration", _toml("duration = 0.0"),
     ParameterError, "bad.toml: duration = 0.0 is invalid; allowed: a finite number > 0 [s]"),
    ("TOML q9", _toml("q9 = 'ten'"),
     ParameterError, "bad.toml: q9 = 'ten' is invalid; allowed: a tether length in "
     "[0.5, 1000] m"),
    ("TOML control.dt", _toml("[control]\ndt = -0.01"),
     ParameterError, "bad.toml: control.dt = -0.01 is invalid; allowed: a finite number > 0 [s]"),
    ("TOML limits", _toml("[limits]\nmax_tension = -1.0"),
     ParameterError, "bad.toml: limits.max_tension = -1.0 is invalid; allowed: a finite "
     "number > 0 [N]"),
    ("TOML base.motion", _toml("[base]\nmotion = 'raft'"),
     ParameterError, "bad.toml: base.motion = 'raft' is invalid; allowed: one of 'fixed', "
     "'velocity', 'harmonic', 'sea_state', 'file', 'ship'"),
    ("TOML base.position", _toml("[base]\nposition = [1.0, 2.0]"),
     ParameterError, "bad.toml: base.position = (1.0, 2.0) is invalid; allowed: 3 finite "
     "numbers in [-1e+06, 1e+06] [m]"),
    ("TOML sea state", _toml("[base]\nmotion = 'sea_state'\npeak_period = 0.5"),
     ParameterError, "bad.toml: base.peak_period = 0.5 is invalid; allowed: a finite number in "
     "[1, 30] [s]"),
    ("TOML sensor rate", _toml("[sensors]\ngps_rate = 3.0"),
     ParameterError, "bad.toml: sensors.gps_rate = 3.0 is invalid; allowed: 0, >= 1/dt = 100 "
     "Hz, or a rate r with 1/(r dt) an integer (dt = 0.01 s)"),
    ("TOML params", _toml("[params.helicopter]\nm_F = -1.0"),
     ParameterError, "bad.toml: helicopter.m_F = -1.0 is invalid; allowed: a finite number > 0 "
     "[kg]"),
    ("TOML tension above the tether's", _toml("[params.tension_control]\nT_ref = 300.0"),
     InfeasibleError, "bad.toml: params.tension_control.T_ref = 300.0 is invalid; allowed: a "
     "tension <= 200 N, the most this tether (K_C = 40 N/m) gives at q9 = 10 m: above it the "
     "natural length LN = q9 - TC/K_C = 2.5 m would be below q9/2 (strain > 100%)"),
]  # fmt: skip


@pytest.mark.parametrize(("what", "call", "error", "message"), REFUSED, ids=[r[0] for r in REFUSED])
def test_bad_input_is_still_refused_where_it_enters(what, call, error, message):
    with pytest.raises(error) as caught:
        call()
    assert str(caught.value) == message
