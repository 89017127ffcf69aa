"""Scenarios: what to simulate, loaded strictly from TOML (Sec. VI's runs ship in scenarios/).

A scenario file::

    name = "paper_sim1_tethered"
    configuration = "tethered"        # or "free" (the tether removed, Sec. VI)
    duration = 60.0                   # [s]
    metrics_start = 0.0               # [s] metrics over t >= this (default 0: the whole run)
    q9 = 10.0                         # tether length at trim [m]
    [control]
    dt = 0.01                         # controller sample time [s] (not given by the paper)
    substeps = 2                      # RK4 steps per sample
    feedforward = true                # eq 55
    Qy = [1, 1, 1, 1, 10, 10, 10, 10] # eq 53 weights (paper)
    Ru = [1, 1, 1, 1]
    controller = "paper"              # or "tether_lqi" (control.tether_lqi), "mpc" (control.mpc)
    [control.tether_lqi]              # the tethered LQI's weights (TetherLQISettings)
    Qy = [...]                        # q1, q2, q3, q6 and their integrators
    q_tension = 0.0                   # [1/N^2] on the tension deviation
    Ru = [...]                        # fMR3, tMR1, tMR2, fTR2, reel rate
    anti_windup = true
    [control.mpc]                     # the MPC's settings (MPCSettings)
    horizon = 10                      # samples
    [winch]                           # the ground winch (WinchSettings)
    model = "ideal"                   # or "drum": drum inertia, speed loop, torque limit
    [limits]
    max_tension = 500.0               # [N]
    max_deviation = 100.0             # [m]
    max_angle_deg = 80.0              # [deg]
    [[wind]]                          # force profiles on HO, see tetherheli.wind
    type = "pulse"
    ...
    [params.tether]                   # overrides of the paper's parameters
    K_C = 40.0

Every key is checked: unknown keys, wrong types and out-of-range values raise a
``ParameterError`` naming the file, the key and what is allowed.
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np

from .._io import OWN_FILE_STEMS, read_toml
from .._validation import Key
from ..control import lqi
from ..errors import ParameterError
from ..layout import (
    GROUND_DAMPING_PA_S_M,
    GROUND_FRICTION,
    GROUND_FRICTION_SPEED_M_S,
    GROUND_STIFFNESS_PA_M,
    WINCH_MIN_LENGTH_M,
)
from ..params import TETHER_LENGTH_RANGE, Params, check_tether_length, check_tether_strain
from ..sensors import SensorConfig, sensor_config_from_dict
from ..wind import (
    Disturbance,
    NoWind,
    check_wind_covers,
    disturbance_from_dict,
    paper_wind,
)

__all__ = [
    "CONTROLLERS",
    "MPC_OBSERVERS",
    "MPC_QY_GNSS",
    "WINCH_MODELS",
    "ActuatorSettings",
    "ControlSettings",
    "Limits",
    "MPCSettings",
    "Scenario",
    "TetherLQISettings",
    "TetherSettings",
    "WinchSettings",
    "check_distinct_names",
    "check_name",
    "load_scenario",
    "metrics_first_sample",
    "paper_scenario",
    "scenario_toml",
]

#: The paper's LQI weights (Sec. V-A, after eq 53) as the diagonals the scenario files list;
#: the one source is ``control.lqi.PAPER_QY`` / ``PAPER_RU``.
PAPER_QY: tuple[float, ...] = tuple(np.diag(lqi.PAPER_QY).tolist())
PAPER_RU: tuple[float, ...] = tuple(np.diag(lqi.PAPER_RU).tolist())


def _key(default: Any, key: Key) -> Any:
    """A dataclass field with its ``Key`` (documentation, unit, allowed values): the one
    description ``_validate`` checks against and ``tetherheli.sim.reference`` prints."""
    return field(default=default, metadata={"key": key})


def field_key(cls: type, name: str) -> Key:
    """The ``Key`` of field ``name`` of a scenario dataclass (``Scenario``,
    ``ControlSettings``, ``Limits``, ``ActuatorSettings``).

    Parameters
    ----------
    cls : type
        The dataclass.
    name : str
        The field's name.

    Returns
    -------
    Key
    """
    return cls.__dataclass_fields__[name].metadata["key"]


#: The controllers ``[control] controller`` selects: the paper's scheme (Sec. V), the LQI
#: on the tethered linearization with the reel rate as a fifth input (``control.tether_lqi``)
#: and the constrained MPC on the same model (``control.mpc``).
CONTROLLERS: tuple[str, ...] = ("paper", "tether_lqi", "mpc")
#: The MPC's estimators of state and wind force (``[control.mpc] observer``): the one-step
#: residual of the measured state (``disturbance_time_constant``), the steady-state Kalman
#: filter on the scenario's sensors (``control.observer``), or "auto": the Kalman filter when
#: the sensors are not perfect or the tether is the lumped chain, else the residual.
MPC_OBSERVERS: tuple[str, ...] = ("auto", "residual", "kalman")


@dataclass(frozen=True)
class TetherLQISettings:
    """Design weights of the tethered LQI (``[control.tether_lqi]``, ``control.tether_lqi``).

    Parameters
    ----------
    Qy, q_tension, Ru, anti_windup, q9_from_tension
        The keys of a scenario's ``[control.tether_lqi]`` table; each field's ``Key`` gives
        its meaning, unit, default and allowed range. Defaults: the weights
        ``python benchmarks/tune_tether_lqi.py --evaluations 700`` found (see its header: the
        paper's runs 1 and 2 with eq 40's saturation, effort within the paper's tethered
        controller's).
    """

    Qy: tuple[float, ...] = _key(
        (11.7435, 11.7435, 1.49411, 2.07043, 21.2098, 21.2098, 10.7023, 12.1298),
        Key("diagonal of the output weight on [q1, q2, q3, q6] and their integrators",
            kind="vector", length=8, low=0.0),
    )  # fmt: skip
    q_tension: float = _key(
        0.000794132, Key("weight on the tension deviation (not integrated)", "1/N^2", low=0.0)
    )
    Ru: tuple[float, ...] = _key(
        (0.632461, 0.878679, 0.878679, 0.641701, 0.510088),
        Key("diagonal of the input weight on [fMR3, tMR1, tMR2, fTR2, reel rate]",
            kind="vector", length=5, low=0.0, low_open=True),
    )  # fmt: skip
    anti_windup: bool = _key(
        True,
        Key("the integrators hold while a rotor command is outside its actuator limits",
            kind="bool"),
    )  # fmt: skip
    q9_from_tension: bool = _key(
        True,
        Key("with imperfect [sensors], the law's tether length is LN + TC / KC (drum encoder, "
            "load cell, design KC; eq 28) while taut, not the position source's",
            kind="bool"),
    )  # fmt: skip


@dataclass(frozen=True)
class MPCSettings:
    """Settings of the constrained linear MPC (``[control.mpc]``, ``control.mpc``).

    Parameters
    ----------
    horizon, Qy, q_tension, Ru, tension_bounds, slack_weight, disturbance_time_constant,
    observer, kalman_force_std, kalman_force_rate, kalman_force_accel, kalman_input_std,
    kalman_tension_std,
    kalman_coordinate_std, kalman_tether_angle_std,
    max_iterations, tolerance
        The keys of a scenario's ``[control.mpc]`` table; each field's ``Key`` gives its
        meaning, unit, default and allowed range. The cost is the tethered LQI's (with the
        DARE of the same weights as terminal cost). The weights and the time constant are
        from ``python benchmarks/bench_mpc.py --tune 30`` (from the tethered LQI's weights
        and 0.1 s), then ``--tune 16 --start=-1.274,-0.509,-0.346,-0.030`` (see its header).
        The Kalman filter's noises (``control.observer``): the wind force's random walk of
        1 N/sqrt(s) against a white 1 N flies every shipped scenario with sensors and the
        lumped tether; 2 N/sqrt(s) flies the sensed runs closer but takes the lumped one to
        0.87 m of altitude deviation, 3 N/sqrt(s) loses it (``python
        benchmarks/mpc_observer.py``; measured before the force's rate state). The rate's
        random walk of 6 N/s^1.5, the tether angles' 3e-4 rad and the inputs' noise at 0.85
        of its first values make the filter consistent on every shipped sensed scenario
        (mean NEES of its 16 states in the 95 % band: ``python
        benchmarks/kalman_consistency.py``, ``tests/test_kalman_consistency.py``). The
        rotor-input and winch bounds come from ``[actuators]``.
    """

    horizon: int = _key(
        10, Key("prediction and control horizon", "samples", kind="integer", low=1, high=400)
    )
    Qy: tuple[float, ...] = _key(
        (5.39899, 5.39899, 1.49411, 2.07043, 9.75105, 9.75105, 10.7023, 12.1298),
        Key("diagonal of the output weight on [q1, q2, q3, q6] and their integrators",
            kind="vector", length=8, low=0.0),
    )  # fmt: skip
    q_tension: float = _key(
        TetherLQISettings().q_tension,
        Key("weight on the tension deviation (not integrated)", "1/N^2", low=0.0),
    )  # fmt: skip
    Ru: tuple[float, ...] = _key(
        (0.632461, 0.401301, 0.401301, 1.02876, 0.510088),
        Key("diagonal of the input weight on [fMR3, tMR1, tMR2, fTR2, reel rate]",
            kind="vector", length=5, low=0.0, low_open=True),
    )  # fmt: skip
    tension_bounds: tuple[float, float] | None = _key(
        None,
        Key("soft bounds on the predicted tether tension [lower, upper]; unset, they follow "
            "the scenario's reference: [T_ref/2, 1.5 T_ref] ([12.5, 37.5] at the paper's 25 "
            "N)", "N", kind="vector", length=2, low=0.0, finite=False,
            note="lower below upper, around params.tension_control.T_ref",
            unset="[T_ref/2, 1.5 T_ref]"),
    )  # fmt: skip
    slack_weight: float = _key(
        100.0,
        Key("penalty on the tension bounds' slack s, per sample: w (s + s^2)", "1/N^2",
            low=0.0, low_open=True),
    )  # fmt: skip
    disturbance_time_constant: float = _key(
        0.0024297,
        Key("time constant of the estimate of the wind force on HO (an input disturbance "
            "of the model; 0: no estimate, integral action only)", "s", low=0.0),
    )  # fmt: skip
    observer: str = _key(
        "auto",
        Key("the estimator of state and wind force: the measured state's one-step residual, "
            "a steady-state Kalman filter on the scenario's sensors, or auto (the filter "
            "with imperfect sensors or the lumped tether)", kind="text",
            choices=MPC_OBSERVERS),
    )  # fmt: skip
    kalman_force_std: float = _key(
        1.0,
        Key("the Kalman filter's white force on HO per sample, per axis: what the linear "
            "model misses over a sample", "N", low=0.0, low_open=True),
    )  # fmt: skip
    kalman_force_rate: float = _key(
        1.0,
        Key("the Kalman filter's wind force on HO as a random walk, density per axis",
            "N/s^0.5", low=0.0, low_open=True),
    )  # fmt: skip
    kalman_input_std: tuple[float, ...] = _key(
        (0.85, 0.425, 0.425, 0.255, 0.0085),
        Key("the Kalman filter's white error of each input per sample: [fMR3, tMR1, tMR2, "
            "fTR2, reel rate] in N, N m, N m, N, m/s", kind="vector", length=5, low=0.0,
            low_open=True),
    )  # fmt: skip
    kalman_force_accel: float = _key(
        6.0,
        Key("the Kalman filter's wind force on HO with a rate state: the rate's random walk, "
            "density per axis (0: no rate state, the force a random walk)", "N/s^1.5",
            low=0.0),
    )  # fmt: skip
    kalman_tension_std: float = _key(
        0.0,
        Key("the Kalman filter's error of eq 28's tension from the state, added to the load "
            "cell's noise: the tether's stiffness and length as the design model knows them",
            "N", low=0.0),
    )  # fmt: skip
    kalman_coordinate_std: float = _key(
        1e-2,
        Key("the Kalman filter's white error of each coordinate q4..q9 per sample: the "
            "linearized kinematics' error", "rad or m", low=0.0, low_open=True),
    )  # fmt: skip
    kalman_tether_angle_std: float | None = _key(
        3e-4,
        Key("the Kalman filter's white error of the tether's angles q7, q8 per sample, when "
            "it differs from kalman_coordinate_std", "rad", low=0.0, low_open=True,
            unset="kalman_coordinate_std"),
    )  # fmt: skip
    max_iterations: int = _key(
        200,
        Key("OSQP's iteration limit per sample (beyond it the previous plan is flown)",
            kind="integer", low=1, high=1_000_000),
    )  # fmt: skip
    tolerance: float = _key(
        1e-4, Key("OSQP's absolute and relative tolerance", low=0.0, low_open=True, high=1.0)
    )

    def bounds_about(self, T_ref: float) -> tuple[float, float]:
        """The tension bounds the MPC uses with the reference ``T_ref`` [N]: ``tension_bounds``
        when given, else [T_ref/2, 1.5 T_ref].

        Parameters
        ----------
        T_ref : float
            The tension reference (``params.tension_control.T_ref``) [N].

        Returns
        -------
        tuple of 2 floats
            Lower and upper soft bound [N].
        """
        if self.tension_bounds is not None:
            return self.tension_bounds
        return (0.5 * T_ref, 1.5 * T_ref)


#: The MPC's output weights for the consumer-GNSS sensing files (``report.sensing_scenario``,
#: scenarios/sensing_gps*.toml): ``MPCSettings.Qy`` with ten times the weight on the yaw q6
#: and its integrator. With the consumer GNSS and eq 40's cyclic limit the default weights
#: let the yaw swing by 0.5 rad after the pulse and the run diverges; with these it completes
#: (``python benchmarks/mpc_observer.py --eq40``).
MPC_QY_GNSS: tuple[float, ...] = tuple(
    10.0 * q if i in (3, 7) else q for i, q in enumerate(MPCSettings().Qy)
)


@dataclass(frozen=True)
class ControlSettings:
    """Controller and integrator settings (Sec. V).

    Parameters
    ----------
    dt, substeps, feedforward, Qy, Ru, controller, tether_lqi, mpc
        The keys of a scenario's ``[control]`` table: ``controller`` one of ``CONTROLLERS``;
        Qy, Ru and feedforward are the paper controller's, ``tether_lqi`` the tethered LQI's
        and ``mpc`` the MPC's (both fly without the feed-forward: their plant model contains
        the tether).
        Each field's ``Key`` gives its meaning, unit, default and allowed range (printed
        in the scenario TOML reference, ``docs/scenario_reference.md``).
    """

    dt: float = _key(
        0.01,
        Key(
            "controller sample time (not given by the paper)", "s", low=0.0, low_open=True,
            note="at most duration, which must be a whole number of samples",
        ),
    )  # fmt: skip
    substeps: int = _key(2, Key("RK4 steps per control sample", kind="integer", low=1, high=1000))
    feedforward: bool = _key(
        True, Key("tether-torque feed-forward C_f-fwd (eqs 54-55)", kind="bool")
    )
    Qy: tuple[float, ...] = _key(
        PAPER_QY,
        Key("diagonal of the LQI output weight Qy (eq 47; paper Sec. V-A)", kind="vector",
            length=8, low=0.0),
    )  # fmt: skip
    Ru: tuple[float, ...] = _key(
        PAPER_RU,
        Key("diagonal of the LQI input weight Ru (eq 47; paper Sec. V-A)", kind="vector",
            length=4, low=0.0, low_open=True),
    )  # fmt: skip
    controller: str = _key(
        "paper",
        Key("the controller flown: the paper's (Sec. V), the LQI on the tethered "
            "linearization with the reel rate as a fifth input, or the constrained MPC on "
            "that model", kind="text", choices=CONTROLLERS),
    )  # fmt: skip
    tether_lqi: TetherLQISettings = field(default_factory=TetherLQISettings)
    mpc: MPCSettings = field(default_factory=MPCSettings)


@dataclass(frozen=True)
class Limits:
    """Bounds that stop a run with a failure status (never reported as success).

    Parameters
    ----------
    max_tension, max_deviation, max_angle_deg
        The keys of a scenario's ``[limits]`` table.
        Each field's ``Key`` gives its meaning, unit, default and allowed range (printed
        in the scenario TOML reference, ``docs/scenario_reference.md``).
    """

    max_tension: float = _key(
        500.0, Key("tether tension above which the run fails", "N", low=0.0, low_open=True)
    )
    max_deviation: float = _key(
        100.0,
        Key("distance of HO from its trim position above which the run fails", "m", low=0.0,
            low_open=True),
    )  # fmt: skip
    max_angle_deg: float = _key(
        80.0,
        Key("roll or pitch angle above which the run fails", "deg", low=0.0, low_open=True,
            high=89.0),
    )  # fmt: skip


_INF = math.inf
_U_UNITS = "N, N m, N m, N"


@dataclass(frozen=True)
class ActuatorSettings:
    """Actuator and tether-device realism (all off by default; Sec. IV-C, eq 40).

    The reel acceleration limit is applied per sample to the PI's command; the paper's PI
    then integrates only while the limit does not bind (a custom controller gets the limited
    rate without being told). Above the breaking tension the safety device releases the
    tether and the run continues free.

    Parameters
    ----------
    u_min, u_max, time_constant, reel_rate_limit, reel_acceleration_limit, breaking_tension
        The keys of a scenario's ``[actuators]`` table.
        Each field's ``Key`` gives its meaning, unit, default and allowed range (printed
        in the scenario TOML reference, ``docs/scenario_reference.md``).
    """

    u_min: tuple[float, float, float, float] = _key(
        (-_INF, -_INF, -_INF, -_INF),
        Key("lower input limits of fMR,3, tMR,1, tMR,2, fTR,2", _U_UNITS, kind="vector",
            length=4, finite=False, note="each below u_max"),
    )  # fmt: skip
    u_max: tuple[float, float, float, float] = _key(
        (_INF, _INF, _INF, _INF),
        Key("upper input limits of fMR,3, tMR,1, tMR,2, fTR,2 (the cyclic ones are eq 40's "
            "tmax_MR1,2)", _U_UNITS, kind="vector", length=4, finite=False),
    )  # fmt: skip
    time_constant: float = _key(
        0.0, Key("first-order actuator lag (0: none)", "s", low=0.0, high=10.0)
    )
    reel_rate_limit: float = _key(
        _INF,
        Key("bound on the winch's reel rate |dLN/dt| (eq 37; anti-windup in eq 56's PI)",
            "m/s", low=0.0, low_open=True, finite=False),
    )  # fmt: skip
    reel_acceleration_limit: float = _key(
        _INF,
        Key("bound on the change of the reel rate, per sample", "m/s^2", low=0.0,
            low_open=True, finite=False),
    )  # fmt: skip
    breaking_tension: float = _key(
        _INF,
        Key("tension above which the safety device releases the tether (Sec. IV-C)", "N",
            low=0.0, low_open=True, finite=False),
    )  # fmt: skip


#: The tether models ``[tether] model`` selects: the paper's massless elastic tether (eq 28)
#: and the lumped-mass chain (``model.tether_lumped``).
TETHER_MODELS: tuple[str, ...] = ("elastic", "lumped")


@dataclass(frozen=True)
class TetherSettings:
    """The tether model (``[tether]``; issue 13). "elastic" is the paper's massless straight
    tether (eq 28, stiffness ``params.tether.K_C``); "lumped" the chain of
    ``model.tether_lumped`` (point masses, axial elasticity slack in compression, axial
    damping, gravity, normal and tangential drag in the gust table's air), whose bottom node
    is the winch and whose top node moves with P. The other keys apply to "lumped" only.

    EA = 0 takes the paper's stiffness: the whole tether's spring constant K_C at the
    massless trim's natural length LN = q9 - T_ref / K_C is EA / LN, so EA = K_C LN
    (``LumpedTether.from_paper_stiffness``; 375 N at the paper's hover).

    A lumped run starts from ``hover_trim_lumped``'s equilibrium (the chain hanging still,
    T_ref at the winch; even in a gust table, whose drag then acts from t = 0) and the paper
    controller flies about that trim. The load cell (eq 56's PI, the sensors) reads the
    tension at the winch; the result records it as ``TC_ground`` next to ``TC`` at P. The
    drag on the nodes is that of the gust table's air, the air the helicopter's drag uses;
    force-only wind profiles (pulse, sine, ...) act on the helicopter alone. The encoders
    read q7, q8 (the direction to P), as for the massless tether. Runs with a lumped
    tether go through the per-run compiled loop (no lanes), ``simulate`` with method "rk4".

    Parameters
    ----------
    model, segments, mass_per_length, EA, damping_ratio, internal_damping, diameter,
    drag_coefficient, tangential_drag_coefficient, ground_stiffness, ground_damping,
    ground_friction, ground_friction_speed, record_nodes
        The keys of a scenario's ``[tether]`` table; each field's ``Key`` gives its meaning,
        unit, default and allowed range. The ground keys are the plane z = 0 through the
        winch under the chain's free nodes (MoorDyn's seabed; ``model.tether_lumped``).
    """

    model: str = _key(
        "elastic",
        Key("the tether model: the paper's massless elastic tether (eq 28) or a lumped-mass "
            "chain with sag and drag (model.tether_lumped)", kind="text",
            choices=TETHER_MODELS),
    )  # fmt: skip
    segments: int = _key(
        10, Key("segments N of the lumped chain (N - 1 free nodes)", kind="integer", low=2,
                high=1000),
    )  # fmt: skip
    mass_per_length: float = _key(
        0.02, Key("mass per unstretched length", "kg/m", low=0.0, low_open=True)
    )
    EA: float = _key(
        0.0,
        Key("axial stiffness; 0: the paper's K_C times the massless trim's natural length "
            "q9 - T_ref / K_C", "N", low=0.0),
    )  # fmt: skip
    damping_ratio: float = _key(
        0.1, Key("damping ratio of the cable's fundamental axial mode (ends fixed), whatever "
                 "N; 0 with internal_damping > 0", low=0.0),
    )  # fmt: skip
    internal_damping: float = _key(
        0.0, Key("internal damping BA: axial damping force per unit strain rate (MoorDyn's "
                 "BA); 0: damping_ratio gives the damping", "N s", low=0.0),
    )  # fmt: skip
    diameter: float = _key(0.005, Key("cable diameter", "m", low=0.0, low_open=True))
    drag_coefficient: float = _key(
        1.1, Key("normal (cross-flow) drag coefficient of the cable", low=0.0, low_open=True)
    )
    tangential_drag_coefficient: float = _key(
        0.0, Key("tangential (skin-friction) drag coefficient on the wetted area", low=0.0)
    )
    ground_stiffness: float = _key(
        GROUND_STIFFNESS_PA_M,
        Key("the ground's normal stiffness kbot under the chain's free nodes, per contact "
            "area d l0 (MoorDyn's seabed default; a cable at rest sinks in by "
            "mass_per_length g / (kbot diameter)); 0: no ground", "Pa/m", low=0.0),
    )  # fmt: skip
    ground_damping: float = _key(
        GROUND_DAMPING_PA_S_M,
        Key("the ground's normal damping cbot per contact area (the default: the default "
            "cable's critically damped contact)", "Pa s/m", low=0.0),
    )  # fmt: skip
    ground_friction: float = _key(
        GROUND_FRICTION,
        Key("Coulomb friction coefficient of the cable on the ground (0: none)", low=0.0),
    )
    ground_friction_speed: float = _key(
        GROUND_FRICTION_SPEED_M_S,
        Key("the friction's regularisation speed: viscous below it", "m/s", low=0.0,
            low_open=True),
    )  # fmt: skip
    record_nodes: bool = _key(
        False, Key("record the chain's node positions at every sample (result extras)",
                   kind="bool"),
    )  # fmt: skip

    @property
    def lumped(self) -> bool:
        """Whether the tether is the lumped-mass chain."""
        return self.model == "lumped"


#: The winch models ``[winch] model`` selects: the paper's (the reel rate of eq 56 applied as
#: commanded, dL_N/dt = R_C, eq 37) and a drum driven by a speed loop (``model.winch``).
WINCH_MODELS: tuple[str, ...] = ("ideal", "drum")


@dataclass(frozen=True)
class WinchSettings:
    """The ground winch (``[winch]``): ideal (the paper's) or a drum with inertia, friction
    and a torque-limited drive whose speed loop follows the reel rate of eq 56
    (``model.winch``: J w' = r T_g - tau_m - b w - tau_c sign(w), dL_N/dt = r w, w > 0
    paying out, the motor torque tau_m > 0 hauling in).

    Default drum, a small tether winch sized for the paper's Tref = 25 N: radius 0.05 m;
    inertia 0.005 kg m^2 = an aluminium drum 0.05 m in radius and 0.1 m long as a solid
    cylinder (rho pi r^2 L r^2 / 2 = 2.7e3 pi 0.05^4 0.1 / 2 = 0.0027 kg m^2) plus a gear
    motor's rotor of 2.3e-5 kg m^2 through a 10:1 gearbox (2.3e-3 kg m^2 reflected); torque
    limit 2.5 N m = the torque holding twice Tref on that drum (2 x 25 N x 0.05 m); Coulomb
    friction 0.05 N m (2% of the torque limit) and viscous friction 0.001 N m s/rad, assumed
    for a geared drive; speed loop bandwidth 50 rad/s, half the 100 Hz control rate in
    rad/s over 2 pi (a drive's speed loop is usually faster: a conservative choice). These
    are a sizing, not a catalogue part.

    Parameters
    ----------
    model, drum_radius, drum_inertia, torque_limit, viscous_friction, coulomb_friction,
    speed_loop_bandwidth, tension_feedforward, min_length, max_length
        The keys of a scenario's ``[winch]`` table; each field's ``Key`` gives its meaning,
        unit, default and allowed range. The drum keys are used by ``model = "drum"`` only;
        the payout limits by both models and both tethers (``engine.winch_limits``: reaching
        one brakes the reel, the run goes on and records it, ``SimulationResult.winch_limit``).
    """

    model: str = _key(
        "ideal",
        Key("the winch: the paper's, which applies the reel rate of eq 56 as commanded, or a "
            "drum with inertia, friction and a torque-limited speed loop (model.winch)",
            kind="text", choices=WINCH_MODELS),
    )  # fmt: skip
    drum_radius: float = _key(
        0.05, Key("drum radius r (dL_N/dt = r w)", "m", low=0.0, low_open=True, high=10.0)
    )
    drum_inertia: float = _key(
        0.005,
        Key("drum inertia J, with the motor's rotor reflected through the gearbox",
            "kg m^2", low=0.0, low_open=True),
    )  # fmt: skip
    torque_limit: float = _key(
        2.5, Key("the drive's motor torque limit at the drum", "N m", low=0.0, low_open=True)
    )
    viscous_friction: float = _key(
        0.001, Key("viscous friction b of drum and drive", "N m s/rad", low=0.0)
    )
    coulomb_friction: float = _key(
        0.05,
        Key("Coulomb friction tau_c of drum and drive (the drum sticks at rest while the net "
            "torque is below it)", "N m", low=0.0),
    )  # fmt: skip
    speed_loop_bandwidth: float = _key(
        50.0,
        Key("bandwidth omega_w of the drive's proportional speed loop, gain J omega_w: the "
            "unloaded drum follows the speed reference R_C / r with time constant "
            "1 / omega_w", "rad/s", low=0.0, low_open=True),
    )  # fmt: skip
    tension_feedforward: bool = _key(
        True,
        Key("the drive adds the load cell's torque r T_meas to the speed loop's (removes the "
            "loop's steady speed error under the tether's load)", kind="bool"),
    )  # fmt: skip
    min_length: float = _key(
        WINCH_MIN_LENGTH_M,
        Key("shortest natural length L_N the winch reels in to (a brake stops the reel "
            "there; the run records it): keeps every natural length positive", "m",
            low=0.0, low_open=True),
    )  # fmt: skip
    max_length: float = _key(
        _INF,
        Key("longest natural length L_N the winch pays out to, the drum's capacity (a brake "
            "stops the reel there; the run records it); inf: no limit", "m", low=0.0,
            low_open=True, finite=False),
    )  # fmt: skip


def _wind_record(wind: Disturbance) -> dict[str, Any]:
    """The wind's table; a custom disturbance without ``to_dict`` is recorded by its class
    and repr (enough to identify it, not to reload it)."""
    try:
        return wind.to_dict()
    except NotImplementedError:
        cls = type(wind)
        return {
            "type": "custom",
            "class": f"{cls.__module__}.{cls.__qualname__}",
            "repr": repr(wind),
        }


@dataclass(frozen=True)
class Scenario:
    """One closed-loop run: configuration, duration, controller settings, wind, parameters.

    Every field is validated on construction (``ParameterError`` naming the field, the value
    and what is allowed); ``load_scenario`` reads the same fields from TOML.

    Parameters
    ----------
    name, configuration, duration, q9, description, seed, metrics_start
        The scenario's top-level keys.
        Each field's ``Key`` gives its meaning, unit, default and allowed range (printed
        in the scenario TOML reference, ``docs/scenario_reference.md``).
    control : ControlSettings, optional
        Controller and integrator settings (Sec. V).
    limits : Limits, optional
        Bounds that stop a failing run.
    wind : Disturbance, optional
        The wind force on HO (``tetherheli.wind``); default none.
    params : Params, optional
        The parameter set (default ``Params.paper()``).
    actuators : ActuatorSettings, optional
        Actuator and winch realism (default: ideal).
    sensors : SensorConfig, optional
        What the controller measures (default: the true state).
    tether : TetherSettings, optional
        The tether model (default: the paper's massless elastic tether).
    winch : WinchSettings, optional
        The ground winch (default: the paper's ideal winch).
    """

    name: str = _key(
        "scenario",
        Key(
            "the run's name, a file stem",
            kind="text",
            note="1-100 letters, digits, '_', '.' or '-', not starting with '.', not one of "
            f"{', '.join(OWN_FILE_STEMS)} (alone or before a '.')",
        ),
    )
    configuration: Literal["free", "tethered"] = _key(
        "tethered",
        Key(
            "the tethered helicopter or the free one (the tether removed, Sec. VI)",
            kind="text",
            choices=("free", "tethered"),
        ),
    )
    duration: float = _key(60.0, Key("length of the run", "s", low=0.0, low_open=True))
    q9: float = _key(
        10.0,
        Key("tether length at trim (tethered; free: the trim altitude's tether length)", "m",
            low=TETHER_LENGTH_RANGE[0], high=TETHER_LENGTH_RANGE[1]),
    )  # fmt: skip
    control: ControlSettings = field(default_factory=ControlSettings)
    limits: Limits = field(default_factory=Limits)
    wind: Disturbance = field(default_factory=NoWind)
    params: Params = field(default_factory=Params.paper)
    description: str = _key("", Key("free text recorded with the results", kind="text"))
    actuators: ActuatorSettings = field(default_factory=ActuatorSettings)
    sensors: SensorConfig = field(default_factory=SensorConfig)
    tether: TetherSettings = field(default_factory=TetherSettings)
    seed: int = _key(
        0, Key("seed of the run's random numbers (sensor noise, turbulence)", kind="integer",
               low=0),
    )  # fmt: skip
    #: [s] the peak, RMS and tension metrics cover t >= metrics_start only (a settling time
    #: excluded; default 0: the whole run); 0 <= metrics_start < duration
    metrics_start: float = _key(
        0.0,
        Key("the peak, RMS and tension metrics cover t >= metrics_start only (a settling "
            "time excluded; 0: the whole run)", "s", low=0.0, note="below duration"),
    )  # fmt: skip
    winch: WinchSettings = field(default_factory=WinchSettings)

    def __post_init__(self) -> None:
        _validate(self, source=None)

    @property
    def n_samples(self) -> int:
        """Number of control intervals in the run."""
        return round(self.duration / self.control.dt)

    @property
    def metrics_first_sample(self) -> int:
        """The first control sample the metrics cover (``metrics_first_sample``)."""
        return metrics_first_sample(self.metrics_start, self.control.dt)

    def replace(self, **changes: Any) -> Scenario:
        """A copy with fields replaced (validated).

        Parameters
        ----------
        **changes
            Field name -> new value.

        Returns
        -------
        Scenario
        """
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict[str, Any]:
        """The full configuration as plain data (recorded next to every result).

        Returns
        -------
        dict
            Every field; the wind and sensors as their tables, the parameters by section.
        """
        return {
            "name": self.name,
            "description": self.description,
            "configuration": self.configuration,
            "duration": self.duration,
            "q9": self.q9,
            "control": dataclasses.asdict(self.control),
            "limits": dataclasses.asdict(self.limits),
            "wind": _wind_record(self.wind),
            "params": self.params.to_dict(),
            "actuators": dataclasses.asdict(self.actuators),
            "sensors": self.sensors.to_dict(),
            "tether": dataclasses.asdict(self.tether),
            "seed": self.seed,
            "metrics_start": self.metrics_start,
            "winch": dataclasses.asdict(self.winch),
        }

    def to_toml(self) -> str:
        """The scenario as a TOML document that ``load_scenario`` reads back to an equal
        Scenario (every key written, defaults included; ``scenario_toml``).

        Returns
        -------
        str
            The TOML document.

        Raises
        ------
        ParameterError
            A custom disturbance without ``to_dict`` cannot be written.
        """
        return scenario_toml(self.to_dict())


#: A scenario name becomes a file stem and a folder name: letters, digits, '_', '.', '-'.
_NAME_PATTERN = re.compile(r"[A-Za-z0-9_.-]{1,100}")
#: The most control samples one run may have (about 12 days at dt = 1 ms, 115 days at 10 ms).
MAX_SAMPLES = 1_000_000_000


def scenario_toml(configuration: dict[str, Any]) -> str:
    """A scenario's plain data as a TOML document ``load_scenario`` reads back.

    Parameters
    ----------
    configuration : dict
        ``Scenario.to_dict()``, as a result records it.

    Returns
    -------
    str

    Raises
    ------
    ParameterError
        A custom disturbance (recorded by class and repr only) cannot be written.
    """
    wind = configuration.get("wind", {})
    if wind.get("type") == "custom":
        raise ParameterError("wind", wind.get("class"), "a disturbance with to_dict (TOML)")
    import tomli_w  # floats as repr (exact round trip), inf/nan, nested tables and arrays

    return tomli_w.dumps(_without_unset(configuration))


def _without_unset(data: Any) -> Any:
    """``data`` without its unset keys (None: ``Key.unset``, e.g. MPC tension bounds that follow
    T_ref): TOML has no None, and an absent key reads back as unset."""
    if isinstance(data, dict):
        return {k: _without_unset(v) for k, v in data.items() if v is not None}
    if isinstance(data, (list, tuple)):
        return [_without_unset(v) for v in data]
    return data


def metrics_first_sample(metrics_start: float, dt: float) -> int:
    """The first control sample the metrics (peak, RMS, tension range) cover.

    Parameters
    ----------
    metrics_start : float
        Start of the metrics window (s).
    dt : float
        Control sample time (s).

    Returns
    -------
    int
        The first k with k dt >= ``metrics_start``.
    """
    return math.ceil(metrics_start / dt - 1e-9)


def check_name(key: str, value: object, *, source: str | None = None) -> str:
    """A name that becomes a file stem or a folder: 1-100 letters, digits, '_', '.', '-'
    (never a path), not starting with '.' (tetherheli's record and temporary files do), and
    not one of the stems of tetherheli's own files (``_io.OWN_FILE_STEMS``, alone or before a
    '.', in any letter case), so that no run's file or folder is ever one of them; else
    ParameterError naming ``key``."""
    if (
        not isinstance(value, str)
        or not _NAME_PATTERN.fullmatch(value)
        or value.startswith(".")
        or value.casefold().partition(".")[0] in OWN_FILE_STEMS
    ):
        raise ParameterError(
            key,
            value,
            "a plain name of 1-100 letters, digits, '_', '.' or '-' (no path separators), "
            "not starting with '.' and not one of tetherheli's own file names "
            f"({', '.join(OWN_FILE_STEMS)}, with or without a suffix)",
            source=source,
        )
    return value


def check_distinct_names(names: Iterable[str], *, key: str = "name") -> None:
    """Refuse runs whose names would share a file or folder: equal names, or names equal
    but for letter case (one file on a case-insensitive file system).

    Parameters
    ----------
    names : iterable of str
        The runs' names (already ``check_name``-ed).
    key : str, optional
        The field to name in the error (default "name").

    Raises
    ------
    ParameterError
        Two names that clash, both named.
    """
    seen: dict[str, str] = {}
    for name in names:
        other = seen.get(name.casefold())
        seen[name.casefold()] = name
        if other is not None:
            raise ParameterError(
                key,
                name,
                f"a name that differs from every other run's (it clashes with {other!r}; "
                "names must differ, also in more than letter case)",
            )


def _validate(s: Scenario, source: str | None) -> None:
    """Check every field of ``s`` and store the checked values (Python floats and ints, so a
    NumPy scalar is accepted and recorded as plain data)."""
    check_name("name", s.name, source=source)
    field_key(Scenario, "configuration").check("configuration", s.configuration, source=source)
    _set(
        s, "duration", field_key(Scenario, "duration").check("duration", s.duration, source=source)
    )
    _set(s, "q9", check_tether_length(s.q9, "q9", source=source))
    _set(
        s,
        "metrics_start",
        field_key(Scenario, "metrics_start").check(
            "metrics_start", s.metrics_start, high=s.duration, high_open=True, source=source
        ),
    )
    c = s.control
    dt = field_key(ControlSettings, "dt").check("control.dt", c.dt, source=source)
    if dt > s.duration:
        raise ParameterError(
            "control.dt", c.dt, f"a sample time <= duration ({s.duration} s)", source=source
        )
    if s.duration / dt > MAX_SAMPLES:
        raise ParameterError(
            "duration",
            s.duration,
            f"at most {MAX_SAMPLES:.0e} control samples (duration / control.dt; dt = {c.dt} s)",
            source=source,
        )
    if abs(s.duration / dt - round(s.duration / dt)) > 1e-9 * s.duration / dt:
        raise ParameterError(
            "duration",
            s.duration,
            f"a whole number of control samples (dt = {c.dt} s)",
            source=source,
        )
    tether_lqi = _checked(TetherLQISettings, "control.tether_lqi", c.tether_lqi, source)
    mpc = _checked(MPCSettings, "control.mpc", c.mpc, source)
    if mpc.tension_bounds is not None and not mpc.tension_bounds[0] < mpc.tension_bounds[1]:
        raise ParameterError(
            "control.mpc.tension_bounds", list(c.mpc.tension_bounds), "[lower, upper] with "
            "lower < upper [N]", source=source,
        )  # fmt: skip
    control = _checked(ControlSettings, "control", c, source, dt=dt, tether_lqi=tether_lqi, mpc=mpc)
    lim = _checked(Limits, "limits", s.limits, source)
    a = s.actuators
    actuators = _checked(ActuatorSettings, "actuators", a, source)
    if any(lo >= hi for lo, hi in zip(actuators.u_min, actuators.u_max, strict=True)):
        raise ParameterError(
            "actuators.u_min", a.u_min, "limits below actuators.u_max", source=source
        )
    if not isinstance(s.winch, WinchSettings):
        raise ParameterError("winch", s.winch, "a WinchSettings", source=source)
    winch = _checked(WinchSettings, "winch", s.winch, source)
    if not winch.min_length < winch.max_length:
        raise ParameterError(
            "winch.max_length", s.winch.max_length,
            f"a length above winch.min_length ({winch.min_length:g} m)", source=source,
        )  # fmt: skip
    if winch.model == "drum" and math.isfinite(actuators.reel_acceleration_limit):
        raise ParameterError(
            "actuators.reel_acceleration_limit",
            a.reel_acceleration_limit,
            'inf with [winch] model = "drum" (the drum\'s inertia and torque limit bound '
            "its acceleration)",
            source=source,
        )
    _set(s, "control", control)
    _set(s, "limits", lim)
    _set(s, "actuators", actuators)
    tether = _checked(TetherSettings, "tether", s.tether, source)
    if tether.lumped and s.configuration != "tethered":
        raise ParameterError(
            "tether.model", tether.model, "'elastic' in the free configuration (no tether)",
            source=source,
        )  # fmt: skip
    if tether.internal_damping > 0.0 and tether.damping_ratio > 0.0:
        raise ParameterError(
            "tether.internal_damping", tether.internal_damping,
            "0 while tether.damping_ratio > 0 (one or the other: set damping_ratio = 0 to "
            "give internal_damping)", source=source,
        )  # fmt: skip
    _set(s, "tether", tether)
    _set(s, "winch", winch)
    if not isinstance(s.sensors, SensorConfig):
        raise ParameterError("sensors", s.sensors, "a SensorConfig", source=source)
    try:
        s.sensors.check_configuration(tethered=s.configuration == "tethered")
        s.sensors.group_timing(s.control.dt)  # rates and latencies on the control grid
    except ParameterError as exc:
        raise ParameterError(exc.field, exc.value, exc.allowed, source=source) from None
    _set(s, "seed", field_key(Scenario, "seed").check("seed", s.seed, source=source))
    if not isinstance(s.params, Params):
        raise ParameterError("params", s.params, "a tetherheli.Params", source=source)
    if s.configuration == "tethered" and s.params.tension_control.T_ref >= lim.max_tension:
        raise ParameterError(
            "params.tension_control.T_ref",
            s.params.tension_control.T_ref,
            f"a reference below limits.max_tension ({lim.max_tension} N)",
            source=source,
        )
    if tether.lumped and not s.params.tension_control.T_ref > 0.0:
        raise ParameterError(
            "params.tension_control.T_ref",
            s.params.tension_control.T_ref,
            "a tension > 0 [N] with [tether] model = 'lumped' (the chain hangs from P with "
            "T_ref at the winch; at 0 N its bottom is slack)",
            source=source,
        )
    if s.configuration == "tethered":  # the trim's natural length must be sensible
        s.params.tether.check_tension(
            s.params.tension_control.T_ref, s.q9, "params.tension_control.T_ref", source=source
        )
    if s.configuration == "free" and s.control.controller == "tether_lqi":
        raise ParameterError(
            "control.controller", "tether_lqi", "'paper' or 'mpc' in the free configuration "
            "(the tethered LQI needs a tether: configuration = 'tethered')", source=source,
        )  # fmt: skip
    bounds = s.control.mpc.tension_bounds
    T_ref = s.params.tension_control.T_ref
    if s.configuration == "tethered" and s.control.controller == "mpc" and bounds is not None:
        if not bounds[0] <= T_ref <= bounds[1]:  # the MPC would fight its own reference
            raise ParameterError(
                "control.mpc.tension_bounds", list(bounds), f"bounds around "
                f"params.tension_control.T_ref = {T_ref:g} N (e.g. [{T_ref / 2:g}, "
                f"{1.5 * T_ref:g}], Tref/2 and 1.5 Tref)", source=source,
            )  # fmt: skip
    if s.configuration == "tethered" and s.tether.lumped and s.tether.EA > 0.0:
        # the same strain limit for the chain: its top carries T_ref and its own weight
        top = (
            s.params.tension_control.T_ref + s.tether.mass_per_length * s.params.helicopter.g * s.q9
        )
        check_tether_strain(top, s.tether.EA, "tether.EA", s.tether.EA, source=source)
    if not isinstance(s.wind, Disturbance):
        raise ParameterError("wind", s.wind, "a tetherheli Disturbance", source=source)
    check_wind_covers(s.wind, s.duration, source=source)


def _set(s: Scenario, name: str, value: Any) -> None:
    object.__setattr__(s, name, value)


def _checked(cls: type, section: str, value: Any, source: str | None, **done: Any) -> Any:
    """A ``cls`` (a settings table) with every field checked against its ``Key``; ``done``:
    fields already checked."""
    return cls(
        **{
            f.name: done[f.name]
            if f.name in done
            else f.metadata["key"].check(f"{section}.{f.name}", getattr(value, f.name),
                                         source=source)
            for f in dataclasses.fields(cls)
        }
    )  # fmt: skip


_TOP_KEYS = {
    "name",
    "description",
    "configuration",
    "duration",
    "q9",
    "control",
    "limits",
    "wind",
    "params",
    "actuators",
    "sensors",
    "tether",
    "seed",
    "metrics_start",
    "winch",
}


def _vectors(source, key, value, cls) -> dict[str, Any]:
    """The TOML table ``value`` of settings ``cls`` (``_table``), its vector keys (a ``Key``
    of kind "vector") turned from TOML arrays into tuples."""
    table = dict(_table(source, key, value, cls))
    for f in dataclasses.fields(cls):
        spec = f.metadata.get("key")
        if spec is None or spec.kind != "vector" or f.name not in table:
            continue
        if table[f.name] is None and spec.unset:  # unset (a JSON record's null)
            continue
        if not isinstance(table[f.name], list):
            raise ParameterError(
                f"{key}.{f.name}", table[f.name], spec.allowed() if spec.unset else
                f"a list of {spec.length} numbers", source=source,
            )  # fmt: skip
        table[f.name] = tuple(table[f.name])
    return table


def _table(source, key, value, allowed_cls) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise ParameterError(key, value, "a table", source=source)
    allowed = {f.name for f in dataclasses.fields(allowed_cls)}
    for k in value:
        if k not in allowed:
            raise ParameterError(f"{key}.{k}", value[k], f"one of {sorted(allowed)}", source=source)
    return value


def scenario_from_dict(data: dict[str, Any], *, source: str | None = None) -> Scenario:
    """Build a validated Scenario from parsed TOML data.

    Parameters
    ----------
    data : dict of str to object
        The scenario's tables, as ``tomllib`` gives them.
    source : str, optional
        Where they came from (a file name), put in front of an error's message.

    Returns
    -------
    Scenario

    Raises
    ------
    ParameterError
        One line naming the first bad key; also for data nested deeper than the validation
        can follow (e.g. thousands of ``sum`` winds inside each other).
    """
    try:
        return _scenario_from_dict(data, source=source)
    except RecursionError:
        raise ParameterError(
            "scenario",
            "nested too deep",
            "tables and lists nested a few levels deep",
            source=source,
        ) from None


def _scenario_from_dict(data: dict[str, Any], *, source: str | None = None) -> Scenario:
    for k in data:
        if k not in _TOP_KEYS:
            raise ParameterError(k, data[k], f"one of {sorted(_TOP_KEYS)}", source=source)
    kwargs: dict[str, Any] = {}
    for k in ("name", "description"):
        if k in data:
            if not isinstance(data[k], str):
                raise ParameterError(k, data[k], "a string", source=source)
            kwargs[k] = data[k]
    if "configuration" in data:
        kwargs["configuration"] = data["configuration"]
    if "duration" in data:
        kwargs["duration"] = field_key(Scenario, "duration").check(
            "duration", data["duration"], source=source
        )
    if "q9" in data:
        kwargs["q9"] = check_tether_length(data["q9"], "q9", source=source)
    if "metrics_start" in data:
        kwargs["metrics_start"] = data["metrics_start"]  # checked with the rest by _validate
    if "control" in data:
        ctl = _vectors(source, "control", data["control"], ControlSettings)
        if "tether_lqi" in ctl:
            tl = _vectors(source, "control.tether_lqi", ctl["tether_lqi"], TetherLQISettings)
            ctl["tether_lqi"] = TetherLQISettings(**tl)
        if "mpc" in ctl:
            ctl["mpc"] = MPCSettings(**_vectors(source, "control.mpc", ctl["mpc"], MPCSettings))
        if "dt" in ctl:
            ctl["dt"] = field_key(ControlSettings, "dt").check(
                "control.dt", ctl["dt"], source=source
            )
        kwargs["control"] = ControlSettings(**ctl)
    if "limits" in data:
        lim = _table(source, "limits", data["limits"], Limits)
        kwargs["limits"] = Limits(
            **{
                k: field_key(Limits, k).check(f"limits.{k}", v, source=source)
                for k, v in lim.items()
            }
        )
    if "actuators" in data:
        act = _vectors(source, "actuators", data["actuators"], ActuatorSettings)
        kwargs["actuators"] = ActuatorSettings(**act)
    if "winch" in data:
        kwargs["winch"] = WinchSettings(**_table(source, "winch", data["winch"], WinchSettings))
    if "sensors" in data:
        if not isinstance(data["sensors"], dict):
            raise ParameterError("sensors", data["sensors"], "a table", source=source)
        kwargs["sensors"] = sensor_config_from_dict(data["sensors"], source=source)
    if "tether" in data:
        kwargs["tether"] = TetherSettings(
            **_table(source, "tether", data["tether"], TetherSettings)
        )
    if "seed" in data:
        kwargs["seed"] = data["seed"]  # checked with the rest by _validate
    if "wind" in data:
        kwargs["wind"] = disturbance_from_dict(data["wind"], source=source)
    if "params" in data:
        if not isinstance(data["params"], dict):
            raise ParameterError("params", data["params"], "a table", source=source)
        kwargs["params"] = Params.from_mapping(data["params"], source=source)
    scenario = Scenario.__new__(Scenario)
    defaults = Scenario.__dataclass_fields__
    for name, f in defaults.items():
        if name in kwargs:
            value = kwargs[name]
        elif f.default is not dataclasses.MISSING:
            value = f.default
        else:
            value = f.default_factory()  # type: ignore[misc]
        object.__setattr__(scenario, name, value)
    _validate(scenario, source)
    return scenario


def load_scenario(path: str | Path) -> Scenario:
    """Load and validate a scenario TOML file.

    Parameters
    ----------
    path : str or pathlib.Path
        The file; its keys are listed in the scenario TOML reference.

    Returns
    -------
    Scenario

    Raises
    ------
    ParameterError
        An unknown key, a wrong type or a value out of range, in one line naming the file,
        the key, the value and what is allowed.
    """
    return scenario_from_dict(read_toml(path, "scenario TOML file"), source=str(path))


def paper_scenario(
    simulation: int,
    configuration: Literal["free", "tethered"],
    *,
    pulse_duration: float = 1.0,
    dt: float = 0.01,
) -> Scenario:
    """Sec. VI's simulation 1 (wind along n1) or 2 (along n2), free or tethered: a 20 N pulse
    at t = 10 s lasting ``pulse_duration`` (not stated in the paper; 1 s assumed), then
    20 sin(2 pi 0.1 t) N from t = 30 s; 60 s; Tref = 25 N; references at trim.

    Parameters
    ----------
    simulation : {1, 2}
        Wind along n1 (1) or n2 (2).
    configuration : {"free", "tethered"}
        With or without the tether.
    pulse_duration : float, optional
        Length of the pulse (s); default 1 s.
    dt : float, optional
        Controller sample time (s); default 0.01 s.

    Returns
    -------
    Scenario
    """
    if simulation not in (1, 2):
        raise ParameterError("simulation", simulation, "1 or 2")
    return Scenario(
        name=f"paper_sim{simulation}_{configuration}",
        description=(
            f"Paper Sec. VI, simulation {simulation}, {configuration} configuration: 20 N pulse "
            f"along n{simulation} at t = 10 s lasting {pulse_duration:g} s (assumed; not stated "
            "in the paper), then 20 sin(2 pi 0.1 t) N from t = 30 s."
        ),
        configuration=configuration,
        duration=60.0,
        control=ControlSettings(dt=dt),
        wind=paper_wind(simulation, pulse_duration=pulse_duration),
    )
