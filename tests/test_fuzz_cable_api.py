"""Issue 43, finding 11: a property-based fuzzer of the public cable API (Hypothesis).

It calls ``tetherheli.tether``'s ``Cable``, ``drive_cable``, ``drive_moordyn`` (when MoorDyn is
installed) and ``buoyant_gravity`` with one or two arguments of a small valid call replaced
by a fuzzed value: NaN, +-inf, 0, negative, tiny and huge numbers, huge integers, wrong types,
and the edges of each cable key's range (``tether.chain.CABLE_KEYS``). Each call must either
return a finite result or raise one validation line naming an argument of the call
(``field = value is invalid; allowed: ...``; a run beyond the memory budget: the budget's
one line), within a time bound (no hang) and a low memory budget (``TETHERHELI_MEMORY_LIMIT``
= 4M, so no call can allocate much).

Bounded in CI: a fixed example budget, derandomized (the same examples on every run), no
deadline, about 3 s (300 cases). ``TETHERHELI_FUZZ_EXAMPLES=2000`` runs longer (and random)
on demand.
"""

from __future__ import annotations

import importlib.util
import math
import os
import re
import time
from collections import Counter

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis")

from hypothesis import HealthCheck, event, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from tetherheli.errors import ParameterError  # noqa: E402
from tetherheli.resources import MEMORY_LIMIT_ENV, ResourceLimitError  # noqa: E402
from tetherheli.tether import Cable, CableRun, buoyant_gravity, drive_cable, drive_moordyn  # noqa: E402
from tetherheli.tether.chain import CABLE_KEYS  # noqa: E402

_ON_DEMAND = int(os.environ.get("TETHERHELI_FUZZ_EXAMPLES", "0") or 0)
_CI_EXAMPLES = 300
_SETTINGS = settings(
    max_examples=_ON_DEMAND or _CI_EXAMPLES,
    derandomize=not _ON_DEMAND,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
    database=None,
)
_MOORDYN = importlib.util.find_spec("moordyn") is not None
#: the longest one fuzzed call may take [s] (the cold Numba compile of the chain step aside:
#: a warm-up call below takes it first)
_CALL_SECONDS = 20.0

#: A refusal: "field = value is invalid; allowed: ..." on one line.
REFUSAL = re.compile(r"^(?P<field>[\w.]+) = .* is invalid; allowed: ")


def _top(t: float) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    return (6.0 + 0.1 * math.sin(t), 0.0, 8.0), (0.1 * math.cos(t), 0.0, 0.0)


#: A small valid call of each function: its arguments (the cable's fields under "cable.")
BASE: dict[str, dict[str, object]] = {
    "Cable": {"unstretched_length": 10.0, "EA": 375.0, "segments": 10},
    "drive_cable": {"duration": 0.05, "dt": 0.01, "substeps": 2, "rho": 1.225, "g": 9.81,
                    "wind": (0.0, 0.0, 0.0), "anchor": (0.0, 0.0, 0.0), "start": "static"},
    "drive_moordyn": {"duration": 0.05, "dt": 0.01, "coupling": 4, "dt_moordyn": 1e-4,
                      "drag_scale": 1.0, "rho": 1.225, "g": 9.81, "wind": (0.0, 0.0, 0.0),
                      "anchor": (0.0, 0.0, 0.0)},
    "buoyant_gravity": {"rho": 1.225, "g": 9.81},
}  # fmt: skip
FUNCTIONS = sorted(f for f in BASE if f != "drive_moordyn" or _MOORDYN)
CABLE_FIELDS = ["unstretched_length", *CABLE_KEYS]

_SPECIAL = [math.nan, math.inf, -math.inf, 0.0, -0.0, -1.0, 5e-324, 1e-300, 1e-9, 1e9, 1e30,
            1e300, 1.7e308, 0, -1, 1, 2, 1000, 1001, 10**6, 10**9, 10**12, 10**400,
            np.float64(1e-12), np.int64(2**62)]  # fmt: skip
_WRONG = st.one_of(
    st.sampled_from([None, True, "1", "static", b"x", [1.0], (1.0, 2.0), {"a": 1}, object()]),
    st.text(max_size=6),
    st.lists(st.floats(allow_nan=True), max_size=4),
)
VALUES = st.one_of(
    st.sampled_from(_SPECIAL),
    st.floats(allow_nan=True, allow_infinity=True, width=64),
    st.integers(-(10**20), 10**20),
    _WRONG,
)


#: Values inside each argument's range (a call that must run): the cable keys' own ranges, and
#: a few for the other arguments
_INSIDE: dict[str, st.SearchStrategy] = {
    "unstretched_length": st.floats(0.5, 20.0),
    **{
        name: (st.integers(2, 40) if key.kind == "integer" else
               st.floats(key.low or 0.0, min(key.high or 10.0, 10.0 * (key.low or 1.0)),
                         exclude_min=key.low_open))
        for name, key in CABLE_KEYS.items()
    },
    "duration": st.floats(1e-3, 0.1),
    "dt": st.floats(2e-3, 0.05),
    "substeps": st.integers(1, 20),
    "coupling": st.integers(1, 8),
    "dt_moordyn": st.floats(1e-5, 2e-4),
    "drag_scale": st.floats(0.1, 10.0),
    "rho": st.floats(0.0, 2.0, exclude_min=True),
    "g": st.floats(0.0, 20.0),
    "wind": st.lists(st.floats(-10.0, 10.0), min_size=3, max_size=3),
    "anchor": st.lists(st.floats(-2.0, 2.0), min_size=3, max_size=3),
}  # fmt: skip


@st.composite
def calls(draw) -> tuple[str, dict[str, object], dict[str, object]]:
    """(function, cable fields, other arguments) with one or two of them fuzzed."""
    function = draw(st.sampled_from(FUNCTIONS))
    fields = dict(BASE["Cable"])
    args = {} if function == "Cable" else dict(BASE[function])
    names = CABLE_FIELDS + [f"arg:{a}" for a in args]
    for name in draw(st.lists(st.sampled_from(names), min_size=1, max_size=2, unique=True)):
        inside = _INSIDE.get(name.removeprefix("arg:"))
        value = draw(st.one_of(VALUES, inside) if inside is not None else VALUES)
        if name.startswith("arg:"):
            args[name[4:]] = value
        else:
            fields[name] = value
    return function, fields, args


def _finite(result: object) -> bool:
    if isinstance(result, CableRun):
        arrays = (result.t, result.top_force, result.anchor_force, result.nodes,
                  result.velocities)  # fmt: skip
        return all(bool(np.all(np.isfinite(a))) for a in arrays)
    return isinstance(result, float) and math.isfinite(result)


def _call(function: str, fields: dict, args: dict) -> object:
    cable = Cable(**fields)
    if function == "Cable":
        return buoyant_gravity(cable)  # a finite number from the checked fields
    if function == "buoyant_gravity":
        return buoyant_gravity(cable, **args)
    drive = drive_cable if function == "drive_cable" else drive_moordyn
    return drive(cable, top=_top, **args)


@pytest.fixture(scope="module")
def warm() -> None:
    """The chain step's Numba compile, once, outside the timed calls."""
    drive_cable(Cable(**BASE["Cable"]), top=_top, **BASE["drive_cable"])


OUTCOMES: Counter = Counter()


@_SETTINGS
@given(call=calls())
def test_fuzzed_cable_api_calls_finish_or_refuse_in_one_line(monkeypatch, warm, call):
    function, fields, args = call
    monkeypatch.setenv(MEMORY_LIMIT_ENV, "4M")
    allowed_fields = {"cable", "top", *args} | {f"cable.{f}" for f in fields}
    t0 = time.perf_counter()
    try:
        result = _call(function, fields, args)
    except ResourceLimitError as exc:  # the memory budget's one line
        assert "\n" not in str(exc), str(exc)[:300]
        OUTCOMES["memory budget"] += 1
        event("memory budget")
    except ParameterError as exc:
        text = str(exc)
        assert "\n" not in text and len(text) < 2_000, text[:300]
        m = REFUSAL.match(text)
        assert m, text[:300]
        assert m.group("field") in allowed_fields, text[:300]
        OUTCOMES[f"refused: {m.group('field')}"] += 1
        event("refused")
    else:
        assert _finite(result), (function, fields, args)
        OUTCOMES["finite result"] += 1
        event("finite result")
    assert time.perf_counter() - t0 < _CALL_SECONDS, (function, fields, args)


def test_fuzzer_budget_is_fixed_in_ci():
    """The CI run is bounded: derandomized with a fixed budget unless asked for more."""
    if not _ON_DEMAND:
        assert _SETTINGS.max_examples == _CI_EXAMPLES and _SETTINGS.derandomize
