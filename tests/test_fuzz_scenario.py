"""Issue 22, class 7: a property-based fuzzer of scenario tables (Hypothesis).

It builds tables from every documented key (``scenario.core``'s ``Key`` of each field of the
top level, ``[control]``, ``[control.tether_lqi]``, ``[control.mpc]``, ``[limits]``,
``[actuators]``, ``[tether]``, ``[winch]``, ``[maneuver]``): values inside, at and beyond
each key's range, non-finite numbers, wrong types, deep nesting and unknown keys; it writes
each as a TOML file and asserts that loading it either gives a valid ``Scenario`` or one
``ParameterError`` line naming a field (the file, ``key = value is invalid; allowed: ...``),
and that the CLI then exits 2 with that one line and no traceback.

The moving base (issue 43): every ``[base]`` key inside its range and one given NaN, inf, a
wrong type, a value past its bound or a finite but absurd one (1e308), and generated CSV
tracks of every shape of ``TRACK_SHAPES`` (blank lines, huge values, underscores, missing or
extra columns, non-monotonic time, too many rows for a small row limit and memory budget,
binary junk, a folder, a missing file, a secret file outside the scenario's folder, secret
content). Property: a one-line refusal (exit 2, no traceback, no byte of the file in the
message) or a run whose recorded values are all finite.

Bounded in CI: a fixed example budget, derandomized (the same examples on every run), no
deadline, about 20 s in all (120 tables, 150 [base] tables, 16 tracks of each of the 15
shapes). ``TETHERHELI_FUZZ_EXAMPLES=5000`` runs longer (and random) on demand.
"""

from __future__ import annotations

import dataclasses
import math
import os
import re

import pytest

hypothesis = pytest.importorskip("hypothesis")

import tomli_w  # noqa: E402
from hypothesis import HealthCheck, event, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from tetherheli.cli import main  # noqa: E402
from tetherheli.errors import ParameterError  # noqa: E402
from tetherheli.scenario.core import (  # noqa: E402
    ActuatorSettings,
    ControlSettings,
    Limits,
    ManeuverSettings,
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
    "maneuver": ManeuverSettings,
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
        assert _BASE_SETTINGS.max_examples == 150 and _BASE_SETTINGS.derandomize
        assert _TRACK_SETTINGS.max_examples == 16 and _TRACK_SETTINGS.derandomize


# --- the moving base: every [base] key, and generated CSV tracks (issue 43) ------------------

#: A secret that a track may hold: never shown by a refusal.
SECRET = "SECRET-TOKEN"
#: The run's length over a fuzzed [base] table [s]: long enough that a finite but absurd
#: value (a velocity of 1e308 m/s) overflows in the recorded values.
_BASE_DURATION = 5.0
#: The run's length over a fuzzed track [s] (short: a track of a few dozen rows covers it).
_TRACK_DURATION = 0.5
_BASE_SETTINGS = settings(_SETTINGS, max_examples=_ON_DEMAND or 150)
_TRACK_SETTINGS = settings(_SETTINGS, max_examples=_ON_DEMAND or 16)  # per shape


def _inside(key) -> st.SearchStrategy:
    """A value inside a [base] key's range (an unbounded side: within 50)."""
    low = -50.0 if key.low is None else key.low
    high = 50.0 if key.high is None else key.high
    if key.kind == "integer":
        return st.integers(math.ceil(low), int(min(high, 10**6)))
    number = st.floats(low, high, exclude_min=key.low_open, exclude_max=key.high_open)
    if key.kind == "vector":
        return st.lists(number, min_size=key.length, max_size=key.length)
    return number


def _outside(key) -> st.SearchStrategy:
    """An adversarial value of a [base] key: NaN, inf, a wrong type or length, just past a
    bound, or finite but absurd (1e308; as one entry of a vector, the others sensible)."""
    past = [v * (1 + 1e-9) + d for v in (key.low, key.high) if v is not None for d in (-1, 1)]
    bad = st.sampled_from([1e308, -1e308, 1.7e308, 1e30, -1e30, math.nan, math.inf, *past])
    if key.kind == "integer":
        bad = st.one_of(st.sampled_from([10**30, -1, 2**63 - 1, *map(int, past)]), bad)
    if key.kind == "vector":
        return st.one_of(
            st.tuples(bad, st.integers(0, key.length - 1), _inside(key)).map(
                lambda b: [b[0] if k == b[1] else v for k, v in enumerate(b[2])]
            ),
            st.lists(bad, min_size=key.length, max_size=key.length),
            _value(key),  # wrong types and lengths among others
        )
    return st.one_of(bad, bad, _WRONG)


@st.composite
def base_tables(draw) -> dict:
    """A scenario with a ``[base]`` table: a motion (now and then a wrong one), some of its
    keys inside their ranges, and mostly one key given an adversarial value (``_outside``;
    now and then another motion's key)."""
    from tetherheli.base.motion import BASE_KEYS, MOTION_KEYS

    kind = draw(st.sampled_from([*sorted(set(MOTION_KEYS) - {"file"}), "boat", 3]))
    table: dict = {"motion": kind}
    keys = [k for k in MOTION_KEYS.get(kind, ("position",)) if k not in ("file", "file_sha256")]
    for name in draw(st.lists(st.sampled_from(keys), unique=True)):
        table[name] = draw(_inside(BASE_KEYS[name]))
    if draw(st.integers(0, 2)):
        pool = keys if draw(st.integers(0, 9)) else sorted(set(BASE_KEYS) - {"motion", "file"})
        name = draw(st.sampled_from(pool))
        table[name] = draw(_outside(BASE_KEYS[name]))
    return {"name": "fuzz_base", "duration": _BASE_DURATION, "base": table}


def _check_finite_base(scenario: Scenario, *, fly: bool = False) -> None:
    """The base's motion (position, velocity, acceleration) is finite over the run; ``fly``:
    the run is flown too (compiled engine, a short run) and every value it records is
    finite, whatever its status (a failure of the flight is honest), and it did not stop on
    an overflow."""
    import numpy as np

    t = np.linspace(0.0, scenario.duration, 101)
    state = scenario.base_motion.state(t)
    assert np.all(np.isfinite(state)), scenario.base
    if not fly:
        return
    from tetherheli.runs import simulate
    from tetherheli.status import Status

    r = simulate(scenario)
    recorded = [r.time, r.states, r.outputs, r.inputs, r.feedforward, r.tension, r.reel_rate]
    recorded += list(r.extra.values())
    assert all(np.all(np.isfinite(np.asarray(v, dtype=float))) for v in recorded), (
        scenario.base,
        r.message,
    )
    # nor did the run stop on a value that overflowed (where the engine names that status)
    nonfinite = getattr(Status, "NONFINITE", None)
    assert nonfinite is None or r.status != nonfinite, (scenario.base, r.message)


def _refused_by_cli(path, out, secret: str | None = None) -> None:
    """``simulate`` refuses the file: exit 2, one line, no traceback, no secret, no output."""
    import contextlib
    import io

    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        code = main(["simulate", str(path), "--out", str(out)])
    text = err.getvalue()
    assert code == 2, text
    assert len(text.strip().splitlines()) == 1 and "Traceback" not in text, text
    assert secret is None or secret not in text, text
    assert not out.exists()


@_BASE_SETTINGS
@given(data=base_tables())
def test_fuzzed_base_tables_load_with_a_finite_motion_or_refuse_in_one_line(tmp_path_factory, data):
    tmp = tmp_path_factory.mktemp("fuzz_base")
    path = tmp / "base.toml"
    try:
        path.write_text(tomli_w.dumps(data), encoding="utf-8")
    except (TypeError, ValueError, OverflowError):  # a value TOML cannot hold: not a file
        return
    try:
        scenario = load_scenario(path)
    except ParameterError as exc:
        event("base refused")  # counts: pytest --hypothesis-show-statistics
        _check_refusal(str(exc), str(path))
        assert str(exc).split(" = ")[0].endswith(tuple(f"base.{k}" for k in data["base"]))
        _refused_by_cli(path, tmp / "out")
        return
    event("base loaded and flown")
    _check_finite_base(scenario, fly=True)


#: The shapes of a generated track (``tracks``).
TRACK_SHAPES = (
    "valid", "blank_lines", "huge", "underscore", "missing_column", "extra_column",
    "non_monotonic", "too_many_rows", "binary", "secret", "secret_file_outside", "folder",
    "missing_file", "no_header", "special_number",
)  # fmt: skip


@st.composite
def tracks(draw, shape: str) -> tuple[str, bytes, str]:
    """(shape, the track's bytes, the path the scenario names) of a track of ``shape``, one
    of ``TRACK_SHAPES``."""
    step = draw(st.sampled_from([0.01, 0.05, 0.1]))
    n = draw(st.integers(4, 40))
    n = max(n, int(_TRACK_DURATION / step) + 3)  # covers the run, unless a shape breaks it
    amp = draw(st.sampled_from([0.0, 0.3, 5.0, 1e5]))
    rows = [
        [f"{-step + i * step:.6f}", "0", f"{amp * (i % 3 - 1):g}", f"{0.2 * (i % 2):g}"]
        for i in range(n)
    ]
    i = draw(st.integers(0, n - 1))
    j = draw(st.integers(0, 3))
    name = "track.csv"
    if shape == "huge":
        rows[i][j] = draw(st.sampled_from(["1e308", "-1e308", "1e300", "1000001", "-1e+309"]))
    elif shape == "underscore":
        rows[i][j] = draw(st.sampled_from(["1_0", "0_0", "1_000.5"]))
    elif shape == "special_number":
        rows[i][j] = draw(st.sampled_from(["inf", "nan", "-Infinity", "0x1p3", "1e", "١"]))
    elif shape == "missing_column":
        del rows[i][j]
    elif shape == "extra_column":
        rows[i].append("0")
    elif shape == "non_monotonic":
        k = max(1, i)
        rows[k][0] = rows[k - 1][0] if draw(st.booleans()) else f"{float(rows[k][0]) - 2 * step}"
    elif shape == "secret":
        rows[i][j] = f"{SECRET}-{draw(st.integers(0, 999))}"
    lines = [",".join(r) for r in rows]
    if shape == "blank_lines":
        for _ in range(draw(st.integers(1, 5))):
            lines.insert(draw(st.integers(0, len(lines))), draw(st.sampled_from(["", " ", "\t"])))
    if shape == "too_many_rows":
        lines = [f"{-step + k * step:.6f},0,0,0" for k in range(draw(st.integers(60, 120)))]
    header = "t,n1,n2,n3" if shape != "no_header" else draw(st.sampled_from(["t,x,y,z", ""]))
    body = "\n".join([header, *lines]).encode() + b"\n"
    if shape == "binary":
        body = draw(st.sampled_from([b"", b"t,n1,n2,n3\n"])) + draw(st.binary(max_size=300))
    if shape == "secret_file_outside":
        body = f"{SECRET}:x:0:0::/:/bin/sh\nPATH=/usr/bin\0{SECRET}=1\0".encode()
        name = draw(st.sampled_from(["../secret/passwd", "ABS"]))
    elif shape == "folder":
        name = draw(st.sampled_from([".", "..", "sub"]))
    elif shape == "missing_file":
        name = "no_such_track.csv"
    return shape, body, name


@pytest.mark.parametrize("shape", TRACK_SHAPES)
@_TRACK_SETTINGS
@given(data=st.data())
def test_fuzzed_tracks_load_with_a_finite_motion_or_refuse_in_one_line(
    tmp_path_factory, shape, data
):
    """A generated track of each shape (``tracks``), with at most 100 rows allowed and a
    memory budget of 80 rows (``TETHERHELI_MEMORY_LIMIT``): a one-line refusal
    that shows none of the file, or a scenario whose base motion is finite over the run
    (flown for the valid shapes), recorded by resolved path and SHA-256."""
    from tetherheli.base import motion
    from tetherheli.errors import TetherheliError

    _, body, name = data.draw(tracks(shape))
    tmp = tmp_path_factory.mktemp("fuzz_track")
    (tmp / "sc").mkdir()
    (tmp / "secret").mkdir()
    (tmp / "sc" / "sub").mkdir()
    if name == "ABS":
        name = str(tmp / "secret" / "passwd")
    target = tmp / "secret" / "passwd" if "passwd" in name else tmp / "sc" / name
    if shape not in ("folder", "missing_file"):
        target.write_bytes(body)
    path = tmp / "sc" / "s.toml"
    path.write_text(
        tomli_w.dumps(
            {"name": "fuzz_track", "duration": _TRACK_DURATION,
             "base": {"motion": "file", "file": name}}
        ),
        encoding="utf-8",
    )  # fmt: skip
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(motion, "FILE_MAX_ROWS", 100)
        mp.setenv("TETHERHELI_MEMORY_LIMIT", str(80 * motion._TRACK_BYTES_PER_ROW))
        try:
            scenario = load_scenario(path)
        except TetherheliError as exc:  # a ParameterError, or the memory budget's refusal
            event(f"track {shape} refused ({type(exc).__name__})")
            text = str(exc)
            assert "\n" not in text and len(text) < 2_000, text[:300]
            assert SECRET not in text and "/bin/sh" not in text, text
            if isinstance(exc, ParameterError):
                assert exc.field.startswith("base.file"), text
            _refused_by_cli(path, tmp / "out", SECRET)
            return
    event(f"track {shape} loaded")
    assert shape in ("valid", "blank_lines", "huge", "non_monotonic", "too_many_rows"), shape
    _check_finite_base(scenario, fly=shape in ("valid", "huge"))
    assert scenario.base.file == str(target.resolve())
    assert len(scenario.base.file_sha256) == 64
