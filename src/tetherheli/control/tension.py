"""PI tension controller of the ground winch (paper Sec. V-B, eq 56).

Continuous law (eq 56): R_C = K_P (T_C - T_ref) + K_I int (T_C - T_ref) dt, where R_C is the
reel rate dL_N/dt of eq 37. Sign: a tension above the reference gives R_C > 0, the winch reels
out, L_N grows and T_C = K_C (q9 - L_N) (eq 28) drops.

Discrete implementation at sample time dt (the rate is held constant between samples)::

    e_k   = T_meas,k - T_ref
    v_k   = K_P e_k + K_I I_k                  (unsaturated command)
    R_k   = clip(v_k, -rate_limit, +rate_limit)
    I_k+1 = I_k + dt e_k                        (forward Euler, unless held, see below)

with I_0 = 0 at the trim start, so I_k = dt (e_0 + ... + e_{k-1}) approximates the integral
of eq 56 up to t_k, and R_k uses the error measured at t_k.

Anti-windup (conditional integration / clamping): when the command is saturated
(|v_k| > rate_limit) and the error would drive it further into saturation
(sign(e_k) = sign(v_k)), the integral is held, I_k+1 = I_k. Otherwise it integrates. With
``rate_limit = inf`` (the paper's case) the controller is the plain PI of eq 56.

The state (the integral I) is explicit and the configuration is a frozen dataclass;
:func:`tension_pi_step` is the scalar core, a pure function of floats so that it can be
compiled with Numba later.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .._validation import check_number
from ..params import TensionControlParams

__all__ = ["TensionPI", "limit_rate_change", "tension_pi_step"]


def tension_pi_step(
    integral: float,
    measured_tension: float,
    K_P: float,
    K_I: float,
    T_ref: float,
    dt: float,
    rate_limit: float,
) -> tuple[float, float]:
    """One sample of the discrete PI law of eq 56 with clamping anti-windup.

    Parameters
    ----------
    integral : float
        I_k, the accumulated tension error [N s].
    measured_tension : float
        Measured tether tension T_meas,k (T_C^est of Sec. V-B) [N].
    K_P : float
        Proportional gain [m/(s N)].
    K_I : float
        Integral gain [m/(s^2 N)].
    T_ref : float
        Reference tension [N].
    dt : float
        Sample time [s].
    rate_limit : float
        Bound on |R_C| [m/s] (``math.inf`` for none).

    Returns
    -------
    rate : float
        R_C,k, the reel rate dL_N/dt to hold over [t_k, t_k + dt) [m/s] (eq 37).
    new_integral : float
        I_{k+1} [N s].
    """
    error = measured_tension - T_ref
    command = K_P * error + K_I * integral
    if command > rate_limit:
        rate = rate_limit
        new_integral = integral if error > 0.0 else integral + dt * error
    elif command < -rate_limit:
        rate = -rate_limit
        new_integral = integral if error < 0.0 else integral + dt * error
    else:
        rate = command
        new_integral = integral + dt * error
    return rate, new_integral


def limit_rate_change(
    rate: float, previous_rate: float, acceleration_limit: float, dt: float
) -> float:
    """``rate`` with its change since ``previous_rate`` bounded by ``acceleration_limit`` dt:
    the winch motor's acceleration limit [m/s^2] over one sample (``math.inf``: none).

    The winch PI (``control.paper.winch_step``) applies it to its own command and holds its
    integral while it binds (conditional integration, no windup); the actuator model applies
    the same bound to any controller's command.

    Parameters
    ----------
    rate : float
        The commanded reel rate [m/s].
    previous_rate : float
        The previous sample's rate [m/s].
    acceleration_limit : float
        The winch's acceleration limit [m/s^2] (``math.inf``: none).
    dt : float
        Sample time [s].

    Returns
    -------
    float
        ``rate`` clipped to previous_rate -+ acceleration_limit dt [m/s].
    """
    step = acceleration_limit * dt
    return min(max(rate, previous_rate - step), previous_rate + step)


@dataclass(frozen=True)
class TensionPI:
    """Configuration of the winch's discrete PI tension controller (eq 56).

    Parameters
    ----------
    K_P : float
        Proportional gain [m/(s N)], finite and >= 0 (paper: 1).
    K_I : float
        Integral gain [m/(s^2 N)], finite and >= 0 (paper: 0.1).
    T_ref : float
        Reference tension T_C^ref [N], finite and >= 0 (paper: 25 N, eq 40).
    dt : float
        Sample time [s], finite and > 0.
    rate_limit : float, optional
        Bound on the reel rate |R_C| [m/s], > 0 (``math.inf``, the default, for none; the
        paper has none). Saturation triggers the clamping anti-windup of the module docstring.

    Notes
    -----
    The controller's state is the integral I [N s] alone; it is passed to and returned by
    :meth:`step`, never stored here. Start it at 0 at trim.
    """

    K_P: float
    K_I: float
    T_ref: float
    dt: float
    rate_limit: float = math.inf

    def __post_init__(self) -> None:
        for name in ("K_P", "K_I", "T_ref"):
            object.__setattr__(self, name, check_number(name, getattr(self, name), low=0.0))
        dt = check_number("dt", self.dt, low=0.0, low_open=True, unit="[s]")
        object.__setattr__(self, "dt", dt)
        limit = check_number(
            "rate_limit", self.rate_limit, low=0.0, low_open=True, finite=False, unit="[m/s]"
        )
        object.__setattr__(self, "rate_limit", limit)

    @classmethod
    def from_params(
        cls, params: TensionControlParams, dt: float, *, rate_limit: float = math.inf
    ) -> TensionPI:
        """The controller with the gains and reference of ``params`` (eq 56, Sec. VI).

        Parameters
        ----------
        params : TensionControlParams
            K_P [m/(s N)], K_I [m/(s^2 N)] and T_ref [N].
        dt : float
            Sample time [s], > 0.
        rate_limit : float, optional
            Bound on |R_C| [m/s] (default ``math.inf``, none).

        Returns
        -------
        TensionPI
            The configured controller.
        """
        return cls(K_P=params.K_P, K_I=params.K_I, T_ref=params.T_ref, dt=dt, rate_limit=rate_limit)

    def step(self, state_integral: float, measured_tension: float) -> tuple[float, float]:
        """One controller sample (eq 56, discretised as in the module docstring).

        Parameters
        ----------
        state_integral : float
            I_k [N s].
        measured_tension : float
            T_meas,k [N].

        Returns
        -------
        rate : float
            Reel rate R_C,k = dL_N/dt [m/s], held until the next sample (eq 37).
        new_integral : float
            I_{k+1} [N s].
        """
        return tension_pi_step(
            float(state_integral),
            float(measured_tension),
            self.K_P,
            self.K_I,
            self.T_ref,
            self.dt,
            self.rate_limit,
        )
