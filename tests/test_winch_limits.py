"""Payout limits ``[winch] min_length``, ``max_length`` (issue 23, item 5): both winch models,
the massless and the lumped tether. Reaching a limit brakes the reel at it (a recorded
event, not a silent clamp: ``SimulationResult.winch_limit``, the message, the summary), the
run goes on; no natural length reaches zero; bad limits are refused with the key named."""

from __future__ import annotations

import json

import numpy as np
import pytest

from tetherheli import cli
from tetherheli.engine import loop as engine
from tetherheli.errors import ParameterError
from tetherheli.layout import (
    ACT_MAX_LENGTH,
    ACT_MIN_LENGTH,
    HELD_DRUM_SPEED,
    HELD_LIMIT_TIME,
    HELD_LIMIT_WHICH,
    HELD_SIZE,
    WINCH_MIN_LENGTH_M,
    default_actuators,
)
from tetherheli.results.result import load_result
from tetherheli.runs.batch import run_batch
from tetherheli.runs.closed_loop import simulate
from tetherheli.runs.packing import winch_into
from tetherheli.runs.setup import engine_setup
from tetherheli.scenario.core import TetherSettings, WinchSettings, paper_scenario
from tetherheli.status import Status

DT = 0.01
L_START = 9.375  # the paper's hover natural length LN = q9 - Tref / K_C [m]


def _act(winch: WinchSettings) -> np.ndarray:
    act = default_actuators()
    winch_into(act, winch)
    act[ACT_MIN_LENGTH], act[ACT_MAX_LENGTH] = winch.min_length, winch.max_length
    return act


@pytest.mark.parametrize("model", ["ideal", "drum"])
def test_the_brake_stops_the_reel_at_the_limit_and_the_length_never_reaches_zero(model):
    """``engine.actuate`` at the default limits: reeling in at 100 m/s from 0.6 m lands the
    length exactly on min_length = 0.5 m at the sample's end (never at zero or below), holds
    it there at rate 0 (the drum braked: speed 0), records the first stop once, and a command
    back inside releases the brake."""
    act = _act(WinchSettings(model=model, torque_limit=1e6, speed_loop_bandwidth=1e4))
    held = np.zeros(HELD_SIZE)
    length, t = 0.6, 0.0
    drum = model == "drum"
    for _ in range(5):
        rate = engine.actuate(
            np.zeros(4), held, -100.0, act, DT, False, (25.0, 25.0), length, t, drum
        )
        length += rate * DT
        t += DT
        assert length >= WINCH_MIN_LENGTH_M - 1e-15
    assert length == pytest.approx(WINCH_MIN_LENGTH_M, abs=1e-15)
    assert rate == pytest.approx(0.0, abs=1e-12)
    assert held[HELD_LIMIT_WHICH] == -1.0 and held[HELD_LIMIT_TIME] == pytest.approx(DT)
    if model == "drum":
        assert held[HELD_DRUM_SPEED] == 0.0
    rate = engine.actuate(np.zeros(4), held, 0.5, act, DT, False, (25.0, 25.0), length, t, drum)
    assert rate > 0.0  # paying out again: the brake let go
    assert held[HELD_LIMIT_WHICH] == -1.0 and held[HELD_LIMIT_TIME] == pytest.approx(DT)


def _sim1(duration: float = 20.0, **winch) -> object:
    return paper_scenario(1, "tethered").replace(duration=duration, winch=WinchSettings(**winch))


@pytest.mark.parametrize("model", ["ideal", "drum"])
@pytest.mark.parametrize("limit", ["min_length", "max_length"])
def test_simulation_1_stops_at_a_payout_limit_and_records_it(model, limit, tmp_path):
    """Simulation 1 pays out to L_N0 + 0.06 m and reels in to L_N0 - 0.09 m in 20 s (the
    pulse of wind at 10 s); limits 2 cm from the start stop it there: the length stays within
    them at every sample and sits at the limit from the recorded time on while the
    controller still asks beyond it; the run completes (status OK) and its message, saved
    metadata and reloaded result say which limit and when."""
    free = simulate(_sim1(model=model))
    sign = 1.0 if limit == "max_length" else -1.0
    value = L_START + sign * 0.02
    r = simulate(_sim1(model=model, **{limit: value}))
    assert r.status == Status.OK
    L = r.winch_length
    assert np.max(sign * (free.winch_length - value)) > 0.0  # unlimited, it would cross
    assert np.max(sign * (L - value)) <= 1e-12
    info = r.winch_limit
    assert info is not None and info["limit"] == limit and info["length"] == value
    k = round(info["time"] / DT)
    assert abs(L[k] - value) < 1e-12 and np.all(np.abs(L[:k] - value) > 1e-12)
    assert f"[winch] {limit} = {value:g} m at t = {info['time']:g} s" in r.message
    assert r.message.startswith("completed")
    r.save(tmp_path, "limited")
    meta = json.loads((tmp_path / "limited.json").read_text())
    assert meta["winch_limit"] == info
    back = load_result(tmp_path / "limited.csv")
    assert back.winch_limit == info and back.message == r.message
    assert free.winch_limit is None and "winch" not in free.message


def test_batch_lanes_python_loop_and_compiled_loop_agree_on_the_limit():
    """The lane engine, one-at-a-time batch and the Python loop record the same stop as
    the compiled loop (one ``actuate`` for all)."""
    s = _sim1(12.0, min_length=L_START - 0.01)
    compiled = simulate(s)
    python = simulate(s, controller=engine_setup(s).paper_controller())
    assert compiled.winch_limit is not None
    assert python.winch_limit == compiled.winch_limit
    batch = run_batch([s, _sim1(12.0)], workers=1)
    alone = run_batch([s, _sim1(12.0)], workers=1, lanes=False)
    np.testing.assert_array_equal(batch.summaries, alone.summaries)
    assert batch.winch_limit(0) == {"time": compiled.winch_limit["time"], "limit": "min_length"}
    assert batch.winch_limit(1) is None
    assert "[winch] min_length at t = " in batch.message(0)


def test_a_lumped_tether_stops_at_the_drum_capacity():
    """The lumped chain's unstretched length L0 = x[12] obeys the same brake."""
    s = paper_scenario(1, "tethered").replace(
        duration=16.0, tether=TetherSettings(model="lumped", segments=4)
    )
    start = engine_setup(s).start.x[12]
    r = simulate(s.replace(winch=WinchSettings(max_length=start + 0.005)))
    assert r.ok and r.winch_limit is not None and r.winch_limit["limit"] == "max_length"
    assert r.winch_length.max() <= start + 0.005 + 1e-12


def test_bad_limits_are_refused_naming_the_key(tmp_path, capsys):
    """min_length <= 0, min >= max, and a start natural length outside the limits: one
    ParameterError naming the key; through the CLI exit 2, one line, no traceback."""
    for key, value in (("min_length", 0.0), ("min_length", -1.0), ("max_length", 0.0)):
        with pytest.raises(ParameterError, match=rf"winch\.{key}"):
            _sim1(**{key: value})
    with pytest.raises(ParameterError, match=r"winch\.max_length"):
        _sim1(min_length=5.0, max_length=5.0)
    with pytest.raises(ParameterError, match=r"winch\.min_length.*9\.375"):
        engine_setup(_sim1(min_length=9.5))
    with pytest.raises(ParameterError, match=r"winch\.max_length.*9\.375"):
        engine_setup(_sim1(max_length=9.0))
    path = tmp_path / "bad.toml"
    path.write_text('configuration = "tethered"\n[winch]\nmax_length = 9.0\n')
    assert cli.main(["simulate", str(path), "--out", str(tmp_path / "out"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert "winch.max_length" in err and "9.375" in err and len(err.splitlines()) == 1
    assert "Traceback" not in err


def test_cli_run_reports_the_limit(tmp_path, capsys):
    """A CLI run that reaches a limit completes (exit 0), prints the stop in its line, and its
    saved metadata records it."""
    path = tmp_path / "limited.toml"
    path.write_text(_sim1(12.0, min_length=L_START - 0.01).to_toml())
    out = tmp_path / "out"
    assert cli.main(["simulate", str(path), "--out", str(out), "--quiet"]) == 0
    printed = capsys.readouterr().out
    assert "completed (the winch stopped at [winch] min_length = 9.365 m at t = " in printed
    meta = json.loads((out / "paper_sim1_tethered.json").read_text())
    assert meta["winch_limit"]["limit"] == "min_length"
    assert "the winch stopped at [winch] min_length" in meta["message"]
