"""Tests of tetherheli.wind: the paper's wind profiles (Sec. VI), the strict loader,
and the turbulence models against the MIL-F-8785C Dryden spectra and first-order filters."""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass

import numpy as np
import pytest
from scipy.integrate import quad, quad_vec
from scipy.linalg import expm, solve_continuous_lyapunov
from scipy.signal import welch

from tetherheli.errors import ParameterError
from tetherheli.wind import (
    ConstantForce,
    Disturbance,
    DragModel,
    DrydenGust,
    GaussMarkovTurbulence,
    GustModel,
    NoWind,
    Pulse,
    Sine,
    Step,
    Turbulence,
    WindSum,
    disturbance_from_dict,
    paper_wind,
)
from tetherheli.wind.evaluate import wind_force
from tetherheli.wind.gusts import _discretize

FT = 0.3048  # m per ft
KT = 1852.0 / 3600.0  # m/s per knot
N1, N2, N3 = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)


# ---------------------------------------------------------------------------------------------
# deterministic profiles
# ---------------------------------------------------------------------------------------------


def test_paper_simulation_1_profile():
    """Sec. VI, simulation 1: 20 N pulse along n1 at t = 10 s (1 s, our default), then
    20 sin(2 pi 0.1 t) N along n1 from t = 30 s, with the absolute time in the sine."""
    wind = paper_wind(1)
    np.testing.assert_array_equal(wind.force(5.0), [0.0, 0.0, 0.0])
    np.testing.assert_array_equal(wind.force(9.999), [0.0, 0.0, 0.0])
    np.testing.assert_array_equal(wind.force(10.0), [20.0, 0.0, 0.0])
    np.testing.assert_array_equal(wind.force(10.5), [20.0, 0.0, 0.0])
    np.testing.assert_array_equal(wind.force(11.0), [0.0, 0.0, 0.0])  # [start, start + 1 s)
    np.testing.assert_array_equal(wind.force(29.0), [0.0, 0.0, 0.0])
    for t in (30.0, 31.0, 32.5, 33.7, 47.2):
        expected = 20.0 * math.sin(2.0 * math.pi * 0.1 * t)
        np.testing.assert_allclose(wind.force(t), [expected, 0.0, 0.0], rtol=0, atol=1e-12)
    # 2 pi 0.1 * 30 = 6 pi: the sine switches on continuously
    assert abs(wind.force(30.0)[0]) < 1e-12
    assert abs(wind.force(29.999)[0]) == 0.0


def test_paper_simulation_2_profile_is_along_n2():
    """Sec. VI, simulation 2: the same profile along n2; the pulse duration is a parameter."""
    wind = paper_wind(2, pulse_duration=2.5)
    np.testing.assert_array_equal(wind.force(11.9), [0.0, 20.0, 0.0])
    np.testing.assert_array_equal(wind.force(12.6), [0.0, 0.0, 0.0])
    np.testing.assert_allclose(wind.force(31.0), [0.0, 20.0 * math.sin(0.2 * math.pi), 0.0])
    with pytest.raises(ParameterError, match="simulation"):
        paper_wind(3)


def test_pulse_step_sine_constant_values():
    """Each profile's defining formula at chosen times; the direction is normalised."""
    pulse = Pulse(start=2.0, duration=0.5, magnitude=10.0, direction=(3.0, 4.0, 0.0))
    assert pulse.direction == (0.6, 0.8, 0.0)
    np.testing.assert_allclose(pulse.force(2.25), [6.0, 8.0, 0.0])
    np.testing.assert_array_equal(pulse.force(2.5), [0.0, 0.0, 0.0])
    np.testing.assert_array_equal(pulse.force(1.99), [0.0, 0.0, 0.0])

    step = Step(start=1.0, magnitude=-5.0, direction=(0.0, 0.0, 2.0))
    np.testing.assert_array_equal(step.force(0.999), [0.0, 0.0, 0.0])
    np.testing.assert_array_equal(step.force(1.0), [0.0, 0.0, -5.0])
    np.testing.assert_array_equal(step.force(1e6), [0.0, 0.0, -5.0])

    sine = Sine(amplitude=3.0, frequency=0.25, start=1.0, direction=N2, phase=0.5)
    np.testing.assert_array_equal(sine.force(0.9), [0.0, 0.0, 0.0])
    np.testing.assert_allclose(
        sine.force(1.7), [0.0, 3.0 * math.sin(2 * math.pi * 0.25 * 1.7 + 0.5), 0]
    )

    np.testing.assert_array_equal(ConstantForce((1.0, -2.0, 3.0)).force(7.0), [1.0, -2.0, 3.0])
    np.testing.assert_array_equal(NoWind().force([0.0, 1.0]), np.zeros((2, 3)))


def test_direction_normalisation_is_idempotent():
    """Re-normalising a stored unit direction returns it unchanged (so to_dict round-trips)."""
    for direction in [(1.0, 1.0, 1.0), (0.3, -7.0, 2.0), (1e-3, 2e-3, 0.0)]:
        p = Pulse(0.0, 1.0, 1.0, direction)
        assert math.isclose(np.linalg.norm(p.direction), 1.0, rel_tol=1e-15)
        assert Pulse(0.0, 1.0, 1.0, p.direction).direction == p.direction


def test_vectorised_equals_scalar():
    """force(t_array) stacks force(t) for each t, with shape (n, 3); also for sums."""
    t = np.linspace(0.0, 60.0, 601)
    for d in (
        paper_wind(1),
        Pulse(3.0, 2.0, 1.5, (1, 2, 3)),
        Step(4.0, 2.0, N3),
        Sine(2.0, 0.3, 1.0, N2, 0.1),
        ConstantForce((1, 2, 3)),
        NoWind(),
        WindSum(()),
    ):
        vec = d.force(t)
        assert vec.shape == (t.size, 3)
        assert d.force(t[7]).shape == (3,)
        np.testing.assert_array_equal(vec, np.array([d.force(tk) for tk in t]))
        np.testing.assert_array_equal(d.force_at(t, np.ones(3)), vec)  # velocity-independent
    assert paper_wind(1).force([10.5]).shape == (1, 3)


def test_sum_and_addition():
    """a + b is a flat WindSum whose force is the sum; sum() of a list works from 0."""
    a, b, c = Pulse(1.0, 1.0, 2.0, N1), Step(0.0, 1.0, N2), ConstantForce((0.0, 0.0, 0.5))
    s = a + b + c
    assert isinstance(s, WindSum) and s.components == (a, b, c)
    assert a + (b + c) == s
    assert sum([a, b, c]) == s
    t = np.array([0.5, 1.5, 3.0])
    np.testing.assert_array_equal(s.force(t), a.force(t) + b.force(t) + c.force(t))
    np.testing.assert_array_equal(s.force(1.5), [2.0, 1.0, 0.5])
    with pytest.raises(TypeError):
        a + 1.0


def test_custom_disturbance_plugs_in():
    """The protocol: a subclass implementing only _force(t) gets force, force_at and +."""

    @dataclass(frozen=True)
    class Ramp(Disturbance):
        rate: float

        def _force(self, t: np.ndarray) -> np.ndarray:
            return np.outer(self.rate * t, [0.0, 1.0, 0.0])

    ramp = Ramp(2.0)
    np.testing.assert_array_equal(ramp.force(3.0), [0.0, 6.0, 0.0])
    np.testing.assert_array_equal(ramp.force_at([1.0, 2.0], np.zeros((2, 3)))[:, 1], [2.0, 4.0])
    np.testing.assert_array_equal((ramp + Step(0.0, 1.0, N1)).force(1.0), [1.0, 2.0, 0.0])
    with pytest.raises(NotImplementedError):
        ramp.to_dict()


# ---------------------------------------------------------------------------------------------
# validation
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("build", "field"),
    [
        (lambda: Pulse(float("nan"), 1.0, 1.0, N1), "Pulse.start"),
        (lambda: Sine(float("inf"), 0.1, 0.0, N1), "Sine.amplitude"),
        (lambda: ConstantForce((1.0, float("nan"), 0.0)), "ConstantForce.vector"),
        (lambda: Step(0.0, 1.0, (np.inf, 0.0, 0.0)), "Step.direction"),
    ],
)
def test_non_finite_numbers_are_rejected(build, field):
    """NaN and infinities in any field raise ParameterError naming the field."""
    with pytest.raises(ParameterError) as exc:
        build()
    assert exc.value.field == field


@pytest.mark.parametrize(
    ("build", "field"),
    [
        (lambda: Pulse(1.0, -1.0, 1.0, N1), "Pulse.duration"),
        (lambda: Pulse(1.0, 0.0, 1.0, N1), "Pulse.duration"),
        (lambda: Pulse(-1.0, 1.0, 1.0, N1), "Pulse.start"),
        (lambda: Sine(1.0, -0.1, 0.0, N1), "Sine.frequency"),
        (lambda: Sine(1.0, 0.1, -2.0, N1), "Sine.start"),
        (lambda: Step(-0.5, 1.0, N1), "Step.start"),
    ],
)
def test_negative_times_and_frequencies_are_rejected(build, field):
    """Negative start, duration or frequency (and a zero-length pulse) are errors."""
    with pytest.raises(ParameterError) as exc:
        build()
    assert exc.value.field == field
    assert "\n" not in str(exc.value) and field in str(exc.value)


def test_bad_directions_and_types_are_rejected():
    """A zero direction, a wrong-length vector and non-numbers raise ParameterError."""
    with pytest.raises(ParameterError, match="nonzero"):
        Pulse(0.0, 1.0, 1.0, (0.0, 0.0, 0.0))
    with pytest.raises(ParameterError, match=r"Step.direction"):
        Step(0.0, 1.0, (1.0, 0.0))
    with pytest.raises(ParameterError, match=r"Sine.amplitude"):
        Sine("20", 0.1, 0.0, N1)  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match=r"Pulse.magnitude"):
        Pulse(0.0, 1.0, True, N1)  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match=r"WindSum.components\[1\]"):
        WindSum((NoWind(), 3.0))  # type: ignore[arg-type]


def test_bad_times_and_velocities_are_rejected():
    """force() needs finite scalar or 1-D times; force_at() needs velocities of shape (3,) or
    (n, 3)."""
    wind = paper_wind(1)
    for t in (float("nan"), [1.0, np.inf], np.zeros((2, 2)), "3", None):
        with pytest.raises(ParameterError, match=r"^t = "):
            wind.force(t)  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="N_v_HO"):
        wind.force_at([1.0, 2.0], np.zeros((3, 3)))
    with pytest.raises(ParameterError, match="N_v_HO"):
        wind.force_at(1.0, [0.0, np.nan, 0.0])


def test_turbulence_parameters_are_validated():
    """MIL-F-8785C low-altitude band 10-1000 ft, positive speeds (Dryden needs forward flight),
    positive poles, nonnegative drag areas, a step within the duration, integer seeds."""
    cases = [
        (lambda: DrydenGust(2.0, 5.0, 10.0), "DrydenGust.altitude_m"),
        (lambda: DrydenGust(400.0, 5.0, 10.0), "DrydenGust.altitude_m"),
        (lambda: DrydenGust(50.0, 0.0, 10.0), "DrydenGust.wind_speed_20ft_mps"),
        (lambda: DrydenGust(50.0, 5.0, 0.0), "DrydenGust.airspeed_mps"),
        (
            lambda: GaussMarkovTurbulence(pole_rad_s=(0.5, 0.0, 0.5)),
            "GaussMarkovTurbulence.pole_rad_s",
        ),
        (lambda: GaussMarkovTurbulence(gain=(0.3, -0.3, 0.2)), "GaussMarkovTurbulence.gain"),
        (lambda: DragModel((0.1, 0.1, 0.1), rho=0.0), "DragModel.rho"),
        (lambda: DragModel((0.1, -0.1, 0.1)), "DragModel.cd_area_m2"),
        (
            lambda: Turbulence(GaussMarkovTurbulence(), DragModel((1, 1, 1)), 1, 1.0, 2.0),
            "Turbulence.dt",
        ),
        (
            lambda: Turbulence(GaussMarkovTurbulence(), DragModel((1, 1, 1)), -1, 1.0, 0.1),
            "Turbulence.seed",
        ),
        (
            lambda: Turbulence(GaussMarkovTurbulence(), DragModel((1, 1, 1)), True, 1.0, 0.1),
            "Turbulence.seed",
        ),
    ]
    for build, field in cases:
        with pytest.raises(ParameterError) as exc:
            build()
        assert exc.value.field == field
    with pytest.raises(ParameterError, match="1000 ft"):
        DrydenGust(305.0, 5.0, 10.0)
    model = GaussMarkovTurbulence()
    with pytest.raises(ParameterError, match="t_grid"):
        model.sample(np.array([0.0, 0.1, 0.3]), np.random.default_rng(0))
    with pytest.raises(ParameterError, match="rng"):
        model.sample(np.arange(3.0), 42)  # type: ignore[arg-type]


# ---------------------------------------------------------------------------------------------
# loader and round trip
# ---------------------------------------------------------------------------------------------

_ALL = [
    Pulse(10.0, 1.0, 20.0, N1),
    Step(3.0, -2.0, (1.0, 1.0, 0.0)),
    Sine(20.0, 0.1, 30.0, N2, phase=0.25),
    ConstantForce((1.0, 2.0, -3.0)),
    NoWind(),
    paper_wind(1),
    WindSum((paper_wind(2), WindSum((NoWind(), Step(1.0, 1.0, N3))))),
    Turbulence(GaussMarkovTurbulence(), DragModel((0.2, 0.2, 0.5)), 7, 5.0, 0.01),
    Turbulence(
        DrydenGust(30.0, 7.0, 5.0, heading_rad=0.3),
        DragModel((0.2, 0.25, 0.5), rho=1.1),
        seed=11,
        duration=3.0,
        dt=0.02,
        spawn_key=(2, 5),
        N_v_mean_wind=(5.0, 0.0, 0.0),
    ),
]


@pytest.mark.parametrize("disturbance", _ALL, ids=lambda d: type(d).__name__)
def test_to_dict_round_trip(disturbance):
    """disturbance_from_dict(d.to_dict()) == d and gives the same forces (so a run can record
    its wind configuration); the table holds only plain TOML types."""
    table = disturbance.to_dict()
    rebuilt = disturbance_from_dict(table)
    assert rebuilt == disturbance
    t = np.linspace(0.0, 2.9, 30)
    np.testing.assert_array_equal(rebuilt.force(t), disturbance.force(t))

    def plain(x):
        if isinstance(x, dict):
            return all(isinstance(k, str) and plain(v) for k, v in x.items())
        if isinstance(x, list):
            return all(plain(v) for v in x)
        return type(x) in (int, float, str)

    assert plain(table)


def test_list_of_tables_from_toml_is_a_sum():
    """An array of TOML tables ([[wind]]) gives the WindSum of its entries: here the paper's
    simulation 1 (Sec. VI)."""
    text = """
    [[wind]]
    type = "pulse"
    start = 10
    duration = 1.0
    magnitude = 20
    direction = [1, 0, 0]

    [[wind]]
    type = "sine"
    amplitude = 20.0
    frequency = 0.1
    start = 30.0
    direction = [1.0, 0.0, 0.0]
    """
    wind = disturbance_from_dict(tomllib.loads(text)["wind"], source="scenario.toml")
    assert wind == paper_wind(1)


@pytest.mark.parametrize(
    ("spec", "field", "text"),
    [
        ({"type": "gust", "start": 1.0}, "wind.type", "'gust'"),
        ({"start": 1.0}, "wind.type", "<missing>"),
        ({"type": "step", "start": 1.0, "magnitude": 2.0}, "wind.direction", "required"),
        (
            {"type": "step", "start": 1.0, "magnitude": 2.0, "direction": N1, "durations": 1},
            "wind.durations",
            "a key among",
        ),
        (
            {"type": "step", "start": "1", "magnitude": 2.0, "direction": N1},
            "wind.start",
            "finite number",
        ),
        (
            {"type": "step", "start": 1.0, "magnitude": 2.0, "direction": [1, 0]},
            "wind.direction",
            "3",
        ),
        (
            {"type": "sine", "amplitude": 1, "frequency": -1, "start": 0, "direction": N1},
            "wind.frequency",
            ">= 0",
        ),
        (
            [
                {"type": "none"},
                {"type": "pulse", "start": 0, "duration": -1, "magnitude": 1, "direction": N1},
            ],
            "wind[1].duration",
            "> 0",
        ),
        (
            {
                "type": "turbulence",
                "model": {
                    "type": "dryden",
                    "altitude_m": 1.0,
                    "wind_speed_20ft_mps": 5,
                    "airspeed_mps": 5,
                },
                "drag": {"cd_area_m2": [0.1, 0.1, 0.1]},
                "seed": 1,
                "duration": 1.0,
                "dt": 0.1,
            },
            "wind.model.altitude_m",
            "1000 ft",
        ),
        (
            {"type": "sum", "components": [{"type": "none", "extra": 1}]},
            "wind.components[0].extra",
            "a key among",
        ),
        ("pulse", "wind", "table"),
    ],
)
def test_loader_errors_name_the_key(spec, field, text):
    """Unknown type, unknown/missing keys, wrong types and bad values raise ParameterError
    naming the key (prefixed, e.g. wind[1].duration), with the source passed through."""
    with pytest.raises(ParameterError) as exc:
        disturbance_from_dict(spec, source="s.toml")
    assert exc.value.field == field
    assert exc.value.source == "s.toml"
    message = str(exc.value)
    assert message.startswith(f"s.toml: {field} = ") and text in message and "\n" not in message


# ---------------------------------------------------------------------------------------------
# turbulence
# ---------------------------------------------------------------------------------------------


def _mil_dryden(h_ft: float, w20_kt: float, V: float):
    """MIL-F-8785C low-altitude Dryden: (sigma_u, sigma_v, sigma_w) [m/s], (L_u, L_v, L_w) [m]
    and the one-sided PSD in Hz of (u, v, w), written out from the spec."""
    sigma_w = 0.1 * w20_kt * KT
    sigma_u = sigma_w / (0.177 + 0.000823 * h_ft) ** 0.4
    L_u = h_ft / (0.177 + 0.000823 * h_ft) ** 1.2 * FT
    L_w = h_ft * FT

    def psd_hz(f):
        w = 2.0 * np.pi * np.asarray(f)
        phi_u = sigma_u**2 * 2 * L_u / (np.pi * V) / (1 + (L_u * w / V) ** 2)
        phi_v = (
            sigma_u**2
            * L_u
            / (np.pi * V)
            * (1 + 3 * (L_u * w / V) ** 2)
            / (1 + (L_u * w / V) ** 2) ** 2
        )
        phi_w = (
            sigma_w**2
            * L_w
            / (np.pi * V)
            * (1 + 3 * (L_w * w / V) ** 2)
            / (1 + (L_w * w / V) ** 2) ** 2
        )
        # Phi(omega) is one-sided per rad/s; per Hz multiply by d(omega)/df = 2 pi
        return 2.0 * np.pi * np.column_stack([phi_u, phi_v, phi_w])

    return (sigma_u, sigma_u, sigma_w), (L_u, L_u, L_w), psd_hz


def test_dryden_parameters_follow_mil_f_8785c():
    """Intensities and scale lengths of the MIL-F-8785C low-altitude model at h = 100 ft and
    W20 = 15 kt (light); at 1000 ft they meet the isotropic values (sigma_u = sigma_w,
    L_u = L_w = 1000 ft)."""
    d = DrydenGust(100 * FT, 15 * KT, 10.0)
    sigmas, lengths, _ = _mil_dryden(100.0, 15.0, 10.0)
    np.testing.assert_allclose([d.sigma_u, d.sigma_v, d.sigma_w], sigmas, rtol=1e-14)
    np.testing.assert_allclose([d.L_u, d.L_v, d.L_w], lengths, rtol=1e-14)
    np.testing.assert_allclose(d.variance, np.square(sigmas), rtol=1e-10)
    high = DrydenGust(1000 * FT, 30 * KT, 20.0)
    assert math.isclose(high.sigma_u, high.sigma_w, rel_tol=1e-12)
    assert math.isclose(high.L_u, 1000 * FT, rel_tol=1e-12)


def test_model_psd_matches_mil_spectra_and_integrates_to_variance():
    """GustModel.psd equals the MIL-F-8785C Dryden spectra written out independently, and the
    one-sided spectra of both models integrate to the stated variances (Dryden sigma^2,
    first-order filter K^2 / (2 a))."""
    d = DrydenGust(100 * FT, 15 * KT, 10.0)
    _, _, psd_hz = _mil_dryden(100.0, 15.0, 10.0)
    f = np.logspace(-4, 2, 200)
    np.testing.assert_allclose(d.psd(f), psd_hz(f), rtol=1e-10)
    h = GaussMarkovTurbulence(gain=(0.3, 0.4, 0.2), pole_rad_s=(0.5, 1.0, 2.0))
    np.testing.assert_allclose(h.variance, [0.09 / 1.0, 0.16 / 2.0, 0.04 / 4.0], rtol=1e-12)
    np.testing.assert_allclose(h.std, np.sqrt(h.variance), rtol=1e-12)
    for model in (d, h):
        for axis in range(3):
            integral = quad(lambda x, m=model, i=axis: m.psd([x])[0, i], 0.0, np.inf, limit=200)[0]
            assert math.isclose(integral, model.variance[axis], rel_tol=1e-6)


@pytest.mark.parametrize(
    "model",
    [DrydenGust(100 * FT, 15 * KT, 10.0), GaussMarkovTurbulence()],
    ids=["dryden", "gauss_markov"],
)
def test_long_series_variance_matches_analytic(model):
    """The variance of 2e5 samples is within 4 % of the analytic one (MIL-F-8785C sigma^2 for
    Dryden, K^2 / (2 a) for the hover model). The grid step (2 s) is of the order of the
    correlation times: exact discretisation keeps the variance right at any step."""
    y = model.sample(2.0 * np.arange(200_000), np.random.default_rng(1))
    assert y.shape == (200_000, 3)
    ratio = y.var(axis=0) / model.variance
    np.testing.assert_allclose(ratio, 1.0, atol=0.04)
    np.testing.assert_allclose(y.mean(axis=0) / np.sqrt(model.variance), 0.0, atol=0.05)


@pytest.mark.parametrize(
    "model",
    [DrydenGust(100 * FT, 15 * KT, 10.0), GaussMarkovTurbulence()],
    ids=["dryden", "gauss_markov"],
)
def test_welch_psd_matches_analytic(model):
    """Welch's estimate (scipy.signal.welch) of a 2^18-sample series at 20 Hz fits the
    analytic one-sided PSD: the mean log ratio over 0.02-2 Hz, and over each decade of it, is
    within 10 % (MIL-F-8785C spectra for Dryden)."""
    fs = 20.0
    y = model.sample(np.arange(2**18) / fs, np.random.default_rng(2))
    f, G = welch(y, fs=fs, nperseg=4096, axis=0)
    for lo, hi in [(0.02, 2.0), (0.02, 0.2), (0.2, 2.0)]:
        band = (f >= lo) & (f <= hi)
        mean_log_ratio = np.mean(np.log(G[band] / model.psd(f[band])), axis=0)
        assert np.all(np.abs(mean_log_ratio) < np.log(1.10)), (lo, hi, mean_log_ratio)


def test_exact_discretisation_autocorrelation():
    """Lag-one autocorrelation at a coarse step equals the continuous one: e^{-a dt} for the
    first-order filter (Euler would give 1 - a dt), and for Dryden (MIL-HDBK-1797 correlation
    functions) R_u = e^{-V tau / L_u}, R_w = (1 - V tau / (2 L_w)) e^{-V tau / L_w}."""

    def lag1(x):
        x = x - x.mean(axis=0)
        return np.sum(x[1:] * x[:-1], axis=0) / np.sum(x * x, axis=0)

    h = GaussMarkovTurbulence()
    dt = 1.0
    rho = lag1(h.sample(dt * np.arange(200_000), np.random.default_rng(3)))
    np.testing.assert_allclose(rho, np.exp(-0.5 * dt), atol=0.01)

    d = DrydenGust(100 * FT, 15 * KT, 10.0)
    dt = d.L_w / d.airspeed_mps  # V tau / L_w = 1
    rho = lag1(d.sample(dt * np.arange(200_000), np.random.default_rng(4)))
    assert math.isclose(rho[0], math.exp(-dt * 10.0 / d.L_u), abs_tol=0.01)
    assert math.isclose(rho[2], 0.5 * math.exp(-1.0), abs_tol=0.01)


def test_discretisation_is_exact_at_any_step():
    """The noise covariance Qd equals int_0^dt e^{As} B B' e^{A's} ds (computed here by
    adaptive quadrature) and keeps the stationary covariance, P = Ad P Ad' + Qd, for the
    Dryden filters from tiny to very coarse steps (dt / (L/V) from 3e-7 to 3e3)."""
    d = DrydenGust(100 * FT, 15 * KT, 10.0)
    for A, B, _ in d._filters():
        P = solve_continuous_lyapunov(A, -B @ B.T)
        for dt in (1e-6, 0.1, 5.0, 1e4):
            Ad, Qd = _discretize(A, B, dt)
            np.testing.assert_allclose(Ad, expm(A * dt), rtol=1e-12, atol=1e-300)
            integrand = lambda s, A=A, B=B: expm(A * s) @ B @ B.T @ expm(A * s).T  # noqa: E731
            ref = quad_vec(integrand, 0.0, dt, epsabs=0.0, epsrel=1e-11)[0]
            np.testing.assert_allclose(Qd, ref, rtol=1e-10, atol=1e-12 * np.abs(ref).max())
            np.testing.assert_allclose(
                Ad @ P @ Ad.T + Qd, P, rtol=1e-10, atol=1e-12 * np.abs(P).max()
            )


def test_series_start_from_stationary_distribution():
    """The first sample of independent draws already has the analytic variance (no transient
    from a zero initial state)."""
    d = DrydenGust(100 * FT, 15 * KT, 10.0)
    rng = np.random.default_rng(5)
    first = np.array([d.sample(np.array([0.0, 0.1]), rng)[0] for _ in range(1000)])
    np.testing.assert_allclose(first.var(axis=0) / d.variance, 1.0, atol=0.2)


def test_dryden_heading_rotates_axes():
    """heading_rad turns the longitudinal gust axis u in the horizontal plane: at 90 deg the
    n1 component is -v and n2 is u (same noise), and the PSDs swap."""
    d0 = DrydenGust(50.0, 8.0, 6.0)
    d90 = DrydenGust(50.0, 8.0, 6.0, heading_rad=math.pi / 2)
    t = 0.05 * np.arange(2000)
    y0 = d0.sample(t, np.random.default_rng(6))
    y90 = d90.sample(t, np.random.default_rng(6))
    np.testing.assert_allclose(y90, np.column_stack([-y0[:, 1], y0[:, 0], y0[:, 2]]), atol=1e-12)
    f = np.array([0.01, 0.1, 1.0])
    np.testing.assert_allclose(d90.psd(f), d0.psd(f)[:, [1, 0, 2]], rtol=1e-12)


def test_seeds_reproduce_and_differ():
    """Equal seeds give identical series, different seeds (or spawn keys) different ones; a
    spawn key (i,) gives the generator of SeedSequence(seed).spawn(n)[i] (STYLE: explicit
    generators)."""
    model, drag = DrydenGust(30.0, 6.0, 5.0), DragModel((0.2, 0.2, 0.5))
    a = Turbulence(model, drag, seed=42, duration=20.0, dt=0.01)
    b = Turbulence(model, drag, seed=42, duration=20.0, dt=0.01)
    c = Turbulence(model, drag, seed=43, duration=20.0, dt=0.01)
    np.testing.assert_array_equal(a.N_v_gust_grid, b.N_v_gust_grid)
    assert a == b
    assert not np.allclose(a.N_v_gust_grid, c.N_v_gust_grid)
    child = Turbulence(model, drag, seed=42, duration=20.0, dt=0.01, spawn_key=(1,))
    expected = model.sample(
        child.t_grid, np.random.default_rng(np.random.SeedSequence(42).spawn(2)[1])
    )
    np.testing.assert_array_equal(child.N_v_gust_grid, expected)
    assert not np.allclose(child.N_v_gust_grid, a.N_v_gust_grid)
    r1 = GaussMarkovTurbulence().sample(np.arange(100.0), np.random.default_rng(9))
    r2 = GaussMarkovTurbulence().sample(np.arange(100.0), np.random.default_rng(9))
    np.testing.assert_array_equal(r1, r2)


class _PlainGaussMarkov(GustModel):
    """A custom gust model (not a frozen dataclass, so discretised anew at every draw) with
    the filters of a ``GaussMarkovTurbulence``."""

    def __init__(self, model: GaussMarkovTurbulence):
        self.model = model

    def _filters(self):
        return self.model._filters()

    @property
    def axes(self):
        return self.model.axes


def test_kept_discretisation_draws_what_a_fresh_one_draws():
    """The discretisation a frozen model keeps between draws (issue 24: the environments'
    resets sampled the same model at the same step anew each time) gives the series of one
    computed for the draw (a custom model's path) bit for bit, per model and step (the
    entries are not mixed up), and the closed-form Gauss-Markov recursion
    x_k+1 = e^(-a dt) x_k + K sqrt((1 - e^(-2 a dt)) / 2a) e_k, x_0 = K / sqrt(2a) e_0."""
    from tetherheli.wind.gusts import _cached_filter

    t = 0.05 * np.arange(601)
    models = [
        GaussMarkovTurbulence(heading_rad=0.7),
        GaussMarkovTurbulence(gain=(0.5, 0.1, 0.2), pole_rad_s=(0.3, 2.0, 1.0)),
    ]
    for model in (*models, *models):  # the second pass draws from the kept entries
        for step in (t, 2.0 * t):
            kept = model.sample(step, np.random.default_rng(17))
            fresh = _PlainGaussMarkov(model).sample(step, np.random.default_rng(17))
            np.testing.assert_array_equal(kept, fresh)
    again = GaussMarkovTurbulence(heading_rad=0.7)  # equal fields: the same entry
    hits = _cached_filter.cache_info().hits
    np.testing.assert_array_equal(
        again.sample(t, np.random.default_rng(17)),
        models[0].sample(t, np.random.default_rng(17)),
    )
    assert _cached_filter.cache_info().hits == hits + 2
    # the recursion's innovations are the generator's normals (up to the order and signs
    # in which the filter's square roots take them: a signed permutation)
    model, dt = models[1], 0.05
    K, a = np.array(model.gain), np.array(model.pole_rad_s)
    x = model.sample(t, np.random.default_rng(17))
    e = np.random.default_rng(17).standard_normal((t.size, 3))
    decay, scale = np.exp(-a * dt), K * np.sqrt((1.0 - np.exp(-2.0 * a * dt)) / (2.0 * a))
    got, normals = (x[1:] - decay * x[:-1]) / scale, e[1:]
    order = np.round(got.T @ normals / np.sum(normals**2, axis=0))
    assert sorted(np.abs(order).sum(axis=0)) == [1.0, 1.0, 1.0]
    np.testing.assert_allclose(got, normals @ order.T, atol=1e-9)
    # and the start is drawn from the stationary distribution K / sqrt(2a) by the first three
    np.testing.assert_allclose(
        np.sort(np.abs(x[0] * np.sqrt(2.0 * a) / K)), np.sort(np.abs(e[0])), rtol=1e-12
    )


def test_drag_model_is_the_bluff_body_law():
    """F_i = 0.5 rho CdA_i |v_rel| v_rel,i, |v_rel| the norm of the whole relative velocity
    (issue 11: the per-axis |v_rel,i| made a sideways gust in a mean wind act as v^2)."""
    drag = DragModel((0.2, 0.3, 0.4), rho=1.2)
    root5 = math.sqrt(5.0)  # |(2, -1, 0)|
    expected = [0.6 * 0.2 * root5 * 2.0, 0.6 * 0.3 * root5 * -1.0, 0.0]
    np.testing.assert_allclose(drag.force([2.0, -1.0, 0.0]), expected, rtol=1e-14)
    np.testing.assert_allclose(drag.force([2.0, -1.0, 0.0], [2.0, -1.0, 0.0]), 0.0)
    np.testing.assert_allclose(drag.force([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]), [0.0, 0.0, -0.24])
    v = np.array([[1.0, 2.0, 3.0], [-1.0, 0.5, 0.0]])
    np.testing.assert_allclose(drag.force(v), np.array([drag.force(row) for row in v]))


def test_small_gust_in_a_mean_wind_acts_linearly():
    """Linearization of the bluff-body law about a mean wind U: dF_i = 0.5 rho CdA_i
    (|U| v_perp,i + 2 |U| v_par,i), i.e. a gust across the wind acts with |U| v, along it with
    2 |U| v (the per-axis law gave ~v^2 across the wind)."""
    drag = DragModel((0.4, 0.5, 0.8), rho=1.225)
    U = np.array([5.0, 0.0, 0.0])
    half_rho_cda = 0.5 * 1.225 * np.array([0.4, 0.5, 0.8])
    for gust in (np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0]), np.array([0.3, -0.7, 0.5])):
        eps = 1e-5
        dF = (drag.force(U + eps * gust) - drag.force(U - eps * gust)) / (2.0 * eps)
        par = gust @ U / (U @ U) * U
        perp = gust - par
        linear = half_rho_cda * (np.linalg.norm(U) * perp + 2.0 * np.linalg.norm(U) * par)
        np.testing.assert_allclose(dF, linear, rtol=1e-8, atol=1e-9)


def test_compiled_wind_force_equals_the_python_drag_model():
    """The engine's compiled drag (wind.evaluate.wind_force, used by RK4) and DragModel.force (the
    Python path) are one law: equal to rounding, on and between gust-grid points."""
    from tetherheli.layout import WIND_COLUMNS

    drag = DragModel((0.4, 0.5, 0.8), rho=1.1)
    gust = np.array([[5.0, 1.0, -0.5], [4.0, -2.0, 0.7], [6.0, 0.3, 0.1]])
    half_rho_cda = 0.5 * drag.rho * np.asarray(drag.cd_area_m2)
    program = np.zeros((0, WIND_COLUMNS))
    out = np.empty(3)
    v = np.array([0.3, -0.2, 0.1])
    for t, air in ((0.0, gust[0]), (0.5, gust[1]), (0.25, 0.5 * (gust[0] + gust[1]))):
        wind_force(program, gust, 0.5, half_rho_cda, t, 1, *v, out)
        np.testing.assert_allclose(out, drag.force(air, v), rtol=1e-13, atol=1e-15)


def test_turbulence_force_interpolates_and_uses_relative_velocity():
    """Turbulence.force is the drag of the (linearly interpolated) gust plus mean wind with HO
    at rest; force_at subtracts the velocity of HO (zero when HO moves with the air); times
    outside the grid are errors."""
    drag = DragModel((0.2, 0.3, 0.5))
    turb = Turbulence(
        GaussMarkovTurbulence(), drag, seed=3, duration=10.0, dt=0.1, N_v_mean_wind=(2.0, 0.0, 0.0)
    )
    grid, gust = turb.t_grid, turb.N_v_gust_grid
    assert grid[0] == 0.0 and grid[-1] >= 10.0 and gust.shape == (grid.size, 3)
    mean = np.array([2.0, 0.0, 0.0])
    np.testing.assert_allclose(turb.force(grid[:5]), drag.force(gust[:5] + mean), rtol=1e-12)
    mid = 0.5 * (grid[3] + grid[4])
    np.testing.assert_allclose(turb.gust_velocity(mid), 0.5 * (gust[3] + gust[4]), rtol=1e-12)
    t = np.array([0.0, 2.55, 9.99])
    air = turb.gust_velocity(t) + mean
    np.testing.assert_allclose(turb.force_at(t, air), 0.0, atol=1e-15)
    v = np.array([0.1, -0.2, 0.3])
    np.testing.assert_allclose(turb.force_at(t, v), drag.force(air, v), rtol=1e-12)
    np.testing.assert_allclose(
        (turb + paper_wind(1)).force_at(t, v), drag.force(air, v) + paper_wind(1).force(t)
    )
    for bad in (-0.1, 10.5):
        with pytest.raises(ParameterError, match="turbulence grid"):
            turb.force(bad)


def test_compatibility_modules_are_gone():
    """The shims ``tetherheli.disturbances``, ``.montecarlo`` and ``.sweep`` are removed
    (CHANGELOG): the wind is ``tetherheli.wind``, the studies ``tetherheli.studies``."""
    import importlib

    for name in ("disturbances", "montecarlo", "sweep"):
        with pytest.raises(ModuleNotFoundError):
            importlib.import_module(f"tetherheli.{name}")
