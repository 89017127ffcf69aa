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
    controller = "paper"              # or "tether_lqi" (control.tether_lqi)
    [control.tether_lqi]              # the tethered LQI's weights (TetherLQISettings)
    Qy = [...]                        # q1, q2, q3, q6 and their integrators
    q_tension = 0.0                   # [1/N^2] on the tension deviation
    Ru = [...]                        # fMR3, tMR1, tMR2, fTR2, reel rate
    anti_windup = true
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
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np

from .._io import dumps_toml, read_toml
from .._validation import check_bool, check_integer, check_number, check_vector
from ..control import lqi
from ..errors import ParameterError
from ..params import Params, check_tether_length
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
    "ActuatorSettings",
    "ControlSettings",
    "Limits",
    "Scenario",
    "TetherLQISettings",
    "load_scenario",
    "metrics_first_sample",
    "paper_scenario",
    "scenario_toml",
]

#: The paper's LQI weights (Sec. V-A, after eq 53) as the diagonals the scenario files list;
#: the one source is ``control.lqi.PAPER_QY`` / ``PAPER_RU``.
PAPER_QY: tuple[float, ...] = tuple(np.diag(lqi.PAPER_QY).tolist())
PAPER_RU: tuple[float, ...] = tuple(np.diag(lqi.PAPER_RU).tolist())


#: The controllers ``[control] controller`` selects: the paper's scheme (Sec. V) and the LQI
#: on the tethered linearization with the reel rate as a fifth input (``control.tether_lqi``).
CONTROLLERS: tuple[str, ...] = ("paper", "tether_lqi")


@dataclass(frozen=True)
class TetherLQISettings:
    """Design weights of the tethered LQI (``[control.tether_lqi]``, ``control.tether_lqi``).

    Qy : weights on [q1, q2, q3, q6] and their integrators (eq 47's y_LQI); q_tension : weight
    on the tension deviation [1/N^2] (not integrated); Ru : weights on [fMR3, tMR1, tMR2,
    fTR2, RC]; anti_windup : the integrators hold while a rotor command is outside its
    actuator limits. Defaults: the weights ``python benchmarks/tune_tether_lqi.py
    --evaluations 700`` found (see its header: the paper's runs 1 and 2 with eq 40's
    saturation, effort within the paper's tethered controller's).
    """

    Qy: tuple[float, ...] = (11.7435, 11.7435, 1.49411, 2.07043, 21.2098, 21.2098, 10.7023, 12.1298)
    q_tension: float = 0.000794132
    Ru: tuple[float, ...] = (0.632461, 0.878679, 0.878679, 0.641701, 0.510088)
    anti_windup: bool = True


@dataclass(frozen=True)
class ControlSettings:
    """Controller and integrator settings (Sec. V); ``controller`` one of ``CONTROLLERS``.
    Qy, Ru and feedforward are the paper controller's; ``tether_lqi`` the tethered LQI's
    (which flies without the feed-forward: its plant model contains the tether)."""

    dt: float = 0.01
    substeps: int = 2
    feedforward: bool = True
    Qy: tuple[float, ...] = PAPER_QY
    Ru: tuple[float, ...] = PAPER_RU
    controller: str = "paper"
    tether_lqi: TetherLQISettings = field(default_factory=TetherLQISettings)


@dataclass(frozen=True)
class Limits:
    """Bounds that stop a run with a failure status (never reported as success)."""

    max_tension: float = 500.0
    max_deviation: float = 100.0
    max_angle_deg: float = 80.0


_INF = math.inf


@dataclass(frozen=True)
class ActuatorSettings:
    """Actuator and tether-device realism (all off by default; Sec. IV-C, eq 40).

    u_min, u_max : input limits [fMR3 N, tMR1 N m, tMR2 N m, fTR2 N] (the cyclic limits are
        eq 40's tmax_MR1,2); time_constant : first-order actuator lag [s] (0: none);
    reel_rate_limit : |dLN/dt| bound of the winch [m/s] (anti-windup in the PI, eq 56);
    reel_acceleration_limit : bound on the change of the reel rate [m/s^2], applied per
        sample to the PI's command; the paper's PI then integrates only while the limit does
        not bind (a custom controller gets the limited rate without being told);
    breaking_tension : the safety device releases the tether above it [N] (Sec. IV-C).
    """

    u_min: tuple[float, float, float, float] = (-_INF, -_INF, -_INF, -_INF)
    u_max: tuple[float, float, float, float] = (_INF, _INF, _INF, _INF)
    time_constant: float = 0.0
    reel_rate_limit: float = _INF
    reel_acceleration_limit: float = _INF
    breaking_tension: float = _INF


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
    """One closed-loop run: configuration, duration, controller settings, wind, parameters."""

    name: str = "scenario"
    configuration: Literal["free", "tethered"] = "tethered"
    duration: float = 60.0
    q9: float = 10.0
    control: ControlSettings = field(default_factory=ControlSettings)
    limits: Limits = field(default_factory=Limits)
    wind: Disturbance = field(default_factory=NoWind)
    params: Params = field(default_factory=Params.paper)
    description: str = ""
    actuators: ActuatorSettings = field(default_factory=ActuatorSettings)
    sensors: SensorConfig = field(default_factory=SensorConfig)
    seed: int = 0
    #: [s] the peak, RMS and tension metrics cover t >= metrics_start only (a settling time
    #: excluded; default 0: the whole run); 0 <= metrics_start < duration
    metrics_start: float = 0.0

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
        """A copy with fields replaced (validated)."""
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict[str, Any]:
        """The full configuration as plain data (recorded next to every result)."""
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
            "seed": self.seed,
            "metrics_start": self.metrics_start,
        }

    def to_toml(self) -> str:
        """The scenario as a TOML document that ``load_scenario`` reads back to an equal
        Scenario (every key written, defaults included; ``scenario_toml``). A custom
        disturbance without ``to_dict`` cannot be written: ``ParameterError`` naming it."""
        return scenario_toml(self.to_dict())


#: A scenario name becomes a file stem and a folder name: letters, digits, '_', '.', '-'.
_NAME_PATTERN = re.compile(r"[A-Za-z0-9_.-]{1,100}")
#: The most control samples one run may have (about 12 days at dt = 1 ms, 115 days at 10 ms).
MAX_SAMPLES = 1_000_000_000


def scenario_toml(configuration: dict[str, Any]) -> str:
    """A scenario's plain data (``Scenario.to_dict``, as a result records it) as a TOML
    document ``load_scenario`` reads back; a custom disturbance (recorded by class and repr
    only) cannot be: ``ParameterError`` naming it."""
    wind = configuration.get("wind", {})
    if wind.get("type") == "custom":
        raise ParameterError("wind", wind.get("class"), "a disturbance with to_dict (TOML)")
    return dumps_toml(configuration)


def metrics_first_sample(metrics_start: float, dt: float) -> int:
    """The first control sample k (time k dt) at or after ``metrics_start`` [s]: the metrics
    (peak, RMS, tension range) cover samples k >= this one."""
    return math.ceil(metrics_start / dt - 1e-9)


def check_name(key: str, value: object, *, source: str | None = None) -> str:
    """A name that becomes a file stem or a folder: 1-100 letters, digits, '_', '.', '-',
    not '.' or '..' (never a path); else ParameterError naming ``key``."""
    if not isinstance(value, str) or not _NAME_PATTERN.fullmatch(value) or value in (".", ".."):
        raise ParameterError(
            key,
            value,
            "a plain name of 1-100 letters, digits, '_', '.' or '-' (not '.' or '..'; no "
            "path separators)",
            source=source,
        )
    return value


def _validate(s: Scenario, source: str | None) -> None:
    """Check every field of ``s`` and store the checked values (Python floats and ints, so a
    NumPy scalar is accepted and recorded as plain data)."""
    check_name("name", s.name, source=source)
    if s.configuration not in ("free", "tethered"):
        raise ParameterError(
            "configuration", s.configuration, "'free' or 'tethered'", source=source
        )
    _set(s, "duration", check_number("duration", s.duration, low=0.0, low_open=True, source=source))
    _set(s, "q9", check_tether_length(s.q9, "q9", source=source))
    _set(
        s,
        "metrics_start",
        check_number(
            "metrics_start", s.metrics_start, low=0.0, high=s.duration, high_open=True,
            unit="[s]", source=source,
        ),
    )  # fmt: skip
    c = s.control
    dt = check_number("control.dt", c.dt, low=0.0, low_open=True, source=source)
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
    control = ControlSettings(
        dt=dt,
        substeps=check_integer("control.substeps", c.substeps, low=1, high=1000, source=source),
        feedforward=check_bool("control.feedforward", c.feedforward, source=source),
        Qy=check_vector("control.Qy", c.Qy, 8, low=0.0, source=source),
        Ru=check_vector("control.Ru", c.Ru, 4, low=0.0, low_open=True, source=source),
        controller=_check_controller(c.controller, source),
        tether_lqi=_check_tether_lqi(c.tether_lqi, source),
    )
    lim = Limits(
        **{
            name: check_number(
                f"limits.{name}",
                getattr(s.limits, name),
                low=0.0,
                low_open=True,
                high=89.0 if name == "max_angle_deg" else None,
                source=source,
            )
            for name in ("max_tension", "max_deviation", "max_angle_deg")
        }
    )
    a = s.actuators
    u_limits = {
        name: check_vector(
            f"actuators.{name}", getattr(a, name), 4, finite=False, unit="[N, N m, N m, N]",
            source=source,
        )
        for name in ("u_min", "u_max")
    }  # fmt: skip
    if any(lo >= hi for lo, hi in zip(u_limits["u_min"], u_limits["u_max"], strict=True)):
        raise ParameterError(
            "actuators.u_min", a.u_min, "limits below actuators.u_max", source=source
        )
    actuators = ActuatorSettings(
        **u_limits,
        time_constant=check_number(
            "actuators.time_constant", a.time_constant, low=0.0, high=10.0, source=source
        ),
        **{
            name: check_number(
                f"actuators.{name}", getattr(a, name), low=0.0, low_open=True, finite=False,
                source=source,
            )
            for name in ("reel_rate_limit", "reel_acceleration_limit", "breaking_tension")
        },
    )  # fmt: skip
    _set(s, "control", control)
    _set(s, "limits", lim)
    _set(s, "actuators", actuators)
    if not isinstance(s.sensors, SensorConfig):
        raise ParameterError("sensors", s.sensors, "a SensorConfig", source=source)
    try:
        s.sensors.check_configuration(tethered=s.configuration == "tethered")
        s.sensors.group_timing(s.control.dt)  # rates and latencies on the control grid
    except ParameterError as exc:
        raise ParameterError(exc.field, exc.value, exc.allowed, source=source) from None
    _set(s, "seed", check_integer("seed", s.seed, low=0, source=source))
    if not isinstance(s.params, Params):
        raise ParameterError("params", s.params, "a tetherheli.Params", source=source)
    if s.configuration == "tethered" and s.params.tension_control.T_ref >= lim.max_tension:
        raise ParameterError(
            "params.tension_control.T_ref",
            s.params.tension_control.T_ref,
            f"a reference below limits.max_tension ({lim.max_tension} N)",
            source=source,
        )
    if s.configuration == "tethered":  # the trim's natural length must be sensible
        s.params.tether.check_tension(
            s.params.tension_control.T_ref, s.q9, "params.tension_control.T_ref", source=source
        )
    if not isinstance(s.wind, Disturbance):
        raise ParameterError("wind", s.wind, "a tetherheli Disturbance", source=source)
    check_wind_covers(s.wind, s.duration, source=source)


def _check_controller(value: Any, source: str | None) -> str:
    if value not in CONTROLLERS:
        raise ParameterError("control.controller", value, f"one of {CONTROLLERS}", source=source)
    return value


def _check_tether_lqi(t: TetherLQISettings, source: str | None) -> TetherLQISettings:
    k = "control.tether_lqi"
    return TetherLQISettings(
        Qy=check_vector(f"{k}.Qy", t.Qy, 8, low=0.0, source=source),
        q_tension=check_number(f"{k}.q_tension", t.q_tension, low=0.0, source=source),
        Ru=check_vector(f"{k}.Ru", t.Ru, 5, low=0.0, low_open=True, source=source),
        anti_windup=check_bool(f"{k}.anti_windup", t.anti_windup, source=source),
    )


def _set(s: Scenario, name: str, value: Any) -> None:
    object.__setattr__(s, name, value)


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
    "seed",
    "metrics_start",
}


def _table(source, key, value, allowed_cls) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise ParameterError(key, value, "a table", source=source)
    allowed = {f.name for f in dataclasses.fields(allowed_cls)}
    for k in value:
        if k not in allowed:
            raise ParameterError(f"{key}.{k}", value[k], f"one of {sorted(allowed)}", source=source)
    return value


def scenario_from_dict(data: dict[str, Any], *, source: str | None = None) -> Scenario:
    """Build a validated Scenario from parsed TOML data."""
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
    for k in ("duration", "q9"):
        if k in data:
            kwargs[k] = check_number(k, data[k], low=0.0, low_open=True, source=source)
    if "metrics_start" in data:
        kwargs["metrics_start"] = data["metrics_start"]  # checked with the rest by _validate
    if "control" in data:
        ctl = dict(_table(source, "control", data["control"], ControlSettings))
        for k in ("Qy", "Ru"):
            if k in ctl:
                if not isinstance(ctl[k], list):
                    raise ParameterError(f"control.{k}", ctl[k], "a list of numbers", source=source)
                ctl[k] = tuple(ctl[k])
        if "tether_lqi" in ctl:
            tl = dict(_table(source, "control.tether_lqi", ctl["tether_lqi"], TetherLQISettings))
            for k in ("Qy", "Ru"):
                if k in tl:
                    if not isinstance(tl[k], list):
                        raise ParameterError(
                            f"control.tether_lqi.{k}", tl[k], "a list of numbers", source=source
                        )
                    tl[k] = tuple(tl[k])
            ctl["tether_lqi"] = TetherLQISettings(**tl)
        if "dt" in ctl:
            ctl["dt"] = check_number("control.dt", ctl["dt"], low=0.0, low_open=True, source=source)
        kwargs["control"] = ControlSettings(**ctl)
    if "limits" in data:
        lim = _table(source, "limits", data["limits"], Limits)
        kwargs["limits"] = Limits(
            **{
                k: check_number(f"limits.{k}", v, low=0.0, low_open=True, source=source)
                for k, v in lim.items()
            }
        )
    if "actuators" in data:
        act = dict(_table(source, "actuators", data["actuators"], ActuatorSettings))
        for k in ("u_min", "u_max"):
            if k in act:
                if not isinstance(act[k], list):
                    raise ParameterError(
                        f"actuators.{k}", act[k], "a list of 4 numbers", source=source
                    )
                act[k] = tuple(act[k])
        kwargs["actuators"] = ActuatorSettings(**act)
    if "sensors" in data:
        if not isinstance(data["sensors"], dict):
            raise ParameterError("sensors", data["sensors"], "a table", source=source)
        kwargs["sensors"] = sensor_config_from_dict(data["sensors"], source=source)
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
    """Load and validate a scenario TOML file (see the module docstring for its keys)."""
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
    20 sin(2 pi 0.1 t) N from t = 30 s; 60 s; Tref = 25 N; references at trim."""
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
