"""The tables of a scenario file, one frozen dataclass each: ``[control]`` (with
``[control.tether_lqi]`` and ``[control.mpc]``), ``[limits]``, ``[actuators]``, ``[tether]``
and ``[winch]``.

Each field carries its ``Key`` (meaning, unit, default, allowed range): the one description
that ``scenario.checks`` checks against and ``scenario.reference`` prints. The scenario itself,
its TOML form and its loader are ``scenario.core``.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from .._validation import RK4_SUBSTEPS, Key
from ..base.motion import BASE_KEYS
from ..control import lqi
from ..control.registry import CONTROLLERS
from ..layout import (
    GROUND_DAMPING_PA_S_M,
    GROUND_FRICTION,
    GROUND_FRICTION_SPEED_M_S,
    GROUND_STIFFNESS_PA_M,
    WINCH_MIN_LENGTH_M,
)
from ..tether.chain import CABLE_KEYS

if TYPE_CHECKING:
    from _typeshed import DataclassInstance

__all__ = [
    "AFTER_TOUCHDOWN",
    "BOUNCE_HEIGHT_M",
    "CONTROLLERS",
    "DECK_LOCK_DAMPING",
    "DECK_LOCK_STIFFNESS",
    "GEAR_IDLE_THRUST_FRACTION",
    "LANDING_MIN_LENGTH_M",
    "LANDING_PRESS_M",
    "MANEUVERS",
    "MPC_OBSERVERS",
    "MPC_QY_GNSS",
    "PAPER_EA_N",
    "REFERENCES",
    "TETHER_LAWS",
    "TETHER_MODELS",
    "WINCH_MODELS",
    "ActuatorSettings",
    "BaseSettings",
    "ControlSettings",
    "LandingGearSettings",
    "Limits",
    "MPCSettings",
    "ManeuverSettings",
    "TetherLQISettings",
    "TetherSettings",
    "WinchSettings",
    "field_key",
]

#: The paper's LQI weights (Sec. V-A, after eq 53) as the diagonals the scenario files list;
#: the one source is ``control.lqi.PAPER_QY`` / ``PAPER_RU``.
PAPER_QY: tuple[float, ...] = tuple(np.diag(lqi.PAPER_QY).tolist())
PAPER_RU: tuple[float, ...] = tuple(np.diag(lqi.PAPER_RU).tolist())


def _key(default: Any, key: Key) -> Any:
    """A dataclass field with its ``Key`` (documentation, unit, allowed values): the one
    description ``scenario_checks`` checks against and ``tetherheli.scenario.reference`` prints."""
    return field(default=default, metadata={"key": key})


def field_key(cls: type[DataclassInstance], name: str) -> Key:
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


# The controllers ``[control] controller`` selects, ``CONTROLLERS``: the names of
# ``control.registry.CONTROLLER_REGISTRY`` (the paper's scheme, Sec. V; the LQI on the
# tethered linearization with the reel rate as a fifth input; the constrained MPC).
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


#: What a controller holds over a moving base (``[control] reference``): a point fixed in N,
#: or a point fixed to the base (the controllers then fly on the position and velocity
#: relative to the base)
REFERENCES: tuple[str, ...] = ("ground", "base")


@dataclass(frozen=True)
class ControlSettings:
    """Controller and integrator settings (Sec. V).

    Parameters
    ----------
    dt, substeps, feedforward, Qy, Ru, controller, tether_lqi, mpc, reference, base_feedforward
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
    substeps: int = _key(2, RK4_SUBSTEPS)
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
    reference: str | None = _key(
        None,
        Key("what the controller holds over a moving base ([base]): a point of N ('ground') "
            "or a point fixed to the base ('base': the controllers fly on the position and "
            "velocity relative to the base)", kind="text", choices=REFERENCES,
            unset="'ground' over a still base, 'base' over a moving one"),
    )  # fmt: skip
    base_feedforward: bool = _key(
        False,
        Key("feed the moving base's known vertical acceleration forward to the thrust, "
            "fMR3 += m b''_3 / (cos q4 cos q5) (control.deck; a deck motion sensor)",
            kind="bool"),
    )  # fmt: skip


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
#: and the lumped-mass chain (``tether.lumped``).
TETHER_MODELS: tuple[str, ...] = ("elastic", "lumped")
#: The massless tether's laws ``[tether] law`` selects (``params.TetherParams``): the paper's
#: eq 28, TC = KC (q9 - LN), and a rope's TC = EA (q9 - LN) / LN (issue 46).
TETHER_LAWS: tuple[str, ...] = ("paper", "rope")
#: The paper's EA [N]: Table III's KC = 40 N/m at L0N = 9.375 m, EA = KC L0N, the rope a
#: tethered landing flies when its scenario names no law.
PAPER_EA_N = 40.0 * 9.375


@dataclass(frozen=True)
class TetherSettings:
    """The tether model (``[tether]``). "elastic" is the paper's massless straight
    tether (eq 28, stiffness ``params.tether.K_C``); "lumped" the chain of
    ``tether.lumped`` (point masses, axial elasticity slack in compression, axial
    damping, gravity, normal and tangential drag in the gust table's air), whose bottom node
    is the winch and whose top node moves with P. The other keys apply to "lumped" only.

    EA = 0 takes the paper's stiffness: the whole tether's spring constant K_C at the
    massless trim's natural length LN = q9 - T_ref / K_C is EA / LN, so EA = K_C LN
    (``LumpedTether.from_paper_stiffness``; 375 N at the paper's hover).

    ``law`` chooses the massless ("elastic") tether's tension law: the paper's eq 28 (KC
    independent of the length) or a rope, TC = EA (q9 - LN) / LN with ``EA`` its axial
    stiffness (required with it), whose stiffness EA / LN grows as the winch reels in: the
    short tether of a landing. Unset, a tethered landing flies the rope with the paper's
    EA = KC L0N = 375 N (or ``EA`` when given), every other run the paper's law. The lumped
    chain is a rope already (each segment EA strain): with it ``law`` stays unset or
    "paper" and ``EA`` is the chain's; at the same EA and unstretched length the massless
    rope is the chain's limit of zero mass (``tests/test_rope.py``).

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
    model, law, segments, mass_per_length, EA, damping_ratio, internal_damping, diameter,
    drag_coefficient, tangential_drag_coefficient, ground_stiffness, ground_damping,
    ground_friction, ground_friction_speed, record_nodes
        The keys of a scenario's ``[tether]`` table; each field's ``Key`` gives its meaning,
        unit, default and allowed range. The ground keys are the plane z = 0 through the
        winch under the chain's free nodes (MoorDyn's seabed; ``tether.lumped``).
    """

    model: str = _key(
        "elastic",
        Key("the tether model: the paper's massless elastic tether (eq 28) or a lumped-mass "
            "chain with sag and drag (tether.lumped)", kind="text",
            choices=TETHER_MODELS),
    )  # fmt: skip
    law: str | None = _key(
        None,
        Key("the massless tether's tension law: the paper's eq 28, KC (q9 - LN), or a rope's "
            "EA (q9 - LN) / LN", kind="text", choices=TETHER_LAWS,
            note="'rope' with model = 'elastic' only",
            unset="'rope' with EA = 375 N (the paper's KC L0N) in a tethered landing, else "
            "'paper'"),
    )  # fmt: skip
    segments: int = _key(10, CABLE_KEYS["segments"])
    mass_per_length: float = _key(0.02, CABLE_KEYS["mass_per_length"])
    EA: float = _key(
        0.0,
        dataclasses.replace(
            CABLE_KEYS["EA"],
            doc="axial stiffness: the lumped chain's (0: the paper's K_C times the massless "
            "trim's natural length q9 - T_ref / K_C) or the rope law's (law = 'rope')",
            low=0.0,
            note="0 or at least 1; with model = 'elastic' only with the rope, then required",
        ),
    )
    damping_ratio: float = _key(0.1, CABLE_KEYS["damping_ratio"])
    internal_damping: float = _key(0.0, CABLE_KEYS["internal_damping"])
    diameter: float = _key(0.005, CABLE_KEYS["diameter"])
    drag_coefficient: float = _key(1.1, CABLE_KEYS["drag_coefficient"])
    tangential_drag_coefficient: float = _key(0.0, CABLE_KEYS["tangential_drag_coefficient"])
    ground_stiffness: float = _key(GROUND_STIFFNESS_PA_M, CABLE_KEYS["ground_stiffness"])
    ground_damping: float = _key(GROUND_DAMPING_PA_S_M, CABLE_KEYS["ground_damping"])
    ground_friction: float = _key(GROUND_FRICTION, CABLE_KEYS["ground_friction"])
    ground_friction_speed: float = _key(
        GROUND_FRICTION_SPEED_M_S, CABLE_KEYS["ground_friction_speed"]
    )
    record_nodes: bool = _key(
        False, Key("record the chain's node positions at every sample (result extras)",
                   kind="bool"),
    )  # fmt: skip

    @property
    def lumped(self) -> bool:
        """Whether the tether is the lumped-mass chain."""
        return self.model == "lumped"


#: The winch models ``[winch] model`` selects: the paper's (the reel rate of eq 56 applied as
#: commanded, dL_N/dt = R_C, eq 37) and a drum driven by a speed loop (``tether.winch``).
WINCH_MODELS: tuple[str, ...] = ("ideal", "drum")


@dataclass(frozen=True)
class WinchSettings:
    """The ground winch (``[winch]``): ideal (the paper's) or a drum with inertia, friction
    and a torque-limited drive whose speed loop follows the reel rate of eq 56
    (``tether.winch``: J w' = r T_g - tau_m - b w - tau_c sign(w), dL_N/dt = r w, w > 0
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
            "drum with inertia, friction and a torque-limited speed loop (tether.winch)",
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


@dataclass(frozen=True)
class BaseSettings:
    """The winch's base (``[base]``): still at the origin of N (the paper's winch,
    the default), or moving (``tetherheli.base``). Over a moving base the engine flies the
    helicopter and the tether in the base's translating frame and the results record the
    base's motion (``base_n1..3``, ``base_v1..3``; over a ship also the deck's attitude,
    ``deck_roll`` ...).

    Parameters
    ----------
    motion, position, velocity, amplitude, frequency, phase, significant_wave_height,
    peak_period, peak_enhancement, seed, sway_scale, surge_scale, components, file, file_sha256,
    wave_heading, speed, pad, rao_file, rao_file_sha256
        The keys of a scenario's ``[base]`` table, described once in
        ``tetherheli.base.motion.BASE_KEYS``; ``MOTION_KEYS`` says which keys each motion
        reads (the others keep their defaults).
    """

    motion: str = _key("fixed", BASE_KEYS["motion"])
    position: tuple[float, ...] = _key((0.0, 0.0, 0.0), BASE_KEYS["position"])
    velocity: tuple[float, ...] = _key((0.0, 0.0, 0.0), BASE_KEYS["velocity"])
    amplitude: tuple[float, ...] = _key((0.0, 0.0, 0.0), BASE_KEYS["amplitude"])
    frequency: tuple[float, ...] = _key((0.0, 0.0, 0.0), BASE_KEYS["frequency"])
    phase: tuple[float, ...] = _key((0.0, 0.0, 0.0), BASE_KEYS["phase"])
    significant_wave_height: float = _key(1.0, BASE_KEYS["significant_wave_height"])
    peak_period: float = _key(8.0, BASE_KEYS["peak_period"])
    peak_enhancement: float = _key(3.3, BASE_KEYS["peak_enhancement"])
    seed: int = _key(0, BASE_KEYS["seed"])
    sway_scale: float = _key(0.0, BASE_KEYS["sway_scale"])
    surge_scale: float = _key(0.0, BASE_KEYS["surge_scale"])
    components: int = _key(128, BASE_KEYS["components"])
    file: str = _key("", BASE_KEYS["file"])
    file_sha256: str = _key("", BASE_KEYS["file_sha256"])
    wave_heading: float = _key(0.0, BASE_KEYS["wave_heading"])
    speed: float = _key(0.0, BASE_KEYS["speed"])
    pad: tuple[float, ...] = _key((0.0, 0.0, 0.0), BASE_KEYS["pad"])
    rao_file: str = _key("", BASE_KEYS["rao_file"])
    rao_file_sha256: str = _key("", BASE_KEYS["rao_file_sha256"])


#: a landing's reference descends this far below the touchdown height [m], so that the
#: touchdown happens while still descending (``control.landing.LandingSchedule``)
LANDING_PRESS_M = 0.05
#: the shortest tether length q9 at a landing's final reference [m]: P this high above the
#: deck keeps the spherical coordinates (eq 27) away from q9 = 0
LANDING_MIN_LENGTH_M = 0.08
#: the maneuvers a ``[maneuver]`` table's ``type`` names: none (hold the hover) or a tethered
#: what follows the first contact of a landing's gear: the run ends there ("stop", the
#: touchdown gate; no ``[landing_gear]`` needed), or goes on with the thrust at ground idle
#: ("thrust_cut") or with the gear points in contact held by the deck lock ("deck_lock")
AFTER_TOUCHDOWN: tuple[str, ...] = ("stop", "thrust_cut", "deck_lock")
#: the ground-idle thrust after a thrust cut, as a fraction of the helicopter's weight m g
#: (assumed: the rotor kept turning at a collective giving a tenth of hover thrust)
GEAR_IDLE_THRUST_FRACTION = 0.1
#: a gear point rising more than this above the deck after the first contact is a bounce [m]
BOUNCE_HEIGHT_M = 0.05
#: the deck lock's anchor (``after_touchdown = "deck_lock"``, a harpoon in a grid): the
#: stiffness [N/m] and damping [N s/m] holding each captured gear point (assumed: ten times
#: the default gear's stiffness, about critically damped for a quarter of the mass)
DECK_LOCK_STIFFNESS = 10000.0
DECK_LOCK_DAMPING = 150.0
#: the most gear points of a ``[landing_gear]``
MAX_GEAR_POINTS = 16


@dataclass(frozen=True)
class LandingGearSettings:
    """The landing gear (``[landing_gear]``): points fixed in the fuselage that touch the deck
    (the plane through the winch's base, normal n3) through a compliant contact
    (``model.contact.gear_contact``: Kelvin-Voigt normal force, regularised Coulomb
    friction), part of the one sample step. The default is a skid for the paper's
    helicopter (assumed: four points at (+-0.4, +-0.3, -0.35) m from HO in F, the 0.35 m
    of ``maneuver.gear_height``), stiff enough for a static deflection m g / (n k) of
    about 1.6 cm and damped at about 0.6 of critical per point (m / n each).

    Parameters
    ----------
    points, stiffness, damping, friction, slip_speed
        The keys of a scenario's ``[landing_gear]`` table; each field's ``Key`` gives its
        meaning, unit, default and allowed range.
    """

    points: tuple[tuple[float, float, float], ...] = _key(
        ((0.4, 0.3, -0.35), (0.4, -0.3, -0.35), (-0.4, 0.3, -0.35), (-0.4, -0.3, -0.35)),
        Key("the gear points from HO in F (f3 up through the rotor: below HO is negative)",
            "m", kind="points", length=MAX_GEAR_POINTS, low=-5.0, high=5.0,
            note="the lowest below HO (f3 component < 0)"),
    )  # fmt: skip
    stiffness: float = _key(
        2000.0, Key("normal stiffness per gear point", "N/m", low=0.0, low_open=True, high=1e7)
    )
    damping: float = _key(100.0, Key("normal damping per gear point", "N s/m", low=0.0, high=1e6))
    friction: float = _key(0.5, Key("Coulomb friction coefficient", "", low=0.0, high=2.0))
    slip_speed: float = _key(
        0.01,
        Key("slip speed below which the friction is viscous (regularised Coulomb)", "m/s",
            low=0.0, low_open=True, high=1.0),
    )  # fmt: skip

    @property
    def gear_height(self) -> float:
        """The lowest gear point's depth below HO along f3 [m]."""
        return -min(p[2] for p in self.points)


#: landing (``control.landing``)
MANEUVERS: tuple[str, ...] = ("none", "tethered_landing")


@dataclass(frozen=True)
class ManeuverSettings:
    """A maneuver flown in the run (``[maneuver]``): by default none (the paper's
    station-keeping); ``type = "tethered_landing"``: from the hover over the winch's base,
    descend relative to it while the winch reels in under a tension schedule, and touch
    down (``control.landing``). The run ends at touchdown (``after_touchdown = "stop"``), or
    goes on ``settle_time`` on the landing gear (``[landing_gear]``), with status "landed",
    or a failure with its reason, and records the touchdown (``SimulationResult.touchdown``).

    Parameters
    ----------
    type, start_time, descent_rate, landing_tension, gear_height, max_touchdown_speed,
    max_touchdown_offset, max_touchdown_attitude, after_touchdown, settle_time, pad_radius
        The keys of a scenario's ``[maneuver]`` table; each field's ``Key`` gives its
        meaning, unit, default and allowed range.
    """

    type: str = _key(
        "none",
        Key("the maneuver: none (hold the hover) or a tethered landing on the winch's base",
            kind="text", choices=MANEUVERS),
    )  # fmt: skip
    start_time: float = _key(
        5.0, Key("hover before the descent starts", "s", low=0.0, note="below duration")
    )
    descent_rate: float = _key(
        0.3,
        Key("the reference height's rate of fall relative to the base", "m/s", low=0.0,
            low_open=True, high=2.0),
    )  # fmt: skip
    landing_tension: float | None = _key(
        None,
        Key("the tension reference at touchdown; it goes linearly with the height from "
            "params.tension_control.T_ref", "N", low=0.0, low_open=True,
            note="at most the tension at LN = q9 / 2 at touchdown (eq 28's KC q9 / 2, the "
            "rope's EA)",
            unset="params.tension_control.T_ref"),
    )  # fmt: skip
    gear_height: float = _key(
        0.35,
        Key("the landing gear's height below HO: touchdown when HO is this high above the "
            "deck (the winch's plane)", "m", low=0.0, low_open=True, high=5.0),
    )  # fmt: skip
    max_touchdown_speed: float = _key(
        0.5,
        Key("the largest vertical speed relative to the deck at touchdown of a landing (a "
            "skid gear's design sink rate is 2-3 m/s; beyond 5 m/s a touchdown is a crash)",
            "m/s", low=0.0, low_open=True, high=5.0),
    )  # fmt: skip
    max_touchdown_offset: float = _key(
        0.5,
        Key("the largest horizontal distance of HO from the pad (the winch) at touchdown "
            "(a landing spot on a ship's deck is a few metres across)",
            "m", low=0.0, low_open=True, high=10.0),
    )  # fmt: skip
    max_touchdown_attitude: float = _key(
        0.26,
        Key("the largest tilt of the fuselage (the angle between f3 and n3) at touchdown",
            "rad", low=0.0, low_open=True, high=1.5),
    )  # fmt: skip
    after_touchdown: str = _key(
        "stop",
        Key("after the first contact: the run ends (stop), or goes on with the thrust at "
            f"ground idle ({GEAR_IDLE_THRUST_FRACTION:g} m g) and the cyclic and tail at trim "
            "(thrust_cut), or with that and the gear points in contact held where they "
            "touched (deck_lock)", kind="text", choices=AFTER_TOUCHDOWN,
            note="thrust_cut and deck_lock need [landing_gear]"),
    )  # fmt: skip
    settle_time: float = _key(
        3.0, Key("how long the run goes on after the first contact", "s", low=0.0,
                 low_open=True, high=60.0),
    )  # fmt: skip
    pad_radius: float = _key(
        1.0, Key("the landing pad's radius about the winch: HO inside it at the end of the "
                 "settling", "m", low=0.0, low_open=True, high=50.0),
    )  # fmt: skip

    @property
    def landing(self) -> bool:
        """Whether the maneuver is a tethered landing."""
        return self.type == "tethered_landing"
