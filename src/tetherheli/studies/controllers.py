"""Flying one scenario under several controllers and measuring what each achieves and costs.

The measures (``controller_metrics``) are: peak and RMS of the
position deviations q1-q3 [m], the peak attitude deviation (q4, q5) [deg], RMS and peak of
each rotor input minus its trim total input (the control effort), the peak cyclic torque
against its limit (eq 40), the tension range [N], the run's status and the compute time per
control sample. ``eq40_saturated`` applies the paper's eq-40 cyclic limit (20% of the free
hover lift times the tether arm, ``sweep.paper_cyclic_limit``) as saturation of tMR1, tMR2.
"""

from __future__ import annotations

import dataclasses
import math
import time
from typing import Any

import numpy as np

from ..control.registry import controller_entry
from ..errors import ParameterError
from ..names import INPUT
from ..scenario.core import CONTROLLERS, Scenario
from .sweep import paper_cyclic_limit, scenario_cyclic_limit

__all__ = [
    "CONTROLLER_METRICS",
    "check_design",
    "controller_metrics",
    "eq40_saturated",
    "fly",
    "with_controller",
]

#: the columns ``controller_metrics`` returns, in table order
CONTROLLER_METRICS: tuple[str, ...] = (
    "peak_q1", "peak_q2", "peak_q3", "rms_q1", "rms_q2", "rms_q3", "peak_attitude_deg",
    *(f"rms_d{n}" for n in INPUT), *(f"peak_d{n}" for n in INPUT),
    "peak_cyclic", "cyclic_limit", "tension_min", "tension_max", "completed",
    "compute_us_per_sample",
)  # fmt: skip


def check_design(scenario: Scenario) -> None:
    """Design ``scenario``'s controller on its own (nominal) parameters and raise the
    ``WeightsError`` of weights that have no stabilising design: a study whose every run is
    designed on the nominal plant refuses them at set-up (naming the file) instead of
    recording every run as failed. A plant that cannot hover is left to the runs, where it is
    a failure of that run (a dispersed draw may hover where the nominal one cannot).

    Parameters
    ----------
    scenario : Scenario
        The nominal run, with its controller.

    Raises
    ------
    WeightsError
        The controller's weights have no stabilising design.
    """
    from ..errors import WeightsError
    from ..runs.mpc_setup import mpc_controller
    from ..runs.setup import engine_setup

    try:
        setup = engine_setup(scenario)
        if not controller_entry(scenario.control.controller).compiled:
            mpc_controller(scenario, setup)
    except WeightsError:
        raise
    except ParameterError:  # infeasible nominal plant: each run says so
        return


def eq40_saturated(scenario: Scenario) -> Scenario:
    """``scenario`` with tMR1, tMR2 saturated at +-eq 40's limit (``paper_cyclic_limit``);
    fMR3 and fTR2 keep their limits.

    Parameters
    ----------
    scenario : Scenario
        The scenario to limit.

    Returns
    -------
    Scenario
        A copy with ``actuators.u_min``, ``u_max`` of tMR1, tMR2 at -+ eq 40's limit [N m].
    """
    lim = paper_cyclic_limit(scenario.params)
    a = scenario.actuators
    act = dataclasses.replace(
        a,
        u_min=(a.u_min[0], -lim, -lim, a.u_min[3]),
        u_max=(a.u_max[0], lim, lim, a.u_max[3]),
    )
    return scenario.replace(actuators=act)


def with_controller(scenario: Scenario, controller: str, **tether_lqi: Any) -> Scenario:
    """``scenario`` flown by ``controller`` (``CONTROLLERS``), with ``[control.tether_lqi]``
    fields replaced by ``tether_lqi``.

    Parameters
    ----------
    scenario : Scenario
        The scenario to fly.
    controller : str
        One of ``CONTROLLERS`` (e.g. "paper", "tether_lqi").
    **tether_lqi
        Fields of ``[control.tether_lqi]`` (``TetherLQISettings``) to replace.

    Returns
    -------
    Scenario
        A copy with ``control.controller`` and ``control.tether_lqi`` replaced.
    """
    if controller not in CONTROLLERS:
        raise ParameterError("controller", controller, f"one of {CONTROLLERS}")
    c = scenario.control
    weights = dataclasses.replace(c.tether_lqi, **tether_lqi)
    return scenario.replace(
        control=dataclasses.replace(c, controller=controller, tether_lqi=weights)
    )


def controller_metrics(result, u_trim: np.ndarray, cyclic_limit: float | None) -> dict[str, Any]:
    """The comparison's measures of a recorded run (``CONTROLLER_METRICS`` but the compute
    time) over the samples from the scenario's ``metrics_start`` on, as every other metric
    (``analysis.run_metrics``). ``u_trim`` (4,) is the trim's total rotor input;
    ``cyclic_limit`` [N m] or None.

    Parameters
    ----------
    result : SimulationResult
        The recorded run.
    u_trim : ndarray, shape (4,)
        The trim's total rotor input [N, N m, N m, N].
    cyclic_limit : float or None
        The scenario's cyclic limit [N m], recorded (NaN when None).

    Returns
    -------
    dict of str to object
        Peak and RMS deviations of q1..q3 [m], the peak attitude [deg], RMS and peak input
        deviations [N, N m, N m, N], the peak cyclic [N m], its limit, the tension range
        [N] and ``completed``.
    """
    from ..analysis import metric_samples, metric_window, run_metrics

    if metric_samples(result) == 0:  # failed before metrics_start: nothing to measure
        out: dict[str, Any] = dict.fromkeys(CONTROLLER_METRICS[:-2], math.nan)
        out["cyclic_limit"] = math.nan if cyclic_limit is None else float(cyclic_limit)
        out["completed"] = bool(result.ok)
        return out

    # one source for the position, attitude and tension metrics and their window
    # (``metrics_start``): analysis.run_metrics, as ``simulate``'s summaries use
    m = run_metrics(result)
    window = metric_window(result)
    du = result.inputs[window] - np.asarray(u_trim)
    out = {}
    for a in range(3):
        out[f"peak_q{a + 1}"] = m.peak_abs_dev[f"q{a + 1}"]
        out[f"rms_q{a + 1}"] = m.rms_dev[f"q{a + 1}"]
    out["peak_attitude_deg"] = max(m.peak_abs_dev["q4_deg"], m.peak_abs_dev["q5_deg"])
    for i, n in enumerate(INPUT):
        out[f"rms_d{n}"] = float(np.sqrt(np.mean(du[:, i] ** 2)))
    for i, n in enumerate(INPUT):
        out[f"peak_d{n}"] = float(np.max(np.abs(du[:, i])))
    out["peak_cyclic"] = float(np.max(np.abs(result.inputs[window, 1:3])))
    out["cyclic_limit"] = math.nan if cyclic_limit is None else float(cyclic_limit)
    out["tension_min"] = m.tension_min
    out["tension_max"] = m.tension_max
    out["completed"] = bool(result.ok)
    return out


def fly(scenario: Scenario, design_params: Any = None) -> tuple[Any, dict[str, Any]]:
    """Simulate ``scenario`` (compiled engine) and measure it (``controller_metrics``, with the
    wall-clock time of ``simulate`` per control sample [us], its set-up and recording
    included: an upper bound of the controller's cost).

    Parameters
    ----------
    scenario : Scenario
        The scenario to simulate.
    design_params : Params, optional
        Parameters the controller is designed on (default: the scenario's own).

    Returns
    -------
    result : SimulationResult
        The run.
    metrics : dict of str to object
        ``controller_metrics`` with ``compute_us_per_sample`` [us].
    """
    from ..runs import simulate
    from ..runs.setup import engine_setup

    setup = engine_setup(scenario, design_params)
    t0 = time.perf_counter()
    result = simulate(scenario, design_params=design_params)
    elapsed = time.perf_counter() - t0
    metrics = controller_metrics(result, setup.trim.u_total, scenario_cyclic_limit(scenario))
    metrics["compute_us_per_sample"] = 1e6 * elapsed / max(1, result.time.size)
    return result, metrics
