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
    [base]                            # the winch's base (BaseSettings); default still
    motion = "sea_state"              # fixed, velocity, harmonic, sea_state or file
    significant_wave_height = 1.0     # [m]
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
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

from .._io import OWN_FILE_STEMS, read_toml
from .._shipped_files import shipped_files, shipped_name
from .._validation import Key
from ..base.motion import BaseMotion
from ..errors import ParameterError
from ..params import TETHER_LENGTH_RANGE, Params
from ..sensing.config import SensorConfig, sensor_config_from_dict
from ..wind import Disturbance, NoWind, disturbance_from_dict, paper_wind
from .checks import MAX_SAMPLES, check_distinct_names, check_name, validate_scenario
from .flight import ReferenceSettings
from .tables import (
    CONTROLLERS,
    MPC_OBSERVERS,
    MPC_QY_GNSS,
    PAPER_QY,
    PAPER_RU,
    TETHER_MODELS,
    WINCH_MODELS,
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
    _key,
    field_key,
)

__all__ = [
    "CONTROLLERS",
    "MAX_SAMPLES",
    "MPC_OBSERVERS",
    "MPC_QY_GNSS",
    "PAPER_QY",
    "PAPER_RU",
    "TETHER_MODELS",
    "WINCH_MODELS",
    "ActuatorSettings",
    "BaseSettings",
    "ControlSettings",
    "LandingGearSettings",
    "Limits",
    "MPCSettings",
    "ManeuverSettings",
    "ReferenceSettings",
    "Scenario",
    "TetherLQISettings",
    "TetherSettings",
    "WinchSettings",
    "check_distinct_names",
    "check_name",
    "field_key",
    "load_scenario",
    "metrics_first_sample",
    "paper_scenario",
    "scenario_from_dict",
    "scenario_toml",
]


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
    base : BaseSettings, optional
        The winch's base (default: still at the origin of N, the paper's); ``base_motion``
        is its motion.
    maneuver : ManeuverSettings, optional
        A maneuver flown in the run (default none: the paper's station-keeping).
    landing_gear : LandingGearSettings or None, optional
        The landing gear in contact with the deck (``[landing_gear]``; default None: none).
    trajectory : ReferenceSettings, optional
        The ``[reference]`` table: what the run flies beyond its hover (default hold: the
        paper's station-keeping; ``scenario.flight``). Named ``trajectory`` here because
        ``reference`` is the held point's frame (``control.reference``).
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
    base: BaseSettings = field(default_factory=BaseSettings)
    maneuver: ManeuverSettings = field(default_factory=ManeuverSettings)
    landing_gear: LandingGearSettings | None = None
    trajectory: ReferenceSettings = field(default_factory=ReferenceSettings)

    def __post_init__(self) -> None:
        validate_scenario(self, source=None)

    @property
    def base_motion(self) -> BaseMotion:
        """The base's motion b(t) (``tetherheli.base``), built and checked with the scenario
        (a ``file`` read then).

        Returns
        -------
        BaseMotion
        """
        return self.__dict__["_base_motion"]

    @property
    def input_files(self) -> dict[str, str]:
        """Every file the scenario names (the base's track, a ship's RAOs, a ``[reference]``
        CSV trajectory), as read when
        the scenario was built: resolved path -> SHA-256 of its bytes. Part of a run's
        identity (a Monte Carlo resumes only over the same bytes) and protected like the
        scenario file by the output rules (``cli._common.scenario_inputs``).

        Returns
        -------
        dict of str to str
        """
        files = {}
        if self.base.motion == "ship" and self.base.rao_file:
            files[self.base.rao_file] = self.base.rao_file_sha256
        if self.base.motion == "file":
            files[self.base.file] = self.base.file_sha256
        if self.trajectory.type == "csv":
            files[self.trajectory.file] = self.trajectory.file_sha256
        return files

    @property
    def reference(self) -> str:
        """What the controller holds: ``control.reference``, or when unset 'ground' over a
        still base and 'base' over a moving one.

        Returns
        -------
        str
        """
        if self.control.reference is not None:
            return self.control.reference
        return "ground" if self.base_motion.fixed else "base"

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
            "base": dataclasses.asdict(self.base),
            "maneuver": dataclasses.asdict(self.maneuver),
            "landing_gear": None
            if self.landing_gear is None
            else dataclasses.asdict(self.landing_gear),
            "reference": dataclasses.asdict(self.trajectory),
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
    "base",
    "maneuver",
    "landing_gear",
    "reference",
}


def _vectors(source, key, value, cls) -> dict[str, Any]:
    """The TOML table ``value`` of settings ``cls`` (``_table``), its vector keys (a ``Key``
    of kind "vector") turned from TOML arrays into tuples."""
    table = dict(_table(source, key, value, cls))
    for f in dataclasses.fields(cls):
        spec = f.metadata.get("key")
        if spec is None or spec.kind not in ("vector", "list") or f.name not in table:
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
    for k in ("duration", "q9", "metrics_start"):
        if k in data:
            kwargs[k] = data[k]  # checked by validate_scenario
    if "control" in data:
        ctl = _vectors(source, "control", data["control"], ControlSettings)
        if "tether_lqi" in ctl:
            tl = _vectors(source, "control.tether_lqi", ctl["tether_lqi"], TetherLQISettings)
            ctl["tether_lqi"] = TetherLQISettings(**tl)
        if "mpc" in ctl:
            ctl["mpc"] = MPCSettings(**_vectors(source, "control.mpc", ctl["mpc"], MPCSettings))
        kwargs["control"] = ControlSettings(**ctl)
    if "limits" in data:
        lim = _table(source, "limits", data["limits"], Limits)
        kwargs["limits"] = Limits(**lim)  # checked by validate_scenario
    if "actuators" in data:
        act = _vectors(source, "actuators", data["actuators"], ActuatorSettings)
        kwargs["actuators"] = ActuatorSettings(**act)
    if "winch" in data:
        kwargs["winch"] = WinchSettings(**_table(source, "winch", data["winch"], WinchSettings))
    if "base" in data:
        table = _vectors(source, "base", data["base"], BaseSettings)
        for key in ("file", "rao_file"):
            if isinstance(table.get(key), str) and table[key] and source is not None:
                # a track or RAO file named relative to the scenario file's folder (an
                # absolute path stays as it is); the checks record it resolved, with its
                # SHA-256
                table[key] = str(Path(source).parent / table[key])
        kwargs["base"] = BaseSettings(**table)
    if "maneuver" in data:
        table = _table(source, "maneuver", data["maneuver"], ManeuverSettings)
        kwargs["maneuver"] = ManeuverSettings(**table)
    if data.get("landing_gear") is not None:  # to_dict writes None for no gear
        table = _table(source, "landing_gear", data["landing_gear"], LandingGearSettings)
        kwargs["landing_gear"] = LandingGearSettings(**table)
    if "reference" in data:
        table = _vectors(source, "reference", data["reference"], ReferenceSettings)
        if isinstance(table.get("file"), str) and table["file"] and source is not None:
            table["file"] = str(Path(source).parent / table["file"])  # as [base]'s track
        kwargs["trajectory"] = ReferenceSettings(**table)
    if "sensors" in data:
        if not isinstance(data["sensors"], dict):
            raise ParameterError("sensors", data["sensors"], "a table", source=source)
        kwargs["sensors"] = sensor_config_from_dict(data["sensors"], source=source)
    if "tether" in data:
        kwargs["tether"] = TetherSettings(
            **_table(source, "tether", data["tether"], TetherSettings)
        )
    if "seed" in data:
        kwargs["seed"] = data["seed"]  # checked by validate_scenario
    if "wind" in data:
        kwargs["wind"] = disturbance_from_dict(data["wind"], source=source)
    echo_EA = None
    if "params" in data:
        if not isinstance(data["params"], dict):
            raise ParameterError("params", data["params"], "a table", source=source)
        mapping = dict(data["params"])
        if isinstance(mapping.get("tether"), dict) and "EA" in mapping["tether"]:
            # the law's echo in a recorded scenario: [tether] law and EA set it
            mapping["tether"] = dict(mapping["tether"])
            echo_EA = mapping["tether"].pop("EA")
        kwargs["params"] = Params.from_mapping(mapping, source=source)
    scenario = Scenario.__new__(Scenario)
    defaults = Scenario.__dataclass_fields__
    for name, f in defaults.items():
        if name in kwargs:
            value = kwargs[name]
        elif f.default is not dataclasses.MISSING:
            value = f.default
        else:
            assert f.default_factory is not dataclasses.MISSING  # every field has a default
            value = f.default_factory()
        object.__setattr__(scenario, name, value)
    validate_scenario(scenario, source)
    if echo_EA is not None and echo_EA != scenario.params.tether.EA:
        raise ParameterError(
            "params.tether.EA", echo_EA, f"{scenario.params.tether.EA:g}, the law [tether] "
            "gives (its law and EA set it; 0: the paper's eq 28)", source=source,
        )  # fmt: skip
    return scenario


def read_scenario_table(path: str | Path) -> tuple[dict[str, Any], str]:
    """The parsed table of a scenario file, or of a shipped scenario named instead of a file
    (``_shipped_files.shipped_name``), and its source for messages.

    Parameters
    ----------
    path : str or pathlib.Path
        A scenario TOML file, or a shipped scenario's name (``tetherheli scenarios`` lists
        them).

    Returns
    -------
    (dict, str)
        The table and its source (the path, or "shipped scenario NAME").
    """
    name = shipped_name(path)
    if name is not None:
        text = shipped_files()[name].read_text(encoding="utf-8")
        return tomllib.loads(text), f"shipped scenario {name}"
    what = (
        "scenario TOML file, or a shipped scenario's name (tetherheli scenarios lists them; "
        "tetherheli.shipped.shipped_scenario)"
    )
    return read_toml(path, what), str(path)


def load_scenario(path: str | Path) -> Scenario:
    """Load and validate a scenario TOML file, or a shipped scenario by name.

    Parameters
    ----------
    path : str or pathlib.Path
        The file; its keys are listed in the scenario TOML reference. A bare name of a
        shipped scenario (``"paper_sim1_tethered"``) where no such file exists loads that
        scenario (``tetherheli.shipped``).

    Returns
    -------
    Scenario

    Raises
    ------
    ParameterError
        An unknown key, a wrong type or a value out of range, in one line naming the file,
        the key, the value and what is allowed.
    """
    data, source = read_scenario_table(path)
    return scenario_from_dict(data, source=source)


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
