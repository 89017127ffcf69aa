"""Every recorded configuration can be re-run (issue 12, item 3): ``Scenario.to_toml`` writes
what ``load_scenario`` reads back equal, and ``simulate``'s output holds a ``scenario.toml``
beside each run that reproduces it."""

from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
import tomli_w

from tetherheli import simulate
from tetherheli._io import OUTPUT_RECORD, read_toml
from tetherheli.errors import ParameterError
from tetherheli.report.paper import SCENARIO_FILE, write_comparison, write_run
from tetherheli.scenario.core import Scenario, load_scenario, scenario_from_dict, scenario_toml
from tetherheli.wind import Disturbance, Pulse

SCENARIOS = sorted((Path(__file__).parent.parent / "scenarios").glob("*.toml"))
PULSE = Pulse(start=0.1, duration=0.2, magnitude=20.0, direction=(0.6, 0.8, 0.0))


@pytest.mark.parametrize("path", SCENARIOS, ids=lambda p: p.stem)
def test_shipped_scenarios_round_trip(path, tmp_path):
    """load -> to_toml -> load gives an equal Scenario (a Monte Carlo file's scenario part:
    its ``montecarlo`` table is the study's, not the scenario's)."""
    data = read_toml(path)
    data.pop("montecarlo", None)
    scenario = scenario_from_dict(data, source=str(path))
    written = tmp_path / "again.toml"
    written.write_text(scenario.to_toml(), encoding="utf-8")
    assert load_scenario(written) == scenario


def test_the_toml_writer_reads_back_equal():
    """``Scenario.to_toml``'s writer (tomli-w) as the scenarios need it: floats exactly
    (repr), inf, nan, strings with quotes/escapes/non-ASCII, dotted and spaced keys, nested and
    empty tables, tables inside lists, arrays of arrays."""
    data = {
        "a": 0.1 + 0.2,
        "tiny": 5e-324,
        "big": -1.7976931348623157e308,
        "inf": math.inf,
        "minus_inf": -math.inf,
        "n": -3,
        "yes": False,
        "text": 'he said "hi"\n\tcafé \\ ☃',
        "a.b c": [1, 2.5, "x", [True]],
        "empty": {},
        "outer": {"inner": {"k": 1.0}, "list": [{"type": "pulse", "dir": [1.0, 0.0]}]},
    }
    back = tomllib.loads(tomli_w.dumps(data))
    assert back == data
    assert math.isnan(tomllib.loads(tomli_w.dumps({"x": math.nan}))["x"])


def test_unset_keys_are_left_out():
    """TOML has no None: ``scenario_toml`` leaves an unset key (None) out, at any depth and
    inside lists, and the file reads back with the key unset (absent)."""
    text = scenario_toml({"name": "x", "seed": None, "mpc": {"bound": None, "n": [{"a": None}]}})
    assert tomllib.loads(text) == {"name": "x", "mpc": {"n": [{}]}}
    with pytest.raises(TypeError):  # what a None would do unfiltered: never a file
        tomli_w.dumps({"table": {"seed": None}})


class _Custom(Disturbance):
    def _force(self, t: np.ndarray) -> np.ndarray:
        return np.zeros((t.size, 3))


def test_custom_wind_cannot_be_written():
    with pytest.raises(ParameterError, match=r"wind = .*_Custom"):
        Scenario(name="custom", duration=0.1, wind=_Custom()).to_toml()


def test_simulate_output_holds_a_scenario_that_reruns_it(tmp_path):
    """``write_run`` (``tetherheli simulate``) writes scenario.toml, recorded as simulate's
    own file; loading it gives the scenario back and running it the same time series."""
    scenario = Scenario(name="rerun", duration=0.3, wind=PULSE, q9=9.5)
    result = simulate(scenario)
    out = tmp_path / "out"
    write_run(result, out, command="test")
    again = load_scenario(out / SCENARIO_FILE)
    assert again == scenario
    np.testing.assert_array_equal(simulate(again).states, result.states)
    record = json.loads((out / OUTPUT_RECORD).read_text())["files"]
    assert record[SCENARIO_FILE]["writer"] == "simulate"


def test_comparison_writes_a_scenario_per_run(tmp_path):
    runs = [
        simulate(Scenario(name=f"cmp_{c}", configuration=c, duration=0.2, wind=PULSE))
        for c in ("free", "tethered")
    ]
    out = tmp_path / "cmp"
    write_comparison(runs, out, command="test")
    for r in runs:
        assert load_scenario(out / r.name / SCENARIO_FILE).to_dict() == r.configuration
