"""Gauss-Markov gusts calibrated from published turbulence models (``gust_calibration``):
IEC 61400-1 ed. 3 (normal turbulence model, Kaimal spectra) and MIL-F-8785C / MIL-HDBK-1797
low-altitude Dryden; the removed name "hover"; the shipped scenarios."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from tetherheli.errors import ParameterError
from tetherheli.scenario.core import load_scenario
from tetherheli.wind import (
    CalibratedGaussMarkovTurbulence,
    DragModel,
    DrydenGust,
    GaussMarkovTurbulence,
    Turbulence,
    disturbance_from_dict,
    gust_calibration,
)

FT = 0.3048  # m per ft
KT = 1852.0 / 3600.0  # m/s per knot
SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"


def _iec(**kw):
    return gust_calibration("iec_61400_1", **kw)


def _mil(**kw):
    return gust_calibration("mil_hdbk_1797_low_altitude", **kw)


def test_iec_normal_turbulence_model_by_hand():
    """IEC 61400-1 ed. 3 (2005), eq. 11 and Table B.1, worked by hand. Class A (I_ref 0.16)
    at V_hub = 5 m/s, z = 10 m: sigma_1 = 0.16 (0.75 * 5 + 5.6) = 1.496 m/s,
    sigma_2 = 0.8 sigma_1 = 1.1968, sigma_3 = 0.5 sigma_1 = 0.748; Lambda_1 = 0.7 * 10 = 7 m,
    Kaimal lengths 8.1, 2.7, 0.66 Lambda_1 = 56.7, 18.9, 4.62 m; times L / V = 11.34, 3.78,
    0.924 s. Class C (0.12) at 10 m/s and z = 80 m: sigma_1 = 0.12 * 13.1 = 1.572 m/s and
    Lambda_1 = 42 m (the cap above 60 m), L_u = 340.2 m."""
    a = _iec(height_m=10.0, mean_wind_m_s=5.0, i_ref=0.16)
    np.testing.assert_allclose(a.sigma_m_s, [1.496, 1.1968, 0.748], rtol=1e-12)
    np.testing.assert_allclose(a.length_scale_m, [56.7, 18.9, 4.62], rtol=1e-12)
    np.testing.assert_allclose(a.correlation_time_s, [11.34, 3.78, 0.924], rtol=1e-12)
    np.testing.assert_allclose(
        a.gain, np.array(a.sigma_m_s) * np.sqrt(2 / np.array([11.34, 3.78, 0.924]))
    )
    c = _iec(height_m=80.0, mean_wind_m_s=10.0, i_ref=0.12)
    assert math.isclose(c.sigma_m_s[0], 1.572, rel_tol=1e-12)
    assert math.isclose(c.length_scale_m[0], 340.2, rel_tol=1e-12)


def test_iec_time_is_the_kaimal_integral_time_scale():
    """A second route: the Gauss-Markov one-sided spectrum at f -> 0, 4 sigma^2 / a, equals the
    Kaimal spectrum of IEC 61400-1 Annex B, S(f) = 4 sigma^2 (L/V) / (1 + 6 f L/V)^(5/3), at
    f = 0, on every axis, and its variance is sigma^2."""
    V = 7.0
    cal = _iec(height_m=25.0, mean_wind_m_s=V, i_ref=0.14)
    model = CalibratedGaussMarkovTurbulence(
        calibration="iec_61400_1", height_m=25.0, mean_wind_m_s=V, i_ref=0.14
    )
    sigma, L = np.array(cal.sigma_m_s), np.array(cal.length_scale_m)

    def kaimal(f):
        return 4 * sigma**2 * (L / V) / (1 + 6 * f * L / V) ** (5 / 3)

    np.testing.assert_allclose(model.psd([0.0])[0], kaimal(0.0), rtol=1e-12)
    np.testing.assert_allclose(model.variance, sigma**2, rtol=1e-12)


def test_mil_low_altitude_by_hand_and_the_1000_ft_isotropy():
    """MIL-F-8785C / MIL-HDBK-1797 low altitude, worked by hand at h = 10 m = 32.808 ft with
    W20 = 15 kt = 7.7167 m/s: 0.177 + 0.000823 h = 0.20400; sigma_w = 0.77167 m/s,
    sigma_u = sigma_v = 0.77167 / 0.20400^0.4 = 0.77167 / 0.52948 = 1.4574 m/s,
    L_u = L_v = 32.808 / 0.20400^1.2 ft = 32.808 / 0.14844 = 221.02 ft = 67.37 m, L_w = 10 m.
    At 1000 ft the factor is 1: sigma_u = sigma_w and L_u = L_w = 1000 ft (the handbook's
    isotropic top of the low-altitude layer)."""
    cal = _mil(height_m=10.0, mean_wind_m_s=5.0, wind_speed_20ft_m_s=15 * KT)
    np.testing.assert_allclose(cal.sigma_m_s, [1.4574, 1.4574, 0.77167], rtol=2e-4)
    np.testing.assert_allclose(cal.length_scale_m, [67.37, 67.37, 10.0], rtol=2e-4)
    top = _mil(height_m=1000 * FT, mean_wind_m_s=20.0, wind_speed_20ft_m_s=30 * KT)
    assert math.isclose(top.sigma_m_s[0], top.sigma_m_s[2], rel_tol=1e-12)
    np.testing.assert_allclose(top.length_scale_m, 1000 * FT, rtol=1e-12)


def test_mil_times_keep_the_dryden_variance_and_low_frequency_level():
    """A second route for the Dryden integral scales (L_u / V longitudinal, L / (2 V) lateral
    and vertical): the calibrated Gauss-Markov model has the variance and the zero-frequency
    spectrum of ``DrydenGust``'s own state-space filters (MIL-F-8785C) at the same h, W20 and
    airspeed V = mean wind, on each axis. With L / V on the v and w axes the level would be
    twice Dryden's."""
    h, w20, V = 20.0, 20 * KT, 6.0
    dryden = DrydenGust(h, w20, V)
    model = CalibratedGaussMarkovTurbulence(
        calibration="mil_hdbk_1797_low_altitude",
        height_m=h,
        mean_wind_m_s=V,
        wind_speed_20ft_m_s=w20,
    )
    np.testing.assert_allclose(model.variance, dryden.variance, rtol=1e-10)
    np.testing.assert_allclose(model.psd([0.0]), dryden.psd([0.0]), rtol=1e-10)


def test_calibrated_series_has_the_calibrated_variance_and_correlation_time():
    """2e5 samples at 1 s of the IEC class-A model at 10 m and 5 m/s: each axis's variance is
    within 6 % of sigma^2, and the correlation time estimated from the lag-one
    autocorrelation, -dt / ln(rho_1), within 5 % of L / V (11.34, 3.78, 0.924 s)."""
    model = CalibratedGaussMarkovTurbulence(
        calibration="iec_61400_1", height_m=10.0, mean_wind_m_s=5.0, i_ref=0.16
    )
    dt = 1.0
    y = model.sample(dt * np.arange(200_000), np.random.default_rng(11))
    np.testing.assert_allclose(y.var(axis=0) / np.array([1.496, 1.1968, 0.748]) ** 2, 1, atol=0.06)
    x = y - y.mean(axis=0)
    rho = np.sum(x[1:] * x[:-1], axis=0) / np.sum(x * x, axis=0)
    np.testing.assert_allclose(-dt / np.log(rho), [11.34, 3.78, 0.924], rtol=0.05)


@pytest.mark.parametrize(
    ("kwargs", "field", "text"),
    [
        ({"mean_wind_m_s": 2.0, "i_ref": 0.16}, "mean_wind_m_s", "sigma_u / V <= 0.5"),
        ({"mean_wind_m_s": 0.0, "i_ref": 0.16}, "mean_wind_m_s", "> 0"),
        ({"mean_wind_m_s": 5.0}, "i_ref", "required"),
        ({"mean_wind_m_s": 5.0, "i_ref": 1.5}, "i_ref", "(0, 1]"),
        ({"mean_wind_m_s": 5.0, "i_ref": 0.1, "wind_speed_20ft_m_s": 5.0}, "wind_speed_20ft", ""),
    ],
)
def test_iec_refuses_meaningless_inputs(kwargs, field, text):
    """Taylor's conversion L / V is refused in near-calm air: class A needs sigma_u / V <= 0.5,
    i.e. V >= 5.6 * 0.16 / (0.5 - 0.75 * 0.16) = 2.36 m/s, so 2 m/s is refused and 2.4 m/s is
    accepted; missing, out-of-range and foreign inputs are one-line errors naming the field."""
    with pytest.raises(ParameterError, match=field) as err:
        _iec(height_m=10.0, **kwargs)
    assert text in str(err.value) and "\n" not in str(err.value)
    _iec(height_m=10.0, mean_wind_m_s=2.4, i_ref=0.16)


def test_mil_refuses_meaningless_inputs():
    """MIL: h within 10-1000 ft, W20 required, sigma_u / V <= 0.5 (sigma_u = 1.4574 m/s at
    10 m and 15 kt, so V = 2.9 m/s is refused and 3 m/s accepted)."""
    with pytest.raises(ParameterError, match=r"height_m.*10 to 1000 ft"):
        _mil(height_m=2.0, mean_wind_m_s=5.0, wind_speed_20ft_m_s=5.0)
    with pytest.raises(ParameterError, match=r"wind_speed_20ft_m_s.*required"):
        _mil(height_m=10.0, mean_wind_m_s=5.0)
    with pytest.raises(ParameterError, match="mean_wind_m_s"):
        _mil(height_m=10.0, mean_wind_m_s=2.9, wind_speed_20ft_m_s=15 * KT)
    _mil(height_m=10.0, mean_wind_m_s=3.0, wind_speed_20ft_m_s=15 * KT)
    with pytest.raises(ParameterError, match="calibration"):
        gust_calibration("esdu", height_m=10.0, mean_wind_m_s=5.0)


def _turbulence_table(model: dict, mean=(5.0, 0.0, 0.0)) -> dict:
    return {
        "type": "turbulence",
        "seed": 1,
        "duration": 1.0,
        "dt": 0.1,
        "N_v_mean_wind": list(mean),
        "model": model,
        "drag": {"cd_area_m2": [0.4, 0.4, 0.8]},
    }


IEC_TABLE = {
    "type": "gauss_markov",
    "calibration": "iec_61400_1",
    "height_m": 10.0,
    "mean_wind_m_s": 5.0,
    "i_ref": 0.16,
}


def test_scenario_form_loads_round_trips_and_checks_the_mean_wind():
    """``[wind.model] type = "gauss_markov"`` with a calibration loads the calibrated model;
    its table round-trips; a convection speed or heading that is not the mean wind's, and a
    gain given with a calibration, are one-line errors naming the key."""
    w = disturbance_from_dict(_turbulence_table(IEC_TABLE))
    assert isinstance(w.model, CalibratedGaussMarkovTurbulence)
    np.testing.assert_allclose(w.model.std, [1.496, 1.1968, 0.748], rtol=1e-12)
    assert disturbance_from_dict(w.to_dict()) == w
    with pytest.raises(ParameterError, match=r"wind\.model\.mean_wind_m_s.*4 m/s"):
        disturbance_from_dict(_turbulence_table(IEC_TABLE, mean=(4.0, 0.0, 0.0)))
    with pytest.raises(ParameterError, match=r"wind\.model\.heading_rad"):
        disturbance_from_dict(_turbulence_table(IEC_TABLE, mean=(0.0, 5.0, 0.0)))
    turned = {**IEC_TABLE, "heading_rad": math.pi / 2}
    assert disturbance_from_dict(_turbulence_table(turned, mean=(0.0, 5.0, 0.0))).model.axes[
        1, 0
    ] == pytest.approx(1.0)
    with pytest.raises(ParameterError, match=r"wind\.model\.gain"):
        disturbance_from_dict(_turbulence_table({**IEC_TABLE, "gain": [1.0, 1.0, 1.0]}))


def test_old_hover_type_is_refused_naming_the_new_one():
    """``type = "hover"`` (the old name of ``"gauss_markov"``, deprecated, now removed) is
    refused in one line listing the allowed types; the old class name is gone too."""
    table = {"type": "hover", "gain": [1.5, 1.5, 0.7], "pole_rad_s": [0.5, 0.5, 0.5]}
    with pytest.raises(ParameterError, match=r"wind\.model\.type.*'hover'.*gauss_markov"):
        disturbance_from_dict(_turbulence_table(table))
    import tetherheli.wind as wind

    assert not hasattr(wind, "HoverTurbulence")


@pytest.mark.parametrize(
    "name", ["turbulence_hover_free", "turbulence_hover_tethered", "montecarlo_turbulence"]
)
def test_shipped_turbulence_scenarios_use_the_iec_calibration(name):
    """The shipped turbulence scenarios are calibrated (IEC class A, 10 m, 5 m/s) with no
    hand-set K, a, and no word "CETI"."""
    path = SCENARIOS / f"{name}.toml"
    text = path.read_text()
    assert "CETI" not in text
    model = tomllib.loads(text)["wind"]["model"]
    assert model == IEC_TABLE
    if name.startswith("turbulence"):
        wind = load_scenario(path).wind
        assert isinstance(wind, Turbulence)
        np.testing.assert_allclose(wind.model.correlation_time_s, [11.34, 3.78, 0.924])


def test_initial_force_is_the_drag_of_the_air_at_t0():
    """``Turbulence.initial_force`` is the drag 1/2 rho CdA_i |U| U_i at rest of the air at
    t = 0, U = mean wind + first gust: without gusts 0.5 * 1.225 * 0.4 * 5 * 5 = 6.125 N
    along the wind; with them, the formula written out here on the first gust sample."""
    drag = DragModel((0.4, 0.4, 0.8))
    calm = Turbulence(
        GaussMarkovTurbulence(gain=(0, 0, 0)), drag, 1, 1.0, 0.1, N_v_mean_wind=(5, 0, 0)
    )
    np.testing.assert_allclose(calm.initial_force, [6.125, 0.0, 0.0], rtol=1e-15)
    w = Turbulence(GaussMarkovTurbulence(), drag, 1, 1.0, 0.1, N_v_mean_wind=(5, 0, 0))
    U = np.array([5.0, 0.0, 0.0]) + w.gust_velocity(0.0)
    want = 0.5 * 1.225 * np.array([0.4, 0.4, 0.8]) * np.linalg.norm(U) * U
    np.testing.assert_allclose(w.initial_force, want, rtol=1e-14)
    assert np.all(w.gust_velocity(0.0) != 0.0)
