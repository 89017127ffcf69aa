"""Closed-loop simulation of a scenario: ``simulate(scenario) -> SimulationResult``.

The controller is sampled every ``dt`` with zero-order hold; between samples the plant is
integrated by fixed-step RK4 with ``substeps`` steps (method "rk4", the default, run entirely
by the compiled engine for the paper's controller) or by SciPy's DOP853 with tight tolerances,
restarted at every sample and at every wind discontinuity (method "adaptive", the accuracy
reference). Both configurations use the tethered-coordinate plant; the free configuration
removes the tether (TC = 0, no winch, no feed-forward), as in Sec. VI.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from typing import Literal

import numpy as np

from .._version import __version__
from ..base.compiled import CompiledBase, base_state
from ..base.ship import ShipBase
from ..control.base import Controller, Measurement
from ..control.deck import DeckFeedforward
from ..control.registry import controller_entry
from ..engine import loop as engine
from ..engine import stepping
from ..errors import ParameterError
from ..layout import (
    CFG_ATTACHED,
    CFG_N_SUB,
    SUMMARY_FIELDS,
    SUMMARY_RELEASE_TENSION,
    SUMMARY_RELEASE_TIME,
    SUMMARY_WINCH_LIMIT,
    SUMMARY_WINCH_LIMIT_TIME,
    WIND_CONSTANT,
    X_U1,
    Signals,
    WindPack,
    no_gear,
)
from ..model import TrimPoint
from ..model.kernels import angle_trig, angle_trig_from
from ..params import Params
from ..resources import check_memory
from ..results.files import (
    BASE_POSITION_COLUMNS,
    BASE_VELOCITY_COLUMNS,
    DECK_ATTITUDE_COLUMNS,
    DECK_RATE_COLUMNS,
)
from ..results.result import DRUM_COLUMNS, TENSION_GROUND_COLUMN, SimulationResult, winch_limit_info
from ..scenario.core import Scenario
from ..sensing.config import N_CHANNELS, N_GROUPS
from ..status import FALLBACK_COLUMN, Status, finite_status, solver_status
from .flight import reference_controller
from .landing import Touchdown, gear_columns, ground_hold_controller, landing_controller
from .mpc_setup import mpc_controller
from .setup import engine_setup, python_controlled

__all__ = ["check_run_memory", "simulate"]

Method = Literal["rk4", "adaptive"]


#: Peak memory of a recorded run over its recorded arrays: the result, the metrics'
#: temporaries and the figures' copies of the plotted lines (measured about 2.2; margin kept).
_RECORDED_PEAK_FACTOR = 3
#: the adaptive reference flies no landing gear (the scenario's checks refuse it)
_NO_GEAR = no_gear()


def check_run_memory(
    scenario: Scenario,
    *,
    record: bool = True,
    concurrent: int = 1,
    per_run_bytes: float = 0,
    what: str | None = None,
    hint: str = "shorten the duration or lengthen control.dt",
) -> int:
    """Estimate the bytes one run of ``scenario`` allocates (recorded signals when ``record``,
    sensor-noise table, ``concurrent`` runs at once) and refuse it (``ResourceLimitError``,
    before anything is allocated) above the memory budget (``tetherheli.resources``).

    Parameters
    ----------
    scenario : Scenario
        The run (its ``n_samples`` and sensors set the size).
    record : bool
        Whether the run records its signals at every sample.
    concurrent : int
        Number of such runs held in memory at once, >= 1.
    per_run_bytes : float, optional
        What each run holds besides its per-sample arrays (an environment copy's state).
    what : str, optional
        The job as the message names it (default: the run, its duration and dt).
    hint : str, optional
        How to make the job smaller, for the message.

    Returns
    -------
    int
        The estimated bytes, all ``concurrent`` runs together.

    Raises
    ------
    ResourceLimitError
        The estimate exceeds the memory budget.
    """
    rows = scenario.n_samples + 1
    # the noise table, and for timed sensors the schedule (sensors.sample_schedule) and ring
    per_run = 0 if scenario.sensors.is_perfect else rows * N_CHANNELS * 8
    if scenario.sensors.is_timed and not scenario.sensors.is_perfect:
        per_run += rows * (N_GROUPS + N_CHANNELS) * 8
    if record:
        floats = Signals.floats_per_row(
            drum=scenario.winch.model == "drum", nodes=_recorded_nodes(scenario)
        )  # what the recorder allocates (``_Recorder``)
        per_run += rows * floats * 8 * _RECORDED_PEAK_FACTOR
    needed = (per_run + per_run_bytes) * concurrent
    at_once = f", {concurrent} runs at once" if concurrent > 1 else ""
    if what is None:
        what = (
            f"run {scenario.name}: duration = {scenario.duration:g} s at dt = "
            f"{scenario.control.dt:g} s ({rows} samples{at_once})"
        )
    check_memory(what, needed, hint=hint)
    return int(needed)


def simulate(
    scenario: Scenario,
    *,
    method: Method = "rk4",
    controller: Controller | None = None,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    design_params: Params | None = None,
) -> SimulationResult:
    """Simulate a scenario in closed loop.

    Parameters
    ----------
    scenario : Scenario
        The run (see ``load_scenario``).
    method : {"rk4", "adaptive"}, optional
        ``"rk4"`` (fixed step, compiled; default) or ``"adaptive"`` (DOP853 reference).
    controller : Controller, optional
        A custom ``tetherheli.control.base.Controller``; None uses the paper's (LQI,
        feed-forward and PI winch).
    rtol, atol : float, optional
        Tolerances of the adaptive method.
    design_params : Params, optional
        Parameters the controller is designed on (default: the scenario's own), as
        ``run_batch``'s: the plant and its trim keep the scenario's (a robustness run).

    Returns
    -------
    SimulationResult
        A run that diverges, becomes non-finite, hits the ground or exceeds the maximum
        tension stops early with ``status`` != 0 and ``message`` saying why.
    """
    if not isinstance(scenario, Scenario):
        raise TypeError(f"scenario must be a tetherheli Scenario, not {type(scenario).__name__}")
    if method not in ("rk4", "adaptive"):
        raise ParameterError("method", method, "'rk4' or 'adaptive'")
    check_run_memory(scenario)
    return _simulate(
        scenario, method=method, controller=controller, rtol=rtol, atol=atol,
        design_params=design_params,
    )  # fmt: skip


def _simulate(
    scenario: Scenario,
    *,
    method: Method = "rk4",
    controller: Controller | None = None,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    design_params: Params | None = None,
) -> SimulationResult:
    """``simulate`` of arguments already checked, its memory included (``check_run_memory``,
    recorded): a command that checked every run before the first (``tetherheli simulate``),
    a batch's run of a Python controller (``run_batch``)."""
    setup = engine_setup(scenario, design_params)
    trim, wind, noise = setup.trim, setup.wind, setup.noise
    n = scenario.n_samples
    landing = scenario.maneuver.landing
    paper = controller is None and not python_controlled(scenario)  # the compiled law
    compiled = paper and method == "rk4" and wind is not None  # the loop without Python
    if controller is None and not compiled:  # a scenario's controller in Python
        if landing:
            controller = landing_controller(scenario, setup)
        elif scenario.trajectory.moving:  # a [reference] beyond hover (``runs.flight``)
            controller = reference_controller(scenario, setup)
        elif scenario.reference == "ground" and not scenario.base_motion.fixed:
            controller = ground_hold_controller(scenario, setup)
        elif controller_entry(scenario.control.controller).compiled:  # its Python copy
            controller = setup.paper_controller()
        else:
            controller = mpc_controller(scenario, setup, design_params)
    if scenario.control.base_feedforward:  # (over a moving base: validated)
        assert controller is not None  # (python_controlled: never the compiled loop)
        motion = scenario.base_motion
        controller = DeckFeedforward(
            controller, lambda t: motion.state(t)[0, 2], scenario.params.helicopter.m
        )
    touchdown = Touchdown(scenario, setup.gear, trim.u) if landing else None
    lumped = scenario.tether.lumped
    if wind is None and setup.base.moving:
        raise ParameterError(
            "wind", type(scenario.wind).__name__, "a built-in wind over a moving base ([base]; "
            "a Python disturbance would see the velocity relative to the base)"
        )  # fmt: skip
    if scenario.landing_gear is not None and not (method == "rk4" and wind is not None):
        raise ParameterError(
            "method", method, "'rk4' with built-in winds for a run with [landing_gear] (the "
            "adaptive reference and a Python disturbance fly no gear)"
        )  # fmt: skip
    if lumped and not (method == "rk4" and wind is not None):
        raise ParameterError(
            "method", method, "'rk4' with built-in winds for a lumped tether ([tether] "
            "model = 'lumped'; the adaptive reference covers the massless tether)"
        )  # fmt: skip
    rec = _Recorder(
        n, drum=scenario.winch.model == "drum", lumped=lumped, nodes=_recorded_nodes(scenario)
    )
    if controller is None:  # the compiled law
        status, done = engine.run_closed_loop(
            *setup.engine_args(n), True, rec.signals, rec.summary, gear=setup.gear
        )
        columns: dict[str, np.ndarray] = {}
    else:  # the same sample step, the controller's slot in Python
        run = setup.step_run(rec.signals, rec.summary)
        status, done, record = _python_loop(
            scenario, setup, run, controller, method, touchdown, rtol=rtol, atol=atol
        )
        columns = controller.recorded()  # e.g. the MPC's fallbacks
    columns = {**columns, **gear_columns(setup.gear, rec.signals.x[:done], rec.signals.y[:done])}
    # a run whose solver failed too often is degraded or failed (status.solver_status)
    status = solver_status(status, columns.get(FALLBACK_COLUMN, ())[:done])
    result = rec.result(
        done, status, scenario, trim, method, sensed=noise.shape[0] > 0, columns=columns,
        base=setup.base,
    )  # fmt: skip
    if landing:
        result = dataclasses.replace(result, touchdown=record)
    return result


def _recorded_nodes(scenario: Scenario) -> int:
    """The lumped chain's nodes a run records (N + 1 with ``tether.record_nodes``, else 0)."""
    t = scenario.tether
    return t.segments + 1 if t.lumped and t.record_nodes else 0


class _Recorder:
    """A run's recorded signals (``layout.Signals``) and summary (its metrics, release and
    payout limit), made a result."""

    def __init__(self, n: int, *, drum: bool = False, lumped: bool = False, nodes: int = 0) -> None:
        self.signals = Signals.zeros(n + 1, drum=drum, nodes=nodes)
        self.summary = np.zeros(len(SUMMARY_FIELDS))
        self.lumped = lumped

    def result(
        self,
        done: int,
        status: int,
        scenario: Scenario,
        trim: TrimPoint,
        method: str,
        *,
        sensed: bool = False,
        columns: dict[str, np.ndarray] | None = None,
        base: CompiledBase | None = None,
    ) -> SimulationResult:
        k = done
        sig = self.signals
        extra = {name: v[:k].copy() for name, v in (columns or {}).items()}
        if sensed:  # the controller's position estimate next to the truth
            for i, name in enumerate(("q1_est", "q2_est", "q3_est")):
                extra[name] = sig.y_est[:k, i].copy()
        if self.lumped:  # the load cell's tension at the winch; the nodes on request
            extra[TENSION_GROUND_COLUMN] = sig.tension_ground[:k].copy()
            for i in range(sig.nodes.shape[1]):
                for a in range(3):
                    extra[f"node{i}_n{a + 1}"] = sig.nodes[:k, i, a].copy()
        if scenario.winch.model == "drum":  # the drum's signals (``result.EXTRA_UNITS``)
            for i, name in enumerate(DRUM_COLUMNS):
                extra[name] = sig.winch[:k, i].copy()
        if base is not None and base.moving:  # the base's motion at the samples, from the
            motion = base_state(base, np.arange(k) * scenario.control.dt)  # engine's form
            for i in range(3):
                extra[BASE_POSITION_COLUMNS[i]] = motion[:, 0, i].copy()
                extra[BASE_VELOCITY_COLUMNS[i]] = motion[:, 1, i].copy()
            if isinstance(scenario.base_motion, ShipBase):  # the deck's attitude, from the
                deck = scenario.base_motion.attitude(np.arange(k) * scenario.control.dt)
                for i in range(3):  # same components as the pad's motion
                    extra[DECK_ATTITUDE_COLUMNS[i]] = deck[:, 0, i]
                    extra[DECK_RATE_COLUMNS[i]] = deck[:, 1, i]
        # a run whose recorded values overflowed is never completed (status.finite_status):
        # the engine's series (a controller's own columns may hold NaN for "no value")
        engine_columns = [v for name, v in extra.items() if name not in (columns or {})]
        status = finite_status(
            status, sig.x[:k], sig.y[:k], sig.u[:k], sig.tension[:k], sig.rate[:k],
            sig.wind[:k], *engine_columns,
        )  # fmt: skip
        # views, not copies: the recorder is dropped here, so a long run is held once
        return SimulationResult(
            time=np.arange(k) * scenario.control.dt,
            states=sig.x[:k],
            outputs=sig.y[:k],
            inputs=sig.u[:k],
            feedforward=sig.ffwd[:k],
            tension=sig.tension[:k],
            reel_rate=sig.rate[:k],
            wind=sig.wind[:k],
            trim_state=trim.x.copy(),
            trim_input=trim.u.copy(),
            trim_output=trim.y.copy(),
            status=int(status),
            configuration=scenario.to_dict(),
            version=__version__,
            method=method,
            extra=extra,
            release_time=_release(self.summary[SUMMARY_RELEASE_TIME]),
            release_tension=_release(self.summary[SUMMARY_RELEASE_TENSION]),
            winch_limit=winch_limit_info(
                self.summary[SUMMARY_WINCH_LIMIT_TIME],
                self.summary[SUMMARY_WINCH_LIMIT],
                scenario.winch,
            ),
        )


def _release(value: float) -> float | None:
    # a summary's release slot: NaN without a release
    return None if math.isnan(value) else float(value)


def _type_key(value):
    # what Numba's type of ``value`` depends on, cheaply: arrays by dtype, rank, layout,
    # writeability and alignment, tuples element by element (a ``StepRun`` always gives the
    # same key)
    if isinstance(value, np.ndarray):
        flags = value.flags
        layout = "C" if flags.c_contiguous else "F" if flags.f_contiguous else "A"
        return (value.dtype.str, value.ndim, layout, flags.writeable, flags.aligned)
    if isinstance(value, tuple):
        return (type(value), *(_type_key(v) for v in value))
    return type(value)


#: compiled entry points by dispatcher and argument types (``_entry_point``)
_ENTRY_POINTS: dict = {}


def _entry_point(dispatcher, *args):
    """The compiled function of ``dispatcher`` for the types of ``args`` (compiled or loaded
    from the cache first; kept for the process). Calling it skips Numba's type dispatch of
    every call, which for a ``StepRun`` costs more than the sample's arithmetic; the caller
    then passes arguments of exactly these types (C-contiguous float64 commands, an int
    sample index)."""
    key = (dispatcher, _type_key(args))
    entry = _ENTRY_POINTS.get(key)
    if entry is None:
        types_ = tuple(dispatcher.typeof_pyval(a) for a in args)
        dispatcher.compile(types_)
        entry = _ENTRY_POINTS[key] = dispatcher.overloads[types_].entry_point
    return entry


def _command_array(value, name: str) -> np.ndarray:
    out = np.ascontiguousarray(value, dtype=np.float64)
    if out.shape != (4,):
        raise ValueError(f"controller command {name} has shape {out.shape}; allowed: (4,)")
    return out


def _python_loop(scenario, setup, run, controller, method, touchdown=None, *, rtol, atol):
    """The closed loop driven from Python: any Controller, RK4 or the adaptive reference;
    returns (status, samples done, the touchdown record or None).

    With ``touchdown`` (a landing's ``runs.landing.Touchdown``) each recorded sample is
    watched for the touchdown, which ends the run with its status (LANDED or
    HARD_TOUCHDOWN); a landing that reaches the run's end without one is NOT_LANDED.

    Each sample is the engine's one sample step (``stepping.step_sense``, the controller,
    ``stepping.step_command``: actuators, checks, metrics, recording and the RK4 or lumped
    step), as the compiled loop runs it; only the integrator may be swapped (the adaptive
    reference, or RK4 over a Python disturbance)."""
    dt = scenario.control.dt
    n = scenario.n_samples
    c = setup.model.constants
    x, cfg = run.x, run.cfg
    x_meas, applied = run.loop.x_meas, run.loop.inputs
    disturbance = scenario.wind if setup.wind is None else None  # a Python disturbance
    compiled_step = method == "rk4" and disturbance is None  # step_command integrates
    out_wind = run.out.wind
    base = run.wind[3]
    breaks = setup.wind.breakpoints(n * dt) if setup.wind is not None else np.array([])
    four = np.zeros(4)
    sense = _entry_point(stepping.step_sense, run, 0)
    command = _entry_point(stepping.step_command, run, 0, four, 0.0, four, 0.0, 0.0, True)
    controller.reset()
    status, done, record = Status.OK, n + 1, None
    for k in range(n + 1):
        t = k * dt
        tension, measured = sense(run, k)
        attached = cfg[CFG_ATTACHED] > 0.5
        cmd = controller.step(t, Measurement(state=x_meas.copy(), tension=measured,
                                             attached=attached))  # fmt: skip
        inp = _command_array(cmd.inputs, "inputs")
        if touchdown is not None:  # after a touchdown that settles: the thrust cut
            inp = touchdown.inputs(inp)
        ffwd = _command_array(cmd.feedforward, "feedforward")
        advance = compiled_step and k < n
        status, rate = command(run, k, inp, float(cmd.reel_rate), ffwd, tension, measured,
                               advance)  # fmt: skip
        if status != Status.OK:
            done = k
            break
        if touchdown is not None:
            ended = touchdown.step(k, run.out.x[k], run.out.y[k])
            record = touchdown.record
            if ended is not None:
                status, done = ended, k + 1
                break
        if disturbance is not None:  # the engine's empty wind program recorded zero
            out_wind[k] = np.asarray(disturbance.force_at(t, x[6:9]), dtype=float)
        if k == n:
            break
        if method == "adaptive":
            x_next = _adaptive_interval(
                x, applied, rate, t, dt, breaks, cfg, c, scenario.wind, setup.wind, base,
                rtol=rtol, atol=atol,
            )  # fmt: skip
            if x_next is None:
                status, done = Status.NONFINITE, k + 1
                break
            x[:] = x_next
        elif not advance:
            _rk4_custom_wind(x, applied, rate, t, dt, int(cfg[CFG_N_SUB]), cfg, c, disturbance,
                             base)  # fmt: skip
    stepping.step_finish(run)
    if touchdown is not None and record is None and status == Status.OK:
        status = Status.NOT_LANDED
    elif touchdown is not None and status == Status.OK and done > 0:  # settling cut short
        ended = touchdown.finish(run.out.x[done - 1], run.out.y[done - 1])
        status = status if ended is None else ended
    return status, done, record


def _adaptive_interval(
    x, inp, rate, t, dt, breaks, cfg, c, disturbance, wind, base, *, rtol, atol
):  # fmt: skip
    """The adaptive reference integrator over one sample [t, t + dt]: DOP853 restarted at
    every wind discontinuity inside it; the new state, or None if the solver failed."""
    from scipy.integrate import solve_ivp  # only the adaptive mode needs it

    inside = breaks[(breaks > t) & (breaks < t + dt)]
    edges = [t, *inside.tolist(), t + dt]
    for a, b in itertools.pairwise(edges):
        mid = 0.5 * (a + b)

        def rhs(tt, xx, mid=mid):
            out = np.empty(13)
            sc = np.empty(10)
            angle_trig(xx, sc)  # libm at every evaluation: the accurate reference
            side = 1 if tt < mid else -1
            _plant(xx, sc, inp, rate, tt, side, cfg, c, disturbance, wind, base, out)
            return out

        sol = solve_ivp(rhs, (a, b), x, method="DOP853", rtol=rtol, atol=atol)
        if not sol.success:
            return None
        x = sol.y[:, -1].copy()
    return x


def _plant(x, sc, inp, rate, t, side, cfg, c, disturbance, wind, base, out):
    if wind is not None:
        engine.plant_derivative(
            x, sc, inp, rate, t, side, cfg, (c, _NO_GEAR),
            WindPack(wind.program, wind.gust, wind.drag, base), out,
        )  # fmt: skip
        return
    # custom disturbance: evaluate in Python, then the compiled plant with a constant force;
    # at a step's end the left limit (the float just below t), as the engine does for its
    # built-in profiles, so a jump placed on a step boundary acts from that boundary on
    t_eval = t if side > 0 else math.nextafter(t, -math.inf)
    force = np.asarray(disturbance.force_at(t_eval, x[X_U1 : X_U1 + 3]), dtype=float)
    program = np.array([[WIND_CONSTANT, 0, 0, 1.0, 0, 0, *force]])
    engine.plant_derivative(
        x, sc, inp, rate, t, side, cfg, (c, _NO_GEAR),
        WindPack(program, np.zeros((0, 3)), np.zeros(3), base), out,
    )  # fmt: skip


def _rk4_custom_wind(x, inp, rate, t0, dt, n_sub, cfg, c, disturbance, base):
    """``engine.rk4_interval`` with a Python disturbance (same stages, same trigonometry)."""
    h = dt / n_sub
    k1, k2, k3, k4 = (np.empty(13) for _ in range(4))
    sc0, sc = np.empty(10), np.empty(10)
    angle_trig(x, sc0)
    for j in range(n_sub):
        ta = t0 + j * h
        _plant(x, sc0, inp, rate, ta, 1, cfg, c, disturbance, None, base, k1)
        for k_prev, k_next, a, t in ((k1, k2, 0.5, 0.5), (k2, k3, 0.5, 0.5), (k3, k4, 1.0, 1.0)):
            stage = x + a * h * k_prev
            angle_trig_from(stage, x, sc0, sc)
            side = -1 if k_next is k4 else 1
            _plant(stage, sc, inp, rate, ta + t * h, side, cfg, c, disturbance, None, base, k_next)
        start = x.copy()
        x += h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
        if j + 1 < n_sub:
            engine.next_step_trig(x, start, sc0, sc, j + 1)
