"""The engine's control sample driven from Python, around any ``Controller``.

``simulate``'s Python path (the MPC, a user's ``Controller``, the adaptive reference)
holds a ``StepRun`` (``runs.setup.EngineSetup.step_run``) and calls, per sample,
``step_sense``, then the controller, then ``step_command`` (which advances the plant, or
leaves that to the caller's own integrator), then at the end ``step_finish``: the compiled
phases of ``engine.loop`` (``sample_sense``, ``sample_apply``, ``sample_record``,
``sample_advance``), compiled once, with the controller's slot in Python.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .._compile import compiled
from ..layout import (
    ACT_DRUM,
    CFG_ATTACHED,
    CHAIN_NODES,
    Gear,
    LoopState,
    Run,
    Scratch,
    Signals,
    WindPack,
)
from ..model.kernels import angle_trig
from .loop import (
    STATUS_NONFINITE,
    STATUS_OK,
    finish_summary,
    sample_advance,
    sample_apply,
    sample_outputs,
    sample_record,
    sample_sense,
    vehicle_outputs,
)

__all__ = ["StepRun", "step_command", "step_finish", "step_sense"]

_jit = compiled(error_model="numpy")
_jit_inline = compiled(error_model="numpy", inline="always")


class StepRun(NamedTuple):
    """One run's arrays for the sample step driven from Python (``step_sense``,
    ``step_command``, ``step_finish``), built by
    ``runs.setup.EngineSetup.step_run``; a named record, so each step function has one
    compiled signature and reads its fields by name.

    Parameters
    ----------
    x : numpy.ndarray, shape (13,)
        The true state [q4..q9, u1..u6, LN] in [rad, m, rad/s, m/s, m], advanced in place.
    cfg : numpy.ndarray, shape (CFG_SIZE,)
        The run's settings (``layout.CFG_*``), a run's own copy (the release switches it).
    ctrl : numpy.ndarray, shape (CTRL_SIZE,)
        The paper controller's settings (``layout.CTRL_*``), a run's own copy.
    c : numpy.ndarray
        The tethered model's constants (``kernels.model_constants("tethered", h)``).
    law : tuple of numpy.ndarray
        The controller's arrays (``layout.LAW_*``; x_ref and y_ref are the metrics' references).
    wind : WindPack
        The wind (``layout.WindPack``); an empty program for a Python disturbance.
    act : numpy.ndarray, shape (ACT_SIZE,)
        The actuators (``layout.ACT_*``).
    sensors : tuple
        ``runs.packing.sensor_tuple``'s.
    chain : tuple of numpy.ndarray
        The lumped chain (``layout.CHAIN_*``; ``layout.empty_chain()``: massless).
    gear : Gear
        The landing gear (``layout.Gear``; ``layout.no_gear()``: none).
    cw : tuple
        The chain's scratch (``lumped_work``).
    work : numpy.ndarray, shape (RK4_WORK_ROWS, 13)
        The integrator's scratch.
    loop : LoopState
        The control phases' state (``engine.new_loop_state``).
    summary : numpy.ndarray, shape (len(SUMMARY_FIELDS),)
        The on-line metrics (``layout.SUMMARY_*``, ``start_summary``).
    out : Signals
        The recorded signals (``layout.Signals``).
    """

    x: np.ndarray  #: (13,) the true state, advanced in place
    cfg: np.ndarray  #: ``layout.CFG_*``, a run's own copy (the release switches it)
    ctrl: np.ndarray  #: ``layout.CTRL_*``, a run's own copy
    c: np.ndarray  #: the model constants
    law: tuple  #: ``layout.LAW_*`` (x_ref and y_ref are the metrics' references)
    wind: WindPack  #: an empty program for a Python disturbance
    act: np.ndarray  #: ``layout.ACT_*``
    sensors: tuple  #: ``runs.packing.sensor_tuple``
    chain: tuple  #: ``layout.CHAIN_*`` (``layout.empty_chain()``: massless)
    gear: Gear  #: ``layout.Gear`` (``layout.no_gear()``: none)
    cw: tuple  #: the chain's scratch (``lumped_work``)
    work: np.ndarray  #: (RK4_WORK_ROWS, 13) the integrator's scratch
    loop: LoopState  #: the control phases' state (``new_loop_state``)
    summary: np.ndarray  #: (len(SUMMARY_FIELDS),) the on-line metrics (``start_summary``)
    out: Signals  #: the recorded signals


@_jit_inline
def _records(run):
    # a ``StepRun``'s run record (``layout.Run``) and scratch (``layout.Scratch``)
    record = Run(run.cfg, run.ctrl, run.c, run.act, run.law, run.wind, run.sensors, run.chain,
                 run.gear)  # fmt: skip
    return record, Scratch(run.work, run.cw, run.work[5, :4])


@_jit
def step_sense(run, k):
    """``sample_sense`` of sample k of a ``StepRun``: the measured state lands in
    ``run.loop.x_meas``; returns (true tension at P, measured tension) [N].

    Parameters
    ----------
    run : StepRun
        The run's arrays.
    k : int
        The control sample's index.

    Returns
    -------
    tuple of float
        (the true tension at P, the measured tension) [N].
    """
    record, scratch = _records(run)
    return sample_sense(record, run.loop, scratch, run.x, k, run.sensors[0].shape[0] > 0,
                        run.chain[CHAIN_NODES].shape[0] > 0)  # fmt: skip


@_jit
def step_command(run, k, command, reel_rate, feedforward, tension, measured, advance):
    """The controller's slot filled from Python, then ``sample_apply`` and ``sample_record``
    (always recording into ``run.out``) of sample k of a ``StepRun``, and with ``advance``
    ``sample_advance`` to sample k + 1 (else the caller integrates: the adaptive reference,
    a Python disturbance). ``command`` (4,) are the rotor inputs, ``reel_rate`` the reel-rate
    command [m/s] (0 once the tether is released), ``feedforward`` (4,) the part of
    ``command`` that is feed-forward (recorded); ``tension``, ``measured`` are
    ``step_sense``'s. A non-finite command is not actuated and fails the sample
    (``Status.NONFINITE``). Returns (status, applied reel rate [m/s]).

    Parameters
    ----------
    run : StepRun
        The run's arrays, updated.
    k : int
        The control sample's index.
    command : numpy.ndarray, shape (4,)
        The rotor inputs [N, N m, N m, N].
    reel_rate : float
        The reel-rate command [m/s].
    feedforward : numpy.ndarray, shape (4,)
        The feed-forward part of ``command`` [N, N m, N m, N].
    tension : float
        The true tension at P [N] (``step_sense``'s).
    measured : float
        The measured tension [N] (``step_sense``'s).
    advance : bool
        Whether to integrate the plant to sample k + 1.

    Returns
    -------
    status : int
        The sample's status code (``Status``).
    rate : float
        The applied reel rate [m/s].
    """
    record, scratch = _records(run)
    loop = run.loop
    x_meas, sc_meas, y_est = loop.x_meas, loop.sc_meas, loop.y_est
    inp, ffwd = loop.inputs, loop.ffwd
    x, cfg = run.x, run.cfg
    sensed = run.sensors[0].shape[0] > 0
    if cfg[CFG_ATTACHED] <= 0.5:
        reel_rate = 0.0
    finite = math.isfinite(reel_rate)
    for i in range(4):
        inp[i] = command[i]
        ffwd[i] = feedforward[i]
        finite = finite and math.isfinite(command[i])
    angle_trig(x_meas, sc_meas)
    vehicle_outputs(x_meas, sc_meas, cfg, run.c, y_est)
    if finite:
        status, rate = sample_apply(record, loop, x, k, reel_rate, tension, measured, sensed,
                                    run.act[ACT_DRUM] > 0.5)  # fmt: skip
    else:
        rate = reel_rate
        status = sample_outputs(record, loop, x, sensed, tension)
        if status == STATUS_OK:
            status = STATUS_NONFINITE
    if status == STATUS_OK:
        sample_record(record, loop, run.summary, run.out, x, k, tension, rate, True,
                      run.work[5])  # fmt: skip
        if advance:
            sample_advance(record, scratch, x, inp, rate, k, run.chain[CHAIN_NODES].shape[0] > 0)
    return status, rate


@_jit
def step_finish(run):
    """``finish_summary`` of a ``StepRun``: the release event and the first payout limit.

    Parameters
    ----------
    run : StepRun
        The run's arrays; its summary is completed.
    """
    finish_summary(run.summary, run.loop.event, run.loop.held)
