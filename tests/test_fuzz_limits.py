"""Issue 43: a property-based fuzzer of flown runs (Hypothesis). It draws short scenarios
across the surfaces whose limits a run must keep: ``[actuators]`` (input bounds around the
hover, lag, reel rate and acceleration limits, a breaking tension), ``[winch]`` payout limits,
``[limits]``, the three controllers, a moving ``[base]`` with either reference, and
``[maneuver]`` landings, with a wind pulse. Each is loaded as a TOML table would be (a refusal
is one ``ParameterError`` line naming a field) and flown; the property: a run that succeeds
(``Status.is_success``) recorded only finite values and kept every limit its scenario sets
over the whole run (``SimulationResult.limit_violations``), and ``run_batch`` gives it the
same status as ``simulate``.

Bounded in CI: a fixed example budget, derandomized, about 30 s.
``TETHERHELI_FUZZ_EXAMPLES=500`` runs longer (and random) on demand.
"""

from __future__ import annotations

import os
import re

import pytest

hypothesis = pytest.importorskip("hypothesis")

from hypothesis import HealthCheck, event, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from tetherheli import simulate  # noqa: E402
from tetherheli.errors import ParameterError  # noqa: E402
from tetherheli.runs.batch import run_batch  # noqa: E402
from tetherheli.scenario.core import scenario_from_dict  # noqa: E402
from tetherheli.status import Status  # noqa: E402

_ON_DEMAND = int(os.environ.get("TETHERHELI_FUZZ_EXAMPLES", "0") or 0)
_SETTINGS = settings(
    max_examples=_ON_DEMAND or 60,
    derandomize=not _ON_DEMAND,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
    database=None,
)

#: A refusal: "[source: ]field = value is invalid; allowed: ..." on one line.
REFUSAL = re.compile(r"^(?P<source>[^\n]*?: )?(?P<field>[\w.\[\]/-]+) = .* is invalid; allowed: ")

#: the hover's total inputs (fMR3, tMR1, tMR2, fTR2), rounded, of the paper's trims: tethered
#: at 25 N (Table V, with the tether's moment) and free (Table IV); the input bounds are drawn
#: around them
_HOVER = {"tethered": (148.66, 1.785, 0.0, 13.76), "free": (123.76, 1.093, 0.0, 11.46)}


def _maybe(strategy):
    return st.one_of(st.none(), strategy)


@st.composite
def scenarios(draw) -> dict:
    """A short scenario table (a TOML file's data) over the limits' surfaces."""
    configuration = draw(st.sampled_from(["tethered", "tethered", "free"]))
    tethered = configuration == "tethered"
    data: dict = {"configuration": configuration, "duration": draw(st.sampled_from([1.0, 2.5]))}
    controller = draw(st.sampled_from(["paper", "paper", "tether_lqi", "mpc"]))
    if controller == "tether_lqi" and not tethered:
        controller = "paper"
    data["control"] = {"controller": controller}
    act: dict = {}
    margin = draw(_maybe(st.floats(0.02, 0.5)))  # input bounds: the hover +- a share of it
    if margin is not None:
        hover = _HOVER[configuration]
        act["u_min"] = [h - margin * max(abs(h), 1.0) for h in hover]
        act["u_max"] = [h + margin * max(abs(h), 1.0) for h in hover]
    for key, strategy in (
        ("time_constant", st.floats(0.0, 0.2)),
        ("reel_rate_limit", st.floats(1e-3, 2.0)),
        ("reel_acceleration_limit", st.floats(0.01, 20.0)),
        ("breaking_tension", st.floats(25.5, 60.0)),
    ):
        value = draw(_maybe(strategy))
        if value is not None:
            act[key] = value
    if act:
        data["actuators"] = act
    if tethered and draw(st.booleans()):
        data["winch"] = {"min_length": draw(st.floats(0.1, 9.3))}
    data["limits"] = {"max_tension": draw(st.sampled_from([60.0, 500.0]))}
    magnitude = draw(st.floats(0.0, 40.0))
    direction = draw(st.sampled_from([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]))
    data["wind"] = [
        {"type": "pulse", "start": 0.2, "duration": 0.5, "magnitude": magnitude,
         "direction": direction}
    ]  # fmt: skip
    kind = draw(st.sampled_from(["still", "moving base", "landing"]))
    if tethered and controller == "paper" and kind != "still":
        data["base"] = {"motion": "velocity", "velocity": [draw(st.floats(-3.0, 3.0)), 0.0, 0.0]}
        data["control"]["reference"] = draw(st.sampled_from(["ground", "base"]))
        if kind == "landing":  # started early, fast enough to touch down within the run
            data["control"]["reference"] = "base"
            data["duration"] = 12.0
            data["maneuver"] = {
                "type": "tethered_landing",
                "start_time": 0.2,
                "descent_rate": draw(st.floats(0.8, 2.0)),
                "landing_tension": 15.0,
            }
            # the rope (a landing's default law) with the shipped landings' PI gains
            data["params"] = {"tension_control": {"K_P": 0.015, "K_I": 0.0015}}
            data["winch"] = {"min_length": 0.02}
    return data


@_SETTINGS
@given(data=scenarios())
def test_a_successful_run_keeps_every_limit_its_scenario_sets(data):
    try:
        scenario = scenario_from_dict(data)
    except ParameterError as exc:
        assert REFUSAL.match(str(exc)) and "\n" not in str(exc), str(exc)
        event(f"refused when loaded: {exc.field}")
        return
    try:
        r = simulate(scenario)
    except ParameterError as exc:  # a set-up the physics cannot meet: one line
        assert REFUSAL.match(str(exc)) and "\n" not in str(exc), str(exc)
        event(f"refused at set-up: {exc.field}")
        return
    event(f"flown: {Status(r.status).name}")
    if r.ok:
        assert r.limit_violations() == [], (data, r.message)
    else:
        assert r.status != Status.OK
    batch = run_batch([scenario], workers=1)
    assert int(batch.status[0]) == r.status, (data, r.message, batch.message(0))


def test_the_ci_run_is_bounded():
    """Derandomized with a fixed budget unless asked for more."""
    if not _ON_DEMAND:
        assert _SETTINGS.max_examples == 60 and _SETTINGS.derandomize
