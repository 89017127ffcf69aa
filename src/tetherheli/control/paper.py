"""The paper's controller (Sec. V): LQI position control with integral action (eqs 47-53),
the tether-torque feed-forward (eqs 54-55), and the winch's PI tension control (eq 56).

``paper_control`` is the compiled kernel the closed-loop engine calls at every sample;
``PaperController`` wraps it as a ``Controller`` object for the Python simulation loop.
"""

from __future__ import annotations

import numpy as np

from .._compile import compiled
from ..model.kernels import angle_trig, tethered_outputs_sc, tethered_tether_torque_sc
from .base import Command, Controller, Measurement
from .tension import tension_pi_step

__all__ = ["CTRL_SIZE", "PaperController", "paper_control"]

_jit = compiled(error_model="numpy")
_jit_inline = compiled(error_model="numpy", inline="always")
_tension_pi_step = _jit(tension_pi_step)

# controller settings, packed in one array
CTRL_DT = 0  # sample time [s]
CTRL_FFWD = 1  # 1: tether-torque feed-forward on (eq 55)
CTRL_WINCH = 2  # 1: winch PI loop runs (eq 56)
CTRL_T_REF = 3  # [N]
CTRL_K_P = 4
CTRL_K_I = 5
CTRL_REEL_RATE_LIMIT = 6  # [m/s] (inf: none)
CTRL_SIZE = 7


@_jit
def paper_control(
    x, measured_tension, z, winch_integral, ctrl, c, gain, x_ref, y_ref, u0, y, inp, ffwd
):
    """Eqs 50-56 at one sample; fills inp (4,), ffwd (4,), y (4,) and returns the reel rate.

    u = -K [x - x_ref; z] + u0 - C_f-fwd (eq 54), with C_f-fwd from the measured tension and
    the measured angles (eq 55); then z += dt (y_ref - y) (eq 50). The winch rate is
    RC = KP e + KI I with e = T - Tref, then I += dt e (eq 56). ``z`` (4,) and
    ``winch_integral`` (1,) are updated in place; x is the (13,) tethered-coordinate state.
    """
    sc = np.empty(10)
    angle_trig(x, sc)
    return paper_control_sc(
        x, sc, measured_tension, z, winch_integral, ctrl, c, gain, x_ref, y_ref, u0, y, inp, ffwd
    )


@_jit_inline
def paper_control_sc(
    x, sc, measured_tension, z, winch_integral, ctrl, c, gain, x_ref, y_ref, u0, y, inp, ffwd
):
    """``paper_control`` with sc (10,) = sin, cos of x[0..4] given (``kernels.angle_trig``);
    the engine's entry point."""
    tethered_outputs_sc(x, sc, c, y)
    for i in range(4):
        acc = u0[i]
        for j in range(12):
            acc -= gain[i, j] * (x[j] - x_ref[j])
        for j in range(4):
            acc -= gain[i, 12 + j] * z[j]
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
    for j in range(4):
        z[j] += dt * (y_ref[j] - y[j])
    rate = 0.0
    if ctrl[CTRL_WINCH] > 0.5:
        rate, winch_integral[0] = _tension_pi_step(
            winch_integral[0],
            measured_tension,
            ctrl[CTRL_K_P],
            ctrl[CTRL_K_I],
            ctrl[CTRL_T_REF],
            dt,
            ctrl[CTRL_REEL_RATE_LIMIT],
        )
    return rate


class PaperController(Controller):
    """The paper's control scheme (Fig. 5) as a ``Controller``.

    Parameters
    ----------
    gain : (4, 16) LQI gain K_LQI|F designed on the free model (Sec. IV-E)
    trim_state : (13,) the configuration's trim x0 (references for q4..u6)
    trim_output : (4,) y0, the output references
    trim_input : (4,) u0|F or u0|T (Tables IV, V)
    ctrl : (CTRL_SIZE,) settings, see the CTRL_* indices
    constants : the tethered model's constants, ``kernels.model_constants("tethered", h)``
    """

    def __init__(self, gain, trim_state, trim_output, trim_input, ctrl, constants) -> None:
        self.gain = np.ascontiguousarray(gain, dtype=float)
        self.x_ref = np.ascontiguousarray(trim_state[:12], dtype=float)
        self.y_ref = np.ascontiguousarray(trim_output, dtype=float)
        self.u0 = np.ascontiguousarray(trim_input, dtype=float)
        self.ctrl = np.ascontiguousarray(ctrl, dtype=float)
        self.c = np.ascontiguousarray(constants, dtype=float)
        self.reset()

    def reset(self) -> None:
        self._z = np.zeros(4)
        self._winch_integral = np.zeros(1)

    def step(self, t: float, measurement: Measurement) -> Command:
        y = np.empty(4)
        inp = np.empty(4)
        ffwd = np.empty(4)
        rate = paper_control(
            measurement.state,
            measurement.tension,
            self._z,
            self._winch_integral,
            self.ctrl,
            self.c,
            self.gain,
            self.x_ref,
            self.y_ref,
            self.u0,
            y,
            inp,
            ffwd,
        )
        return Command(inputs=inp, reel_rate=float(rate), feedforward=ffwd)
