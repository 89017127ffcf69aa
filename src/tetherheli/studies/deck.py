"""The moving-deck study: station-keeping relative to a heaving deck over
sea states, free against tethered, with perfect sensors, GNSS or the tether as the position
sensor; and the tethered landing's success rate and touchdown figures over a Monte Carlo of
sea-state seeds (the waves' phases).

The runs are the shipped scenarios ``deck_sea_state_tethered``/``deck_sea_state_free``
(the paper's simulation 1 winds over the deck) and ``landing_sea_state``, with the
significant wave height and the seed varied; the sensors are the shipped sensing suites'
(``sensing_gps``, ``sensing_tether``: consumer GNSS or the tether's geometry as the position
source). Over the deck the sensors measure the state relative to it: the GNSS as the
helicopter's receiver minus the deck's (its noise model applied once: the common-mode errors
cancel, the deck receiver's own noise is not added), the laser altimeter the height above the
deck, the tether its geometry from the deck's winch. The study returns rows; the docs page
(``docs/studies/deck.md``, ``benchmarks/deck_study.py``) draws them.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ..base.motion import BASE_KEYS
from ..errors import ParameterError
from ..runs.batch import run_batch
from ..runs.closed_loop import simulate
from ..scenario.core import Scenario
from ..shipped import shipped_scenario
from ..status import Status

__all__ = [
    "SENSINGS",
    "LandingRow",
    "StationRow",
    "landing_rows",
    "sea_state",
    "station_rows",
]

#: the position sensing of the station-keeping runs: the true state, or a shipped suite's
SENSINGS: dict[str, str | None] = {
    "perfect": None,
    "gnss": "sensing_gps",
    "tether": "sensing_tether",
}
#: the configurations flown (``deck_sea_state_<configuration>``)
CONFIGURATIONS = ("free", "tethered")
#: the most values of one argument of the grid (heights, seeds, ...)
MAX_GRID = 10_000


def _grid(name: str, values: Any, allowed: str, ok: Callable[[Any], bool]) -> tuple:
    """``values`` (a list, tuple, range or 1-D array) as a tuple of 1 to ``MAX_GRID`` items,
    each passing ``ok``; else ParameterError naming ``name`` with ``allowed``."""
    allowed = f"1 to {MAX_GRID} values, each {allowed}"
    if isinstance(values, np.ndarray):
        values = values.tolist() if values.ndim == 1 else None
    if not isinstance(values, list | tuple | range) or not 1 <= len(values) <= MAX_GRID:
        raise ParameterError(name, values, allowed)
    items = tuple(values)
    if not all(ok(v) for v in items):
        raise ParameterError(name, values, allowed)
    return items


def _keyed(name: str, values: Any, key: str) -> tuple:
    """``values`` for ``_grid``, each as the ``[base]`` key ``key`` allows (``BASE_KEYS``)."""
    rule = BASE_KEYS[key]

    def ok(value: Any) -> bool:
        try:
            rule.check(name, value)
        except ParameterError:
            return False
        return True

    return tuple(rule.check(name, v) for v in _grid(name, values, rule.allowed(), ok))


def _choices(name: str, values: Any, choices: Sequence) -> tuple:
    allowed = "one of " + ", ".join(map(repr, choices))
    return _grid(name, values, allowed, lambda v: isinstance(v, str) and v in choices)


def _feedforwards(values: Any) -> tuple[bool, ...]:
    items = _grid("feedforwards", values, "true or false", lambda v: isinstance(v, bool | np.bool_))
    return tuple(bool(v) for v in items)


def sea_state(scenario: Scenario, height: float, seed: int) -> Scenario:
    """``scenario`` over a deck in the sea state of significant wave height ``height`` [m]
    and ``seed`` (its other ``[base]`` keys kept; a still base becomes a sea state); the seed
    is also the run's (its sensor noise).

    Parameters
    ----------
    scenario : Scenario
        The scenario to fly over the deck.
    height : float
        The sea state's significant wave height [m].
    seed : int
        The sea state's seed, also the run's (its sensor noise).

    Returns
    -------
    Scenario
        The scenario over that sea state, named ``<name>_hs<height>_seed<seed>``.
    """
    base = replace(scenario.base, motion="sea_state", significant_wave_height=height, seed=seed)
    name = f"{scenario.name}_hs{height:g}_seed{seed}"
    return scenario.replace(base=base, seed=seed, name=name)


@dataclass(frozen=True)
class StationRow:
    """Station-keeping relative to the deck in one sea state, one configuration and sensing,
    over the seeds: the means of the runs' RMS and peak deviations of HO from its point of
    the deck [m] (``summary_metrics``), of the tension's range [N], and the runs that failed.

    Parameters
    ----------
    height : float
        The sea state's significant wave height [m].
    configuration : str
        "free" or "tethered".
    sensing : str
        The sensor suite (a ``SENSINGS`` name).
    feedforward : bool
        Whether the deck's heave was fed forward (``[control] base_feedforward``).
    rms_horizontal, rms_vertical : float
        The mean over the completed runs of HO's RMS horizontal and vertical deviation from its
        point of the deck [m] (NaN: none completed).
    peak_vertical : float
        The mean peak vertical deviation [m].
    tension_min, tension_max : float
        The means of the runs' least and largest tension [N].
    runs : int
        The runs flown (one per seed).
    failed : int
        The runs that did not complete.
    """

    height: float
    configuration: str
    sensing: str
    feedforward: bool
    rms_horizontal: float
    rms_vertical: float
    peak_vertical: float
    tension_min: float
    tension_max: float
    runs: int
    failed: int


def station_rows(
    heights: Sequence[float],
    seeds: Sequence[int],
    *,
    configurations: Sequence[str] = ("free", "tethered"),
    sensings: Sequence[str] = ("perfect", "gnss", "tether"),
    feedforwards: Sequence[bool] = (False, True),
    duration: float | None = None,
) -> list[StationRow]:
    """The station-keeping table: every height x configuration x sensing (the tether as a
    sensor on the tethered configuration only) x deck feed-forward (``[control]
    base_feedforward``), over ``seeds`` (each the sea state's and the sensor noise's).

    Parameters
    ----------
    heights : sequence of float
        Significant wave heights [m].
    seeds : sequence of int
        The sea states' seeds (one run each).
    configurations, sensings, feedforwards
        Which to fly (``SENSINGS``' names; the deck's heave fed forward or not).
    duration : float, optional
        Shorter runs than the shipped 60 s (a quick check).

    Returns
    -------
    list of StationRow

    Raises
    ------
    ParameterError
        An argument that is empty, too long or holds a value outside its range (one line
        naming the argument).
    """
    heights = _keyed("heights", heights, "significant_wave_height")
    seeds = _keyed("seeds", seeds, "seed")
    configurations = _choices("configurations", configurations, CONFIGURATIONS)
    sensings = _choices("sensings", sensings, tuple(SENSINGS))
    feedforwards = _feedforwards(feedforwards)
    cases = []
    for configuration in configurations:
        base = shipped_scenario(f"deck_sea_state_{configuration}")
        if duration is not None:
            base = base.replace(duration=duration)
        for sensing in sensings:
            if sensing == "tether" and configuration == "free":
                continue
            suite = SENSINGS[sensing]
            sensed = (
                base if suite is None else base.replace(sensors=shipped_scenario(suite).sensors)
            )
            for ff in feedforwards:
                control = replace(sensed.control, base_feedforward=ff)
                flown = sensed.replace(control=control)
                for h in heights:
                    cases.append((h, configuration, sensing, ff,
                                  [sea_state(flown, h, s) for s in seeds]))  # fmt: skip
    batch = run_batch([s for *_, runs in cases for s in runs])
    rows, i = [], 0
    for h, configuration, sensing, ff, runs in cases:
        metrics = [batch.metrics(i + j) for j in range(len(runs))]
        ok = batch.ok[i : i + len(runs)]
        i += len(runs)
        good = [m for m, fine in zip(metrics, ok, strict=True) if fine]

        def mean(name: str, good=good) -> float:
            return float(np.mean([m[name] for m in good])) if good else math.nan

        horizontal = [math.hypot(m["rms_q1"], m["rms_q2"]) for m in good]
        rows.append(StationRow(
            height=h, configuration=configuration, sensing=sensing, feedforward=ff,
            rms_horizontal=float(np.mean(horizontal)) if good else math.nan,
            rms_vertical=mean("rms_q3"), peak_vertical=mean("peak_q3"),
            tension_min=mean("tension_min"), tension_max=mean("tension_max"),
            runs=len(runs), failed=int(len(runs) - np.sum(ok)),
        ))  # fmt: skip
    return rows


@dataclass(frozen=True)
class LandingRow:
    """The tethered landing in one sea state over the seeds: the share that landed, the
    touchdown's vertical speed relative to the deck [m/s] (mean, largest), offset [m] and
    tilt [rad] (largest), and the failures' statuses.

    Parameters
    ----------
    height : float
        The sea state's significant wave height [m].
    feedforward : bool
        Whether the deck's heave was fed forward (``[control] base_feedforward``).
    runs : int
        The runs flown (one per seed).
    landed : int
        The runs that landed (``Status.LANDED``).
    speed_mean, speed_max : float
        The mean and largest touchdown vertical speed relative to the deck [m/s] (NaN: no
        touchdown).
    offset_max : float
        The largest horizontal offset of HO from the winch at touchdown [m].
    attitude_max : float
        The largest tilt at touchdown, acos(cos q4 cos q5) [rad].
    failures : dict of str to int
        The runs that did not land, by their status's name (lower case).
    """

    height: float
    feedforward: bool
    runs: int
    landed: int
    speed_mean: float
    speed_max: float
    offset_max: float
    attitude_max: float
    failures: dict[str, int]

    @property
    def success_rate(self) -> float:
        """The share of the runs that landed."""
        return self.landed / self.runs


def landing_rows(
    heights: Sequence[float], seeds: Sequence[int], feedforwards: Sequence[bool] = (False, True)
) -> list[LandingRow]:
    """The landing table: ``landing_sea_state`` at each height over ``seeds``, the deck's
    heave fed forward or not.

    Parameters
    ----------
    heights : sequence of float
        Significant wave heights [m].
    seeds : sequence of int
        The sea states' seeds.
    feedforwards : sequence of bool
        ``[control] base_feedforward`` values to fly.

    Returns
    -------
    list of LandingRow

    Raises
    ------
    ParameterError
        An argument that is empty, too long or holds a value outside its range (one line
        naming the argument).
    """
    heights = _keyed("heights", heights, "significant_wave_height")
    seeds = _keyed("seeds", seeds, "seed")
    feedforwards = _feedforwards(feedforwards)
    shipped = shipped_scenario("landing_sea_state")
    rows = []
    for ff, h in ((ff, h) for ff in feedforwards for h in heights):
        base = shipped.replace(control=replace(shipped.control, base_feedforward=ff))
        statuses, touched = [], []  # a run's status and touchdown, not its whole record
        for s in seeds:
            r = simulate(sea_state(base, h, s))
            statuses.append(Status(r.status))
            if r.touchdown is not None:
                touched.append(r.touchdown)
        landed = sum(status == Status.LANDED for status in statuses)
        failures: dict[str, int] = {}
        for status in statuses:
            if status != Status.LANDED:
                name = status.name.lower()
                failures[name] = failures.get(name, 0) + 1
        speeds = [t["vertical_speed"] for t in touched]
        rows.append(LandingRow(
            height=h, feedforward=ff, runs=len(statuses), landed=landed,
            speed_mean=float(np.mean(speeds)) if speeds else math.nan,
            speed_max=max(speeds, default=math.nan),
            offset_max=max((t["offset"] for t in touched), default=math.nan),
            attitude_max=max((t["attitude"] for t in touched), default=math.nan),
            failures=failures,
        ))  # fmt: skip
    return rows
