"""The scenario TOML reference (``docs/scenario_reference.md``), written from the code's own
descriptions of its keys so that it cannot drift from what the loader accepts:

- the scenario's own keys, ``[control]``, ``[limits]``, ``[actuators]``, ``[tether]``: each
  field's ``Key`` (``tetherheli._validation.Key``), the object the validation checks against;
- ``[params.*]``: each parameter field's ``Key`` (``tetherheli.params``), defaults from
  ``Params.paper()``;
- ``[sensors]``: ``SensorConfig``'s fields, its ``Parameters`` documentation and the range
  table its validation uses;
- ``[[wind]]``: every ``type`` the loader knows, its class's fields and ``Parameters``
  documentation (which states each field's unit and range; the class checks them).

Regenerate with ``python docs/gen_scenario_reference.py``; ``tests/test_docs.py`` fails when
the committed page differs.
"""

from __future__ import annotations

import dataclasses
import functools
import inspect
import math
import re
from typing import Any

from .._validation import Key
from ..params import HelicopterParams, Params, TensionControlParams, TetherParams
from ..sensing.config import _NUMERIC_FIELDS, POSITION_SOURCES, SENSOR_GROUPS, SensorConfig
from ..sensing.presets import SENSOR_PRESETS
from ..wind import loader as wind_loader
from .core import (
    _TOP_KEYS,
    ActuatorSettings,
    BaseSettings,
    ControlSettings,
    LandingGearSettings,
    Limits,
    ManeuverSettings,
    MPCSettings,
    Scenario,
    TetherLQISettings,
    TetherSettings,
    WinchSettings,
)
from .flight import ReferenceSettings

__all__ = ["scenario_reference"]

_TABLES = {
    "control": ControlSettings,
    "control.tether_lqi": TetherLQISettings,
    "control.mpc": MPCSettings,
    "limits": Limits,
    "actuators": ActuatorSettings,
    "tether": TetherSettings,
    "winch": WinchSettings,
    "base": BaseSettings,
    "maneuver": ManeuverSettings,
    "landing_gear": LandingGearSettings,
    "reference": ReferenceSettings,
}
_PARAM_SECTIONS = {
    "helicopter": HelicopterParams,
    "tether": TetherParams,
    "tension_control": TensionControlParams,
}


def _value(value: Any) -> str:
    """A default as TOML would spell it."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return f"{value:g}"
    if value is None:  # an unset key (``Key.unset``): absent from the file
        return "unset"
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, (tuple, list)):
        return "[" + ", ".join(_value(v) for v in value) + "]"  # nested for points
    return str(value)


_CODE = re.compile(r"(`+)(.+?)\1")


def _cell(text: str) -> str:
    """``text`` for a table cell: pipes escaped, and brackets outside code spans (a "[m]"
    would otherwise be read as a reference link)."""
    out, last = [], 0
    for m in _CODE.finditer(text):
        out += [text[last : m.start()].replace("[", "\\["), m.group(0)]
        last = m.end()
    out.append(text[last:].replace("[", "\\["))
    return "".join(out).replace("|", "\\|").replace("\n", " ")


def _key_rows(prefix: str, cls: type, defaults: Any) -> list[str]:
    rows = []
    for f in dataclasses.fields(cls):
        key = f.metadata.get("key")
        if key is None:
            continue
        allowed = key.allowed() + (f"; {key.note}" if key.note else "")
        rows.append(
            f"| `{prefix}{f.name}` | {_cell(key.doc)} | {key.unit or '-'} | "
            f"`{_value(getattr(defaults, f.name))}` | {_cell(allowed)} |"
        )
    return rows


def _parameter_docs(doc: str | None) -> dict[str, str]:
    """The entries of a numpydoc docstring's ``Parameters`` section, read by griffe (the
    reader of the API reference, ``mkdocstrings``).

    Parameters
    ----------
    doc : str or None
        A docstring (raw, as ``__doc__`` holds it).

    Returns
    -------
    dict of str to str
        Each documented name (``a, b : float`` documents both) -> its description, its lines
        joined into one.
    """
    try:
        from griffe import Docstring, DocstringSectionKind
    except ImportError:
        raise ImportError(
            "griffe is needed to write the scenario reference and is not installed: pip install "
            "griffelib (or tetherheli[docs])"
        ) from None

    parsed = Docstring(inspect.cleandoc(doc or ""), lineno=1).parse("numpy", warnings=False)
    return {
        entry.name: " ".join(
            line.strip() for line in entry.description.splitlines() if line.strip()
        )
        for section in parsed
        if section.kind is DocstringSectionKind.parameters
        for entry in section.value
    }


_HEADER = ["| key | meaning | unit | default | allowed |", "|---|---|---|---|---|"]


def _sensor_key(name: str) -> Key:
    kind, nonnegative = _NUMERIC_FIELDS[name]
    low = 0.0 if nonnegative else None
    if kind == "scalar":
        return Key("", low=low)
    return Key("", kind="vector", length=3, low=low)


def _sensor_rows() -> list[str]:
    docs = _parameter_docs(SensorConfig.__doc__)
    default = SensorConfig()
    rows = []
    for f in dataclasses.fields(SensorConfig):
        name = f.name
        group = name.rsplit("_", 1)[0]
        doc = docs.get(name, "") or "see `SensorConfig`"
        if group in SENSOR_GROUPS and name.endswith("_rate"):  # one row per group
            doc = f"sample rate of the {group} sensor (0: every control sample)"
        elif group in SENSOR_GROUPS and name.endswith("_latency"):
            doc = f"delay of the {group} sensor's output (0: none)"
        if name == "position_source":
            allowed = "one of " + ", ".join(f"`{s}`" for s in sorted(POSITION_SOURCES))
        elif name == "gps_outage":
            allowed = "[] or [t_start, t_end] with 0 <= t_start < t_end [s]"
        else:
            allowed = _sensor_key(name).allowed()
        bracket = re.search(r"\[([^\]]+)\]", doc)
        unit = "Hz" if name.endswith("_rate") else "s" if name.endswith("_latency") else "-"
        if name == "gps_outage":
            unit = "s"
        elif unit == "-" and bracket and docs.get(name):
            unit = bracket.group(1)
        rows.append(
            f"| `sensors.{name}` | {_cell(doc)} | {unit} | "
            f"`{_value(getattr(default, name))}` | {_cell(allowed)} |"
        )
    presets = ", ".join(f"`{p}`" for p in sorted(SENSOR_PRESETS))
    rows.append(
        "| `sensors.presets` | datasheet-class sensors applied first (the other keys override "
        f"them) | - | `[]` | a list of: {presets} |"
    )
    return rows


def _summary(cls: type) -> str:
    return inspect.cleandoc(cls.__doc__ or "").split("\n\n")[0].replace("\n", " ")


def _wind_rows(registry: dict[str, type], where: str, title: str = "") -> list[str]:
    out = []
    for type_name, cls in sorted(registry.items()):
        docs = _parameter_docs(cls.__doc__)
        heading = title or f'`type = "{type_name}"`'
        out += ["", f"#### {heading} ({cls.__name__})", ""]
        summary = _summary(cls)
        out += [_cell(summary), ""]
        fields = [f for f in dataclasses.fields(cls) if f.init]
        if not fields:
            out.append("No other keys.")
            continue
        out += ["| key | type | default | meaning, unit and range |", "|---|---|---|---|"]
        for f in fields:
            if f.default is not dataclasses.MISSING:
                default = f"`{_value(f.default)}`"
            elif f.default_factory is not dataclasses.MISSING:
                default = f"`{_value(f.default_factory())}`"
            else:
                default = "required"
            doc = docs.get(f.name, "")
            out.append(f"| `{where}.{f.name}` | {_cell(str(f.type))} | {default} | {_cell(doc)} |")
    return out


def _track_rows() -> list[str]:
    """The rules of a track file (``motion = "file"``): which paths, its grammar, its columns."""
    from ..base.motion import (
        FILE_MAX_BYTES,
        FILE_MAX_ROWS,
        TRACK_COLUMNS,
        TRACK_MAX_LINE,
        TRACK_MIN_STEP_S,
    )

    out = [
        "",
        '### Track files (`motion = "file"`)',
        "",
        "Which files: `base.file` may name any regular file that the user running tetherheli",
        "may read (not a folder, device or pipe); a relative path is taken from the scenario",
        "file's folder. tetherheli reads with the user's own rights, so a scenario reaches no",
        "file its user could not read anyway, and no message ever shows a byte of the file: a",
        "refusal names the file, the row and the column and says what is wrong. The run",
        "records the resolved path and the SHA-256 of the bytes it read (`base.file`,",
        "`base.file_sha256` in the saved `scenario.toml` and the result), so the saved",
        "scenario flies the same track again from any folder and refuses a track that has",
        "changed; a Monte Carlo resumes only over the same bytes, and `--out` may not be a",
        "folder that holds the track (as for the scenario file).",
        "",
        "The file: the header `t,n1,n2,n3`, then one row per line of four plain decimal",
        "numbers (digits, one `.`, an optional exponent such as `1.5e-3`; no `_`, `inf` or",
        f"`nan`); at most {FILE_MAX_BYTES} bytes, lines of at most {TRACK_MAX_LINE} bytes and",
        f"{FILE_MAX_ROWS} rows after the header (blank lines count); at least 4 rows; times",
        f"strictly increasing by at least {TRACK_MIN_STEP_S:g} s a row and by at most ten",
        "times the median step, the first at or before 0, the last at or after `duration`.",
        "",
        "| column | meaning | unit | allowed |",
        "|---|---|---|---|",
    ]
    for name, key in TRACK_COLUMNS.items():
        out.append(f"| `{name}` | {_cell(key.doc)} | {key.unit} | {_cell(key.allowed())} |")
    return out


def _rao_rows() -> list[str]:
    """The rules of an RAO file (``motion = "ship"``): its grammar, its columns."""
    from ..base.ship import RAO_COLUMNS, RAO_HEADER, RAO_MAX_BYTES, RAO_MAX_ROWS

    out = [
        "",
        '### RAO files (`motion = "ship"`)',
        "",
        "`base.rao_file` names a CSV of the ship's response amplitude operators, read and",
        "recorded as a track file is (any regular file the user may read, relative to the",
        "scenario file's folder; refusals name the row and the column, never a byte of the",
        "file; `base.rao_file_sha256` records its bytes). Empty: the default ship",
        "(`tetherheli.base.ship`, `benchmarks/ship_raos.py`). The header is",
        f"`{','.join(RAO_HEADER)}`, then one row per wave frequency and heading: frequencies",
        "increasing, under each the same headings, increasing; at least two frequencies; each",
        f"cell a plain decimal number; at most {RAO_MAX_BYTES} bytes and {RAO_MAX_ROWS} rows.",
        "Between rows the RAOs are interpolated linearly (complex values); below the lowest",
        "frequency they are the lowest's, above the highest zero; `base.wave_heading` must lie",
        "within the headings. The ship's axes: x forward, y to port, z up; a motion is",
        "amplitude x a x cos(w t + e + phase) for waves a cos(w t + e) at the centre of motion.",
        "",
        "| column | meaning | unit | allowed |",
        "|---|---|---|---|",
    ]
    for name, key in RAO_COLUMNS.items():
        out.append(f"| `{name}` | {_cell(key.doc)} | {key.unit} | {_cell(key.allowed())} |")
    return out


def scenario_reference() -> str:
    """The scenario TOML reference as a Markdown page.

    Returns
    -------
    str
        The page ``docs/scenario_reference.md`` holds.
    """
    scenario = Scenario()
    paper = Params.paper()
    top = [
        "# Scenario TOML reference",
        "",
        "<!-- Generated by docs/gen_scenario_reference.py from the code's own key metadata "
        "(tetherheli.scenario.reference); do not edit by hand. -->",
        "",
        "A scenario file describes one closed-loop run; `tetherheli simulate FILE` runs it and",
        "`tetherheli.load_scenario(path)` loads it. Every key is optional (its default is",
        "given); an unknown key, a value of the wrong type or out of its range stops the load",
        "with one line naming the file, the key, the value and what is allowed. Units are SI",
        "unless the unit column says otherwise; `inf` is TOML's infinity.",
        "",
        "## Top-level keys",
        "",
        *_HEADER,
        *_key_rows("", Scenario, scenario),
        "",
        "The tables `[control]`, `[limits]`, `[actuators]`, `[tether]`, `[winch]`, `[base]`, "
        "`[sensors]`,"
        " `[params.*]`",
        "and the array `[[wind]]` follow.",
    ]
    for table, cls in _TABLES.items():
        top += ["", f"## `[{table}]`", "", _summary(cls), ""]
        defaults = (  # (the field is ``trajectory``: ``Scenario.reference`` is the frame)
            scenario.trajectory if table == "reference"
            else functools.reduce(getattr, table.split("."), scenario)
        )  # fmt: skip
        if defaults is None:  # a table absent by default ([landing_gear]): its defaults
            defaults = cls()
        top += [*_HEADER, *_key_rows(f"{table}.", cls, defaults)]
        if table == "base":
            top += _track_rows()
            top += _rao_rows()
    top += [
        "",
        "## `[params.helicopter]`, `[params.tether]`, `[params.tension_control]`",
        "",
        "Overrides of the paper's parameters (Tables II and III, eq 56); the default is the",
        "paper's value. `Params.from_toml` reads the same tables without the `params.`",
        "prefix.",
    ]
    for section, cls in _PARAM_SECTIONS.items():
        top += ["", f"### `[params.{section}]`", "", *_HEADER]
        top += _key_rows(f"params.{section}.", cls, getattr(paper, section))
    top += [
        "",
        "## `[sensors]`",
        "",
        "What the controller measures (`SensorConfig`). All zero by default: perfect sensors,",
        "the paper's assumption. Standard deviations and biases carry the unit of the",
        "quantity measured (given in the meaning).",
        "",
        *_HEADER,
        *_sensor_rows(),
        "",
        "## `[[wind]]`",
        "",
        "The wind force on HO: one table, or several `[[wind]]` tables whose forces add. Each",
        "has a `type` and that type's keys; each class checks its ranges, as stated below.",
    ]
    top += _wind_rows(wind_loader._DISTURBANCES, "wind")
    top += [
        "",
        "### Turbulence `model` and `drag` tables",
        "",
        "A `turbulence` wind holds a `model` table (a gust model, by `type`; a",
        "`gauss_markov` model with a `calibration` key is calibrated from a published",
        "turbulence standard) and a `drag` table.",
    ]
    calibrated = wind_loader.CalibratedGaussMarkovTurbulence
    models = dict(wind_loader._GUST_MODELS)
    top += _wind_rows(models, "wind.model")
    top += _wind_rows(
        {"": calibrated}, "wind.model", '`type = "gauss_markov"` with a `calibration`'
    )
    top += _wind_rows({"": wind_loader.DragModel}, "wind.drag", "The `drag` table")
    # (the field ``trajectory`` is the table ``[reference]``)
    fields = {f.name for f in dataclasses.fields(Scenario)} - {"trajectory"}
    assert set(_TOP_KEYS) >= fields | {"reference"}
    return "\n".join(top) + "\n"
