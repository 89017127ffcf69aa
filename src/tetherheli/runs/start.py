"""Where a run starts: the paper's LQI gain (``paper_gain``), the hover trims a run flies
from (the lumped tether's as the load cell sees it, ``load_cell_trim``; the free hover's
input after a release, ``free_trim_input``), the lumped chain at rest (``chain_start``), the
paper controller's law (``paper_law``) and the start in the wind (``start_point``).

A run starts at rest in the equilibrium of the air it meets at t = 0 (``start_point``): in a
turbulence that is the trim in the drag of its mean wind plus the gust drawn for t = 0 (the
gusts start from their stationary distribution), with the LQI's integrators z0 at the values
that make the paper controller command exactly that trim's inputs, as if the loop had been
flying in that air for a long time. Otherwise it is the windless trim with z0 = 0 (the
paper's runs: their force profiles arrive as they come).
"""

from __future__ import annotations

import functools
from functools import lru_cache
from typing import NamedTuple

import numpy as np

from .._linalg import _discretize_zoh
from .._validation import trusted
from ..control.lqi import LQIGain, _augment_lqi, _design_lqi
from ..control.tether_lqi import TetherLQIGain
from ..errors import InfeasibleError
from ..layout import CTRL_FFWD, CTRL_WINCH, empty_chain
from ..model import TetheredHelicopter, TrimPoint, kernels
from ..model.linearization import _linearize
from ..model.trim import _hover_trim
from ..names import TETHERED_STATE
from ..params import Params
from ..scenario.core import Scenario
from ..tether.chain import LumpedTether, static_chain
from ..tether.lumped import CHAIN_MAX_SUBSTEPS, COUPLING_OMEGA_H, chain_omega_max, ros2_work
from ..wind import initial_wind_force
from ..wind.profiles import Disturbance

__all__ = [
    "LQI_STATES",
    "MAX_KZ_CONDITION",
    "StartPoint",
    "chain_start",
    "free_trim_input",
    "load_cell_trim",
    "lumped_tether",
    "paper_gain",
    "paper_law",
    "start_point",
]


LQI_STATES = TETHERED_STATE[:12]


@lru_cache(maxsize=64)
def paper_gain(
    params: Params, dt: float, Qy: tuple[float, ...], Ru: tuple[float, ...], q9: float = 10.0
) -> LQIGain:
    """K_LQI|F: the LQI gain designed on the linearized tethered equations at TC = 0 (the free
    helicopter) about Table IV's hover (Sec. V-A, eqs 46-53), for sample time dt.

    Parameters
    ----------
    params : Params
        Parameters of the design model.
    dt : float
        Control sample time [s].
    Qy : tuple of 4 floats
        Diagonal of the output weight on q1, q2, q3, q6 (eq 50).
    Ru : tuple of 4 floats
        Diagonal of the input weight on fMR3, tMR1, tMR2, fTR2 (eq 50).
    q9 : float
        Tether length of the design hover [m].

    Returns
    -------
    LQIGain
        The discrete LQI gain K = [K_x, K_z], shape (4, 16).
    """
    model = TetheredHelicopter(params)
    lin = _linearize(model, _hover_trim(params, 0.0, q9)).select(LQI_STATES)
    G, H = _discretize_zoh(lin.A, lin.B, dt)  # dt, Qy and Ru: checked by the scenario
    G_lqi, H_lqi, C_lqi = _augment_lqi(G, H, lin.C, dt)
    return _design_lqi(G_lqi, H_lqi, C_lqi, dt, np.diag(Qy), np.diag(Ru))


def load_cell_trim(trim: TrimPoint, ground_tension: float, model: TetheredHelicopter) -> TrimPoint:
    """A lumped tether's trim as the paper controller flies it: the feed-forward C_f-fwd
    (eq 55) is built from the load cell's tension, the winch's T_g, not the tension at P of
    ``trim`` (T_g + mu g L0), so u0 = u_total + C_f-fwd(T_g) makes eq 54 command the trim's
    actual inputs u_total at the start (the massless tether's u0|T has T_g = T_P).

    Parameters
    ----------
    trim : TrimPoint
        ``hover_trim_lumped``'s helicopter trim (its feed-forward at the tension at P).
    ground_tension : float
        The tension at the winch [N].
    model : TetheredHelicopter
        The run's model.

    Returns
    -------
    TrimPoint
        The same state, outputs, tension at P and actual inputs; u and feedforward at T_g.
    """
    torque = np.empty(2)
    kernels.tethered_tether_torque(trim.x, float(ground_tension), model.constants, torque)
    ffwd = np.array([0.0, torque[0], torque[1], 0.0])
    return TrimPoint(
        x=trim.x, u=trim.u_total + ffwd, y=trim.y, tension=trim.tension, feedforward=ffwd
    )


def lumped_tether(scenario: Scenario) -> LumpedTether:
    """The ``LumpedTether`` of a scenario's ``[tether]`` table; EA = 0 takes the paper's
    stiffness, EA = K_C LN with the massless trim's natural length LN = q9 - T_ref / K_C
    (eq 28; ``LumpedTether.from_paper_stiffness``). Built ``trusted``: the scenario checked
    every key.

    Parameters
    ----------
    scenario : Scenario
        The run (any tether model: its ``[tether]`` keys are read).

    Returns
    -------
    LumpedTether
        The chain's parameters (air density ``wind.drag``'s default).
    """
    t = scenario.tether
    params = scenario.params
    kw = dict(
        segments=t.segments,
        mass_per_length_kg_m=t.mass_per_length,
        damping_ratio=t.damping_ratio if t.internal_damping == 0.0 else None,
        internal_damping_Ns=t.internal_damping if t.internal_damping > 0.0 else None,
        diameter_m=t.diameter,
        drag_coefficient=t.drag_coefficient,
        tangential_drag_coefficient=t.tangential_drag_coefficient,
        ground_stiffness_Pa_m=t.ground_stiffness,
        ground_damping_Pa_s_m=t.ground_damping,
        ground_friction=t.ground_friction,
        ground_friction_speed_m_s=t.ground_friction_speed,
    )
    build = functools.partial(trusted, LumpedTether)
    if t.EA > 0.0:
        return build(EA_N=t.EA, **kw)
    # L_N > 0: the scenario checked T_ref against the tether at q9
    L_N = params.tether.natural_length(scenario.q9, params.tension_control.T_ref)
    return LumpedTether._from_paper_stiffness(params.tether.K_C, L_N, build, **kw)


def chain_start(scenario: Scenario, trim: TrimPoint) -> tuple:
    """The run's ``chain`` (``layout.CHAIN_*``): for a lumped tether the static chain hanging
    from P straight down to the winch at rest (``tether.chain.static_chain``, the discrete
    catenary whose winch tension equals hover_trim_lumped's), fresh arrays; otherwise
    ``layout.empty_chain()``.

    Parameters
    ----------
    scenario : Scenario
        The run.
    trim : TrimPoint
        Its trim (x[5] = q9, x[12] = L0).

    Returns
    -------
    tuple of numpy.ndarray
        (nodes (N+1, 3), velocities (N+1, 3), params (LUMPED_SIZE,), ROS2 scratch).
    """
    if not scenario.tether.lumped:
        return empty_chain()
    tether = lumped_tether(scenario)
    g = scenario.params.helicopter.g
    q9, L0 = float(trim.x[5]), float(trim.x[12])
    T_g = scenario.params.tension_control.T_ref  # hover_trim_lumped's tension at the winch
    packed = tether._packed(g)  # g: a Params field, checked
    # the coupled step's rule (``tether.lumped.coupling_substeps``) at the trim's length: a
    # cable it cannot step within CHAIN_MAX_SUBSTEPS per sample is refused here, instead of
    # being flown for minutes with capped, unstable steps to a failure
    dt = scenario.control.dt
    needed = dt * chain_omega_max(packed, L0, tether.segments) / COUPLING_OMEGA_H
    if needed > CHAIN_MAX_SUBSTEPS:
        ea_max = tether.EA_N * (CHAIN_MAX_SUBSTEPS / needed) ** 2  # omega_max ~ sqrt(EA)
        raise InfeasibleError(
            "tether.EA",
            tether.EA_N,
            f"at most about {ea_max:.3g} N at this mass per length, segments and dt (the "
            f"coupled step would need {needed:.3g} RK4 steps per {dt:g} s sample, above the "
            f"engine's {CHAIN_MAX_SUBSTEPS})",
        )
    nodes = static_chain(np.zeros(3), np.array([0.0, 0.0, q9]), L0, tether, g, ground_tension_N=T_g)
    return (nodes, np.zeros_like(nodes), packed, ros2_work(tether.segments))


def free_trim_input(scenario: Scenario, model: TetheredHelicopter, trim: TrimPoint) -> np.ndarray:
    """u0|F (4,): the free hover's trim input (Table IV) at the scenario's q9, which the paper
    controller uses once the safety device has released the tether (``engine.paper_sample``).
    The free trim's state q4..u6 and outputs equal the tethered trim's (the tension acts along
    the shaft at hover), so only u0 changes; the free configuration's is its own trim input.

    Parameters
    ----------
    scenario : Scenario
        The run.
    model : TetheredHelicopter
        The run's model (``run_setup``).
    trim : TrimPoint
        The run's windless trim (``run_setup``).

    Returns
    -------
    numpy.ndarray, shape (4,)
        u0|F = (fMR3, tMR1, tMR2, fTR2) [N, N m, N m, N].
    """
    if scenario.configuration != "tethered":
        return trim.u.copy()
    return _free_trim_input(model.params, scenario.q9).copy()


@lru_cache(maxsize=256)
def _free_trim_input(params: Params, q9: float) -> np.ndarray:
    """``free_trim_input`` of a tethered run, once per (parameters, q9): a batch's runs share
    it (read-only)."""
    u = _hover_trim(params, 0.0, q9).u.copy()
    u.setflags(write=False)
    return u


def paper_law(
    gain: LQIGain | TetherLQIGain, trim: TrimPoint, u0_free: np.ndarray, z0: np.ndarray
) -> tuple:
    """The paper controller's law (gain, x_ref, y_ref, u0, u0_free, z0) (``layout.LAW_*``):
    ``trim`` is the windless trim (its state and outputs are the references), z0 the
    integrators' start (``start_point``). The tethered LQI's law works about the trim's total
    input (no feed-forward) and references LN too.

    Parameters
    ----------
    gain : LQIGain or TetherLQIGain
        The controller's gain, K of shape (4, 16) or (5, 17).
    trim : TrimPoint
        The windless trim.
    u0_free : numpy.ndarray, shape (4,)
        The free hover's trim input (``free_trim_input``).
    z0 : numpy.ndarray, shape (4,)
        The integrators' initial state (``start_point``).

    Returns
    -------
    tuple of 6 numpy.ndarray
        (K, x_ref, y_ref (4,), u0 (4,), u0_free (4,), z0 (4,)), contiguous.
    """
    K = np.ascontiguousarray(gain.K)
    return (
        K,
        np.ascontiguousarray(trim.x[: K.shape[1] - 4]),
        trim.y.copy(),
        trim.u_total.copy() if isinstance(gain, TetherLQIGain) else trim.u.copy(),
        np.ascontiguousarray(u0_free, dtype=float),
        np.array(z0, dtype=float),
    )


class StartPoint(NamedTuple):
    """Where a run starts (``start_point``): the trim in the steady wind and the LQI's
    integrator state z0 [m s, m s, m s, rad s] that holds it.

    Attributes
    ----------
    trim : TrimPoint
        The trim in the wind at t = 0 (its ``x`` is the initial state).
    z : numpy.ndarray, shape (4,)
        The integrators' initial state z0 [m s, m s, m s, rad s].
    """

    trim: TrimPoint
    z: np.ndarray  # (4,)

    @property
    def x(self) -> np.ndarray:
        """The initial state (13,)."""
        return self.trim.x


#: the largest condition number of the LQI's integrator block K_z accepted by ``start_point``
MAX_KZ_CONDITION = 1e10


def start_point(
    model: TetheredHelicopter,
    trim: TrimPoint,
    gain: LQIGain | TetherLQIGain,
    ctrl: np.ndarray,
    wind: Disturbance,
    q9: float,
    base_velocity: np.ndarray | None = None,
) -> StartPoint:
    """The equilibrium a run starts from in the air of ``wind`` at t = 0: the drag F of the
    turbulence's mean wind plus its gust at t = 0 (``wind.initial_wind_force``), relative
    to HO, which starts at rest relative to the winch's base (over a moving base it moves at
    the base's velocity b'(0) in N: a ship under way meets its apparent wind).

    The trim in F (``hover_trim(..., N_F_wind=F)``) keeps the windless
    trim's outputs, which stay the controller's references. The paper law (eq 54),
    u = u0 - K_x (x - x_ref) - K_z z - C_f-fwd, gives that trim's rotor inputs when
    K_z z0 = u0 - K_x (x_w - x_ref) - u_cmd, with u_cmd the trim's u0|T (feed-forward on) or
    its total input (off). K_z, the gain's 4 x 4 integrator block, must be invertible
    (condition number below ``MAX_KZ_CONDITION``). Without turbulence: ``trim`` and z0 = 0.

    Parameters
    ----------
    model : TetheredHelicopter
        As returned by ``run_setup``.
    trim : TrimPoint
        The windless trim (``run_setup``).
    gain : LQIGain or TetherLQIGain
        As returned by ``run_setup``.
    ctrl : numpy.ndarray, shape (CTRL_SIZE,)
        As returned by ``run_setup``.
    wind : Disturbance
        The run's disturbance.
    q9 : float
        The tether length of the windless trim [m].
    base_velocity : numpy.ndarray, shape (3,), optional
        The base's velocity b'(0) in N [m/s] (default None: a still base).

    Returns
    -------
    StartPoint
        The trim in the wind at t = 0 and z0.

    Raises
    ------
    InfeasibleError
        No trim in that wind (naming ``N_F_wind``).
        Or K_z is singular (naming ``control.Qy/Ru``).
    """
    force = initial_wind_force(wind, np.zeros(3) if base_velocity is None else base_velocity)
    if not np.any(force):
        return StartPoint(trim, np.zeros(4))
    windy = _hover_trim(model.params, trim.tension, q9, force)
    K = np.asarray(gain.K)
    n_x = K.shape[1] - 4  # 12, or 13 for the tethered LQI (whose rows 0-3 are its rotor law)
    K_x, K_z = K[:4, :n_x], K[:4, n_x:]
    cond = np.linalg.cond(K_z)
    if not cond < MAX_KZ_CONDITION:
        raise InfeasibleError(
            "control.Qy/Ru",
            f"an LQI gain whose integrator block K_z has condition number {cond:.3g}",
            f"weights giving an invertible K_z (condition < {MAX_KZ_CONDITION:g}), so that an "
            "integrator state holds the trim in the wind at t = 0",
        )
    u_law = trim.u_total if isinstance(gain, TetherLQIGain) else trim.u

    def integrators(windy: TrimPoint) -> np.ndarray:
        u_cmd = windy.u if ctrl[CTRL_FFWD] > 0.5 else windy.u_total
        rhs = u_law - K_x @ (windy.x[:n_x] - trim.x[:n_x]) - u_cmd
        return np.linalg.solve(K_z, rhs)

    z0 = integrators(windy)
    if isinstance(gain, TetherLQIGain) and ctrl[CTRL_WINCH] > 0.5:
        windy, z0 = _reel_at_rest(model, trim, K, force, q9, windy, z0, integrators)
    return StartPoint(windy, z0)


def _reel_at_rest(model, trim, K, force, q9, windy, z0, integrators):
    """The tethered LQI's start in wind: its fifth row (the reel rate) must command zero too.
    The windy trims of any tension keep the outputs (``hover_trim``), so the tension is the
    free unknown: the secant method on the reel command r(T) = -K_5 [x_w(T) - x_ref; z0(T)]
    (near-linear in T), from the windless trim's tension; returns (windy trim, z0)."""

    def reel(w: TrimPoint, z: np.ndarray) -> float:
        return float(-K[4, :13] @ (w.x[:13] - trim.x[:13]) - K[4, 13:] @ z)

    T_prev, r_prev = trim.tension, reel(windy, z0)
    T = 1.02 * T_prev
    for _ in range(12):
        # T is the secant's, not the scenario's: the tether must still give it (physics)
        model.params.tether.check_tension(T, q9, "tension")
        windy = _hover_trim(model.params, T, q9, force)
        z0 = integrators(windy)
        r = reel(windy, z0)
        if abs(r) < 1e-12 or r == r_prev:
            break
        T, T_prev, r_prev = T - r * (T - T_prev) / (r - r_prev), T, r
        if not T > 0.0:
            raise InfeasibleError(
                "control.tether_lqi", "a start in the wind", "weights whose reel row holds "
                "the winch at rest at a positive tension"
            )  # fmt: skip
    return windy, z0
