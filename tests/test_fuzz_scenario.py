"""Issue 22, class 7: a property-based fuzzer of scenario tables (Hypothesis).

It builds tables from every documented key (``sim.scenario``'s ``Key`` of each field of the
top level, ``[control]``, ``[control.tether_lqi]``, ``[control.mpc]``, ``[limits]``,
``[actuators]``, ``[tether]``, ``[winch]``): values inside, at and beyond each key's range,
non-finite numbers, wrong types, deep nesting and unknown keys; it writes each as a TOML file
and asserts that loading it either gives a valid ``Scenario`` or one ``ParameterError`` line
naming a field (the file, ``key = value is invalid; allowed: ...``), and that the CLI then
exits 2 with that one line and no traceback.

Bounded in CI: a fixed example budget, derandomized (the same examples on every run), no
deadline, about 10 s. ``TETHERHELI_FUZZ_EXAMPLES=5000`` runs longer (and random) on demand.
"""

from __future__ import annotations

import dataclasses
import math
import os
import re

import pytest

hypothesis = pytest.importorskip("hypothesis")

import tomli_w  # noqa: E402
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from tetherheli.cli import main  # noqa: E402
from tetherheli.errors import ParameterError  # noqa: E402
from tetherheli.sim.scenario import (  # noqa: E402
    ActuatorSettings,
    ControlSettings,
    Limits,
    MPCSettings,
    Scenario,
    TetherLQISettings,
    TetherSettings,
    WinchSettings,
    load_scenario,
)

_ON_DEMAND = int(os.environ.get("TETHERHELI_FUZZ_EXAMPLES", "0") or 0)
_SETTINGS = settings(
    max_examples=_ON_DEMAND or 120,
    derandomize=not _ON_DEMAND,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
    database=None,
)

#: The tables a scenario file has, and the settings class documenting each one's keys.
SECTIONS: dict[str, type] = {
    "": Scenario,
    "control": ControlSettings,
    "control.tether_lqi": TetherLQISettings,
    "control.mpc": MPCSettings,
    "limits": Limits,
    "actuators": ActuatorSettings,
    "tether": TetherSettings,
    "winch": WinchSettings,
}

#: A refusal: "[source: ]field = value is invalid; allowed: ..." on one line.
REFUSAL = re.compile(r"^(?P<source>[^\n]*?: )?(?P<field>[\w.\[\]/-]+) = .* is invalid; allowed: ")


def _documented(cls: type) -> dict[str, object]:
    """field name -> its Key, for the fields of ``cls`` that have one."""
    out = {}
    for f in dataclasses.fields(cls):
        key = f.metadata.get("key")
        if key is not None:
            out[f.name] = key
    return out


_WRONG = st.one_of(
    st.text(max_size=8),
    st.booleans(),
    st.lists(st.integers(-3, 3), max_size=3),
    st.dictionaries(st.sampled_from(["a", "type"]), st.integers(0, 2), max_size=2),
)


def _number(key) -> st.SearchStrategy:
    """Numbers inside, at and beyond a key's range, and non-finite ones."""
    edges = [v for v in (key.low, key.high) if v is not None]
    near = [e + d for e in edges for d in (-1.0, -1e-9, 0.0, 1e-9, 1.0)]
    return st.one_of(
        st.sampled_from(near or [0.0]),
        st.floats(allow_nan=True, allow_infinity=True, width=64),
        st.integers(-(10**6), 10**6),
    )


def _value(key) -> st.SearchStrategy:
    kind = key.kind
    if kind == "bool":
        good = st.booleans()
    elif kind == "text":
        good = st.sampled_from(key.choices) if key.choices else st.text(max_size=12)
    elif kind == "integer":
        good = st.one_of(
            _number(key).map(lambda v: int(v) if math.isfinite(v) else 1), st.integers()
        )
    elif kind == "vector":
        good = st.lists(_number(key), min_size=max(0, key.length - 1), max_size=key.length + 1)
    else:
        good = _number(key)
    return st.one_of(good, good, good, _WRONG)  # mostly well-typed, sometimes not


def _nested(depth: int) -> object:
    value: object = 1.0
    for _ in range(depth):
        value = {"a": value}
    return value


@st.composite
def scenario_tables(draw) -> dict:
    """A scenario file's data: some documented keys of some tables, now and then an unknown
    key or a deeply nested value."""
    data: dict = {}
    for section in draw(st.lists(st.sampled_from(sorted(SECTIONS)), max_size=4, unique=True)):
        keys = _documented(SECTIONS[section])
        if not keys:
            continue
        names = draw(st.lists(st.sampled_from(sorted(keys)), min_size=1, max_size=4, unique=True))
        table = data
        for part in filter(None, section.split(".")):
            table = table.setdefault(part, {})
        for name in names:
            table[name] = draw(_value(keys[name]))
    if draw(st.integers(0, 9)) == 0:
        data[draw(st.sampled_from(["bogus", "Duration", "controll"]))] = 1.0
    if draw(st.integers(0, 9)) == 0:
        data.setdefault("control", {})["Qy"] = _nested(draw(st.sampled_from([3, 40, 400])))
    # a valid run's duration is at least its sample time: keep most tables loadable
    if "duration" not in data and draw(st.booleans()):
        data["duration"] = 1.0
    return data


def _check_refusal(text: str, source: str) -> None:
    assert "\n" not in text.strip(), text
    assert len(text) < 2_000, text[:300]
    m = REFUSAL.match(text)
    assert m, text[:300]
    assert m.group("source") in (None, f"{source}: "), text[:300]


@_SETTINGS
@given(data=scenario_tables())
def test_fuzzed_scenario_tables_load_or_refuse_in_one_line(tmp_path_factory, data):
    tmp = tmp_path_factory.mktemp("fuzz")
    path = tmp / "fuzz.toml"
    try:
        text = tomli_w.dumps(data)  # the writer of Scenario.to_toml
    except (TypeError, ValueError, RecursionError):  # a value TOML cannot hold: not a file
        return
    path.write_text(text, encoding="utf-8")
    try:
        scenario = load_scenario(path)
    except ParameterError as exc:
        _check_refusal(str(exc), str(path))
        code = main(["simulate", str(path), "--out", str(tmp / "out")])
        assert code == 2
        assert not (tmp / "out").exists()
        return
    assert isinstance(scenario, Scenario)
    assert scenario.n_samples >= 1


def test_fuzzer_budget_is_fixed_in_ci():
    """The CI run is bounded: derandomized with a fixed budget unless asked for more."""
    if not _ON_DEMAND:
        assert _SETTINGS.max_examples == 120 and _SETTINGS.derandomize
