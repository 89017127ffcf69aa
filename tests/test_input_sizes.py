"""Issue 22, class 5: every size from input is estimated and refused above the memory budget
before anything is allocated (``resources.check_memory``, the rule ``simulate`` applies):
``compare --montecarlo --runs``, the environments' copies and episodes, TOML files. The
budget is set small here (``TETHERHELI_MEMORY_LIMIT``), so the tests hold on any machine."""

from __future__ import annotations

import time
import tracemalloc
from pathlib import Path

import pytest

from tetherheli.cli import main
from tetherheli.errors import ParameterError
from tetherheli.resources import ResourceLimitError
from tetherheli.scenario import load_scenario
from tetherheli.scenario.core import Scenario
from tetherheli.sensing.config import SensorConfig

MONTECARLO = str(Path(__file__).resolve().parents[1] / "scenarios" / "montecarlo_paper_sim1.toml")


def _one_error_line(capsys) -> str:
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    assert "internal error" not in err
    return err


# --- compare --montecarlo --runs ------------------------------------------------------------


@pytest.mark.parametrize("runs", [1_000_000_000, 20_000_000])
def test_compare_runs_above_the_montecarlo_limit_refused(tmp_path, capsys, runs):
    from tetherheli.studies.montecarlo import load_montecarlo
    from tetherheli.studies.robust import montecarlo_compare

    base, config = load_montecarlo(MONTECARLO)
    with pytest.raises(ParameterError, match=r"^runs = .* in \[1, 1e\+07\]"):
        montecarlo_compare(base, config, ("paper",), runs=runs)
    out = tmp_path / "o"
    assert (
        main(["compare", "--montecarlo", MONTECARLO, "--runs", str(runs), "--out", str(out)]) == 2
    )
    assert f"--runs = {runs} is invalid" in _one_error_line(capsys)
    assert not out.exists()


def test_compare_runs_within_the_limit_estimated_before_any_draw(tmp_path, capsys, monkeypatch):
    from tetherheli.studies.montecarlo import load_montecarlo
    from tetherheli.studies.robust import check_comparison_memory, montecarlo_compare

    monkeypatch.setenv("TETHERHELI_MEMORY_LIMIT", "1G")
    base, config = load_montecarlo(MONTECARLO)
    t0 = time.perf_counter()
    tracemalloc.start()
    with pytest.raises(ResourceLimitError, match=r"10000000 draws x 3 run kinds needs about"):
        montecarlo_compare(base, config, ("paper", "tether_lqi"), runs=10_000_000)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 50e6 and time.perf_counter() - t0 < 5.0  # refused, not attempted
    assert check_comparison_memory(1_000, 3) < 2**30  # a real comparison fits
    out = tmp_path / "o"
    args = ["compare", "--montecarlo", MONTECARLO, "--runs", "10000000", "--out", str(out)]
    assert main(args) == 2
    err = _one_error_line(capsys)
    assert "TETHERHELI_MEMORY_LIMIT" in err and "--runs" in err
    assert not out.exists()


# --- the environments -----------------------------------------------------------------------


def test_vector_env_copies_refused_before_allocating(monkeypatch):
    pytest.importorskip("gymnasium")
    from tetherheli.envs.env import check_env_memory
    from tetherheli.envs.vector import TetheredHoverVectorEnv

    monkeypatch.setenv("TETHERHELI_MEMORY_LIMIT", "1G")
    with pytest.raises(ResourceLimitError, match=r"^10000000 environment copies: .*num_envs"):
        TetheredHoverVectorEnv(10_000_000, wind="pulse")
    noisy = Scenario(sensors=SensorConfig.typical_gps())
    with pytest.raises(ResourceLimitError, match=r"^20000 environment copies with noisy sensors"):
        TetheredHoverVectorEnv(20_000, noisy, wind="pulse")
    # a noisy copy's table is its episode's samples x channels: the estimate grows with both
    quiet = check_env_memory(Scenario(duration=30.0), 100, 0.05)
    assert check_env_memory(noisy.replace(duration=30.0), 100, 0.05) > 5 * quiet


def test_long_noisy_episode_refused_before_allocating(monkeypatch):
    pytest.importorskip("gymnasium")
    from tetherheli.envs.env import TetheredHoverEnv

    monkeypatch.setenv("TETHERHELI_MEMORY_LIMIT", "1G")
    noisy = Scenario(sensors=SensorConfig.typical_gps())
    with pytest.raises(ResourceLimitError, match=r"max_episode_time = 1e\+06 s"):
        TetheredHoverEnv(noisy, max_episode_time=1e6, wind="pulse")


# --- TOML input -----------------------------------------------------------------------------


def test_a_huge_toml_file_is_refused_before_parsing(tmp_path, capsys, monkeypatch):
    """200 MB of [[wind]] tables took 150 s and 5.3 GB before failing; the file's size is
    checked against the budget (about 32 bytes of memory per byte of TOML) before reading.
    Here 2 MB against a 32 MB budget."""
    monkeypatch.setenv("TETHERHELI_MEMORY_LIMIT", "32M")
    block = (
        '[[wind]]\ntype = "pulse"\nstart = 0.5\nduration = 0.1\nmagnitude = 1.0\n'
        "direction = [1.0, 0.0, 0.0]\n"
    )
    path = tmp_path / "winds.toml"
    path.write_text("duration = 1.0\n" + block * (2_000_000 // len(block)))
    t0 = time.perf_counter()
    with pytest.raises(ResourceLimitError, match=r"^reading .*winds\.toml \(\d+ bytes\) needs"):
        load_scenario(path)
    assert time.perf_counter() - t0 < 1.0
    assert main(["simulate", str(path), "--out", str(tmp_path / "o")]) == 2
    assert "winds.toml" in _one_error_line(capsys)
    small = tmp_path / "small.toml"
    small.write_text("duration = 1.0\n" + block)
    assert load_scenario(small).duration == 1.0  # an ordinary file still loads


# --- the MPC's horizon ----------------------------------------------------------------------


def test_long_mpc_horizon_announces_its_run_time_before_starting():
    """horizon = 400 (allowed) takes about 0.37 s per sample: a 60 s run is announced as
    about 37 minutes before its design (warnings are errors here: nothing runs)."""
    from tetherheli.control.mpc import mpc_sample_seconds
    from tetherheli.resources import SlowJobWarning
    from tetherheli.runs import simulate
    from tetherheli.scenario.core import ControlSettings, MPCSettings

    assert mpc_sample_seconds(400) == pytest.approx(0.37, rel=0.01)
    assert mpc_sample_seconds(10) < 1e-3
    control = ControlSettings(controller="mpc", mpc=MPCSettings(horizon=400))
    s = Scenario(duration=60.0, control=control)
    t0 = time.perf_counter()
    with pytest.raises(SlowJobWarning, match=r"control\.mpc\.horizon = 400 over 6000 samples "
                       r"will take about 37 min; shorten control\.mpc\.horizon"):  # fmt: skip
        simulate(s)
    assert time.perf_counter() - t0 < 30.0


@pytest.mark.filterwarnings("default::tetherheli.resources.SlowJobWarning")
def test_slow_job_warning_is_one_line_from_the_cli(tmp_path, capsys, monkeypatch):
    import tetherheli.resources as resources
    from tetherheli.scenario.core import ControlSettings

    monkeypatch.setattr(resources, "SLOW_JOB_SECONDS", 0.0)  # any run is "slow" here
    s = Scenario(name="short", duration=0.05, control=ControlSettings(controller="mpc"))
    path = tmp_path / "s.toml"
    path.write_text(s.to_toml())
    assert main(["simulate", str(path), "--out", str(tmp_path / "o")]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        "tetherheli: warning: run short: the MPC with control.mpc.horizon = 10 over 5 samples "
        "will take about 0 min; shorten control.mpc.horizon (default 10) or the duration"
    ]
