"""The MPC of a scenario: ``[control.mpc]``, ``[actuators]``, ``[sensors]`` and the run's
set-up (``runs.setup.engine_setup``: trim, model constants, the paper's free law) unpacked
into the explicit arguments of ``control.mpc_design`` (``hover_design``,
``design_mpc_kalman``) and ``control.mpc`` (``MPCController``), which read no scenario."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..control.mpc import MPCController
from ..control.mpc_design import _design_mpc_kalman, _hover_design, mpc_sample_seconds
from ..control.observer import DisturbanceKalman
from ..errors import DesignError, design_failure
from ..resources import warn_slow

if TYPE_CHECKING:
    from ..params import Params
    from ..scenario.core import Scenario
    from .setup import EngineSetup

__all__ = ["mpc_controller", "mpc_kalman", "uses_kalman"]


def mpc_controller(
    scenario: Scenario, setup: EngineSetup, design_params: Params | None = None
) -> MPCController:
    """The MPC of ``scenario``'s ``[control.mpc]`` on the run's set-up.

    The model is designed on ``design_params`` (default the run's own parameters) at the
    hover trim (Table V tethered, Table IV free); the references and the trim input are the
    run's own trim (as for the paper's law); the bounds come from ``[actuators]``; the
    estimator from ``[control.mpc] observer`` (the Kalman filter's measurement noise from
    ``[sensors]``, ``control.observer.measurement_covariance``).

    Parameters
    ----------
    scenario : Scenario
        The run (``control.controller`` = "mpc").
    setup : EngineSetup
        Its set-up (``runs.setup.engine_setup``): trim, model constants, the paper's free
        gain (flown after a release) and u0|F.
    design_params : Params, optional
        The parameters of the design model (a Monte Carlo's nominal ones).

    Returns
    -------
    MPCController
    """
    from ..wind import initial_wind_force

    s = scenario.control.mpc
    a = scenario.actuators
    n = scenario.n_samples
    warn_slow(  # before the design: a long horizon is allowed, and said what it costs
        f"run {scenario.name}: the MPC with control.mpc.horizon = {s.horizon} over {n} samples",
        n * mpc_sample_seconds(s.horizon),
        hint="shorten control.mpc.horizon (default 10) or the duration",
    )
    tethered = scenario.configuration == "tethered"
    tension_ref = scenario.params.tension_control.T_ref if tethered else 0.0
    params = scenario.params if design_params is None else design_params
    T_ref = params.tension_control.T_ref if tethered else 0.0
    try:
        design = _hover_design(  # T_ref, q9 and dt: checked by the scenario
            params, scenario.configuration, T_ref, scenario.q9, scenario.control.dt,
            tuple(s.Qy), tuple(s.Ru), s.q_tension, s.horizon,
        )  # fmt: skip
    except DesignError as exc:
        raise design_failure(
            "control.mpc.Qy/q_tension/Ru",
            f"Qy = {list(s.Qy)}, q_tension = {s.q_tension!r}, Ru = {list(s.Ru)}",
            exc,
        ) from None
    trim = setup.trim
    kalman = mpc_kalman(scenario, setup, design_params)
    return MPCController(
        design,
        x_ref=trim.x,
        y_ref=trim.y,
        u_trim=trim.u_total,
        constants=setup.model.constants,
        dt=scenario.control.dt,
        u_min=np.array(a.u_min),
        u_max=np.array(a.u_max),
        reel_rate_limit=a.reel_rate_limit,
        reel_acceleration_limit=a.reel_acceleration_limit,
        tension_ref=tension_ref,
        tension_bounds=s.bounds_about(tension_ref),
        slack_weight=s.slack_weight,
        disturbance_time_constant=s.disturbance_time_constant,
        max_iterations=s.max_iterations,
        tolerance=s.tolerance,
        free_gain=np.asarray(setup.gain.K) if tethered else None,
        free_trim_input=setup.u0_free,
        d_init=initial_wind_force(scenario.wind),
        kalman=kalman,
    )


def mpc_kalman(
    scenario: Scenario, setup: EngineSetup, design_params: Params | None = None
) -> DisturbanceKalman | None:
    """The MPC's Kalman filter on ``scenario`` (``control.mpc.design_mpc_kalman``), or None
    when ``[control.mpc] observer`` does not select it (``uses_kalman``).

    Parameters
    ----------
    scenario : Scenario
        The run.
    setup : EngineSetup
        Its set-up (``runs.setup.engine_setup``; the trim).
    design_params : Params, optional
        The parameters of the design model (default the run's own).

    Returns
    -------
    DisturbanceKalman or None
        The filter designed on the ``[control.mpc] kalman_*`` noises and the sensors' R.
    """
    if not uses_kalman(scenario):
        return None
    s = scenario.control.mpc
    tethered = scenario.configuration == "tethered"
    tension_ref = scenario.params.tension_control.T_ref if tethered else 0.0
    params = scenario.params if design_params is None else design_params
    T_ref = params.tension_control.T_ref if tethered else 0.0
    return _design_mpc_kalman(  # T_ref, q9 and dt: checked by the scenario
        params, scenario.configuration, T_ref, scenario.q9, scenario.control.dt,
        sensors=scenario.sensors, x_trim=setup.trim.x, tension_ref=tension_ref,
        tether_arm=scenario.params.helicopter.tether_arm,
        load_cell=tethered and scenario.tether.model != "lumped",
        tension_std=s.kalman_tension_std, force_std=s.kalman_force_std,
        force_rate=s.kalman_force_rate, input_std=np.array(s.kalman_input_std),
        coordinate_std=s.kalman_coordinate_std, force_accel=s.kalman_force_accel,
        tether_angle_std=s.kalman_tether_angle_std,
    )  # fmt: skip


def uses_kalman(scenario: Scenario) -> bool:
    """``[control.mpc] observer``: "auto" is the Kalman filter when the sensors are not
    perfect or the tether is the lumped chain (the design model's massless tether misses its
    waves and sag), else the residual estimate.

    Parameters
    ----------
    scenario : Scenario
        The run.

    Returns
    -------
    bool
        True when the MPC estimates with the Kalman filter.
    """
    observer = scenario.control.mpc.observer
    if observer == "auto":
        return not scenario.sensors.is_perfect or scenario.tether.model == "lumped"
    return observer == "kalman"
