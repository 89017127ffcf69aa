"""A scenario's tethered landing (``[maneuver] type = "tethered_landing"``): the
schedule and controller of ``control.landing`` built from the scenario and its set-up, and
the touchdown the Python loop detects (``Touchdown``) with the status it gives the run."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from ..control.landing import GroundHoldController, LandingController, LandingSchedule
from ..model.kinematics import tether_direction
from ..model.trim import _hover_trim
from ..scenario.tables import LANDING_PRESS_M
from ..status import Status

if TYPE_CHECKING:
    from ..scenario.core import Scenario
    from .setup import EngineSetup

__all__ = [
    "LANDING_TRIMS",
    "Touchdown",
    "ground_hold_controller",
    "landing_controller",
    "landing_schedule",
]

#: hover trims along a landing's tension schedule, interpolated by the controller
LANDING_TRIMS = 9


def landing_schedule(scenario: Scenario, setup: EngineSetup) -> LandingSchedule:
    """The descent of ``scenario``'s ``[maneuver]`` from its start's trim.

    Parameters
    ----------
    scenario : Scenario
        A run with a tethered landing.
    setup : EngineSetup
        Its set-up (the start's trim).

    Returns
    -------
    LandingSchedule
    """
    m = scenario.maneuver
    T_ref = scenario.params.tension_control.T_ref
    return LandingSchedule(
        start_time=m.start_time,
        descent_rate=m.descent_rate,
        start_height=float(setup.trim.y[2]),
        final_height=m.gear_height - LANDING_PRESS_M,
        start_tension=T_ref,
        landing_tension=T_ref if m.landing_tension is None else m.landing_tension,
        tether=scenario.params.tether,
    )


def landing_controller(scenario: Scenario, setup: EngineSetup) -> LandingController:
    """The paper's controller on the landing's schedule, with hover trims at
    ``LANDING_TRIMS`` tensions along it (at the scenario's q9: the trim's attitude does not
    depend on the tether's length, only its height does).

    Parameters
    ----------
    scenario : Scenario
        A run with a tethered landing.
    setup : EngineSetup
        Its set-up.

    Returns
    -------
    LandingController
    """
    schedule = landing_schedule(scenario, setup)
    tensions = np.linspace(schedule.start_tension, schedule.landing_tension, LANDING_TRIMS)
    if tensions[0] > tensions[-1]:
        tensions = tensions[::-1]
    # between T_ref and the landing tension, both checked against the tether by the scenario
    trims = [_hover_trim(setup.model.params, float(T), scenario.q9) for T in tensions]
    K, _, y_ref, u0, u0_free, z0 = setup.law
    trim = setup.trim
    return LandingController(
        schedule,
        tensions,
        np.array([t.u for t in trims]),
        np.array([t.x for t in trims]),
        float(trim.y[2] - trim.x[5]),
        K, trim.x, y_ref, u0, setup.ctrl, setup.model.constants,
        free_trim_input=u0_free, z_init=z0,
    )  # fmt: skip


class Touchdown:
    """Watches a landing's samples for the touchdown: the landing gear, ``gear_height`` below
    HO, reaching the deck (HO's height above the base, the recorded q3, at ``gear_height``).

    Parameters
    ----------
    scenario : Scenario
        A run with a tethered landing (its ``[maneuver]`` limits).
    """

    def __init__(self, scenario: Scenario) -> None:
        self.maneuver = scenario.maneuver
        self.dt = scenario.control.dt
        self._previous: tuple[float, np.ndarray, np.ndarray] | None = None

    def observe(self, k: int, x: np.ndarray, y: np.ndarray) -> dict[str, Any] | None:
        """The touchdown record (``SimulationResult.touchdown``) if sample k (its true state
        x and outputs y, relative to the base) is the first at or below the gear's height,
        interpolated linearly from the sample before; else None.

        Parameters
        ----------
        k : int
            The control sample's index.
        x : numpy.ndarray, shape (13,)
            The true state relative to the base [q4..q9, u1..u6, LN] in [rad, m, rad/s, m/s, m].
        y : numpy.ndarray, shape (4,)
            The true outputs q1, q2, q3, q6 relative to the base [m, m, m, rad].

        Returns
        -------
        dict or None
            The touchdown record: ``"time"`` [s], ``"vertical_speed"`` [m/s, downward positive],
            ``"offset"`` [m], ``"attitude"`` [rad] and ``"reasons"`` (empty); None before the
            touchdown.
        """
        height = self.maneuver.gear_height
        t = k * self.dt
        now = (t, x.copy(), y.copy())
        before, self._previous = self._previous, now
        if y[2] > height:
            return None
        if before is None:
            before = now
        t0, x0, y0 = before
        span = y0[2] - y[2]
        w = 1.0 if span <= 0.0 else (y0[2] - height) / span  # 0 at the sample before
        xs = x0 + w * (x - x0)
        ys = y0 + w * (y - y0)
        return {
            "time": t0 + w * (t - t0),
            "vertical_speed": float(-xs[8]),  # u3 relative to the base, downward positive
            "offset": float(math.hypot(ys[0], ys[1])),
            "attitude": float(math.acos(min(1.0, math.cos(xs[0]) * math.cos(xs[1])))),
            "reasons": [],
        }

    def judge(self, record: dict[str, Any]) -> int:
        """The run's status for a touchdown: LANDED within the limits, else HARD_TOUCHDOWN
        with the limits broken added to ``record["reasons"]``.

        Parameters
        ----------
        record : dict
            A touchdown record (``observe``'s); the limits broken are added to its ``"reasons"``.

        Returns
        -------
        int
            ``Status.LANDED`` or ``Status.HARD_TOUCHDOWN``.
        """
        m = self.maneuver
        checks = (
            ("vertical_speed", abs(record["vertical_speed"]), m.max_touchdown_speed, "m/s",
             "maneuver.max_touchdown_speed"),
            ("offset", record["offset"], m.max_touchdown_offset, "m",
             "maneuver.max_touchdown_offset"),
            ("attitude", record["attitude"], m.max_touchdown_attitude, "rad",
             "maneuver.max_touchdown_attitude"),
        )  # fmt: skip
        for name, value, limit, unit, key in checks:
            if value > limit:
                record["reasons"].append(f"{name} {value:.3g} {unit} > {key} = {limit:g}")
        return int(Status.HARD_TOUCHDOWN if record["reasons"] else Status.LANDED)


def ground_hold_controller(scenario: Scenario, setup: EngineSetup) -> GroundHoldController:
    """The paper's controller holding its start's point of N over the scenario's moving base
    (``[control] reference = "ground"``, ``control.landing.GroundHoldController``).

    Parameters
    ----------
    scenario : Scenario
        A run over a moving base.
    setup : EngineSetup
        Its set-up.

    Returns
    -------
    GroundHoldController
    """
    K, _, y_ref, u0, u0_free, z0 = setup.law
    trim = setup.trim
    q7, q8, q9 = trim.x[3:6]
    trim_P = q9 * tether_direction(q7, q8)  # P = q9 c3 (eq 27)
    motion = scenario.base_motion
    return GroundHoldController(
        lambda t: motion.state(t)[0], trim_P, K, trim.x, y_ref, u0, setup.ctrl,
        setup.model.constants, free_trim_input=u0_free, z_init=z0,
    )  # fmt: skip
