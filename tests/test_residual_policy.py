"""examples/train_residual.py: the residual policy's pipeline, run tiny (issue 25, item 3).

The full runs take minutes (``# not-for-ci``); here each trainer runs a few thousand steps
and its outputs are checked for form. The zero action that the example compares against is
checked against ``simulate`` of the same scenario and wind (the return, peak and RMS it
reports are those of the paper's controller).
"""

from __future__ import annotations

import importlib.util
import json
import math
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("gymnasium")

from tetherheli import simulate
from tetherheli.envs.env import TetheredHoverEnv
from tetherheli.scenario.core import Scenario
from tetherheli.wind import Pulse, Sine

# the example imports Stable-Baselines3 (and PyTorch, about 2.5 s) when it runs, not while
# every worker collects the suite
pytestmark = pytest.mark.extra("rl")

SCRIPT = Path(__file__).resolve().parents[1] / "examples" / "train_residual.py"


@pytest.fixture(scope="module")
def example():
    spec = importlib.util.spec_from_file_location("train_residual", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _check_outputs(out: Path, algo: str, test_episodes: int) -> dict:
    figure = out / f"residual_{algo}_curve.png"
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and figure.stat().st_size > 10_000
    record = json.loads((out / f"residual_{algo}.json").read_text())
    curve = record["curve"]
    assert curve[0][0] == 0 and len(curve) >= 2
    steps = [s for s, _ in curve]
    assert steps == sorted(steps) and steps[-1] == record["trained_steps"] > 0
    assert all(math.isfinite(r) and r <= 0.0 for _, r in curve)
    figures = record["figures"]
    for name in ("zero action", "lqi feedback x2", "policy"):
        for key in ("return", "peak", "rms", "rms_force"):
            mean, std = figures[name][key]
            assert math.isfinite(mean) and math.isfinite(std) and std >= 0.0
        assert 0 <= figures[name]["failures"] <= test_episodes
        assert figures[name]["peak"][0] >= figures[name]["rms"][0] > 0.0
    assert figures["zero action"]["rms_force"] == [0.0, 0.0]
    assert figures["paired"]["episodes"] == test_episodes
    table = (out / f"residual_{algo}_table.md").read_text().splitlines()
    assert table[0].startswith("| controller | return |") and len(table[0].split("|")) == 8
    assert table[2].startswith("| paper's LQI (zero action) |")
    assert table[3].startswith("| paper's LQI, state feedback doubled")
    assert table[4].startswith("| LQI + ")
    assert f"over {test_episodes} held-out episodes" in table[6]
    assert "Made by `python examples/train_residual.py" in table[6]
    return record


def test_ars_pipeline_runs_tiny_and_writes_its_outputs(example, tmp_path, capsys):
    args = ["--steps", "1", "--directions", "2", "--episodes", "1", "--curve-episodes", "2",
            "--test-episodes", "3", "--out", str(tmp_path)]  # fmt: skip
    assert example.main(args) == 0
    record = _check_outputs(tmp_path, "ars", 3)
    # one iteration: 2 directions x 2 signs x 1 episode of 1000 samples
    assert record["trained_steps"] == 4 * 1000
    gains = np.load(tmp_path / "residual_ars_gains.npy")
    assert gains.shape == (4, 13) and np.all(np.isfinite(gains))
    assert "wrote " + str(tmp_path / "residual_ars_curve.png") in capsys.readouterr().out


def test_ppo_pipeline_runs_tiny_and_writes_its_outputs(example, tmp_path):
    args = ["--algo", "ppo", "--steps", "256", "--n-envs", "2", "--eval-every", "256",
            "--curve-episodes", "2", "--test-episodes", "2", "--out", str(tmp_path)]  # fmt: skip
    assert example.main(args) == 0
    record = _check_outputs(tmp_path, "ppo", 2)
    assert record["trained_steps"] == 256  # one rollout of 2 copies x 128 steps
    assert (tmp_path / "residual_ppo_model.zip").is_file()


@pytest.mark.parametrize(
    ("args", "flag"),
    [(["--steps", "0"], "--steps = '0'"), (["--test-episodes", "1"], "--test-episodes = '1'")],
)
def test_bad_argument_gives_one_line_and_exit_2(example, capsys, args, flag):
    assert example.main([*args, "--out", "unused"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and flag in err[0] and "allowed" in err[0]
    assert not Path("unused").exists()


def test_zero_action_evaluation_is_simulate_of_the_same_wind(example):
    """The zero action's return, peak and RMS deviation on a seed are those of ``simulate``
    flying the paper's controller in that seed's wind (effort 0, no failure)."""
    env = TetheredHoverEnv(**example.TASK)
    checked = 0
    for seed in range(example.TEST_SEED, example.TEST_SEED + 40):
        env.reset(seed=seed)
        wind = env.wind_disturbance
        if not isinstance(wind, Pulse | Sine) or checked == 2:
            continue
        checked += 1
        run = example.evaluate(example.zero_policy, [seed])
        result = simulate(Scenario(duration=example.TASK["max_episode_time"], wind=wind))
        assert result.ok and not run["failed"][0]
        error = np.linalg.norm(result.outputs[1:, :3] - result.trim_output[:3], axis=1)
        assert error.max() > 0.02  # the wind moved the helicopter: not a trivial comparison
        assert run["return"][0] == pytest.approx(-np.sum(error**2), rel=1e-9)
        assert run["peak"][0] == pytest.approx(error.max(), rel=1e-9)
        assert run["rms"][0] == pytest.approx(np.sqrt(np.mean(error**2)), rel=1e-9)
        assert run["steps"][0] == len(error)
    assert checked == 2


def test_linear_policy_shared_and_per_copy_gains_agree(example):
    rng = np.random.default_rng(0)
    gains = 0.1 * rng.standard_normal((4, 13))
    obs = (rng.standard_normal((3, 13)) * example.OBS_SCALE).astype(np.float32)
    shared = example.linear_policy(gains)(obs)
    per_copy = example.linear_policy(np.repeat(gains[None], 3, axis=0))(obs)
    np.testing.assert_allclose(shared, per_copy, rtol=1e-6, atol=1e-7)
    expected = np.clip((obs / example.OBS_SCALE) @ gains.T, -1.0, 1.0)
    np.testing.assert_allclose(shared, expected, rtol=1e-5, atol=1e-6)
    assert np.all(example.linear_policy(np.zeros((4, 13)))(obs) == 0.0)


def test_hand_made_residual_is_the_lqi_state_feedback_scaled(example):
    """lqi_feedback_gains(alpha) acting on the observation gives -alpha Kx (x - x0) /
    action_scale of the true state, to the output map's linearisation error."""
    from tetherheli.runs.setup import run_setup

    env = TetheredHoverEnv(wind=Pulse(0.0, 1.0, 15.0, (0.6, 0.8, 0.0)), **example.TASK)
    _, trim, gain, _, _ = run_setup(env.scenario)
    kx = np.asarray(gain.K)[:, :12]
    policy = example.linear_policy(example.lqi_feedback_gains(0.5))
    obs, _ = env.reset(seed=0)
    largest = 0.0
    for _ in range(100):
        obs, *_ = env.step(np.zeros(4, dtype=np.float32))
        expected = -0.5 * kx @ (env.state[:12] - trim.x[:12]) / env.action_scale
        np.testing.assert_allclose(policy(obs[None])[0], expected, rtol=0, atol=5e-3)
        largest = max(largest, float(np.abs(expected).max()))
    assert largest > 0.05  # the pulse moved the state: the comparison is not at zero
