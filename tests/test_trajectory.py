"""control.trajectory: the rest-to-rest minimum-jerk (Flash & Hogan 1985, the quintic
10 s^3 - 15 s^4 + 6 s^5) and minimum-snap (Mellinger & Kumar 2011, the septic
35 s^4 - 84 s^5 + 70 s^6 - 20 s^7) segments meet their boundary conditions, peak at
1.875 D / T and 2.1875 D / T, and join continuously; steps; the CSV reader refuses bad files
in one line naming row and column, never echoing the file; the [reference] table's rules."""

from __future__ import annotations

import numpy as np
import pytest

from tetherheli.control.trajectory import (
    PEAK_SPEED_FACTOR,
    Climb,
    Hold,
    Steps,
    Waypoints,
    read_trajectory_csv,
    smooth_step,
)
from tetherheli.errors import ParameterError
from tetherheli.scenario.core import scenario_from_dict

# the derivatives by central differences of the profile's own s and s' (an independent check
# of the closed forms of s', s'')
H = 1e-5


@pytest.mark.parametrize("smoothing", ["min_jerk", "min_snap"])
def test_segments_meet_their_boundary_conditions(smoothing):
    """s(0) = 0, s(1) = 1, s' = s'' = 0 at both ends (and s''' = 0 for minimum-snap)."""
    for tau, s_end in ((0.0, 0.0), (1.0, 1.0)):
        s, ds, dds = smooth_step(tau, smoothing)
        assert s == s_end
        assert ds == 0.0 and dds == 0.0
    # the profile's polynomial (recovered by an exact fit of degree 7 to its samples): its
    # third derivative vanishes at both ends for minimum-snap, is 60 for minimum-jerk
    taus = np.linspace(0.0, 1.0, 41)
    poly = np.polynomial.Polynomial.fit(taus, [smooth_step(t, smoothing)[0] for t in taus], 7)
    jerk = poly.deriv(3)
    expected = 0.0 if smoothing == "min_snap" else 60.0
    assert jerk(0.0) == pytest.approx(expected, abs=1e-6)
    assert jerk(1.0) == pytest.approx(expected, abs=1e-6)
    for tau in np.linspace(0.05, 0.95, 7):  # the closed-form derivatives are the profile's
        s_p, s_m = smooth_step(tau + H, smoothing)[0], smooth_step(tau - H, smoothing)[0]
        assert abs((s_p - s_m) / (2 * H) - smooth_step(tau, smoothing)[1]) < 1e-7
        d_p, d_m = smooth_step(tau + H, smoothing)[1], smooth_step(tau - H, smoothing)[1]
        assert abs((d_p - d_m) / (2 * H) - smooth_step(tau, smoothing)[2]) < 1e-6


@pytest.mark.parametrize(("smoothing", "factor"), [("min_jerk", 1.875), ("min_snap", 2.1875)])
def test_peak_speed_is_the_stated_multiple_of_the_mean(smoothing, factor):
    """A segment of length D flown at peak speed v lasts T = factor D / v, its speed peaks
    at v = factor D / T (at mid-segment)."""
    assert PEAK_SPEED_FACTOR[smoothing] == factor
    D, v = 5.0, 0.8
    path = Waypoints([[3.0, 0.0, 4.0]], [v], smoothing)
    T = path.end
    assert T == pytest.approx(factor * D / v, rel=1e-14)
    speeds = [np.linalg.norm(path.at(t).velocity) for t in np.linspace(0, T, 2001)]
    assert max(speeds) == pytest.approx(factor * D / T, rel=1e-9)
    assert np.argmax(speeds) == 1000  # at T / 2


@pytest.mark.parametrize("smoothing", ["min_jerk", "min_snap"])
def test_waypoints_are_continuous_and_rest_at_each_point(smoothing):
    points = [[2.0, 0.0, 0.0], [2.0, 2.0, 1.0], [0.0, 2.0, 1.0]]
    path = Waypoints(points, [0.5, 0.4, 0.6], smoothing, start_time=1.5)
    knots = path.knots
    assert knots[0] == 1.5
    for i, t in enumerate(knots):
        before, after = path.at(t - 1e-9), path.at(t + 1e-9)
        np.testing.assert_allclose(before.position, after.position, atol=1e-8)
        np.testing.assert_allclose(after.velocity, 0.0, atol=1e-6)
        expected = np.zeros(3) if i == 0 else np.asarray(points[i - 1])
        np.testing.assert_allclose(path.at(t).position, expected, atol=1e-12)
    np.testing.assert_array_equal(path.at(knots[-1] + 5).position, points[-1])
    # the velocity is the position's rate (finite differences mid-segment)
    t = 0.5 * (knots[1] + knots[2])
    fd = (path.at(t + 1e-6).position - path.at(t - 1e-6).position) / 2e-6
    np.testing.assert_allclose(path.at(t).velocity, fd, atol=1e-6)


def test_steps_jump_or_move_by_min_jerk():
    jump = Steps([1.0, 4.0], [[2.0, 0.0, 0.0], [2.0, 0.0, 1.0]])
    np.testing.assert_array_equal(jump.at(0.99).position, 0.0)
    np.testing.assert_array_equal(jump.at(1.0).position, [2.0, 0.0, 0.0])
    smooth = Steps([1.0, 4.0], [[2.0, 0.0, 0.0], [2.0, 0.0, 1.0]], transition=2.0)
    assert smooth.at(2.0).position[0] == pytest.approx(1.0)  # half-way at mid-transition
    assert smooth.at(2.0).velocity[0] == pytest.approx(1.875 * 2.0 / 2.0)
    np.testing.assert_array_equal(smooth.at(3.0).position, [2.0, 0.0, 0.0])
    assert smooth.end == 6.0
    with pytest.raises(ParameterError, match=r"^reference\.times"):
        Steps([1.0, 2.0], [[1, 0, 0], [2, 0, 0]], transition=2.0)  # overlapping moves


def test_hold_and_climb():
    assert not Hold().at(3.0).position.any()
    climb = Climb(2.0, 0.5, 3.0)
    assert climb.end == 8.0
    assert climb.at(4.0).position[2] == pytest.approx(1.0)
    assert climb.at(4.0).velocity[2] == 0.5


def test_waypoints_refuse_speeds_that_are_not_positive():
    with pytest.raises(ParameterError, match=r"^reference\.speeds") as err:
        Waypoints([[1.0, 0.0, 0.0]], [0.0])
    assert "\n" not in str(err.value)


# -- the CSV reader --------------------------------------------------------------------------


def _csv(tmp_path, text: str):
    path = tmp_path / "path.csv"
    path.write_text(text, encoding="ascii")
    return path


def test_csv_trajectory_interpolates_a_path(tmp_path):
    t = np.linspace(0.0, 10.0, 41)
    rows = "".join(f"{a:.17g},{np.sin(a):.17g},{0.1 * a:.17g},0,{0.01 * a:.17g}\n" for a in t)
    path = read_trajectory_csv(_csv(tmp_path, "t,x,y,z,yaw\n" + rows))
    p = path.at(3.3)
    assert p.position[0] == pytest.approx(np.sin(3.3), abs=2e-4)  # the cubic spline's error
    assert p.velocity[0] == pytest.approx(np.cos(3.3), abs=2e-3)
    assert p.velocity[1] == pytest.approx(0.1, abs=1e-9)
    assert p.yaw == pytest.approx(0.033, abs=1e-9)
    assert len(path.sha256) == 64


@pytest.mark.parametrize(
    ("text", "where"),
    [
        ("t,x,y\n0,0,0\n", "reference.file row 1"),  # wrong header
        ("t,x,y,z\n0,0,0,0\n1,0,0,0\n2,0,SECRET,0\n3,0,0,0\n", "row 4 column y"),
        ("t,x,y,z\n0,0,0,0\n1,0,0,0\n1,0,0,0\n3,0,0,0\n", "row 4 column t"),  # not increasing
        ("t,x,y,z\n0,0,0,0\n1,0,0,1e9\n", "row 3 column z"),  # out of range
        ("t,x,y,z\n0,0,0,0\n1,0,0\n", "reference.file row 3"),  # a cell missing
    ],
)
def test_csv_reader_refuses_bad_files_naming_row_and_column(tmp_path, text, where):
    with pytest.raises(ParameterError) as err:
        read_trajectory_csv(_csv(tmp_path, text))
    message = str(err.value)
    assert where in message
    assert "\n" not in message and "SECRET" not in message


# -- the [reference] table's rules -----------------------------------------------------------


def _scenario(**reference):
    return {"name": "t", "duration": 20.0, "reference": reference}


@pytest.mark.parametrize(
    ("data", "field"),
    [
        ({**_scenario(type="waypoints", x=[1.0], y=[0.0], z=[0.0], speeds=[-1.0])},
         "reference.speeds"),
        ({**_scenario(type="steps", times=[1.0], x=[1.0], y=[0.0], z=[0.0]),
          "maneuver": {"type": "tethered_landing", "landing_tension": 15.0},
          "winch": {"min_length": 0.02}, "params": {"tether": {"K_C": 400.0}}}, "reference.type"),
        (_scenario(type="steps", times=[30.0], x=[1.0], y=[0.0], z=[0.0]), "reference.times"),
        (_scenario(type="steps", times=[1.0], x=[1.0], y=[0.0, 1.0], z=[0.0]), "reference.y"),
        (_scenario(type="hold", speeds=[1.0]), "reference.speeds"),  # not the type's key
        ({**_scenario(type="takeoff", height=20.0), "configuration": "free"}, "reference.type"),
        (_scenario(type="takeoff", height=10.0), "reference.height"),  # below q9 = 10 m's HO
        ({**_scenario(type="steps", times=[1.0], x=[1.0], y=[0.0], z=[0.0]),
          "control": {"controller": "mpc"}}, "control.controller"),
    ],
)  # fmt: skip
def test_reference_table_rules_refuse_in_one_line(data, field):
    with pytest.raises(ParameterError) as err:
        scenario_from_dict(data)
    assert str(err.value).startswith(field + " ")
    assert "\n" not in str(err.value)


def test_csv_reference_must_cover_the_run(tmp_path):
    path = _csv(tmp_path, "t,x,y,z\n0,0,0,0\n1,0,0,0\n2,0,0,0\n3,0,0,0\n")
    with pytest.raises(ParameterError, match=r"^reference\.file .*covering the run"):
        scenario_from_dict(_scenario(type="csv", file=str(path)))
    s = scenario_from_dict({**_scenario(type="csv", file=str(path)), "duration": 3.0})
    assert s.input_files == {str(path.resolve()): s.trajectory.file_sha256}


def test_a_montecarlo_refuses_a_takeoff(tmp_path):
    """Each Monte Carlo draw flies free and tethered; a take-off has no free run."""
    from tetherheli.studies.montecarlo.config import load_montecarlo

    path = tmp_path / "mc.toml"
    path.write_text(
        'name = "mc"\nq9 = 1.0\n[params.tension_control]\nT_ref = 15.0\n'
        '[reference]\ntype = "takeoff"\nheight = 5.0\n[montecarlo]\nruns = 2\n'
    )
    with pytest.raises(ParameterError, match=r"reference\.type = 'takeoff'") as err:
        load_montecarlo(path)
    assert "\n" not in str(err.value)
