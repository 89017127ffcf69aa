"""The tether study's static half (``studies.tether_study``): each cable hanging straight
from P to the winch: the ground tension for the paper's 25 N at P, the thrust and its margin
with 25 N at the winch, the lateral stiffness at P (``lateral_stiffness``), and the lengths
at which hover becomes impossible (``hover_limits``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

from scipy import optimize

from .._validation import check_number
from ..params import TETHER_LENGTH_RANGE, Params
from ..tether.chain import LumpedTether
from ..tether.lumped_trim import hover_trim_lumped
from .tether_cables import DEFAULT_THRUST_TO_WEIGHT, StudyCable

__all__ = ["hover_limits", "lateral_stiffness", "static_rows"]


def _top_tension_length(q9: float, top_tension_N: float, w: float, EA: float) -> float:
    """Unstretched length L0 [m] of a vertical cable of height q9 with tension T_P at the top:
    the smaller root of (w / 2EA) L0^2 - (1 + T_P / EA) L0 + q9 = 0 (T(s) = T_P - w (L0 - s))."""
    b = 1.0 + top_tension_N / EA
    disc = b * b - 2.0 * w * q9 / EA
    if disc < 0.0:
        return math.nan
    return 2.0 * q9 / (b + math.sqrt(disc))


def lateral_stiffness(
    ground_tension_N: float, tether: LumpedTether, g: float, unstretched_length_m: float
) -> float:
    """Quasi-static lateral stiffness [N/m] of a vertical hanging cable at its top, pinned at
    the winch: k = 1 / (ln(T_P / T_g) / (mu g) + L0 / EA); a massless cable's limit is
    T / (L0 (1 + T / EA)) = T / q9, the paper's pendulum.

    Parameters
    ----------
    ground_tension_N : float
        Tension at the winch [N], > 0 (at P: T_P = T_g + mu g L0).
    tether : LumpedTether
        The cable (mu, EA).
    g : float
        Gravity [m/s^2].
    unstretched_length_m : float
        L0 [m].

    Returns
    -------
    float
        dH/dx at P [N/m].
    """
    w = tether.mass_per_length_kg_m * g
    Tg, L0 = ground_tension_N, unstretched_length_m
    # ln(Tp/Tg)/w, written so that w -> 0 (Tp -> Tg) stays accurate: L0 log1p(x)/x, x = wL0/Tg
    x = w * L0 / Tg
    compliance = (L0 / Tg) * (math.log1p(x) / x if x > 1e-12 else 1.0 - 0.5 * x)
    return 1.0 / (compliance + L0 / tether.EA_N)


def _free_thrust(params: Params) -> float:
    from ..model.trim import hover_trim

    return float(hover_trim(params, 0.0).u_total[0])


def _max_thrust(params: Params, max_thrust_N: float | None) -> float:
    """The largest fMR3 [N], checked: ``max_thrust_N``, or by default
    ``DEFAULT_THRUST_TO_WEIGHT`` x the free hover thrust."""
    if max_thrust_N is None:
        max_thrust_N = DEFAULT_THRUST_TO_WEIGHT * _free_thrust(params)
    return check_number("max_thrust_N", max_thrust_N, low=0.0, low_open=True, unit="[N]")


def static_rows(
    params: Params,
    cables: Sequence[StudyCable],
    lengths_m: Sequence[float],
    *,
    top_tension_N: float = 25.0,
    ground_tension_N: float = 25.0,
    max_thrust_N: float | None = None,
) -> list[dict[str, Any]]:
    """The static half per (cable, length): see the module docstring.

    Parameters
    ----------
    params : Params
        The helicopter (Table II).
    cables : sequence of StudyCable
        The cables.
    lengths_m : sequence of float
        Heights q9 of P above the winch [m].
    top_tension_N : float, optional
        The tension to keep at P [N] (the paper's 25 N).
    ground_tension_N : float, optional
        The load cell's tension of the second policy [N] (the paper's 25 N).
    max_thrust_N : float, optional
        Maximum fMR3 [N]; default ``DEFAULT_THRUST_TO_WEIGHT`` x the free hover thrust.

    Returns
    -------
    list of dict
        Per (cable, length): ``L0_m`` and ``ground_tension_for_top_N`` (NaN when T_g <= 0:
        impossible) for 25 N at P; with 25 N at the winch ``top_tension_N``, ``fMR3_N``,
        ``extra_lift_N`` (over the massless tether's trim), ``lift_margin_N``;
        ``k_lateral_N_m`` (cable, 25 N at the winch) and ``k_lateral_massless_N_m``
        (T_ref / q9).
    """
    from ..model.trim import hover_trim

    g = params.helicopter.g
    Tp = check_number("top_tension_N", top_tension_N, low=0.0, low_open=True, unit="[N]")
    Tg = check_number("ground_tension_N", ground_tension_N, low=0.0, low_open=True, unit="[N]")
    fmax = _max_thrust(params, max_thrust_N)
    rows = []
    for cable in cables:
        t = cable.tether
        w = t.mass_per_length_kg_m * g
        for q9 in lengths_m:
            massless = float(hover_trim(params, Tg, q9).u_total[0])
            L0_top = _top_tension_length(q9, Tp, w, t.EA_N)
            Tg_top = Tp - w * L0_top if L0_top == L0_top else math.nan
            lt = hover_trim_lumped(params, t, Tg, q9)
            f = float(lt.trim.u_total[0])
            rows.append(
                {
                    "cable": cable.key,
                    "length_m": float(q9),
                    "L0_m": L0_top,
                    "ground_tension_for_top_N": Tg_top if Tg_top > 0.0 else math.nan,
                    "top_tension_N": lt.top_tension_N,
                    "fMR3_N": f,
                    "extra_lift_N": f - massless,
                    "lift_margin_N": fmax - f,
                    "k_lateral_N_m": lateral_stiffness(Tg, t, g, lt.unstretched_length_m),
                    "k_lateral_massless_N_m": Tg / q9,
                }
            )
    return rows


def hover_limits(
    params: Params,
    cables: Sequence[StudyCable],
    *,
    top_tension_N: float = 25.0,
    ground_tension_N: float = 25.0,
    max_thrust_N: float | None = None,
) -> list[dict[str, Any]]:
    """The lengths at which hover becomes impossible, per cable.

    Parameters
    ----------
    params : Params
        The helicopter.
    cables : sequence of StudyCable
        The cables.
    top_tension_N, ground_tension_N, max_thrust_N : float, optional
        As ``static_rows``.

    Returns
    -------
    list of dict
        ``cable``; ``max_length_top_tension_m``: the height at which the ground tension for
        ``top_tension_N`` at P reaches 0 (L0 = T_P / (mu g), q9 = L0 (1 + T_P / (2 EA)));
        ``max_length_thrust_m``: the height at which fMR3 with ``ground_tension_N`` at the
        winch reaches ``max_thrust_N`` (NaN: not within ``TETHER_LENGTH_RANGE``);
        ``max_thrust_N``.
    """
    g = params.helicopter.g
    fmax = _max_thrust(params, max_thrust_N)
    Tp = check_number("top_tension_N", top_tension_N, low=0.0, low_open=True, unit="[N]")
    out = []
    for cable in cables:
        t = cable.tether
        w = t.mass_per_length_kg_m * g
        L0 = Tp / w
        q9_top = L0 * (1.0 + Tp / (2.0 * t.EA_N))

        def excess(q9: float, t: LumpedTether = t) -> float:
            lt = hover_trim_lumped(params, t, ground_tension_N, q9)
            return float(lt.trim.u_total[0]) - fmax

        lo, hi = TETHER_LENGTH_RANGE
        if excess(lo) >= 0.0:
            q9_thrust = 0.0
        elif excess(hi) < 0.0:
            q9_thrust = math.nan
        else:
            q9_thrust = float(optimize.brentq(excess, lo, hi, xtol=1e-6))
        out.append(
            {
                "cable": cable.key,
                "max_length_top_tension_m": q9_top,
                "max_length_thrust_m": q9_thrust,
                "max_thrust_N": fmax,
            }
        )
    return out
