"""The air relative to a moving base (issue 44 item 4, issue 46's ship under way): Galilean
invariance with drag. A winch on a base moving at a constant velocity V through air of mean
velocity W (plus gusts) must fly, relative to the base, exactly as a still winch in air of
mean velocity W - V with the same gusts: the helicopter's drag, the chain's drag, the recorded
wind force and the start's trim all see the air relative to the base. Every moving-base test
before this one was drag-free; on b9b549d the start's trim balanced the air relative to N
instead (states 0.1-0.2 apart)."""

from __future__ import annotations

import numpy as np
import pytest

from tetherheli import simulate
from tetherheli.scenario.core import scenario_from_dict
from tetherheli.wind.turbulence import initial_wind_force


def _scenario(velocity, mean_wind, *, lumped=False, duration=3.0, gain=(0.5, 0.5, 0.3)):
    data = {
        "configuration": "tethered",
        "duration": duration,
        "wind": {
            "type": "turbulence",
            "seed": 7,
            "duration": duration,
            "dt": 0.01,
            "N_v_mean_wind": list(mean_wind),
            "model": {"type": "gauss_markov", "gain": list(gain)},
            "drag": {"cd_area_m2": [0.4, 0.4, 0.8], "rho": 1.225},
        },
    }
    if any(velocity):
        data["base"] = {"motion": "velocity", "velocity": list(velocity)}
        data["control"] = {"reference": "base"}
    if lumped:
        data["tether"] = {"model": "lumped", "segments": 4}
    return scenario_from_dict(data)


@pytest.mark.parametrize("lumped", [False, True], ids=["massless", "lumped"])
def test_a_base_under_way_flies_as_a_still_base_in_its_apparent_wind(lumped):
    """V = (3, -2, 0) m/s through W = (5, 0, 0) m/s equals a still base in W - V = (2, 2, 0):
    states, tension and the recorded wind force within 1e-12 (rounding)."""
    duration = 1.0 if lumped else 3.0
    moving = simulate(_scenario((3.0, -2.0, 0.0), (5.0, 0.0, 0.0), lumped=lumped,
                                duration=duration))  # fmt: skip
    still = simulate(_scenario((0.0, 0.0, 0.0), (2.0, 2.0, 0.0), lumped=lumped,
                               duration=duration))  # fmt: skip
    assert moving.ok and still.ok
    assert np.abs(moving.states - still.states).max() < 1e-12
    assert np.abs(moving.tension - still.tension).max() < 1e-9
    assert np.abs(moving.wind - still.wind).max() < 1e-9
    # the air does act: the same base in still air is another run
    calm = simulate(_scenario((3.0, -2.0, 0.0), (0.0, 0.0, 0.0), lumped=lumped,
                              duration=duration))  # fmt: skip
    assert np.abs(calm.states - moving.states).max() > 1e-3


def test_the_start_balances_the_air_relative_to_the_helicopter():
    """``initial_wind_force`` at HO's velocity: a base moving with the mean wind meets no
    air at the start (no gusts), one moving against it twice the speed (four times the
    drag)."""
    wind = _scenario((0.0, 0.0, 0.0), (5.0, 0.0, 0.0), gain=(0.0, 0.0, 0.0)).wind
    at_rest = initial_wind_force(wind)
    assert at_rest[0] > 0
    assert np.allclose(initial_wind_force(wind, (5.0, 0.0, 0.0)), 0.0)
    assert initial_wind_force(wind, (-5.0, 0.0, 0.0))[0] == pytest.approx(4 * at_rest[0])


def _steady(velocity, wind, duration=2.0):
    data = {
        "configuration": "tethered",
        "duration": duration,
        "wind": {"type": "steady", "N_v_wind": list(wind), "drag": {"cd_area_m2": [0.4, 0.4, 0.8]}},
    }
    if any(velocity):
        data["base"] = {"motion": "velocity", "velocity": list(velocity)}
        data["control"] = {"reference": "base"}
    return scenario_from_dict(data)


def test_a_ship_under_way_in_still_air_feels_its_head_wind():
    """``[wind] type = "steady"``: a ship at 5 m/s along n1 through still air flies as a
    still deck in a 5 m/s wind from ahead, and the recorded force at the start is the drag
    0.5 rho CdA U^2 against the ship's motion (CdA 0.4 m^2: 6.125 N)."""
    ship = simulate(_steady((5.0, 0.0, 0.0), (0.0, 0.0, 0.0)))
    still = simulate(_steady((0.0, 0.0, 0.0), (-5.0, 0.0, 0.0)))
    assert ship.ok and still.ok
    assert np.abs(ship.states - still.states).max() < 1e-12
    assert ship.wind[0] == pytest.approx([-0.5 * 1.225 * 0.4 * 25.0, 0.0, 0.0], abs=1e-12)
    calm = simulate(_steady((5.0, 0.0, 0.0), (5.0, 0.0, 0.0)))  # the air moves with the ship
    assert np.abs(calm.wind).max() < 1e-9
    assert np.abs(calm.states - ship.states).max() > 1e-3


@pytest.mark.parametrize(
    "base",
    [
        {"motion": "velocity", "velocity": [3.0, -2.0, 0.0]},
        {"motion": "harmonic", "amplitude": [0.5, 0.3, 0.4], "frequency": [0.3, 0.2, 0.25],
         "phase": [0.0, 1.0, 0.5]},
    ],
    ids=["velocity", "harmonic"],
)  # fmt: skip
def test_recorded_wind_is_the_drag_of_the_air_relative_to_the_helicopter(base):
    """Over a moving base the coordinates and u1..u3 are relative to the base
    (``derive(moving_base=True)``): HO moves at b'(t) + u in N, so the recorded wind force
    is the drag 0.5 rho CdA |r| r of r = v_air - b'(t) - u (the mean wind plus the gust,
    ``Turbulence.gust_velocity``; b'(t) from ``BaseMotion.state``; the drag typed here).
    A flipped sign of b', b' taken in a z-down frame, or b' dropped each fail it."""
    wind = _scenario((0.0, 0.0, 0.0), (4.0, 1.0, 0.0), duration=1.0).wind
    s = scenario_from_dict({
        "configuration": "tethered", "duration": 1.0, "wind": wind.to_dict(), "base": base,
        "control": {"reference": "base"},
    })  # fmt: skip
    r = simulate(s)
    assert r.ok
    air = np.asarray(wind.N_v_mean_wind) + wind.gust_velocity(r.time)
    b_dot = s.base_motion.state(r.time)[:, 1, :]
    rel = air - b_dot - r.states[:, 6:9]
    speed = np.linalg.norm(rel, axis=1, keepdims=True)
    expected = 0.5 * 1.225 * np.array([0.4, 0.4, 0.8]) * speed * rel
    assert np.abs(b_dot).max() > 0.5  # the base does move
    np.testing.assert_allclose(r.wind, expected, rtol=1e-9, atol=1e-12)
