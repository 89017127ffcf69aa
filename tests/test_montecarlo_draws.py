"""Monte Carlo dispersions pinned against values computed here (issue 10, item 6).

Every expectation is built in this file from the draw's recorded factors (``amplitude_scale``,
``direction_deg``, ``phase_rad``, ``start_shift_s``) and the nominal profile, with a rotation
matrix and a time delay written out by hand: a dispersed wind must be the nominal wind scaled,
rotated about n3 (right-handed: a positive angle turns n1 towards n2) and delayed by the shift
(the sine keeps its absolute-time convention of Sec. VI, ``sin(2 pi f t + phase)``, so its
phase becomes ``p0 - 2 pi f s``). The summary's percentiles are checked on a table with failed
rows against percentiles computed by hand.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from tetherheli.runs.batch import METRIC_NAMES
from tetherheli.scenario.core import Scenario
from tetherheli.studies.montecarlo import MonteCarloConfig, draw, draw_seed
from tetherheli.wind import (
    ConstantForce,
    DragModel,
    GaussMarkovTurbulence,
    Pulse,
    Sine,
    Step,
    Turbulence,
)

#: Nominal profiles. Their starts (>= 2 s) lie beyond four standard deviations of the 0.5 s
#: jitter, so no draw below is clipped at t = 0 and the delay is exact.
PULSE = Pulse(start=2.0, duration=0.5, magnitude=20.0, direction=(1.0, 0.5, 0.3))
STEP = Step(start=3.0, magnitude=5.0, direction=(0.0, 1.0, 0.0))
SINE = Sine(amplitude=10.0, frequency=0.3, start=4.0, direction=(1.0, 0.0, 0.0), phase=0.7)
CONSTANT = ConstantForce((2.0, -1.0, 0.5))
PROFILES = (PULSE, STEP, SINE, CONSTANT)

BASE = Scenario(name="disp", duration=12.0, wind=PULSE + STEP + SINE + CONSTANT)
JITTER = MonteCarloConfig(
    runs=50,
    seed=20261122,
    amplitude_std_percent=20.0,
    direction_std_deg=30.0,
    start_jitter_s=0.5,
)

#: times that avoid every discontinuity of the nominal and dispersed profiles (irrational
#: offset), from before the earliest start to after the latest
T = np.linspace(0.0, 12.0, 2401) + 1e-3 * math.pi


def _rz(deg: float) -> np.ndarray:
    """Rotation about n3 by ``deg`` degrees, right-handed (n1 -> n2 for deg > 0)."""
    a = math.radians(deg)
    return np.array([[math.cos(a), -math.sin(a), 0.0], [math.sin(a), math.cos(a), 0.0], [0, 0, 1]])


def _expected(nominal, d, t: np.ndarray) -> np.ndarray:
    """Nominal profile scaled by the draw, rotated about n3 and delayed by its shift; the sine
    with the drawn phase (at its nominal time origin) when phases are drawn."""
    if isinstance(nominal, ConstantForce):  # time-invariant: scale and rotation only
        return d.amplitude_scale * np.tile(
            _rz(d.direction_deg) @ np.asarray(nominal.vector), (t.size, 1)
        )
    if isinstance(nominal, Sine) and not math.isnan(d.phase_rad):
        nominal = dataclasses.replace(nominal, phase=d.phase_rad)
    before = t - d.start_shift_s
    out = np.zeros((t.size, 3))
    ok = before >= 0.0
    out[ok] = nominal.force(before[ok])
    return d.amplitude_scale * out @ _rz(d.direction_deg).T


@pytest.mark.parametrize("random_phase", [False, True])
def test_every_profile_is_scaled_rotated_and_delayed(random_phase):
    """Pulse, step, sine and constant of one draw: force(t) = a R3(theta) F_nominal(t - s), with
    (a, theta, s) the draw's recorded amplitude scale, direction and start shift."""
    config = dataclasses.replace(JITTER, random_phase=random_phase)
    signs = set()
    for i in range(12):
        d = draw(BASE, config, draw_seed(config.seed, i), i)
        parts = d.scenario.wind.components
        assert [type(p) for p in parts] == [type(p) for p in PROFILES]
        assert min(p.start for p in PROFILES[:3]) + d.start_shift_s > 0.0  # no clipping
        assert math.isnan(d.phase_rad) != random_phase
        for nominal, got in zip(PROFILES, parts, strict=True):
            np.testing.assert_allclose(
                got.force(T), _expected(nominal, d, T), rtol=0, atol=1e-11, err_msg=str(got)
            )
        signs.add((d.amplitude_scale > 1.0, d.direction_deg > 0.0, d.start_shift_s > 0.0))
    # the draws exercised larger and smaller scales, both turning senses, both shift signs
    assert (
        {s[0] for s in signs}
        == {s[1] for s in signs}
        == {s[2] for s in signs}
        == {
            False,
            True,
        }
    )


def test_rotation_sense_and_axis():
    """A positive direction draw turns n1 towards +n2 about n3: the n3 component and the
    magnitude are kept."""
    for i in range(20):
        d = draw(BASE, JITTER, draw_seed(JITTER.seed, i), i)
        pulse = d.scenario.wind.components[0]
        sine = d.scenario.wind.components[2]
        # the sine's nominal direction is n1: after the draw it is (cos, sin, 0) of the angle
        a = math.radians(d.direction_deg)
        assert sine.direction == pytest.approx((math.cos(a), math.sin(a), 0.0), abs=1e-15)
        assert math.copysign(1.0, sine.direction[1]) == math.copysign(1.0, d.direction_deg)
        assert pulse.direction[2] == pytest.approx(PULSE.direction[2], abs=1e-15)
        assert np.linalg.norm(pulse.direction) == pytest.approx(1.0, abs=1e-15)


@pytest.mark.parametrize("random_phase", [False, True])
def test_sine_phase_sign_when_the_start_is_shifted(random_phase):
    """The sine keeps its absolute-time form A sin(2 pi f t + p) (Sec. VI's convention): shifted
    by s its phase is p0 - 2 pi f s, which is the nominal waveform delayed by s (not advanced),
    p0 being the file's phase or, with random_phase, the drawn one."""
    config = dataclasses.replace(JITTER, random_phase=random_phase)
    for i in range(10):
        d = draw(BASE, config, draw_seed(config.seed, i), i)
        sine = d.scenario.wind.components[2]
        p0 = d.phase_rad if random_phase else SINE.phase
        want = p0 - 2.0 * math.pi * SINE.frequency * d.start_shift_s
        assert (math.cos(sine.phase), math.sin(sine.phase)) == pytest.approx(
            (math.cos(want), math.sin(want)), abs=1e-12
        )
        assert sine.start == pytest.approx(SINE.start + d.start_shift_s, abs=1e-15)
        # delayed: the value at t + s equals the undispersed (scaled, rotated) value at t
        t = SINE.start + np.linspace(0.05, 5.0, 100)
        undelayed = Sine(
            d.amplitude_scale * SINE.amplitude, SINE.frequency, SINE.start, sine.direction, p0
        )
        np.testing.assert_allclose(
            sine.force(t + d.start_shift_s), undelayed.force(t), rtol=0, atol=1e-11
        )
        # the opposite sign (p0 + 2 pi f s, an advanced waveform) is a different phase
        advanced = p0 + 2.0 * math.pi * SINE.frequency * d.start_shift_s
        gap = abs(
            complex(math.cos(sine.phase), math.sin(sine.phase))
            - complex(math.cos(advanced), math.sin(advanced))
        )
        assert gap == pytest.approx(
            2.0 * abs(math.sin(2.0 * math.pi * SINE.frequency * d.start_shift_s)), abs=1e-12
        )


def test_dispersion_statistics():
    """Over 800 draws the recorded factors follow the documented laws: scale ~ N(1, 0.2) (never
    negative), direction ~ N(0, 30 deg), shift ~ N(0, 0.5 s), phase ~ U(0, 2 pi), parameter
    factors ~ U(1 - p, 1 + p); the dispersed parameter is the nominal times its factor."""
    config = dataclasses.replace(
        JITTER, random_phase=True, params=(("helicopter.m_F", 5.0), ("tether.K_C", 10.0))
    )
    n = 800
    draws = [draw(BASE, config, draw_seed(config.seed, i), i) for i in range(n)]
    scale = np.array([d.amplitude_scale for d in draws])
    angle = np.array([d.direction_deg for d in draws])
    shift = np.array([d.start_shift_s for d in draws])
    phase = np.array([d.phase_rad for d in draws])
    m_F = np.array([d.param_factors[0][1] for d in draws])
    K_C = np.array([d.param_factors[1][1] for d in draws])
    se = 1.0 / math.sqrt(n)
    assert abs(scale.mean() - 1.0) < 4 * 0.2 * se and np.all(scale >= 0.0)
    assert scale.std() == pytest.approx(0.2, rel=0.1)
    assert abs(angle.mean()) < 4 * 30.0 * se and angle.std() == pytest.approx(30.0, rel=0.1)
    assert abs(shift.mean()) < 4 * 0.5 * se and shift.std() == pytest.approx(0.5, rel=0.1)
    assert np.all((phase >= 0.0) & (phase < 2.0 * math.pi))
    quarters = np.bincount((phase // (0.5 * math.pi)).astype(int), minlength=4) / n
    np.testing.assert_allclose(quarters, 0.25, atol=0.05)
    for f, p in ((m_F, 0.05), (K_C, 0.10)):
        assert np.all(np.abs(f - 1.0) <= p) and f.std() == pytest.approx(p / math.sqrt(3), rel=0.1)
    for d in draws[:5]:
        params = d.scenario.params
        assert params.helicopter.m_F == pytest.approx(
            BASE.params.helicopter.m_F * d.param_factors[0][1], rel=1e-15
        )
        assert params.tether.K_C == pytest.approx(
            BASE.params.tether.K_C * d.param_factors[1][1], rel=1e-15
        )


def test_amplitude_scale_is_clipped_at_zero():
    """A 100 % amplitude std draws negative scales about 16 % of the time: they are 0 (no wind),
    never a reversed wind."""
    config = dataclasses.replace(JITTER, amplitude_std_percent=100.0)
    draws = [draw(BASE, config, draw_seed(config.seed, i), i) for i in range(60)]
    zero = [d for d in draws if d.amplitude_scale == 0.0]
    assert zero and all(d.amplitude_scale >= 0.0 for d in draws)
    for d in zero:
        assert np.all(d.scenario.wind.force(T) == 0.0)


def test_turbulence_gets_rotation_and_a_fresh_series_but_no_scale_or_shift():
    """The module's documented rule for turbulence: its mean wind is rotated by the draw's
    direction (n3 kept), and the gust model's axes with it (heading + the draw's angle), its
    gusts are a fresh series (seed = root entropy, spawn key (i, 0)), and neither the
    amplitude scale nor the time shift applies (gust statistics): every other field is the
    nominal one."""
    turbulence = Turbulence(
        GaussMarkovTurbulence(),
        DragModel(cd_area_m2=(0.4, 0.4, 0.8)),
        seed=1,
        duration=2.0,
        dt=0.05,
        N_v_mean_wind=(3.0, 0.0, 0.5),
    )
    base = Scenario(name="turb", duration=2.0, wind=turbulence)
    config = dataclasses.replace(JITTER, runs=3)
    for i in range(3):
        d = draw(base, config, draw_seed(config.seed, i), i)
        got = d.scenario.wind
        mean = _rz(d.direction_deg) @ np.array(turbulence.N_v_mean_wind)
        assert got.N_v_mean_wind == pytest.approx(tuple(mean), abs=1e-15)
        assert got.N_v_mean_wind[2] == 0.5
        model = dataclasses.replace(turbulence.model, heading_rad=math.radians(d.direction_deg))
        np.testing.assert_allclose(got.model.axes @ [1.0, 0.0, 0.0], _rz(d.direction_deg)[:, 0])
        want = dataclasses.replace(
            turbulence,
            model=model,
            seed=config.seed,
            spawn_key=(i, 0),
            N_v_mean_wind=got.N_v_mean_wind,
        )
        assert got == want  # model, drag, duration, grid: nominal
        fresh = want.rng().standard_normal(3)
        again = np.random.default_rng(np.random.SeedSequence(config.seed, spawn_key=(i, 0)))
        np.testing.assert_array_equal(fresh, again.standard_normal(3))
        np.testing.assert_array_equal(got.N_v_gust_grid, want.N_v_gust_grid)


# --- percentiles over completed runs only ---------------------------------------------------


def _table(rows: list[tuple[str, int, float, float]]) -> dict[str, np.ndarray]:
    """Columns of a results table: (configuration, status, metric value, release time); every
    metric column holds the same value so each summary metric can be checked."""
    cols: dict[str, np.ndarray] = {
        "configuration": np.array([r[0] for r in rows]),
        "status": np.array([float(r[1]) for r in rows]),
        "release_time": np.array([r[3] for r in rows]),
    }
    for name in METRIC_NAMES:
        cols[name] = np.array([r[2] for r in rows])
    return cols


def test_failed_runs_are_in_the_tail_of_the_percentiles():
    """Completed free runs 1, 2, 3, 4, 5 and tethered 10, 20; failed rows (a diverged run
    whose metrics are finite and huge, a set-up failure with NaN) are counted as failed and
    as the worst value (+inf; -inf for tension_min) in the percentiles, null where they
    reach it; mean and max over the completed runs. Expected percentiles by hand (linear
    interpolation at rank p (n - 1) / 100 of 1, 2, 3, 4, 5, inf, inf): p1 1.06, p5 1.3,
    p25 2.5, p50 4, p75 and above null; for tension_min (-inf, -inf, 1, ..., 5): p50 2,
    p75 3.5, p95 4.7, p99 4.94, below null."""
    from tetherheli.engine import loop as engine
    from tetherheli.studies.montecarlo.runner import _summarize

    nan = math.nan
    rows = [
        ("free", engine.STATUS_OK, 3.0, nan),
        ("tethered", engine.STATUS_OK, 10.0, 4.5),  # completed after a tether release
        ("free", engine.STATUS_DIVERGED, 1e6, nan),
        ("tethered", engine.STATUS_SETUP, nan, nan),
        ("free", engine.STATUS_OK, 1.0, nan),
        ("free", engine.STATUS_OK, 5.0, nan),
        ("tethered", engine.STATUS_DIVERGED, 1e6, 2.0),
        ("free", engine.STATUS_OK, 2.0, nan),
        ("free", engine.STATUS_SETUP, nan, nan),
        ("tethered", engine.STATUS_OK, 20.0, nan),
        ("free", engine.STATUS_OK, 4.0, nan),
    ]
    stats = _summarize(BASE, JITTER, _table(rows))["statistics"]
    free, tethered = stats["free"], stats["tethered"]
    assert (free["runs"], free["completed"], free["failed"]) == (7, 5, 2)
    assert (tethered["runs"], tethered["completed"], tethered["failed"]) == (4, 2, 2)
    assert (free["tether_released"], tethered["tether_released"]) == (0, 2)
    worse_up = {"p1": 1.06, "p5": 1.3, "p25": 2.5, "p50": 4.0, "p75": None, "p95": None}
    worse_down = {"p1": None, "p5": None, "p25": None, "p50": 2.0, "p75": 3.5, "p95": 4.7}
    for metric in ("peak_q1", "peak_q2", "peak_q3", "rms_q1", "rms_q2", "tension_min"):
        by_hand = worse_down if metric == "tension_min" else worse_up
        for k, v in by_hand.items():
            got = free[metric][k]
            assert got is None if v is None else got == pytest.approx(v, rel=1e-12), (metric, k)
        assert (free[metric]["mean"], free[metric]["max"]) == (3.0, 5.0)
        assert tethered[metric]["mean"] == 15.0 and tethered[metric]["max"] == 20.0
        assert tethered[metric]["p50"] is None  # 10, 20 and two failures: the median is one
    # every run of a configuration failed: counted, no statistics
    none = _summarize(BASE, JITTER, _table([("free", engine.STATUS_DIVERGED, 1.0, nan)]))
    assert none["statistics"]["free"] == {
        "runs": 1,
        "completed": 0,
        "failed": 1,
        "tether_released": 0,
    }
