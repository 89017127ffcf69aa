"""The paper's controller (Sec. V): LQI position control with integral action (eqs 47-53),
the tether-torque feed-forward (eqs 54-55), and the winch's PI tension control (eq 56).

``paper_control`` is the compiled kernel the closed-loop engine calls at every sample;
``PaperController`` wraps it as a ``Controller`` object for the Python simulation loop.
"""

from __future__ import annotations

import numpy as np

from .._compile import compiled
from ..errors import ParameterError
from ..layout import (
    CONTROL_LAW_GAIN_SHAPES,
    CONTROL_LAW_TETHER_LQI,
    CONTROL_LAWS,
    CTRL_ANTI_WINDUP,
    CTRL_DT,
    CTRL_FFWD,
    CTRL_K_I,
    CTRL_K_P,
    CTRL_LAW,
    CTRL_REEL_ACCEL,
    CTRL_REEL_RATE_LIMIT,
    CTRL_SIZE,
    CTRL_T_REF,
    CTRL_TENSION_K_C,
    CTRL_U_MAX,
    CTRL_U_MIN,
    CTRL_WINCH,
    WINCH_INTEGRAL,
    WINCH_PREVIOUS_RATE,
    WINCH_SIZE,
    X_LN,
    X_Q9,
)
from ..model.kernels import angle_trig, tethered_outputs_sc, tethered_tether_torque_sc
from .base import Command, Controller, Measurement
from .tension import limit_rate_change, tension_pi_step

__all__ = [
    "CTRL_SIZE", "WINCH_SIZE", "PaperController", "check_law", "paper_control", "winch_step",
]  # fmt: skip

_jit = compiled(error_model="numpy")
_jit_inline = compiled(error_model="numpy", inline="always")
_tension_pi_step = _jit_inline(tension_pi_step)
limit_rate_change_jit = _jit_inline(limit_rate_change)


@_jit_inline
def winch_step(winch, measured_tension, ctrl):
    """The winch's reel-rate command at one sample: the PI of eq 56 with its rate limit
    (clamping anti-windup), then the winch's acceleration limit relative to the previous
    command, the integral held while that limit binds (conditional integration). ``winch``
    (WINCH_SIZE,) holds I_k and the previous command and is updated in place; returns the
    reel rate R_C,k [m/s] (eq 37).

    Parameters
    ----------
    winch : numpy.ndarray, shape (WINCH_SIZE,)
        The winch PI's state (``layout.WINCH_*``): I_k [N s] and the previous reel-rate
        command [m/s]; updated in place.
    measured_tension : float
        The load cell's tension T [N].
    ctrl : numpy.ndarray, shape (CTRL_SIZE,)
        The controller's settings (``layout.CTRL_*``).

    Returns
    -------
    float
        The reel rate R_C,k [m/s].
    """
    limited, integral = winch_pi(
        winch[WINCH_INTEGRAL], winch[WINCH_PREVIOUS_RATE], measured_tension, ctrl[CTRL_K_P],
        ctrl[CTRL_K_I], ctrl[CTRL_T_REF], ctrl[CTRL_DT], ctrl[CTRL_REEL_RATE_LIMIT],
        ctrl[CTRL_REEL_ACCEL],
    )  # fmt: skip
    winch[WINCH_INTEGRAL] = integral
    winch[WINCH_PREVIOUS_RATE] = limited
    return limited


@_jit_inline
def winch_pi(integral, previous, measured_tension, k_p, k_i, t_ref, dt, rate_limit, accel):
    """``winch_step`` on scalars: (R_C,k [m/s], I_{k+1} [N s]) from I_k, the previous
    command [m/s] and the measured tension [N] (eq 56's PI with its rate limit, then the
    acceleration limit, the integral held while that binds). The one formula of the winch
    PI, for a single run and the lane engine's block.

    Parameters
    ----------
    integral : float
        The PI's integral I_k [N s].
    previous : float
        The reel rate commanded at the previous sample [m/s].
    measured_tension : float
        The load cell's tension T [N].
    k_p : float
        The proportional gain KP [m/(N s)].
    k_i : float
        The integral gain KI [m/(N s^2)].
    t_ref : float
        The tension reference Tref [N].
    dt : float
        The sample time [s].
    rate_limit : float
        The winch's reel-rate limit [m/s] (``math.inf``: none).
    accel : float
        The winch's acceleration limit [m/s^2] (``math.inf``: none).

    Returns
    -------
    rate : float
        The reel rate R_C,k [m/s].
    integral : float
        The integral I_{k+1} [N s] (I_k while the acceleration limit binds).
    """
    rate, new_integral = _tension_pi_step(
        integral, measured_tension, k_p, k_i, t_ref, dt, rate_limit
    )
    limited = limit_rate_change_jit(rate, previous, accel, dt)
    return limited, (new_integral if limited == rate else integral)


@_jit
def paper_control(x, measured_tension, integrators, ctrl, c, law, outputs):
    """Eqs 50-56 at one sample; fills inp (4,), ffwd (4,), y (4,) and returns the reel rate.

    u = -K [x - x_ref; z] + u0 - C_f-fwd (eq 54), with C_f-fwd from the measured tension and
    the measured angles (eq 55); then z += dt (y_ref - y) (eq 50). The winch rate is
    RC = KP e + KI I with e = T - Tref, then I += dt e (eq 56, ``winch_step``). ``z`` (4,) and
    ``winch`` (WINCH_SIZE,) are updated in place; x is the (13,) tethered-coordinate state.
    The arrays come in three groups (tuples, unpacked at no cost in compiled code): the
    integrators (z, winch), the law about its trim (gain, x_ref, y_ref, u0) and the outputs
    (y, inp, ffwd).

    Parameters
    ----------
    x : numpy.ndarray, shape (13,)
        The measured state in tethered coordinates [q4..q9, u1..u6, LN]: q4..q8 [rad], q9 and
        LN [m], u1..u3 [m/s], u4..u6 [rad/s].
    measured_tension : float
        The load cell's tension T [N].
    integrators : tuple of numpy.ndarray
        (z, winch): the LQI's output-error integral (eq 50) (4,) [m s, rad s] and the winch
        PI's state (``layout.WINCH_*``): I_k [N s] and the previous reel-rate command [m/s];
        updated in place.
    ctrl : numpy.ndarray, shape (CTRL_SIZE,)
        The controller's settings (``layout.CTRL_*``).
    c : numpy.ndarray
        The tethered model's constants (``kernels.model_constants("tethered", h)``).
    law : tuple of numpy.ndarray
        (gain, x_ref, y_ref, u0): the law's gain (``layout.LAW_GAIN``: K_LQI|F (4, 16), or
        the tethered LQI's packed gain (9, 17)), the state references (12,) or (13,) (the
        trim's q4..u6, and LN for the tethered LQI; units as ``x``), the output references
        y0 (4,) [q1, q2, q3 in m, q6 in rad] and the trim inputs u0 (4,) [N, N m, N m, N].
    outputs : tuple of numpy.ndarray
        (y, inp, ffwd), each (4,), filled with the outputs [q1, q2, q3 in m, q6 in rad], the
        rotor inputs u [N, N m, N m, N] (feed-forward included) and their feed-forward part
        C_f-fwd (eq 55) [N, N m, N m, N].

    Returns
    -------
    float
        The reel rate R_C,k [m/s] (0 while the winch loop is off).
    """
    sc = np.empty(10)
    angle_trig(x, sc)
    return paper_control_sc(x, sc, measured_tension, integrators, ctrl, c, law, outputs)


@_jit_inline
def paper_control_sc(x, sc, measured_tension, integrators, ctrl, c, law, outputs):
    """``paper_control`` with sc (10,) = sin, cos of x[0..4] given (``kernels.angle_trig``);
    the engine's entry point.

    ctrl[CTRL_LAW] names the law (``layout.CONTROL_LAWS``): "paper", the paper's LQI on
    q4..u6 (gain (4, 16)); "tether_lqi", the tethered LQI (``control.tether_lqi``) on q4..u6
    and LN (gain (9, 17)), whose fifth row commands the reel rate in place of the winch PI
    while the winch runs (rows 5-8, the free law, once it stops: a release or the free
    configuration); the set-up pairs each law with its gain (``check_law``). With
    ctrl[CTRL_ANTI_WINDUP] the integrators hold while a rotor command lies outside
    [ctrl[CTRL_U_MIN + i], ctrl[CTRL_U_MAX + i]] (conditional integration). With
    ctrl[CTRL_TENSION_K_C] = KC > 0 the tethered law takes q9 = LN + TC / KC (eq 28, measured
    tension and drum encoder) while the measured tension is positive (``tension_q9``).

    Parameters
    ----------
    x : numpy.ndarray, shape (13,)
        The measured state in tethered coordinates [q4..q9, u1..u6, LN]: q4..q8 [rad], q9 and
        LN [m], u1..u3 [m/s], u4..u6 [rad/s].
    sc : numpy.ndarray, shape (10,)
        sin and cos of x[0..4] (``kernels.angle_trig``).
    measured_tension : float
        The load cell's tension T [N].
    integrators : tuple of numpy.ndarray
        (z, winch): the LQI's output-error integral (eq 50) (4,) [m s, rad s] and the winch
        PI's state (``layout.WINCH_*``): I_k [N s] and the previous reel-rate command [m/s];
        updated in place.
    ctrl : numpy.ndarray, shape (CTRL_SIZE,)
        The controller's settings (``layout.CTRL_*``).
    c : numpy.ndarray
        The tethered model's constants (``kernels.model_constants("tethered", h)``).
    law : tuple of numpy.ndarray
        (gain, x_ref, y_ref, u0): the law's gain (``layout.LAW_GAIN``: K_LQI|F (4, 16), or
        the tethered LQI's packed gain (9, 17)), the state references (12,) or (13,) (the
        trim's q4..u6, and LN for the tethered LQI; units as ``x``), the output references
        y0 (4,) [q1, q2, q3 in m, q6 in rad] and the trim inputs u0 (4,) [N, N m, N m, N].
    outputs : tuple of numpy.ndarray
        (y, inp, ffwd), each (4,), filled with the outputs [q1, q2, q3 in m, q6 in rad], the
        rotor inputs u [N, N m, N m, N] (feed-forward included) and their feed-forward part
        C_f-fwd (eq 55) [N, N m, N m, N].

    Returns
    -------
    float
        The reel rate R_C,k [m/s] (0 while the winch loop is off).
    """
    z, winch = integrators
    gain, x_ref, y_ref, u0 = law
    y, inp, ffwd = outputs
    tethered_outputs_sc(x, sc, c, y)
    n_x = gain.shape[1] - 4
    winch_on = ctrl[CTRL_WINCH] > 0.5
    tether_law = ctrl[CTRL_LAW] == CONTROL_LAW_TETHER_LQI
    row0 = 5 if (tether_law and not winch_on) else 0
    q9 = x[X_Q9]
    if tether_law and winch_on:
        q9 = tension_q9(x, measured_tension, ctrl)
    for i in range(4):
        acc = u0[i]
        for j in range(n_x):
            acc -= gain[row0 + i, j] * ((q9 if j == X_Q9 else x[j]) - x_ref[j])
        for j in range(4):
            acc -= gain[row0 + i, n_x + j] * z[j]
        inp[i] = acc
    ffwd[0] = 0.0
    ffwd[3] = 0.0
    if ctrl[CTRL_FFWD] > 0.5:
        tethered_tether_torque_sc(x, sc, measured_tension, c, ffwd[1:3])
        inp[1] -= ffwd[1]
        inp[2] -= ffwd[2]
    else:
        ffwd[1] = 0.0
        ffwd[2] = 0.0
    dt = ctrl[CTRL_DT]
    integrate = True
    if ctrl[CTRL_ANTI_WINDUP] > 0.5:
        for i in range(4):
            if inp[i] < ctrl[CTRL_U_MIN + i] or inp[i] > ctrl[CTRL_U_MAX + i]:
                integrate = False
    if integrate:
        for j in range(4):
            z[j] += dt * (y_ref[j] - y[j])
    if not winch_on:
        return 0.0
    if tether_law:
        return reel_law_step(x, q9, z, winch, ctrl, gain, x_ref, n_x)
    return winch_step(winch, measured_tension, ctrl)


@_jit_inline
def tension_q9(x, measured_tension, ctrl):
    """The tether length [m] the tethered LQI feeds back: LN + TC / KC (eq 28 inverted, from
    the load cell and the drum encoder LN = x[12]) when ctrl[CTRL_TENSION_K_C] = KC > 0 and the
    measured tension is positive (taut), else the position source's q9 = x[5]. A GNSS-derived
    q9 errs by metres, KC (q9 - LN) then by tens of newtons; the load cell's by millimetres.

    Parameters
    ----------
    x : numpy.ndarray, shape (13,)
        The measured state in tethered coordinates [q4..q9, u1..u6, LN]: q4..q8 [rad], q9 and
        LN [m], u1..u3 [m/s], u4..u6 [rad/s].
    measured_tension : float
        The load cell's tension T [N].
    ctrl : numpy.ndarray, shape (CTRL_SIZE,)
        The controller's settings (``layout.CTRL_*``).

    Returns
    -------
    float
        The tether length q9 [m] the law feeds back.
    """
    return tension_q9_of(x[X_Q9], x[X_LN], measured_tension, ctrl[CTRL_TENSION_K_C])


@_jit_inline
def tension_q9_of(q9, length, measured_tension, k_c):
    """``tension_q9`` on scalars: length + measured_tension / k_c when k_c > 0 and the
    tension is positive, else the position source's q9 [m].

    Parameters
    ----------
    q9 : float
        The position source's tether length q9 [m].
    length : float
        The drum encoder's natural length LN [m].
    measured_tension : float
        The load cell's tension T [N].
    k_c : float
        The tether elasticity KC [N/m] (0: q9 from the position source).

    Returns
    -------
    float
        The tether length q9 [m] the law feeds back.
    """
    if k_c > 0.0 and measured_tension > 0.0:
        return length + measured_tension / k_c
    return q9


@_jit_inline
def reel_law_step(x, q9, z, winch, ctrl, gain, x_ref, n_x):
    """The tethered LQI's reel-rate command (row 4 of the gain; the trim's rate is zero) on
    the state x with q9 in place of x[5] (``tension_q9``), clamped to the winch's rate limit,
    then its acceleration limit relative to the previous command, as ``winch_step`` does for
    the PI; returns the reel rate [m/s].

    Parameters
    ----------
    x : numpy.ndarray, shape (13,)
        The measured state in tethered coordinates [q4..q9, u1..u6, LN]: q4..q8 [rad], q9 and
        LN [m], u1..u3 [m/s], u4..u6 [rad/s].
    q9 : float
        The tether length [m] used in place of x[5] (``tension_q9``).
    z : numpy.ndarray, shape (4,)
        The LQI's output-error integral (eq 50) [m s, rad s].
    winch : numpy.ndarray, shape (WINCH_SIZE,)
        The winch PI's state (``layout.WINCH_*``): its previous reel-rate command [m/s] is read and
        updated in place.
    ctrl : numpy.ndarray, shape (CTRL_SIZE,)
        The controller's settings (``layout.CTRL_*``).
    gain : numpy.ndarray, shape (9, 17)
        The tethered LQI's packed gain (``layout.LAW_GAIN``); row 4 commands the reel rate.
    x_ref : numpy.ndarray, shape (13,)
        The state references (the trim's q4..u6 and LN), units as ``x``.
    n_x : int
        The number of state columns of ``gain`` (its width less the 4 integrators).

    Returns
    -------
    float
        The reel rate [m/s].
    """
    acc = 0.0
    for j in range(n_x):
        acc -= gain[4, j] * ((q9 if j == 5 else x[j]) - x_ref[j])
    for j in range(4):
        acc -= gain[4, n_x + j] * z[j]
    limited = reel_command(
        acc, winch[WINCH_PREVIOUS_RATE], ctrl[CTRL_REEL_RATE_LIMIT], ctrl[CTRL_REEL_ACCEL],
        ctrl[CTRL_DT],
    )  # fmt: skip
    winch[WINCH_PREVIOUS_RATE] = limited
    return limited


@_jit_inline
def reel_command(command, previous, rate_limit, accel, dt):
    """The tethered LQI's reel-rate command [m/s] clamped to the winch's rate limit, then its
    acceleration limit relative to the previous command (``reel_law_step``).

    Parameters
    ----------
    command : float
        The law's reel-rate command [m/s].
    previous : float
        The reel rate commanded at the previous sample [m/s].
    rate_limit : float
        The winch's reel-rate limit [m/s] (``math.inf``: none).
    accel : float
        The winch's acceleration limit [m/s^2] (``math.inf``: none).
    dt : float
        The sample time [s].

    Returns
    -------
    float
        The limited reel rate [m/s].
    """
    command = min(max(command, -rate_limit), rate_limit)
    return limit_rate_change_jit(command, previous, accel, dt)


def check_law(ctrl: np.ndarray, gain: np.ndarray) -> str:
    """Check that the compiled law ``ctrl[CTRL_LAW]`` names (``layout.CONTROL_LAWS``) is
    one the engine has and that ``gain`` has its shape; the engine then trusts both.

    Parameters
    ----------
    ctrl : numpy.ndarray, shape (CTRL_SIZE,)
        Controller settings (``layout.CTRL_*``).
    gain : numpy.ndarray
        The law's gain (``layout.LAW_GAIN``).

    Returns
    -------
    str
        The law's name.

    Raises
    ------
    ParameterError
        An unknown law code, or a gain of another law's shape.
    """
    code = float(ctrl[CTRL_LAW])
    names = ", ".join(f"{i} ({n})" for i, n in enumerate(CONTROL_LAWS))
    if code not in range(len(CONTROL_LAWS)):
        raise ParameterError("ctrl[CTRL_LAW]", code, names)
    name = CONTROL_LAWS[int(code)]
    shape = CONTROL_LAW_GAIN_SHAPES[int(code)]
    if np.shape(gain) != shape:
        raise ParameterError(
            "gain", f"an array of shape {np.shape(gain)}", f"shape {shape} for the {name} law"
        )
    return name


class PaperController(Controller):
    """The paper's control scheme (Fig. 5) as a ``Controller``.

    After a release (``Measurement.attached`` false) the winch and the feed-forward stop and
    the LQI works about u0|F, as the compiled engine does (``engine.paper_sample``).

    Parameters
    ----------
    gain : array_like, shape (4, 16) or (9, 17)
        The LQI gain K_LQI|F designed on the free model (Sec. IV-E), or the tethered LQI's
        packed gain (``layout.LAW_GAIN``, ``control.tether_lqi.pack_gain``), as
        ``ctrl[CTRL_LAW]`` names the law (``check_law``).
    trim_state : array_like, shape (13,)
        The configuration's trim x0 [q4..q9, u1..u6, LN] (references for q4..u6, and LN for
        the tethered LQI).
    trim_output : array_like, shape (4,)
        y0, the output references [q1, q2, q3 in m, q6 in rad].
    trim_input : array_like, shape (4,)
        u0|F or u0|T (Tables IV, V) [N, N m, N m, N].
    ctrl : array_like, shape (CTRL_SIZE,)
        Settings, see the ``layout.CTRL_*`` indices.
    constants : array_like
        The tethered model's constants, ``kernels.model_constants("tethered", h)``.
    free_trim_input : array_like, shape (4,), optional
        u0|F, used once the tether is released (``runs.start.free_trim_input``); default
        ``trim_input``.
    z_init : array_like, shape (4,), optional
        The integrators' state at the start and after ``reset`` [m s, rad s] (default zero;
        ``runs.start.start_point`` gives the one that holds the trim in a steady wind).
    """

    def __init__(
        self,
        gain,
        trim_state,
        trim_output,
        trim_input,
        ctrl,
        constants,
        *,
        free_trim_input=None,
        z_init=None,
    ) -> None:
        # own writable C copies: ``paper_control`` then has one compiled signature whatever
        # the caller hands in (a read-only gain of a frozen scenario would compile a second)
        self.gain = np.array(gain, dtype=float, order="C")
        # the law's one check: where its arrays enter (the set-up pairs them, unchecked, for
        # the compiled loop, which builds no controller)
        check_law(np.asarray(ctrl, dtype=float), self.gain)
        # q4..u6, and LN for the tethered LQI's (9, 17) gain (``layout.LAW_GAIN``)
        self.x_ref = np.array(trim_state[: self.gain.shape[1] - 4], dtype=float, order="C")
        self.y_ref = np.array(trim_output, dtype=float, order="C")
        self.u0 = np.array(trim_input, dtype=float, order="C")
        free = trim_input if free_trim_input is None else free_trim_input
        self.u0_free = np.array(free, dtype=float, order="C")
        self._settings = np.array(ctrl, dtype=float)
        self.c = np.array(constants, dtype=float, order="C")
        self._z_init = np.zeros(4) if z_init is None else np.array(z_init, dtype=float)
        self.reset()

    def reset(self) -> None:
        """Restore the settings, the integrators (to ``z_init``) and the winch state."""
        self.ctrl = self._settings.copy()
        self._z = self._z_init.copy()
        self._winch = np.zeros(WINCH_SIZE)

    def step(self, t: float, measurement: Measurement) -> Command:
        """Eqs 50-56 at one sample (``paper_control``).

        Parameters
        ----------
        t : float
            Sample time [s] (the law is time-invariant; unused).
        measurement : Measurement
            The measured state, tension and attachment.

        Returns
        -------
        Command
            Rotor inputs, reel rate R_C [m/s] and the feed-forward part.
        """
        if not measurement.attached:  # released: no winch, no feed-forward (Sec. IV-C)
            self.ctrl[CTRL_WINCH] = 0.0
            self.ctrl[CTRL_FFWD] = 0.0
        u0 = self.u0 if measurement.attached else self.u0_free
        y = np.empty(4)
        inp = np.empty(4)
        ffwd = np.empty(4)
        rate = paper_control(
            measurement.state,
            measurement.tension,
            (self._z, self._winch),
            self.ctrl,
            self.c,
            (self.gain, self.x_ref, self.y_ref, u0),
            (y, inp, ffwd),
        )
        return Command(inputs=inp, reel_rate=float(rate), feedforward=ffwd)
