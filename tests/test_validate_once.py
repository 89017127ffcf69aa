"""Validate once (issue 24, item 3): input is checked where it enters (a ``Scenario``, a
public function's or class's arguments); the set-up of a run trusts the scenario it is
handed, and loading a scenario checks each field once.

Traced with ``sys.setprofile``: (a) setting up and flying every shipped scenario (and the
MPC and the tethered LQI on a few) calls no check but ``simulate``'s own at its entry (its
memory): no check of ``tetherheli._validation``, no ``params.check_tether_length`` nor
``TetherParams.check_tension``, and no function of the package named ``check*``,
``_check*``, ``validate*`` or ``_validate*`` (nor ``_linalg.real_matrix``), with the design
caches emptied first, so nothing is skipped for having been done before (issue 44, item 2:
the designs' dt, the law's gain, the linearization's state, the formats); (b) loading a
shipped scenario checks each field (the checks' ``field`` argument) at most once, and a run
from a file's tables checks each rule once: the scenario's validation, then ``simulate``'s
memory; (c) ``run_batch`` checks each run once at its entry and ``tetherheli simulate`` and
the writers check each format once; (d) bad input through the public routes the set-up now
bypasses is still refused with the same one-line message.
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
from tetherheli.runs import run_batch, simulate
from tetherheli.runs.setup import python_controlled
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


#: every check by its name: a function of the package named so (``Key.check`` too) ...
CHECK_PREFIXES = ("check", "_check", "validate", "_validate")
#: ... and the array checks of the designs' public functions
NAMED_CHECKS = {("tetherheli._linalg", "real_matrix")}
#: ``simulate``'s own checks at its entry: the run's memory (``check_run_memory``)
SIMULATE_ENTRY = {
    "tetherheli.runs.closed_loop.check_run_memory <- tetherheli.runs.closed_loop:simulate",
    "tetherheli.resources.check_memory <- tetherheli.runs.closed_loop:check_run_memory",
}

#: a paper law flown by Python: its one check, where its arrays enter its controller
PYTHON_LAW = "tetherheli.control.paper.check_law <- tetherheli.control.paper:__init__"


def _is_check(module: str, name: str) -> bool:
    return name.startswith(CHECK_PREFIXES) or (module, name) in NAMED_CHECKS


class _Calls:
    """What ``sys.setprofile`` saw: the checks called (with their callers: ``checks`` those
    of ``CHECKS``, ``every`` every check by ``_is_check``, the outermost only: a check
    called by a check of its own module is a part of it), the ``field`` of every outermost
    check of ``_validation``, and every tetherheli function entered."""

    def __init__(self) -> None:
        self.checks: collections.Counter[str] = collections.Counter()
        self.every: collections.Counter[str] = collections.Counter()
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
        caller = frame.f_back
        outer = caller.f_globals.get("__name__")
        where = f"{outer}:{caller.f_code.co_name}"
        if _is_check(module, name) and not (
            outer == module and _is_check(outer, caller.f_code.co_name)
        ):
            self.every[f"{module}.{name} <- {where}"] += 1
        if (module, name) not in CHECKS:
            return
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
    # every check at all, by name: simulate's own at its entry, once, and none in the set-up;
    # a paper law flown by Python (a landing, a point held over a moving base) is checked
    # once, where its arrays enter its controller; the compiled law builds none
    expected = dict.fromkeys(SIMULATE_ENTRY, 1)
    if python_controlled(scenario) and scenario.control.controller != "mpc":
        expected[PYTHON_LAW] = 1
    assert calls.every == expected, f"{name}: {dict(calls.every)}"


def test_a_run_from_its_tables_checks_each_rule_once():
    """A run from a file's tables checks each field once, in the scenario's validation
    (``scenario_from_dict``), and then, in ``simulate``, only the run's memory (issue 44,
    item 2: no dt, law, trim or format check repeated on the way)."""
    data = _data("paper_sim1_tethered")
    data["duration"] = 1.0
    simulate(scenario_from_dict(data))  # compiled outside the trace
    _empty_caches()
    with _traced() as loading:
        scenario = scenario_from_dict(data)
    with _traced() as flying:
        simulate(scenario)
    assert len(loading.fields) > 100
    assert set(loading.fields.values()) == {1}, loading.fields
    assert "tetherheli.runs.start:paper_gain" in flying.entered  # designed anew
    assert not flying.fields
    assert flying.every == dict.fromkeys(SIMULATE_ENTRY, 1), dict(flying.every)


def test_run_batch_checks_each_run_once_at_its_entry():
    """``run_batch`` checks its workers once and each run once (a Scenario of a built-in
    wind, its memory as flown: recorded for the MPC's Python loop), before any work; the
    set-up and ``simulate``'s loop for the MPC run check nothing again."""
    s = _short("paper_sim1_tethered")
    mass = s.params.helicopter.m_F
    runs = [s.replace(params=s.params.replace(helicopter={"m_F": mass * f})) for f in (0.99, 1.01)]
    runs.append(_short("paper_sim1_tethered", "mpc"))
    run_batch(runs, workers=1)  # compiled outside the trace
    _empty_caches()
    with _traced() as calls:
        batch = run_batch(runs, workers=1)
    assert batch.ok.all()
    n = len(runs)
    assert calls.every == {
        "tetherheli._validation.check_integer <- tetherheli.runs.batch:run_batch": 1,
        "tetherheli.runs.batch._check <- tetherheli.runs.batch:run_batch": n,
        "tetherheli.runs.closed_loop.check_run_memory <- tetherheli.runs.batch:run_batch": n,
        "tetherheli.resources.check_memory <- tetherheli.runs.closed_loop:check_run_memory": n,
    }


def test_the_formats_are_checked_once(tmp_path):
    """A writer checks its data and figure formats once, at its entry, and writes the files
    without checking again (``SimulationResult.save``'s and ``save_figure``'s checks are
    theirs, for their callers); ``tetherheli simulate`` checks ``--format`` once (its
    packages, before the runs; both formats are argparse's choices) and each run's memory
    once."""
    from tetherheli.cli import main
    from tetherheli.report.paper import write_run

    s = _short("paper_sim1_free")
    result = simulate(s)
    with _traced() as calls:
        write_run(result, tmp_path / "api", data_format="csv", figure_format="svg")
    formats = {k: n for k, n in calls.every.items() if "_format" in k}
    assert formats == {
        "tetherheli.results.files.check_result_format <- tetherheli.report.paper:write_run": 1,
        "tetherheli.viz.formats.check_figure_format <- tetherheli.report.paper:write_run": 1,
    }
    (tmp_path / "run.toml").write_text(f"name = 'short'\nduration = {s.duration}\n")
    with _traced() as calls:
        code = main(["simulate", str(tmp_path / "run.toml"), "--out", str(tmp_path / "cli"),
                     "--figure-format", "svg"])  # fmt: skip
    assert code == 0
    formats = {k: n for k, n in calls.every.items() if "_format" in k or "run_memory" in k}
    assert formats == {
        "tetherheli.results.files.check_result_format <- tetherheli.cli.simulate:run": 1,
        "tetherheli.runs.closed_loop.check_run_memory <- tetherheli.cli.simulate:run": 1,
        "tetherheli.resources.check_memory <- tetherheli.runs.closed_loop:check_run_memory": 1,
    }


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
