"""The checks of a scenario: every field against its ``Key``, the rules that join fields
(sample time and duration, limits and references, tether model and configuration, ...), and
the names that become file stems (``check_name``, ``check_distinct_names``).

``Scenario`` runs ``validate_scenario`` on construction, and ``scenario_from_dict`` on the
scenario it reads (``scenario.core``); each failure is one ``ParameterError`` naming the key.
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Iterable
from typing import TYPE_CHECKING, Any

from .._io import NONFINITE_JSON, OWN_FILE_STEMS
from .._validation import MAX_SAMPLES, check_samples, trusted
from ..base.motion import MOTION_KEYS, FileBase, _base_motion_from
from ..base.ship import ShipBase
from ..control.registry import CONTROLLER_REGISTRY, controller_entry
from ..errors import ParameterError
from ..params import Params, TetherParams, check_tether_length, check_tether_strain
from ..sensing.config import SensorConfig
from ..tether.chain import CABLE_KEYS
from ..wind import Disturbance, check_wind_covers
from .flight import REFERENCE_KEYS, ReferenceSettings, build_trajectory
from .tables import (
    LANDING_MIN_LENGTH_M,
    LANDING_PRESS_M,
    PAPER_EA_N,
    ActuatorSettings,
    BaseSettings,
    ControlSettings,
    LandingGearSettings,
    Limits,
    ManeuverSettings,
    MPCSettings,
    TetherLQISettings,
    TetherSettings,
    WinchSettings,
    field_key,
)

if TYPE_CHECKING:
    from .core import Scenario

__all__ = ["MAX_SAMPLES", "check_distinct_names", "check_name", "validate_scenario"]

#: A scenario name becomes a file stem and a folder name: letters, digits, '_', '.', '-'.
_NAME_PATTERN = re.compile(r"[A-Za-z0-9_.-]{1,100}")


def check_name(key: str, value: object, *, source: str | None = None) -> str:
    """A name that becomes a file stem or a folder: 1-100 letters, digits, '_', '.', '-'
    (never a path), not starting with '.' (tetherheli's record and temporary files do), and
    not one of the stems of tetherheli's own files (``_io.OWN_FILE_STEMS``, alone or before a
    '.', in any letter case), so that no run's file or folder is ever one of them, nor one of
    the JSON files' words for non-finite numbers (``_io.NONFINITE_JSON``); else
    ParameterError naming ``key``.

    Parameters
    ----------
    key : str
        The setting's key, named by the error.
    value : object
        The name to check.
    source : str, optional
        Where the value came from (a file), for the error; None (default): not named.

    Returns
    -------
    str
        ``value``, checked.

    Raises
    ------
    ParameterError
        When ``value`` is not such a name.
    """
    if (
        not isinstance(value, str)
        or not _NAME_PATTERN.fullmatch(value)
        or value.startswith(".")
        or value.casefold().partition(".")[0] in OWN_FILE_STEMS
        or value in NONFINITE_JSON  # the JSON files' words for non-finite numbers
    ):
        raise ParameterError(
            key,
            value,
            "a plain name of 1-100 letters, digits, '_', '.' or '-' (no path separators), "
            "not starting with '.' and not one of tetherheli's own file names "
            f"({', '.join(OWN_FILE_STEMS)}, with or without a suffix) or "
            f"{', '.join(NONFINITE_JSON)}",
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


def _rope_EA(s: Scenario, tether: TetherSettings, source: str | None) -> float:
    """The massless tether's law as ``params.TetherParams.EA``: the rope's EA [N], or 0 for
    the paper's eq 28; refuses a law the tether model cannot fly (``TetherSettings``)."""
    law = tether.law
    if law is None:  # landings default to the rope (issue 46), the rest to the paper's law
        landing = getattr(s.maneuver, "type", None) == "tethered_landing" and not tether.lumped
        law = "rope" if landing else "paper"
        if landing and tether.EA == 0.0:
            return PAPER_EA_N
    if law == "rope" and tether.lumped:
        raise ParameterError(
            "tether.law", law, "'paper' or unset with model = 'lumped' (the chain is a rope "
            "already: tether.EA is its axial stiffness)", source=source,
        )  # fmt: skip
    if law == "rope" and tether.EA == 0.0:
        raise ParameterError(
            "tether.EA", tether.EA, f"an axial stiffness >= 1 N with law = 'rope' (the "
            f"paper's: EA = KC L0N = {PAPER_EA_N:g} N)", source=source,
        )  # fmt: skip
    if law == "paper" and not tether.lumped and tether.EA != 0.0:
        raise ParameterError(
            "tether.EA", tether.EA, "0 (unset) with the paper's law of the massless tether "
            "(eq 28's KC, params.tether.K_C); law = 'rope' takes an EA", source=source,
        )  # fmt: skip
    return tether.EA if law == "rope" else 0.0


def validate_scenario(s: Scenario, source: str | None) -> None:
    """Check every field of ``s`` and store the checked values (Python floats and ints, so a
    NumPy scalar is accepted and recorded as plain data).

    Parameters
    ----------
    s : Scenario
        The scenario; its checked values are stored back into it.
    source : str or None
        Where the scenario came from (a file), for the errors.

    Raises
    ------
    ParameterError
        When a field is invalid.
    """
    check_name("name", s.name, source=source)
    field_key(type(s), "description").check("description", s.description, source=source)
    field_key(type(s), "configuration").check("configuration", s.configuration, source=source)
    _set(s, "duration", field_key(type(s), "duration").check("duration", s.duration, source=source))
    _set(s, "q9", check_tether_length(s.q9, "q9", source=source))
    _set(
        s,
        "metrics_start",
        field_key(type(s), "metrics_start").check(
            "metrics_start", s.metrics_start, high=s.duration, high_open=True, source=source
        ),
    )
    c = s.control
    dt = field_key(ControlSettings, "dt").check("control.dt", c.dt, source=source)
    if dt > s.duration:
        raise ParameterError(
            "control.dt", c.dt, f"a sample time <= duration ({s.duration} s)", source=source
        )
    check_samples(s.duration, dt, dt_field="control.dt", source=source)
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
        assert c.mpc.tension_bounds is not None  # as its checked copy
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
    if tether.EA != 0.0:  # 0: the paper's stiffness; any other EA as the cable API's
        CABLE_KEYS["EA"].check("tether.EA", tether.EA, source=source)
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
    if not isinstance(s.params, Params):
        raise ParameterError("params", s.params, "a tetherheli.Params", source=source)
    EA = _rope_EA(s, tether, source)  # checked: built trusted, no field checked twice
    if EA != s.params.tether.EA:
        law = trusted(TetherParams, **{**dataclasses.asdict(s.params.tether), "EA": EA})
        _set(s, "params", dataclasses.replace(s.params, tether=law))
    if not isinstance(s.sensors, SensorConfig):
        raise ParameterError("sensors", s.sensors, "a SensorConfig", source=source)
    try:
        s.sensors.check_configuration(tethered=s.configuration == "tethered")
        s.sensors._group_timing(dt)  # rates and latencies on the grid of the checked dt
    except ParameterError as exc:
        if exc.source is not None:  # a file's own error, naming it
            raise
        raise ParameterError(exc.field, exc.value, exc.allowed, source=source) from None
    _set(s, "seed", field_key(type(s), "seed").check("seed", s.seed, source=source))
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
    if s.configuration not in controller_entry(s.control.controller).configurations:
        able = [n for n, e in CONTROLLER_REGISTRY.items() if s.configuration in e.configurations]
        raise ParameterError(
            "control.controller", s.control.controller, f"one of {able} in the "
            f"{s.configuration} configuration (control.registry)", source=source,
        )  # fmt: skip
    if (
        s.params.tether.law == "rope"
        and s.control.controller == "tether_lqi"
        and s.control.tether_lqi.q9_from_tension
        and not s.sensors.is_perfect
    ):  # the compiled law's q9 = LN + TC / KC is eq 28's (``control.paper.tension_q9``)
        raise ParameterError(
            "control.tether_lqi.q9_from_tension", True, "false with [tether] law = 'rope' "
            "(the tether length from the load cell is eq 28's LN + TC / KC)", source=source,
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
    _check_base(s, source)
    _check_maneuver(s, source)
    _check_landing_gear(s, source)
    _check_reference(s, source)


def _check_base(s: Scenario, source: str | None) -> None:
    """The ``[base]`` table: its keys, only the motion's own set (``MOTION_KEYS``), the
    motion built (a file read and checked, covering the run), and ``control.reference``."""
    if not isinstance(s.base, BaseSettings):
        raise ParameterError("base", s.base, "a BaseSettings", source=source)
    base = _checked(BaseSettings, "base", s.base, source)
    defaults = BaseSettings()
    used = MOTION_KEYS[base.motion]
    for f in dataclasses.fields(BaseSettings):
        if (
            f.name != "motion"
            and f.name not in used
            and getattr(base, f.name) != getattr(defaults, f.name)
        ):
            readers = [m for m, keys in MOTION_KEYS.items() if f.name in keys]
            raise ParameterError(
                f"base.{f.name}", getattr(s.base, f.name),
                f"unset with motion = {base.motion!r} (used by motion = "
                f"{' or '.join(map(repr, readers))})", source=source,
            )  # fmt: skip
    try:
        motion = _base_motion_from(base)  # its keys checked just above
    except ParameterError as exc:
        raise ParameterError(
            exc.field, exc.value, exc.allowed, source=exc.source or source
        ) from None
    if isinstance(motion, FileBase):
        if motion.end < s.duration:
            raise ParameterError(
                "base.file", base.file, f"a track covering the run (duration = {s.duration:g} "
                "s; this one ends before)", source=source,
            )  # fmt: skip
        # the run records the track it flew: its resolved path and the SHA-256 of its bytes
        base = dataclasses.replace(base, file=motion.source, file_sha256=motion.sha256)
    if isinstance(motion, ShipBase) and base.rao_file:  # the RAO file it read, as a track's
        base = dataclasses.replace(
            base, rao_file=motion.rao_file, rao_file_sha256=motion.rao_file_sha256
        )
    _set(s, "base", base)
    object.__setattr__(s, "_base_motion", motion)
    reference = s.control.reference
    if reference == "base" and motion.fixed:
        raise ParameterError(
            "control.reference", reference, "'ground' or unset with a still base ([base] "
            "motion = 'fixed': a point of N and of the base are the same)", source=source,
        )  # fmt: skip
    if s.control.base_feedforward and motion.fixed:
        raise ParameterError(
            "control.base_feedforward", True, "false with a still base ([base] motion = "
            "'fixed': no acceleration to feed forward)", source=source,
        )  # fmt: skip
    if reference == "ground" and not motion.fixed:
        if not controller_entry(s.control.controller).ground_hold:
            raise ParameterError(
                "control.reference", reference, "'base' or unset over a moving base with "
                f"control.controller = {s.control.controller!r} (only the paper's holds a "
                "point of N over a moving winch yet)", source=source,
            )  # fmt: skip
        if s.maneuver.landing or s.control.base_feedforward:
            raise ParameterError(
                "control.reference", reference, "'base' or unset with a landing or "
                "control.base_feedforward (both fly relative to the deck)", source=source,
            )  # fmt: skip


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


def _check_landing_gear(s: Scenario, source: str | None) -> None:
    """The ``[landing_gear]`` table: its keys, the lowest point below HO, a run that flies
    it (the massless tether's step: not the lumped chain's), and a landing whose touchdown
    gate (``maneuver.gear_height``) is that lowest point; a landing that goes on after the
    first contact (``maneuver.after_touchdown``) needs it."""
    gear, m = s.landing_gear, s.maneuver
    if gear is None:
        if m.landing and m.after_touchdown != "stop":
            raise ParameterError("maneuver.after_touchdown", m.after_touchdown, "'stop' "
                                 "without [landing_gear]", source=source)  # fmt: skip
        return
    if not isinstance(gear, LandingGearSettings):
        raise ParameterError("landing_gear", gear, "a LandingGearSettings", source=source)
    gear = _checked(LandingGearSettings, "landing_gear", gear, source)
    _set(s, "landing_gear", gear)
    if not gear.gear_height > 0.0:
        raise ParameterError("landing_gear.points", gear.points, "a lowest point below HO "
                             "(an f3 component < 0)", source=source)  # fmt: skip
    if s.tether.lumped:
        raise ParameterError("tether.model", s.tether.model, "'elastic' with [landing_gear] "
                             "(the lumped chain's step flies no gear)", source=source)  # fmt: skip
    if m.landing and abs(m.gear_height - gear.gear_height) > 1e-9:
        raise ParameterError("maneuver.gear_height", m.gear_height, f"the lowest gear point's "
                             f"depth below HO, {gear.gear_height:g} m ([landing_gear] points: "
                             "the touchdown gate)", source=source)  # fmt: skip


def _check_maneuver(s: Scenario, source: str | None) -> None:
    """The ``[maneuver]`` table: its keys, and a landing the model and the winch can fly:
    tethered, the paper's controller on the massless tether, a final tether length of at
    least ``LANDING_MIN_LENGTH_M``, a landing tension eq 28 allows there (LN >= q9 / 2) and
    a natural length the winch reels to (``winch.min_length``)."""
    if not isinstance(s.maneuver, ManeuverSettings):
        raise ParameterError("maneuver", s.maneuver, "a ManeuverSettings", source=source)
    m = _checked(ManeuverSettings, "maneuver", s.maneuver, source)
    _set(s, "maneuver", m)
    if not m.landing:
        return

    def refuse(key: str, value: Any, allowed: str) -> None:
        raise ParameterError(key, value, allowed, source=source)

    if s.configuration != "tethered":
        refuse("maneuver.type", m.type, "'none' in the free configuration (a tethered "
               "landing needs the tether)")  # fmt: skip
    if not controller_entry(s.control.controller).landing:
        able = [n for n, e in CONTROLLER_REGISTRY.items() if e.landing]
        refuse("control.controller", s.control.controller, f"one of {able} with a tethered "
               "landing (the other controllers do not fly its moving references yet)")  # fmt: skip
    if s.tether.lumped:
        refuse("tether.model", s.tether.model, "'elastic' with a tethered landing (the "
               "lumped chain's landing on the deck is not modelled yet)")  # fmt: skip
    if not m.start_time < s.duration:
        refuse("maneuver.start_time", m.start_time, f"a time below duration ({s.duration:g} s)")
    arm = s.params.helicopter.tether_arm  # HO = P - arm f3: HO is -arm above P
    final_length = m.gear_height - LANDING_PRESS_M + arm
    if final_length < LANDING_MIN_LENGTH_M:
        refuse("maneuver.gear_height", m.gear_height, f"at least "
               f"{LANDING_MIN_LENGTH_M + LANDING_PRESS_M - arm:.4g} m (P, {-arm:.4g} m below "
               f"HO, stays {LANDING_MIN_LENGTH_M:g} m above the deck at the reference's end, "
               f"{LANDING_PRESS_M:g} m below touchdown)")  # fmt: skip
    start_height = s.q9 - arm
    if not m.gear_height < start_height - 0.5:
        refuse("maneuver.gear_height", m.gear_height, f"at least 0.5 m below the start's "
               f"height of HO ({start_height:.4g} m at q9 = {s.q9:g} m)")  # fmt: skip
    tension = s.params.tension_control.T_ref if m.landing_tension is None else m.landing_tension
    law = s.params.tether  # eq 28's or the rope's (``TetherParams``)
    if tension > law.max_tension(final_length):
        refuse("maneuver.landing_tension", tension, f"at most "
               f"{law.max_tension(final_length):.4g} N at the final tether length q9 = "
               f"{final_length:.4g} m (LN >= q9 / 2: eq 28's KC q9 / 2, the rope's EA; a "
               "stiffer tether, params.tether.K_C or tether.EA, allows more)")  # fmt: skip
    if tension >= s.limits.max_tension:
        refuse("maneuver.landing_tension", tension,
               f"a tension below limits.max_tension ({s.limits.max_tension:g} N)")  # fmt: skip
    natural = law.natural_length(final_length, tension)
    if s.winch.min_length > natural:
        refuse("winch.min_length", s.winch.min_length, f"at most the landing's final natural "
               f"length LN = {natural:.4g} m (q9 - T / KC, eq 28, or the rope's "
               "q9 EA / (EA + T))")  # fmt: skip


def _check_reference(s: Scenario, source: str | None) -> None:
    """The ``[reference]`` table (``scenario.flight``): its keys, only its type's own
    (``REFERENCE_KEYS``), the trajectory built (a CSV read, its path and SHA-256 recorded)
    and joined with the run: not with a landing, a controller that flies references
    (``ControllerEntry.reference``), the massless tether, no point of N held over a moving
    base, a path that covers the run (steps within the duration, a CSV from t <= 0 to
    t >= duration; a run shorter than a waypoints path flies its beginning), a take-off
    tethered, climbing above its start."""
    if not isinstance(s.trajectory, ReferenceSettings):
        raise ParameterError("reference", s.trajectory, "a ReferenceSettings", source=source)
    r = _checked(ReferenceSettings, "reference", s.trajectory, source)
    defaults = ReferenceSettings()
    used = REFERENCE_KEYS[r.type]
    for f in dataclasses.fields(ReferenceSettings):
        if (
            f.name != "type"
            and f.name not in used
            and getattr(r, f.name) != getattr(defaults, f.name)
        ):
            raise ParameterError(
                f"reference.{f.name}", getattr(r, f.name), f"unset with type = {r.type!r} "
                f"(used by type = {[t for t, k in REFERENCE_KEYS.items() if f.name in k]})",
                source=source,
            )  # fmt: skip
    _set(s, "trajectory", r)
    if not r.moving:
        return

    def refuse(key: str, value: Any, allowed: str) -> None:
        raise ParameterError(key, value, allowed, source=source)

    if s.maneuver.landing:
        refuse("reference.type", r.type, "'hold' with a landing maneuver ([maneuver] flies "
               "its own descent)")  # fmt: skip
    if not controller_entry(s.control.controller).reference:
        able = [n for n, e in CONTROLLER_REGISTRY.items() if e.reference]
        refuse(
            "control.controller",
            s.control.controller,
            f"one of {able} with a "
            "[reference] (the other controllers do not fly moving references yet)",
        )
    if s.tether.lumped:
        refuse("tether.model", s.tether.model, "'elastic' with a [reference] (the lumped "
               "chain is not flown along references yet)")  # fmt: skip
    if s.reference == "ground" and not s.base_motion.fixed:
        refuse("control.reference", "ground", "'base' or unset with a [reference] over a "
               "moving base (the path is flown relative to the base)")  # fmt: skip
    if r.type in ("steps", "waypoints"):
        if not r.x:
            refuse("reference.x", r.x, "at least one point")
        for key in ("y", "z", "times") if r.type == "steps" else ("y", "z"):
            if len(getattr(r, key)) != len(r.x):
                refuse(f"reference.{key}", getattr(r, key), f"{len(r.x)} numbers, one per "
                       "point (as reference.x)")  # fmt: skip
    if r.type == "waypoints" and len(r.speeds) != len(r.x):
        refuse("reference.speeds", r.speeds, f"{len(r.x)} speeds > 0 [m/s], one per point")
    if r.yaw and len(r.yaw) != len(r.x):
        refuse("reference.yaw", r.yaw, f"empty or {len(r.x)} angles [rad], one per point")
    arm = s.params.helicopter.tether_arm  # HO = P - arm f3: HO is -arm above P
    start_height = s.q9 - arm
    try:
        path = build_trajectory(r, start_height=start_height)
    except ParameterError as exc:
        if exc.source is not None:  # a file's own error, naming it
            raise
        raise ParameterError(exc.field, exc.value, exc.allowed, source=source) from None
    if r.type == "steps" and not path.end < s.duration:
        refuse("reference.times", r.times, f"times (plus transition) below duration "
               f"({s.duration:g} s)")  # fmt: skip
    if r.type == "csv":
        start = float(path.times[0])  # type: ignore[attr-defined]
        if start > 0.0 or path.end < s.duration:
            refuse(
                "reference.file",
                r.file,
                f"a path covering the run (t from <= 0 to >= "
                f"duration = {s.duration:g} s; it covers [{start:g}, {path.end:g}] s)",
            )
        r = dataclasses.replace(r, file=path.source, file_sha256=path.sha256)  # type: ignore[attr-defined]
        _set(s, "trajectory", r)
    if r.type == "takeoff":
        if s.configuration != "tethered":
            refuse("reference.type", r.type, "'hold', 'steps', 'waypoints' or 'csv' in the "
                   "free configuration (a take-off pays out the tether)")  # fmt: skip
        if not r.start_time < s.duration:
            refuse("reference.start_time", r.start_time, f"a time below duration "
                   f"({s.duration:g} s)")  # fmt: skip
        if not r.height >= start_height + 0.5:
            refuse("reference.height", r.height, f"at least 0.5 m above the start's height of "
                   f"HO ({start_height:.4g} m at q9 = {s.q9:g} m)")  # fmt: skip
        top = s.params.tension_control.T_ref if r.top_tension is None else r.top_tension
        if top >= s.limits.max_tension:
            refuse(
                "reference.top_tension",
                top,
                f"a tension below limits.max_tension ({s.limits.max_tension:g} N)",
            )
