"""Gauss-Markov gusts calibrated from published turbulence models: ``gust_calibration``
(MIL-HDBK-1797 low altitude, IEC 61400-1) gives each gust axis its sigma, length scale and
correlation time (``GustCalibration``); ``CalibratedGaussMarkovTurbulence`` is the
``GaussMarkovTurbulence`` with K and a taken from them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from .._validation import check_number
from ..errors import ParameterError
from ._common import Vec3, _plain_dict, _set
from .gusts import _FT, DrydenGust, GaussMarkovTurbulence

__all__ = [
    "CALIBRATIONS",
    "TAYLOR_MAX_INTENSITY",
    "CalibratedGaussMarkovTurbulence",
    "GustCalibration",
    "gust_calibration",
]

#: the calibrations ``gust_calibration`` knows
CALIBRATIONS = ("iec_61400_1", "mil_hdbk_1797_low_altitude")
#: Taylor's frozen-turbulence conversion (time = length / mean wind) is refused above this
#: turbulence intensity sigma_u / V: a common rule of thumb for its validity
TAYLOR_MAX_INTENSITY = 0.5
_KNOT = 1852.0 / 3600.0  # m/s per knot (exact)


@dataclass(frozen=True)
class GustCalibration:
    """Standard deviations, length scales and correlation times of the gust axes (u, v, w)
    that a published turbulence model gives (``gust_calibration``).

    Parameters
    ----------
    sigma_m_s : tuple of 3 floats
        Standard deviations [m/s].
    length_scale_m : tuple of 3 floats
        The model's length scales [m].
    correlation_time_s : tuple of 3 floats
        The Gauss-Markov correlation time 1/a of each axis [s]: the integral time scale of
        the model's spectrum at the convection speed (its value at zero frequency divided by
        4 sigma^2).
    """

    sigma_m_s: tuple[float, float, float]
    length_scale_m: tuple[float, float, float]
    correlation_time_s: tuple[float, float, float]

    @property
    def pole_rad_s(self) -> tuple[float, float, float]:
        """a = 1 / correlation time per axis [rad/s]."""
        return tuple(1.0 / T for T in self.correlation_time_s)  # type: ignore[return-value]

    @property
    def gain(self) -> tuple[float, float, float]:
        """K = sigma sqrt(2 a) per axis [m s^-3/2]."""
        return tuple(  # type: ignore[return-value]
            s * math.sqrt(2.0 * a) for s, a in zip(self.sigma_m_s, self.pole_rad_s, strict=True)
        )


def gust_calibration(
    calibration: str,
    *,
    height_m: float,
    mean_wind_m_s: float,
    wind_speed_20ft_m_s: float | None = None,
    i_ref: float | None = None,
    prefix: str = "",
) -> GustCalibration:
    """Gust standard deviations and correlation times from quantities a user knows.

    Both models give spatial statistics; the mean wind V convects them past the hovering
    helicopter (Taylor's frozen-turbulence hypothesis), so a length L becomes a time L / V.
    That conversion means nothing as V goes to zero, and it is refused (one-line
    ``ParameterError`` naming ``mean_wind_m_s``) when the intensity sigma_u / V exceeds
    ``TAYLOR_MAX_INTENSITY`` = 0.5.

    ``"mil_hdbk_1797_low_altitude"`` (MIL-F-8785C / MIL-HDBK-1797 low-altitude Dryden model;
    the formulas are ``DrydenGust``'s): with h in ft (10 ft <= h <= 1000 ft) and W20 the wind
    at 20 ft, sigma_w = 0.1 W20, sigma_u = sigma_v = sigma_w / (0.177 + 0.000823 h)^0.4,
    L_u = L_v = h / (0.177 + 0.000823 h)^1.2, L_w = h. The longitudinal Dryden spectrum is
    first-order, so T_u = L_u / V reproduces it exactly. The lateral and vertical Dryden
    spectra are second-order with autocorrelation sigma^2 e^(-x/L) (1 - x / (2 L)), whose
    integral scale is L / 2: T_v = L_v / (2 V), T_w = L_w / (2 V), which keeps each axis's
    variance and low-frequency spectral level 4 sigma^2 T.

    ``"iec_61400_1"`` (IEC 61400-1 ed. 3, 2005: normal turbulence model eq. 11, Sec. 6.3, and
    the Kaimal model of Annex B, Table B.1): sigma_1 = I_ref (0.75 V + 5.6 m/s),
    sigma_2 = 0.8 sigma_1, sigma_3 = 0.5 sigma_1; Lambda_1 = 0.7 z for z <= 60 m (42 m above);
    Kaimal lengths L = 8.1, 2.7, 0.66 Lambda_1. The Kaimal spectrum
    S(f) = 4 sigma^2 (L / V) / (1 + 6 f L / V)^(5/3) has integral time scale L / V, so
    T = L / V per axis. I_ref is 0.16 for turbulence class A, 0.14 for B, 0.12 for C. The
    standard is written for wind-turbine hub heights; at a few metres it is an extrapolation.

    Parameters
    ----------
    calibration : str
        One of ``CALIBRATIONS``.
    height_m : float
        Height above ground [m]: MIL h in [3.048, 304.8] m (10 to 1000 ft); IEC z > 0.
    mean_wind_m_s : float
        Mean wind speed at that height [m/s], > 0: the convection speed V (IEC: V_hub).
    wind_speed_20ft_m_s : float, optional
        MIL only, required there: W20, the wind speed at 20 ft [m/s], > 0 (MIL-F-8785C:
        15 kt light, 30 kt moderate, 45 kt severe turbulence).
    i_ref : float, optional
        IEC only, required there: the reference turbulence intensity I_ref in (0, 1].
    prefix : str, optional
        Prefix of the field names in error messages (e.g. ``"wind.model."``).

    Returns
    -------
    GustCalibration
    """
    allowed = f"one of {list(CALIBRATIONS)}"
    if calibration not in CALIBRATIONS:
        raise ParameterError(f"{prefix}calibration", calibration, allowed)
    mil = calibration == "mil_hdbk_1797_low_altitude"
    unused = ("i_ref", i_ref) if mil else ("wind_speed_20ft_m_s", wind_speed_20ft_m_s)
    needed = ("wind_speed_20ft_m_s", wind_speed_20ft_m_s) if mil else ("i_ref", i_ref)
    if unused[1] is not None:
        raise ParameterError(f"{prefix}{unused[0]}", unused[1], f"absent with {calibration}")
    if needed[1] is None:
        raise ParameterError(f"{prefix}{needed[0]}", None, f"a required key with {calibration}")
    V = check_number(f"{prefix}mean_wind_m_s", mean_wind_m_s, low=0.0, low_open=True, unit="[m/s]")
    if mil:
        h = check_number(
            f"{prefix}height_m",
            height_m,
            low=10 * _FT,
            high=1000 * _FT,
            allowed="3.048 <= h <= 304.8 [m] (10 to 1000 ft, MIL-F-8785C low altitude)",
        )
        w20 = check_number(
            f"{prefix}wind_speed_20ft_m_s", wind_speed_20ft_m_s, low=0.0, low_open=True
        )
        d = DrydenGust(h, w20, V)
        sigma = (d.sigma_u, d.sigma_v, d.sigma_w)
        length = (d.L_u, d.L_v, d.L_w)
        times = (d.L_u / V, d.L_v / (2.0 * V), d.L_w / (2.0 * V))
    else:
        z = check_number(f"{prefix}height_m", height_m, low=0.0, low_open=True, unit="[m]")
        iref = check_number(f"{prefix}i_ref", i_ref, low=0.0, high=1.0, low_open=True)
        s1 = iref * (0.75 * V + 5.6)
        lam = 0.7 * min(z, 60.0)
        sigma = (s1, 0.8 * s1, 0.5 * s1)
        length = (8.1 * lam, 2.7 * lam, 0.66 * lam)
        times = (length[0] / V, length[1] / V, length[2] / V)
    if sigma[0] > TAYLOR_MAX_INTENSITY * V:
        raise ParameterError(
            f"{prefix}mean_wind_m_s",
            V,
            f"a mean wind at which sigma_u / V <= {TAYLOR_MAX_INTENSITY:g} (here sigma_u = "
            f"{sigma[0]:.3g} m/s): the frozen-turbulence time L/V means nothing in near-calm air",
        )
    return GustCalibration(sigma, length, times)


@dataclass(frozen=True, kw_only=True)
class CalibratedGaussMarkovTurbulence(GaussMarkovTurbulence):
    """``GaussMarkovTurbulence`` with K and a from a published turbulence model
    (``gust_calibration``): a = 1 / T and K = sigma sqrt(2 a) per gust axis (u, v, w).

    In a scenario: ``[wind.model] type = "gauss_markov"`` with ``calibration`` and the
    calibration's inputs instead of ``gain`` and ``pole_rad_s``. A ``Turbulence`` checks that
    ``mean_wind_m_s`` is the speed of its mean wind and ``heading_rad`` its direction.

    Parameters
    ----------
    calibration : str
        ``"iec_61400_1"`` or ``"mil_hdbk_1797_low_altitude"``.
    height_m, mean_wind_m_s, wind_speed_20ft_m_s, i_ref : float
        As for ``gust_calibration``.
    heading_rad : float, optional
        Azimuth of the gust axis u (along the mean wind) in N [rad] (default 0).
    """

    gain: Vec3 = field(init=False, default=(0.0, 0.0, 0.0))
    pole_rad_s: Vec3 = field(init=False, default=(1.0, 1.0, 1.0))
    calibration: str
    height_m: float
    mean_wind_m_s: float
    wind_speed_20ft_m_s: float | None = None
    i_ref: float | None = None

    def __post_init__(self) -> None:
        cal = gust_calibration(
            self.calibration,
            height_m=self.height_m,
            mean_wind_m_s=self.mean_wind_m_s,
            wind_speed_20ft_m_s=self.wind_speed_20ft_m_s,
            i_ref=self.i_ref,
            prefix="CalibratedGaussMarkovTurbulence.",
        )
        _set(self, "height_m", float(self.height_m))
        _set(self, "mean_wind_m_s", float(self.mean_wind_m_s))
        for name in ("wind_speed_20ft_m_s", "i_ref"):
            if getattr(self, name) is not None:
                _set(self, name, float(getattr(self, name)))
        _set(self, "gain", cal.gain)
        _set(self, "pole_rad_s", cal.pole_rad_s)
        super().__post_init__()

    @property
    def calibrated(self) -> GustCalibration:
        """The calibration's sigma, length scales and correlation times."""
        return gust_calibration(
            self.calibration,
            height_m=self.height_m,
            mean_wind_m_s=self.mean_wind_m_s,
            wind_speed_20ft_m_s=self.wind_speed_20ft_m_s,
            i_ref=self.i_ref,
        )

    def to_dict(self) -> dict[str, Any]:
        """The calibration's inputs (absent optional ones left out); K and a follow.
        Returns
        -------
        dict of str to object
            ``type`` and the calibration's given fields.
        """
        return {k: v for k, v in _plain_dict(self).items() if v is not None}
