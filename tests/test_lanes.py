"""The lane engine (``lanes.run_lanes``): a block of runs advanced together gives, lane by
lane, the numbers of the single-run engine and of ``simulate``, with actuators, sensors,
turbulence, releases and failures in the same block."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from tetherheli.analysis import run_metrics
from tetherheli.engine import lanes
from tetherheli.engine import loop as engine
from tetherheli.layout import CTRL_LAW, LANES, SUMMARY_FIELDS, WIND_SINE, Signals
from tetherheli.model.kernels import (
    SIN_BRANCHLESS_MAX_ARG,
    angle_trig,
    angle_trig_lanes,
    sin_branchless,
)
from tetherheli.runs import simulate
from tetherheli.runs.batch import lane_block, run_batch
from tetherheli.runs.setup import engine_setup
from tetherheli.scenario.core import ActuatorSettings, load_scenario, paper_scenario
from tetherheli.sensing.config import SensorConfig
from tetherheli.status import Status
from tetherheli.wind import DragModel, GaussMarkovTurbulence, Pulse, Sine, Step, Turbulence


def _dispersed_runs() -> list:
    """More runs than one block, every feature of the engine in some lane: dispersed plants,
    both configurations, pulses/sines/steps, actuator limits and lag, a low breaking tension
    (release), noisy sensors (GPS and tether sources), turbulence with drag, a run that
    diverges, and different durations and sample times."""
    rng = np.random.default_rng(7)
    runs = []
    for i in range(LANES + 5):
        configuration = ("free", "tethered")[i % 2]
        base = paper_scenario(1 + i % 2, configuration)
        angle = 0.4 * i
        d = (math.cos(angle), math.sin(angle), 0.0)
        wind = Pulse(1.0, 0.5, 12.0 + i, d) + Sine(6.0, 0.3 + 0.05 * i, 2.0, d, phase=0.1 * i)
        if i % 7 == 3:
            wind = wind + Step(2.5, -4.0, (0.0, 1.0, 0.0))
        s = base.replace(
            duration=4.0 + 0.5 * (i % 3),
            wind=wind,
            params=base.params.replace(
                {"helicopter.m_F": 12.0 * (1 + 0.05 * rng.standard_normal())}
            ),
        )
        if i % 4 == 1:
            s = s.replace(
                actuators=ActuatorSettings(
                    u_min=(0.0, -4.0, -4.0, -20.0),
                    u_max=(250.0, 4.0, 4.0, 20.0),
                    time_constant=0.02,
                    reel_acceleration_limit=0.3,
                )
            )
        if i % 5 == 3 and configuration == "tethered":
            s = s.replace(actuators=ActuatorSettings(breaking_tension=25.01))
        if i % 6 == 2:
            source = "tether" if configuration == "tethered" else "gps"
            sensors = (
                SensorConfig.typical_tether() if source == "tether" else SensorConfig.typical_gps()
            )
            s = s.replace(sensors=sensors, seed=100 + i)
        if i % 6 == 5:
            gusts = Turbulence(
                GaussMarkovTurbulence(gain=(1.5, 1.5, 0.7), pole_rad_s=(0.5, 0.5, 0.5)),
                DragModel(cd_area_m2=(0.4, 0.4, 0.8)),
                seed=i,
                duration=6.0,
                dt=0.01,
                N_v_mean_wind=(4.0, 0.0, 0.0),
            )
            s = s.replace(wind=gusts + Pulse(1.0, 0.5, 5.0, d))
        if i == 9:  # a gust the free helicopter cannot ride out within 0.5 m: it fails
            s = s.replace(limits=dataclasses.replace(s.limits, max_deviation=0.05))
        if i == 11:
            s = s.replace(control=dataclasses.replace(s.control, dt=0.02))
        runs.append(s)
    return runs


@pytest.fixture(scope="module")
def runs():
    return _dispersed_runs()


@pytest.fixture(scope="module")
def lane_batch(runs):
    return run_batch(runs, workers=2)


def test_lanes_equal_single_runs_bit_for_bit(runs, lane_batch):
    """Every lane performs a single run's operations in the same order: summaries, statuses
    and sample counts equal the one-run-at-a-time engine's exactly."""
    single = run_batch(runs, workers=1, lanes=False)
    np.testing.assert_array_equal(lane_batch.status, single.status)
    np.testing.assert_array_equal(lane_batch.samples_done, single.samples_done)
    np.testing.assert_array_equal(lane_batch.summaries, single.summaries)
    # the block really held every feature: a release, a failure, completed runs
    assert np.isfinite(lane_batch.release_time).any()
    assert (lane_batch.status == Status.DIVERGED).any()
    assert lane_batch.ok.sum() >= len(runs) - 3


def test_lanes_equal_simulate(runs, lane_batch):
    """The recorded metrics of ``simulate`` (a different loop that records every sample)
    agree with each lane's on-line summary to 1e-9 relative."""
    for i in (0, 1, 2, 3, 5, 11, 13):
        r = simulate(runs[i])
        assert r.ok == bool(lane_batch.ok[i])
        m = run_metrics(r)
        got = lane_batch.metrics(i)
        for name, want in (
            ("peak_q1", m.peak_abs_dev["q1"]),
            ("peak_q2", m.peak_abs_dev["q2"]),
            ("rms_q3", m.rms_dev["q3"]),
            ("tension_max", m.tension_max),
        ):
            assert got[name] == pytest.approx(want, rel=1e-9, abs=1e-12), (i, name)


def test_partial_block_and_padding():
    """A block of fewer runs than LANES: the padding lanes never run and leave the runs'
    results alone."""
    s = paper_scenario(1, "tethered").replace(duration=2.0)
    setups = [engine_setup(s), engine_setup(s.replace(q9=9.0))]
    args = lane_block(setups, [s.n_samples, s.n_samples])
    summary = np.empty((LANES, len(SUMMARY_FIELDS)))
    status = np.empty(LANES, np.int64)
    done = np.empty(LANES, np.int64)
    lanes.run_lanes(*args, (summary, status, done))
    single = np.empty(len(SUMMARY_FIELDS))
    for j in range(2):
        st, k = engine.run_closed_loop(
            *setups[j].engine_args(s.n_samples), False, _dummy_out(), single
        )
        assert (status[j], done[j]) == (st, k)
        np.testing.assert_array_equal(summary[j], single)
    assert np.all(done[2:] == 0) and np.all(summary[2:, SUMMARY_FIELDS.index("n_samples")] == 0)


def test_mixed_substeps_go_in_separate_blocks(runs):
    two = runs[0]
    four = two.replace(control=dataclasses.replace(two.control, substeps=4))
    batch = run_batch([two, four, two], workers=1)
    alone = run_batch([two, four, two], workers=1, lanes=False)
    np.testing.assert_array_equal(batch.summaries, alone.summaries)
    assert batch.summaries[0, 0] != batch.summaries[1, 0]  # 4 RK4 steps: other rounding


def test_run_lanes_refuses_mixed_substeps():
    s = paper_scenario(1, "free").replace(duration=0.1)
    a, b = engine_setup(s), engine_setup(s)
    b.cfg[engine.CFG_N_SUB] = 4
    args = lane_block([a, b], [10, 10])
    with pytest.raises(ValueError, match="same RK4 steps"):
        lanes.run_lanes(
            *args,
            (
                np.empty((LANES, len(SUMMARY_FIELDS))),
                np.empty(LANES, np.int64),
                np.empty(LANES, np.int64),
            ),
        )


def test_sin_branchless_agrees_with_libm():
    """The wind profiles' sine (no branch, no call: it vectorises over lanes) is within one
    unit in the last place of libm on the range the engine allows."""
    rng = np.random.default_rng(3)
    xs = np.concatenate(
        [
            rng.uniform(-8.0, 8.0, 20000),
            rng.uniform(-SIN_BRANCHLESS_MAX_ARG, SIN_BRANCHLESS_MAX_ARG, 20000),
            np.arange(-64, 65) * (math.pi / 4),  # the reduction's quadrant boundaries
        ]
    )
    got = np.array([sin_branchless(x) for x in xs])
    want = np.sin(xs)
    assert np.max(np.abs(got - want)) <= 2.3e-16


def test_angle_trig_lanes_equals_angle_trig():
    """The lanes' sine and cosine of the angles (``angle_trig_lanes``) are the single run's
    (``angle_trig``, libm) bit for bit."""
    rng = np.random.default_rng(4)
    x = np.zeros((LANES, 13))
    x[:, :5] = rng.uniform(-3.5, 3.5, (LANES, 5))
    one = np.empty((LANES, 10))
    for j in range(LANES):
        angle_trig(x[j], one[j])
    flat = np.empty(10 * LANES)
    angle_trig_lanes(np.ascontiguousarray(x.T).ravel(), flat)
    np.testing.assert_array_equal(flat.reshape(10, LANES).T, one)
    np.testing.assert_array_equal(one[:, :5], np.sin(x[:, :5]))


def test_lane_wind_converts_no_float_to_integer():
    """The lane engine's wind profiles (``wind.evaluate.profile_value`` with
    ``sin_branchless``) keep every value a double: a float-to-integer conversion (``fptosi``,
    as ``math.floor`` gives) has no vector instruction without AVX-512, so on such a
    processor LLVM converted each lane alone inside the vectorised loop (issue 24). Checked in
    the IR of a fresh compilation, which does not depend on the processor's vectors."""
    from numba import njit

    from tetherheli.model.kernels import sin_branchless as sine
    from tetherheli.wind.evaluate import profile_value

    @njit(error_model="numpy", cache=False)
    def profiles(t, out):  # the lane engine's pass over lanes (``_lanes_program_force``)
        for j in range(t.shape[0]):
            out[j] = profile_value(WIND_SINE, 1.0, 2.0, 4.0, 0.3, 0.1, t[j], 1, True) + sine(t[j])

    t = np.linspace(0.0, 9.0, LANES)
    out = np.empty(LANES)
    profiles(t, out)
    ir = "".join(profiles.inspect_llvm().values())
    assert "fptosi" not in ir and "sitofp" not in ir
    assert out[-1] == pytest.approx(4.0 * math.sin(2 * math.pi * 0.3 * 9.0 + 0.1) + math.sin(9.0))


def test_restrict_arguments_drops_the_run_time_overlap_checks():
    """``_compile.restrict_arguments`` (behind ``rk4_lanes`` and its stages, issue 24 item 4)
    marks a compiled function's arrays ``noalias`` for LLVM: its loop vectorises with no
    run-time overlap check (LLVM's ``vector.memcheck`` blocks), which the same loop without it
    needs, and it computes the same values."""
    from numba import njit

    from tetherheli._compile import restrict_arguments

    @njit(cache=False)
    def restricted(a, x, y):
        restrict_arguments()
        for i in range(y.shape[0]):
            y[i] += a * x[i]

    @njit(cache=False)
    def plain(a, x, y):  # the same loop, without the marks
        for i in range(y.shape[0]):
            y[i] += a * x[i]

    x = np.linspace(-1.0, 1.0, 37)
    y1, y2 = np.cos(x), np.cos(x)
    restricted(0.3, x, y1)
    plain(0.3, x, y2)
    np.testing.assert_array_equal(y1, y2)

    def entry(function) -> tuple[str, str]:  # the compiled function's IR (not its Python wrappers)
        ir = "".join(function.inspect_llvm().values())
        head = next(line for line in ir.splitlines() if line.startswith("define") and
                    "cpython" not in line and "cfunc" not in line)  # fmt: skip
        return head, ir

    head, ir = entry(restricted)
    assert "noalias" in head.split("%arg.x.4")[0].rsplit(",", 1)[-1]  # x's data pointer
    assert "noalias" in head.split("%arg.y.4")[0].rsplit(",", 1)[-1]
    assert "vector.memcheck" not in ir
    assert "vector.memcheck" in entry(plain)[1]


def test_scenario_files_run_in_lanes():
    """Shipped scenarios with every sensor at its own rate and latency (the flown GNSS and
    tether suites) and the turbulence pair in the trim of their wind give the same numbers in
    one block as alone."""
    names = ("sensing_gps", "sensing_tether", "turbulence_hover_free", "turbulence_hover_tethered")
    runs = [load_scenario(f"scenarios/{name}.toml").replace(duration=3.0) for name in names]
    assert any(s.sensors.is_timed for s in runs)
    lanes = run_batch(runs, workers=1)
    alone = run_batch(runs, workers=1, lanes=False)
    assert lanes.ok.all()
    np.testing.assert_array_equal(lanes.summaries, alone.summaries)


def _dummy_out():
    return Signals.zeros(1)


def test_tethered_lqi_lanes_equal_single_runs_bit_for_bit():
    """The tethered LQI over lanes (its reel row, the load cell's q9 of eq 28, the free rows
    once the winch stops after a release, the anti-windup) gives each lane the single run's
    numbers exactly, with sensors and a drum winch in the same block."""
    runs = []
    for i in range(LANES + 3):
        s = paper_scenario(1 + i % 2, "tethered").replace(duration=3.0 + 0.25 * (i % 4))
        s = s.replace(control=dataclasses.replace(s.control, controller="tether_lqi"))
        if i % 5 == 2:  # released mid-run: the winch stops, the free rows take over
            s = s.replace(actuators=ActuatorSettings(breaking_tension=25.05))
        if i % 4 == 1:
            s = s.replace(sensors=SensorConfig.typical_tether(), seed=200 + i)
        if i % 6 == 3:
            s = s.replace(
                actuators=ActuatorSettings(
                    u_min=(0.0, -3.0, -3.0, -20.0), u_max=(250.0, 3.0, 3.0, 20.0),
                    time_constant=0.03,
                )
            )  # fmt: skip
        runs.append(s)
    lanes = run_batch(runs, workers=1)
    alone = run_batch(runs, workers=1, lanes=False)
    np.testing.assert_array_equal(lanes.status, alone.status)
    np.testing.assert_array_equal(lanes.samples_done, alone.samples_done)
    np.testing.assert_array_equal(lanes.summaries, alone.summaries)
    assert np.isfinite(lanes.release_time).any()  # a release happened in the block
    assert lanes.ok.sum() >= len(runs) - 2


def test_run_lanes_refuses_mixed_laws(runs):
    """A block flies one law (``run_batch`` groups runs by controller)."""
    setups = [engine_setup(runs[0]), engine_setup(runs[0])]
    args = list(lane_block(setups, [10, 10]))
    ctrl = args[3].copy()
    ctrl[1, CTRL_LAW] = 1.0
    args[3] = ctrl
    with pytest.raises(ValueError, match="same law"):
        lanes.run_lanes(
            *args,
            (
                np.empty((LANES, len(SUMMARY_FIELDS))),
                np.empty(LANES, np.int64),
                np.empty(LANES, np.int64),
            ),
        )
