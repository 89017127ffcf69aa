"""Saved results read back: ``load_result`` is the inverse of ``SimulationResult.save``."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

import tetherheli
from tetherheli import ParameterError, load_result
from tetherheli.results import SimulationResult, list_results
from tetherheli.runs import simulate
from tetherheli.scenario import Scenario
from tetherheli.scenario.core import ActuatorSettings
from tetherheli.sensing.config import SensorConfig
from tetherheli.wind import Step

_ARRAYS = [f.name for f in dataclasses.fields(SimulationResult) if f.type == "np.ndarray"]


def _assert_same(loaded: SimulationResult, saved: SimulationResult) -> None:
    for name in _ARRAYS:
        np.testing.assert_array_equal(getattr(loaded, name), getattr(saved, name), err_msg=name)
    assert loaded.extra.keys() == saved.extra.keys()
    for name, values in saved.extra.items():
        np.testing.assert_array_equal(loaded.extra[name], values, err_msg=name)
    for name in ("status", "message", "method", "version", "release_time", "release_tension"):
        assert getattr(loaded, name) == getattr(saved, name), name
    assert loaded.configuration == json.loads(json.dumps(saved.configuration))


def test_save_then_load_gives_the_same_result_with_a_release_and_sensor_estimates(
    tmp_path: Path,
):
    """An upward step breaks the tether (release fields set); GPS sensing adds the
    q1_est..q3_est columns (``extra``)."""
    scenario = Scenario(
        name="released",
        duration=3.0,
        wind=Step(0.5, 20.0, (0.0, 0.0, 1.0)),
        actuators=ActuatorSettings(breaking_tension=25.5),
        sensors=SensorConfig.typical_gps(),
    )
    saved = simulate(scenario)
    assert saved.released and set(saved.extra) == {"q1_est", "q2_est", "q3_est"}
    saved.save(tmp_path)
    assert list_results(tmp_path) == ["released"]
    loaded = load_result(tmp_path)
    _assert_same(loaded, saved)
    assert loaded.release_info() == saved.release_info()
    assert not loaded.states.flags.writeable
    assert tetherheli.load_result is load_result


def test_a_failed_run_round_trips_and_stems_are_checked(tmp_path: Path):
    wind = Step(0.5, 20.0, (1.0, 0.0, 0.0))
    limits = dataclasses.replace(Scenario().limits, max_deviation=0.05)
    saved = simulate(Scenario(name="drifts", duration=3.0, wind=wind, limits=limits))
    assert not saved.ok
    saved.save(tmp_path, "a")
    saved.save(tmp_path, "b")
    _assert_same(load_result(tmp_path, "b"), saved)
    assert load_result(tmp_path, "a").end_time == saved.end_time
    with pytest.raises(ParameterError, match="several"):
        load_result(tmp_path)
    with pytest.raises(ParameterError, match=r"stem = '\.\./a' is invalid; allowed: one of"):
        load_result(tmp_path, "../a")


@pytest.mark.parametrize(
    ("change", "match"),
    [
        (lambda m: m["trim"].pop("state"), "trim.state"),
        (lambda m: m.update(status=True), "status"),
        (lambda m: m.update(tether_release={"time": 1.0}), "tether_release"),
        (lambda m: m["configuration"].update(configuration="x"), "configuration.configuration"),
    ],
)
def test_malformed_metadata_is_one_line_naming_the_field(tmp_path: Path, change, match: str):
    simulate(Scenario(name="r", duration=0.1)).save(tmp_path)
    meta = json.loads((tmp_path / "r.json").read_text())
    change(meta)
    (tmp_path / "r.json").write_text(json.dumps(meta))
    with pytest.raises(ParameterError, match=match) as info:
        load_result(tmp_path, "r")
    assert "r.json" in str(info.value) and "\n" not in str(info.value)
