"""One validation style: every entry point treats the same good and bad values alike.

A number is a Python or NumPy real scalar, never a bool; an integer is a Python or NumPy
integer, never a bool or a float; a refusal is one ``ParameterError`` line naming the field,
the value and what is allowed (``tetherheli._validation``)."""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tetherheli import ParameterError, Params, TetherParams
from tetherheli._validation import check_number, check_vector, describe
from tetherheli.envs.env import TetheredHoverEnv
from tetherheli.scenario import ControlSettings, Limits, Scenario
from tetherheli.scenario.core import ActuatorSettings
from tetherheli.sensing.config import SensorConfig
from tetherheli.sensing.noise import noise_table
from tetherheli.sensing.sensors import hover_error_std
from tetherheli.studies.montecarlo import montecarlo_config_from_dict
from tetherheli.viz.animation import animate, render_frame
from tetherheli.wind import DragModel, GaussMarkovTurbulence, Pulse, Turbulence

MISSING = Path("no-such-result-directory")
DRAG = DragModel((0.1, 0.1, 0.1))

#: field -> a call that validates the value as that field (a positive number; any other
#: failure of the call, e.g. a later argument or a missing directory, means "accepted")
NUMBER_ENTRY_POINTS: dict[str, Callable[[Any], object]] = {
    "helicopter.m_F": lambda v: Params.paper().replace(helicopter={"m_F": v}),
    "tether.K_C": lambda v: TetherParams(L_N0=9.375, K_C=v),
    "duration": lambda v: Scenario(duration=v, control=ControlSettings(dt=0.5)),
    "limits.max_deviation": lambda v: Scenario(limits=Limits(max_deviation=v)),
    "Pulse.duration": lambda v: Pulse(0.0, v, 1.0, (1.0, 0.0, 0.0)),
    "DragModel.rho": lambda v: DragModel((0.1, 0.1, 0.1), rho=v),
    "sensors.load_cell_std": lambda v: SensorConfig(load_cell_std=v),
    "q9": lambda v: hover_error_std(SensorConfig(), q9=v),
    "montecarlo.amplitude_std_percent": lambda v: montecarlo_config_from_dict(
        {"amplitude_std_percent": v}
    ),
    "gust_dt": lambda v: TetheredHoverEnv(gust_dt=v, drag="not a drag model"),
    "speed": lambda v: animate(MISSING, "a.gif", speed=v),
    "rotor_radius": lambda v: render_frame(MISSING, "a.png", time=0.0, rotor_radius=v),
}
#: the same for limits where inf means "none"
UNBOUNDED_ENTRY_POINTS: dict[str, Callable[[Any], object]] = {
    "actuators.reel_rate_limit": lambda v: Scenario(actuators=ActuatorSettings(reel_rate_limit=v)),
    "actuators.breaking_tension": lambda v: Scenario(
        actuators=ActuatorSettings(breaking_tension=v)
    ),
}
INTEGER_ENTRY_POINTS: dict[str, Callable[[Any], object]] = {
    "seed": lambda v: Scenario(seed=v),
    "control.substeps": lambda v: Scenario(control=ControlSettings(substeps=v)),
    "montecarlo.runs": lambda v: montecarlo_config_from_dict({"runs": v}),
    "n_samples": lambda v: noise_table(SensorConfig(), v, np.random.default_rng(0)),
    "Turbulence.seed": lambda v: Turbulence(GaussMarkovTurbulence(), DRAG, v, 1.0, 0.1),
    "max_frames": lambda v: animate(MISSING, "a.gif", max_frames=v),
}

ACCEPT, REJECT = "accepted", "rejected"
#: value -> verdict for a positive number; an integer differs on floats
VALUES: list[tuple[Any, str, str]] = [  # (value, as a number, as an integer)
    (True, REJECT, REJECT),
    (np.True_, REJECT, REJECT),
    (math.nan, REJECT, REJECT),
    (math.inf, REJECT, REJECT),
    ("40", REJECT, REJECT),
    (None, REJECT, REJECT),
    (np.int64(40), ACCEPT, ACCEPT),
    (40, ACCEPT, ACCEPT),
    (np.float32(1.5), ACCEPT, REJECT),
    (1.5, ACCEPT, REJECT),
    (-1, REJECT, REJECT),
    (np.float64(-1.5), REJECT, REJECT),
]


def _verdict(field: str, call: Callable[[Any], object], value: Any) -> str:
    try:
        call(value)
    except ParameterError as exc:
        if exc.field != field:
            return ACCEPT  # the value passed; something after it failed
        message = str(exc)
        assert "\n" not in message and f"{field} = {value!r} is invalid; allowed: " in message
        return REJECT
    return ACCEPT


@pytest.mark.parametrize(("value", "as_number", "_as_integer"), VALUES, ids=repr)
@pytest.mark.parametrize("field", NUMBER_ENTRY_POINTS)
def test_every_number_entry_point_treats_a_value_alike(field, value, as_number, _as_integer):
    assert _verdict(field, NUMBER_ENTRY_POINTS[field], value) == as_number


@pytest.mark.parametrize(("value", "as_number", "_as_integer"), VALUES, ids=repr)
@pytest.mark.parametrize("field", UNBOUNDED_ENTRY_POINTS)
def test_limits_take_inf_as_none_and_are_otherwise_alike(field, value, as_number, _as_integer):
    expected = ACCEPT if value == math.inf else as_number
    assert _verdict(field, UNBOUNDED_ENTRY_POINTS[field], value) == expected


@pytest.mark.parametrize(("value", "_as_number", "as_integer"), VALUES, ids=repr)
@pytest.mark.parametrize("field", INTEGER_ENTRY_POINTS)
def test_every_integer_entry_point_treats_a_value_alike(field, value, _as_number, as_integer):
    assert _verdict(field, INTEGER_ENTRY_POINTS[field], value) == as_integer


def test_accepted_numpy_scalars_are_stored_as_plain_python_numbers():
    s = Scenario(duration=np.int64(40), seed=np.int64(3), limits=Limits(max_tension=np.float32(50)))
    assert type(s.duration) is float and type(s.seed) is int
    assert type(s.limits.max_tension) is float and s.to_dict()["seed"] == 3
    assert type(Params.paper().replace(tether={"K_C": np.int64(40)}).tether.K_C) is float
    assert type(SensorConfig(gps_std=np.array([1, 2, 3])).gps_std[0]) is float


def test_the_allowed_text_is_one_description_of_the_check():
    assert describe(low=0.0, low_open=True) == "a finite number > 0"
    assert describe(integer=True, low=1, high=10) == "an integer in [1, 10]"
    assert describe(low=0.0, high=100.0, high_open=True) == "a finite number in [0, 100)"
    assert describe(finite=False, low=0.0, low_open=True) == "a number > 0 (inf: none)"
    with pytest.raises(ParameterError, match=r"^x = 'a' is invalid; allowed: a nonzero finite"):
        check_number("x", "a", nonzero=True)
    with pytest.raises(ParameterError, match=r"v = \[1, 2\] is invalid; allowed: 3 finite"):
        check_vector("v", [1, 2], 3)
    assert check_vector("v", (1, np.float32(2.5), np.int8(3)), 3) == (1.0, 2.5, 3.0)
