"""A scenario's tethered landing (``[maneuver] type = "tethered_landing"``): the
schedule and controller of ``control.landing`` built from the scenario and its set-up, and
the touchdown the Python loop detects (``Touchdown``) with the status it gives the run.

Without ``[landing_gear]`` (or with ``after_touchdown = "stop"``) the touchdown is a gate:
the run ends when the gear's height reaches the deck. With gear and ``after_touchdown``
``"thrust_cut"`` or ``"deck_lock"`` the run goes on for ``settle_time`` on the gear's
contact (``model.contact``, in the engine's step); the thrust goes to ground idle
(``GEAR_IDLE_THRUST_FRACTION`` m g), the cyclic and tail to the hover trim's, the winch
keeps its tension loop; with the deck lock each gear point is held where it first touches.
The run is "landed" when at the end of the settling every gear point is in contact, no
bounce rose above ``BOUNCE_HEIGHT_M``, the tilt is below ``max_touchdown_attitude`` and HO
is inside ``pad_radius`` (else NOT_SETTLED, with the reasons)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from ..control.landing import GroundHoldController, LandingController, LandingSchedule
from ..layout import DECK_SIZE, GEAR_WORK_DECK, LOADS_FORCE_N, LOCK_ANCHOR, LOCK_HELD, Gear
from ..model.contact import body_array, gear_contact
from ..model.kinematics import direction_cosines, tether_direction
from ..model.trim import _hover_trim
from ..results.files import GEAR_CONTACT_PREFIX, GEAR_FORCE_COLUMN, GEAR_PENETRATION_PREFIX
from ..scenario.tables import BOUNCE_HEIGHT_M, GEAR_IDLE_THRUST_FRACTION, LANDING_PRESS_M
from ..status import Status

if TYPE_CHECKING:
    from ..scenario.core import Scenario
    from .setup import EngineSetup

__all__ = [
    "LANDING_TRIMS",
    "Touchdown",
    "gear_columns",
    "gear_signals",
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


def gear_signals(gear: Gear, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, float]:
    """The gear's contact at a recorded sample, by the engine's own kernel
    (``model.contact.gear_contact`` against the gear's deck): each point's penetration and
    the total normal force.

    Parameters
    ----------
    gear : layout.Gear
        The run's gear (with points).
    x : numpy.ndarray, shape (13,)
        The true state relative to the base [q4..q9, u1..u6, LN] in [rad, m, rad/s, m/s, m].
    y : numpy.ndarray, shape (4,)
        The true outputs q1, q2, q3, q6 relative to the base [m, m, m, rad].

    Returns
    -------
    penetration : numpy.ndarray, shape (n,)
        Each point's depth below the deck [m] (<= 0: not in contact).
    force : float
        The deck's total force on the gear along n3 [N] (the normal force of the level
        deck).
    """
    R = direction_cosines(x[0], x[1], x[2])
    body = body_array(y[:3], x[6:9], R, x[9:12])
    loads = np.zeros(6)
    penetration = np.zeros(gear.points.shape[0])
    deck = gear.work[GEAR_WORK_DECK : GEAR_WORK_DECK + DECK_SIZE].copy()
    gear_contact(gear.points, gear.law, body, deck, loads, penetration)
    return penetration, float(loads[LOADS_FORCE_N + 2])


class Touchdown:
    """Watches a landing's samples for the touchdown and, with landing gear that goes on
    after it (``[maneuver] after_touchdown``), for the settling.

    Without gear the touchdown is the gear's height ``gear_height`` below HO reaching the
    deck (HO's height above the base, the recorded q3, at ``gear_height``); with gear, the
    first contact of a gear point (its penetration, ``gear_signals``). The run ends there
    ("stop"), or ``settle_time`` later, judged by ``settle``.

    Parameters
    ----------
    scenario : Scenario
        A run with a tethered landing (its ``[maneuver]`` limits).
    gear : layout.Gear, optional
        The run's gear (``runs.setup.run_gear``; None or no points: no gear).
    trim_input : numpy.ndarray, shape (4,), optional
        The hover trim's rotor inputs [N, N m, N m, N]: the cyclic and tail after a thrust
        cut (needed when the run settles).
    """

    def __init__(
        self, scenario: Scenario, gear: Gear | None = None, trim_input: np.ndarray | None = None
    ) -> None:
        self.maneuver = scenario.maneuver
        self.dt = scenario.control.dt
        self._previous: tuple[float, np.ndarray, np.ndarray, float] | None = None
        self.gear = gear if gear is not None and gear.points.shape[0] > 0 else None
        self.settles = self.gear is not None and self.maneuver.after_touchdown != "stop"
        h = scenario.params.helicopter
        trim = np.zeros(4) if trim_input is None else np.asarray(trim_input, dtype=float)
        #: the rotor inputs after a thrust cut: ground idle, the trim's cyclic and tail
        self.idle_inputs = np.array([GEAR_IDLE_THRUST_FRACTION * h.m * h.g, *trim[1:4]])
        #: the first contact's record (``observe``), None before it
        self.record: dict[str, Any] | None = None
        self._end = math.inf
        self._airborne = False
        self._bounces = 0
        self._max_penetration = 0.0
        self._rows: list[np.ndarray] = []
        self._judged = False

    def _height(self, x: np.ndarray, y: np.ndarray) -> float:
        # the gear's height above the deck: the lowest point's, or HO's less gear_height
        if self.gear is None:
            return float(y[2] - self.maneuver.gear_height)
        penetration = gear_signals(self.gear, x, y)[0]
        self._rows.append(penetration)
        return float(-penetration.max())

    def observe(self, k: int, x: np.ndarray, y: np.ndarray) -> dict[str, Any] | None:
        """The touchdown record (``SimulationResult.touchdown``) if sample k (its true state
        x and outputs y, relative to the base) is the first with the gear at or below the
        deck, interpolated linearly from the sample before; else None.

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
        height = self._height(x, y)
        t = k * self.dt
        now = (t, x.copy(), y.copy(), height)
        before, self._previous = self._previous, now
        if height > 0.0:
            return None
        if before is None:
            before = now
        t0, x0, y0, h0 = before
        span = h0 - height
        w = 1.0 if span <= 0.0 else h0 / span  # 0 at the sample before
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

    def inputs(self, command: np.ndarray) -> np.ndarray:
        """The rotor inputs to apply: ``command`` before the touchdown (or without
        settling), the thrust cut's (``idle_inputs``) after it.

        Parameters
        ----------
        command : numpy.ndarray, shape (4,)
            The controller's rotor inputs [N, N m, N m, N].

        Returns
        -------
        numpy.ndarray, shape (4,)
            The inputs [N, N m, N m, N].
        """
        if self.settles and self.record is not None:
            return self.idle_inputs.copy()
        return command

    def step(self, k: int, x: np.ndarray, y: np.ndarray) -> int | None:
        """Sample k watched: the run's final status when it ends here (a touchdown without
        settling, a hard touchdown, the end of the settling), else None.

        Parameters
        ----------
        k : int
            The control sample's index.
        x : numpy.ndarray, shape (13,)
            The true state relative to the base [rad, m, rad/s, m/s, m].
        y : numpy.ndarray, shape (4,)
            The true outputs relative to the base [m, m, m, rad].

        Returns
        -------
        int or None
            The status (``Status``) or None: the run goes on.
        """
        if self.record is None:
            record = self.observe(k, x, y)
            if record is None:
                return None
            self.record = record
            status = self.judge(record)
            if self.gear is not None:
                self._max_penetration = float(self._rows[-1].max())
                record.update(settled=False, max_penetration=self._max_penetration, bounces=0)
            if not self.settles or status != Status.LANDED:
                return status
            self._end = record["time"] + self.maneuver.settle_time
            self._capture(x, y)
            return None
        assert self.gear is not None  # (settles)
        self._height(x, y)  # this sample's row
        depth = self._rows[-1]
        self._capture(x, y)
        self._max_penetration = max(self._max_penetration, float(depth.max()))
        lowest = -float(depth.max())
        if lowest > BOUNCE_HEIGHT_M and not self._airborne:
            self._bounces += 1
        if lowest > BOUNCE_HEIGHT_M:
            self._airborne = True
        elif lowest <= 0.0:
            self._airborne = False
        if k * self.dt < self._end - 1e-9:
            return None
        return self.settle(x, y, depth)

    def _capture(self, x: np.ndarray, y: np.ndarray) -> None:
        # the deck lock: each gear point in contact and not yet held is held where it is
        # (the engine's ``contact.lock_loads`` reads the same ``Gear.lock``)
        if self.maneuver.after_touchdown != "deck_lock" or self.gear is None:
            return
        lock, depth = self.gear.lock, self._rows[-1]
        R = direction_cosines(x[0], x[1], x[2])
        for i in range(depth.shape[0]):
            if depth[i] > 0.0 and lock[i, LOCK_HELD] < 0.5:
                lock[i, LOCK_ANCHOR : LOCK_ANCHOR + 3] = y[:3] + R @ self.gear.points[i]
                lock[i, LOCK_HELD] = 1.0

    def settle(self, x: np.ndarray, y: np.ndarray, depth: np.ndarray, *, cut: bool = False) -> int:
        """The verdict at the end of the settling (or of the run, ``cut``): LANDED when every
        gear point is in contact, no bounce rose above ``BOUNCE_HEIGHT_M``, the tilt is
        below ``max_touchdown_attitude`` and HO is within ``pad_radius`` of the pad; else
        NOT_SETTLED with the reasons added to the record (``settled``: every point in
        contact; ``max_penetration`` [m]; ``bounces``).

        Parameters
        ----------
        x : numpy.ndarray, shape (13,)
            The true state relative to the base at the end [rad, m, rad/s, m/s, m].
        y : numpy.ndarray, shape (4,)
            The true outputs relative to the base at the end [m, m, m, rad].
        depth : numpy.ndarray, shape (n,)
            Each gear point's penetration at the end [m].
        cut : bool, optional
            Whether the run's end cut the settling short.

        Returns
        -------
        int
            ``Status.LANDED`` or ``Status.NOT_SETTLED``.
        """
        record, m = self.record, self.maneuver
        assert record is not None
        self._judged = True
        reasons = record["reasons"]
        touching = int((depth > 0.0).sum())
        if cut:
            reasons.append(f"the run ended before maneuver.settle_time = {m.settle_time:g} s")
        if touching < depth.shape[0]:
            reasons.append(f"{touching} of {depth.shape[0]} gear points in contact at the end")
        if self._bounces:
            reasons.append(f"{self._bounces} bounce(s) above {BOUNCE_HEIGHT_M:g} m")
        tilt = math.acos(min(1.0, math.cos(x[0]) * math.cos(x[1])))
        if tilt > m.max_touchdown_attitude:
            reasons.append(f"tilt {tilt:.3g} rad > maneuver.max_touchdown_attitude = "
                           f"{m.max_touchdown_attitude:g}")  # fmt: skip
        offset = math.hypot(y[0], y[1])
        if offset > m.pad_radius:
            reasons.append(f"offset {offset:.3g} m > maneuver.pad_radius = {m.pad_radius:g}")
        record.update(settled=touching == depth.shape[0],
                      max_penetration=self._max_penetration, bounces=self._bounces)  # fmt: skip
        return int(Status.NOT_SETTLED if reasons else Status.LANDED)

    def finish(self, x: np.ndarray, y: np.ndarray) -> int | None:
        """The verdict of a run that ended while settling (``settle`` with ``cut``), else None.

        Parameters
        ----------
        x : numpy.ndarray, shape (13,)
            The last recorded true state relative to the base [rad, m, rad/s, m/s, m].
        y : numpy.ndarray, shape (4,)
            The last recorded outputs relative to the base [m, m, m, rad].

        Returns
        -------
        int or None
            The status, or None when not settling.
        """
        if not self.settles or self.record is None or self._judged or self.gear is None:
            return None
        depth = self._rows[-1]
        return self.settle(x, y, depth, cut=True)


def gear_columns(gear: Gear, x: np.ndarray, y: np.ndarray) -> dict[str, np.ndarray]:
    """A run's gear as per-sample columns (``results.files.EXTRA_UNITS``): ``gear_force``
    [N], then per point i ``gear_penetration<i>`` [m] and ``gear_contact<i>`` (1: in
    contact), from the recorded samples (``gear_signals``); empty without gear points.

    Parameters
    ----------
    gear : layout.Gear
        The run's gear.
    x : numpy.ndarray, shape (samples, 13)
        The recorded true states relative to the base.
    y : numpy.ndarray, shape (samples, 4)
        The recorded true outputs relative to the base.

    Returns
    -------
    dict of str to numpy.ndarray
        The columns, one value per sample.
    """
    n = gear.points.shape[0]
    if n == 0:
        return {}
    force = np.empty(x.shape[0])
    depth = np.empty((x.shape[0], n))
    for k in range(x.shape[0]):
        depth[k], force[k] = gear_signals(gear, x[k], y[k])
    out = {GEAR_FORCE_COLUMN: force}
    for i in range(n):
        out[f"{GEAR_PENETRATION_PREFIX}{i}"] = depth[:, i]
    for i in range(n):
        out[f"{GEAR_CONTACT_PREFIX}{i}"] = (depth[:, i] > 0.0).astype(float)
    return out


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
