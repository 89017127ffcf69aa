"""The drum winch: a motor drive with a speed loop turning a drum of finite inertia.

The ideal winch of the paper applies the reel rate R_C of eq 56 at once (dL_N/dt = R_C,
eq 37). The drum winch (``[winch] model = "drum"``, ``scenario.core.WinchSettings``) puts a
drive between the command and the tether. Signs: the drum speed w is positive paying out
(dL_N/dt = r w, the sign of R_C), the tether's pull r T_g turns the drum that way, and the
motor torque tau_m counts positive hauling in (the sense that holds the tether). The drum
obeys

    J w' = r T_g - tau_m - b w - tau_c sign(w),  dL_N/dt = r w,

with T_g the tension at the winch (the tether tension for the massless tether; the tension
at the ground node for a lumped tether), b the viscous and tau_c the Coulomb friction; at
w = 0 the drum sticks while |r T_g - tau_m| <= tau_c. At rest the motor holds tau_m = r T_g.

The speed loop, inside the motor drive, runs far faster than the control sample and is
modelled in continuous time: the PI of eq 56 gives the drum-speed reference w_c = R_C / r,
held over the sample, and the drive's torque is

    tau_m = sat(K_w (w - w_c) + tau_ff, tau_max),  K_w = J omega_w,

a proportional speed loop of bandwidth omega_w [rad/s] (without tension and friction the drum
follows w_c as a first-order lag of time constant 1/omega_w) plus the load-cell feed-forward
tau_ff = r T_meas (optional, ``tension_feedforward``), which removes the proportional loop's
steady speed error under the tether's load. A limit tau_max below r T_g cannot hold the
tether: the drum pays out until the tension falls to tau_max / r.

Discretisation (``drum_step``): over one control sample the command w_c, the feed-forward and
the tension T_g are held (T_g at its sampled value). The right-hand side f(w) is then
piecewise linear in w, f = alpha - beta w, with breakpoints where the torque saturates and at
w = 0, and nonincreasing (beta = K_w + b or b >= 0, and the Coulomb jump at 0 is downward), so
w moves monotonically towards its equilibrium or the stick set: the solution is the exact
exponential (or, with beta = 0, linear) solution in each piece, joined at the breakpoints
(at most three crossings and one stick per sample). The only approximation is holding T_g
over the sample; its effect is measured against an adaptive solution of the joint
helicopter, tether and drum ODE (``benchmarks/winch_drum.py --reference``).
"""

from __future__ import annotations

import math

from .._compile import compiled

__all__ = ["drum_step"]

_jit_inline = compiled(error_model="numpy", inline="always")

#: most pieces one sample can take: three breakpoint crossings, a stick, and a margin
_MAX_PIECES = 8


@_jit_inline
def _torque(w, w_cmd, tau_ff, gain, torque_limit):
    """The drive's torque along w (paying out), -tau_m = sat(K_w (w_c - w) + tau_ff,
    tau_max) with tau_ff the feed-forward along w [N m]."""
    return min(max(gain * (w_cmd - w) + tau_ff, -torque_limit), torque_limit)


@_jit_inline
def drum_step(
    w0: float,
    w_cmd: float,
    tension_torque: float,
    ffwd_torque: float,
    h: float,
    inertia: float,
    gain: float,
    torque_limit: float,
    viscous: float,
    coulomb: float,
) -> tuple[float, float, float]:
    """Advance the drum over one interval of length h with the command, the feed-forward and
    the load held, by the exact piecewise solution (module docstring).

    Parameters
    ----------
    w0 : float
        Drum speed at the start [rad/s] (positive: paying out, L_N growing).
    w_cmd : float
        Speed reference w_c = R_C / r [rad/s].
    tension_torque : float
        r T_g, the tether's torque on the drum, paying out [N m] (T_g the tension at the
        winch).
    ffwd_torque : float
        The drive's feed-forward torque tau_ff, hauling in [N m] (r T_meas, or 0).
    h : float
        Interval [s], > 0.
    inertia : float
        J, drum and motor reflected [kg m^2], > 0.
    gain : float
        K_w = J omega_w, the speed loop's proportional gain [N m s/rad], > 0.
    torque_limit : float
        tau_max [N m], > 0.
    viscous : float
        b [N m s/rad], >= 0.
    coulomb : float
        tau_c [N m], >= 0.

    Returns
    -------
    w1 : float
        Drum speed at the end [rad/s].
    speed_integral : float
        int w dt over the interval [rad] (the reel length paid out is r times it).
    torque_integral : float
        int tau_m dt over the interval [N m s] (tau_m hauling in).
    """
    # the solver works with torques along w: the drive's -tau_m, the load opposing w -r T_g
    load_torque = -tension_torque
    tau_ff = -ffwd_torque
    w = w0
    left = h
    speed_integral = 0.0
    torque_integral = 0.0
    # breakpoints of f(w): the torque saturates at +tau_max for w <= w_lo, -tau_max for w >= w_hi
    w_lo = w_cmd + (tau_ff - torque_limit) / gain
    w_hi = w_cmd + (tau_ff + torque_limit) / gain
    for _ in range(_MAX_PIECES):
        if left <= 0.0:
            break
        if w == 0.0:
            net = _torque(0.0, w_cmd, tau_ff, gain, torque_limit) - load_torque
            if abs(net) <= coulomb:  # stiction: the drum stays at rest
                torque_integral += _torque(0.0, w_cmd, tau_ff, gain, torque_limit) * left
                left = 0.0
                break
            d = 1.0 if net > 0.0 else -1.0
            s = d
        else:
            s = 1.0 if w > 0.0 else -1.0
            f = _torque(w, w_cmd, tau_ff, gain, torque_limit) - load_torque
            f -= viscous * w + coulomb * s
            if f == 0.0:  # at an equilibrium
                speed_integral += w * left
                torque_integral += _torque(w, w_cmd, tau_ff, gain, torque_limit) * left
                left = 0.0
                break
            d = 1.0 if f > 0.0 else -1.0
        # the piece adjacent to w in the direction of motion d
        if w < w_lo or (w == w_lo and d < 0.0):
            sat, alpha, beta = 1.0, torque_limit, viscous
        elif w > w_hi or (w == w_hi and d > 0.0):
            sat, alpha, beta = -1.0, -torque_limit, viscous
        else:
            sat, alpha, beta = 0.0, gain * w_cmd + tau_ff, gain + viscous
        alpha -= load_torque + coulomb * s
        edge = math.inf * d
        for b_pt in (w_lo, w_hi, 0.0):
            if (b_pt - w) * d > 0.0 and abs(b_pt - w) < abs(edge - w):
                edge = b_pt
        # time to reach the edge, and the integrals over tau = min(that time, left)
        if beta > 0.0:
            w_eq = alpha / beta
            rate = beta / inertia
            if math.isfinite(edge) and (w_eq - edge) * d > 0.0:
                t_edge = math.log((w - w_eq) / (edge - w_eq)) / rate
            else:
                t_edge = math.inf
            tau = min(t_edge, left)
            decay = -math.expm1(-rate * tau)  # 1 - exp(-rate tau)
            piece_integral = w_eq * tau + (w - w_eq) * decay / rate
            w_end = edge if tau == t_edge else w_eq + (w - w_eq) * (1.0 - decay)
        else:  # saturated without viscous friction: constant acceleration
            accel = alpha / inertia
            t_edge = (edge - w) / accel if math.isfinite(edge) else math.inf
            tau = min(t_edge, left)
            piece_integral = w * tau + 0.5 * accel * tau * tau
            w_end = edge if tau == t_edge else w + accel * tau
        speed_integral += piece_integral
        if sat == 0.0:
            torque_integral += (gain * w_cmd + tau_ff) * tau - gain * piece_integral
        else:
            torque_integral += sat * torque_limit * tau
        w = w_end
        left -= tau
    if left > 0.0:  # not reached (at most four pieces); hold rather than lose time
        speed_integral += w * left
        torque_integral += _torque(w, w_cmd, tau_ff, gain, torque_limit) * left
    return w, speed_integral, -torque_integral
