"""The environment in Gymnasium's and Stable-Baselines3's hands (issue 12, item 1): render
modes, registration on import and by module path, ``max_episode_steps``, Gymnasium's own
checker and vector wrappers."""

from __future__ import annotations

import dataclasses
import os
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

from gymnasium.utils.env_checker import check_env  # noqa: E402
from gymnasium.vector import AsyncVectorEnv, AutoresetMode, SyncVectorEnv  # noqa: E402

from tetherheli import simulate  # noqa: E402
from tetherheli.envs.env import (  # noqa: E402
    DEFAULT_EPISODE_TIME,
    ENV_ID,
    MAX_EPISODE_STEPS,
    RenderModeError,
    TetheredHoverEnv,
)
from tetherheli.envs.vector import TetheredHoverVectorEnv  # noqa: E402
from tetherheli.errors import ParameterError  # noqa: E402
from tetherheli.scenario.core import Scenario  # noqa: E402
from tetherheli.viz.animation import RunData, frame_rgb  # noqa: E402
from tetherheli.wind import Pulse  # noqa: E402

SRC = Path(__file__).resolve().parents[1] / "src"
PULSE = Pulse(start=0.1, duration=0.3, magnitude=20.0, direction=(0.6, 0.8, 0.0))


def test_check_env_with_rgb_array_rendering():
    """Gymnasium's checker, render check included: ``render()`` returns an RGB uint8 frame;
    the only remark is that an env without a spec cannot be re-made in other modes."""
    env = TetheredHoverEnv(max_episode_time=0.2, render_mode="rgb_array")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(env)
    messages = [str(w.message) for w in caught]
    assert len(messages) == 1 and "alternative render modes" in messages[0], messages
    frame = env.render()
    assert frame.dtype == np.uint8 and frame.ndim == 3 and frame.shape[2] == 3
    assert env.metadata["render_fps"] == pytest.approx(1.0 / env.dt)
    base = Scenario()
    coarse = base.replace(control=dataclasses.replace(base.control, dt=0.02))
    assert TetheredHoverEnv(coarse).metadata["render_fps"] == pytest.approx(50.0)


def test_rgb_frame_is_the_animation_scene_of_the_run():
    """The rendered frame is the animation's scene (``frame_rgb``) of the same run flown by
    ``simulate``: a zero residual reproduces simulate (test_envs), so the recorded episode
    equals the simulated samples and the pictures are the same."""
    scenario = Scenario(duration=0.3, wind=PULSE)
    result = simulate(scenario)
    env = TetheredHoverEnv(scenario, wind=PULSE, max_episode_time=0.3, render_mode="rgb_array")
    env.reset(seed=0)
    for _ in range(20):
        env.step(np.zeros(4, dtype=np.float32))
    episode = env.episode()
    n = episode.time.size
    assert n == 21
    q = np.column_stack([result.outputs[:n, :3], result.states[:n, :6]])
    np.testing.assert_allclose(episode.q, q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(episode.wind, result.wind[:n], rtol=0, atol=1e-9)
    np.testing.assert_allclose(episode.tension, result.tension[:n], rtol=0, atol=1e-9)
    assert np.abs(episode.wind).max() > 1.0  # the pulse is on: the arrow is drawn
    simulated = dataclasses.replace(
        episode, time=result.time[:n].copy(), q=q, wind=result.wind[:n].copy(),
        tension=result.tension[:n].copy(),
    )  # fmt: skip
    frame = env.render()
    expected = frame_rgb([simulated], float(result.time[n - 1]))
    differing = np.any(frame != expected, axis=2).mean()
    assert differing < 1e-3, differing
    # and the frame changes as the helicopter moves
    for _ in range(9):
        env.step(np.ones(4, dtype=np.float32))
    assert np.any(env.render() != frame)
    assert isinstance(episode, RunData)


def test_unknown_render_mode_and_human_without_display_are_refused(monkeypatch):
    with pytest.raises(RenderModeError, match="render_mode = 'ansi'") as err:
        TetheredHoverEnv(render_mode="ansi")
    assert isinstance(err.value, gymnasium.error.UnsupportedMode)
    assert isinstance(err.value, ParameterError) and err.value.field == "render_mode"
    import matplotlib

    monkeypatch.setattr(matplotlib, "get_backend", lambda: "agg")
    with pytest.raises(RenderModeError, match="no display") as err:
        TetheredHoverEnv(render_mode="human")
    assert "\n" not in str(err.value)
    with pytest.raises(RenderModeError, match="render_mode"):
        TetheredHoverVectorEnv(2, render_mode="rgb_array")


def test_render_without_mode_warns_and_returns_none():
    env = TetheredHoverEnv(max_episode_time=0.1)
    env.reset(seed=0)
    with pytest.warns(UserWarning, match="render_mode=None"):
        assert env.render() is None


def test_registration_has_max_episode_steps_of_the_default_episode():
    spec = gymnasium.spec(ENV_ID)
    assert spec.max_episode_steps == MAX_EPISODE_STEPS
    assert MAX_EPISODE_STEPS * Scenario().control.dt == pytest.approx(DEFAULT_EPISODE_TIME)
    assert TetheredHoverEnv().n_max == MAX_EPISODE_STEPS  # TimeLimit and env agree
    env = gymnasium.make(ENV_ID)
    assert env.spec.max_episode_steps == MAX_EPISODE_STEPS
    env.close()


def test_time_limit_and_vector_env_truncate_at_the_same_step():
    """A ``max_episode_steps`` shorter than the episode truncates both the made environment
    (Gymnasium's TimeLimit) and the vector entry point at that step."""
    env = gymnasium.make(ENV_ID, wind="none", max_episode_time=1.0, max_episode_steps=7)
    env.reset(seed=0)
    steps = [env.step(np.zeros(4, dtype=np.float32))[3] for _ in range(7)]
    assert steps == [False] * 6 + [True]
    env.close()
    vec = gymnasium.make_vec(
        ENV_ID, num_envs=2, vectorization_mode="vector_entry_point", wind="none",
        max_episode_time=1.0, max_episode_steps=7,
    )  # fmt: skip
    vec.reset(seed=0)
    truncated = [vec.step(np.zeros((2, 4)))[3].all() for _ in range(7)]
    assert truncated == [False] * 6 + [True]
    vec.close()
    with pytest.raises(ParameterError, match="max_episode_steps"):
        TetheredHoverVectorEnv(2, max_episode_steps=0)


def _fresh(code: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        timeout=300,
        env={**os.environ, "PYTHONPATH": str(SRC)},
        check=False,
    )


def test_make_by_module_path_in_a_fresh_process():
    """``gymnasium.make("tetherheli.envs.env:tetherheli/TetheredHover-v0")`` imports the module
    (which registers the id) in a process that never imported tetherheli."""
    out = _fresh(
        "import sys, gymnasium\n"
        "assert 'tetherheli' not in sys.modules\n"
        f"env = gymnasium.make('tetherheli.envs.env:{ENV_ID}', max_episode_time=0.1)\n"
        "obs, _ = env.reset(seed=0)\n"
        "print(type(env.unwrapped).__name__, obs.shape, env.spec.max_episode_steps)\n"
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["TetheredHoverEnv", "(13,)", str(MAX_EPISODE_STEPS)]


def test_async_vector_env_autoreset_matches_the_vector_env():
    """Gymnasium's AsyncVectorEnv (copies in subprocesses, next-step autoreset) gives the
    same batches as the compiled vector environment through a truncation and autoreset."""
    n, kwargs = 2, {"max_episode_time": 0.05, "wind": ("pulse", "sine")}
    vec = TetheredHoverVectorEnv(n, **kwargs)
    workers = AsyncVectorEnv(
        [lambda: TetheredHoverEnv(**kwargs) for _ in range(n)],
        autoreset_mode=AutoresetMode.NEXT_STEP,
    )
    try:
        rng = np.random.default_rng(1)
        np.testing.assert_array_equal(vec.reset(seed=3)[0], workers.reset(seed=3)[0])
        truncations = 0
        for _ in range(12):
            a = rng.uniform(-1.0, 1.0, size=(n, 4)).astype(np.float32)
            mine, theirs = vec.step(a), workers.step(a)
            for x, y in zip(mine[:4], theirs[:4], strict=True):
                np.testing.assert_array_equal(x, y)
            truncations += int(mine[3].sum())
        assert truncations == 2 * n  # steps 5 and 11 truncate; 6 is the autoreset step
    finally:
        workers.close()


def test_sync_vector_env_of_made_envs_autoresets():
    """``gymnasium.make_vec`` in sync mode (``SyncVectorEnv`` of made, TimeLimit-wrapped
    environments) truncates and resets each copy."""
    vec = gymnasium.make_vec(ENV_ID, num_envs=2, vectorization_mode="sync", max_episode_time=0.03)
    assert isinstance(vec, SyncVectorEnv)
    vec.reset(seed=0)
    flags = [vec.step(np.zeros((2, 4)))[3].all() for _ in range(4)]
    assert flags == [False, False, True, False]  # step 4 is the autoreset
    vec.close()


@pytest.mark.extra("rl")
def test_sb3_make_vec_env():
    """Stable-Baselines3's ``make_vec_env`` asks for ``render_mode="rgb_array"``."""
    env_util = pytest.importorskip("stable_baselines3.common.env_util")
    vec = env_util.make_vec_env(ENV_ID, n_envs=2, env_kwargs={"max_episode_time": 0.1})
    obs = vec.reset()
    assert obs.shape == (2, 13)
    assert vec.render_mode == "rgb_array"
    vec.close()


def test_check_env_of_made_env_passes_headless(monkeypatch):
    """Issue 25, item 2: on a machine without a display, ``check_env`` of ``gymnasium.make``'s
    env re-makes it in every listed render mode; "human" is listed only where a window can
    open, so the checker passes (it raised ``RenderModeError`` before)."""
    import matplotlib

    monkeypatch.setattr(matplotlib, "get_backend", lambda: "agg")
    env = gymnasium.make(ENV_ID, max_episode_time=0.2)
    assert env.unwrapped.metadata["render_modes"] == ["rgb_array"]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(env.unwrapped)
    assert [str(w.message) for w in caught] == []
    env.close()
    monkeypatch.setattr(matplotlib, "get_backend", lambda: "qtagg")
    assert TetheredHoverEnv(max_episode_time=0.1).metadata["render_modes"] == [
        "human",
        "rgb_array",
    ]


def test_import_tetherheli_registers_the_ids_without_the_compiled_stack():
    """``import tetherheli`` registers ``ENV_ID`` (Gymnasium 1.x loads no plugins) and imports
    neither Numba nor the environment module; ``make`` then imports them."""
    out = _fresh(
        "import sys, gymnasium\n"
        f"assert {ENV_ID!r} not in gymnasium.registry\n"
        "import tetherheli\n"
        "print('numba' in sys.modules, 'tetherheli.envs.env' in sys.modules,"
        f" {ENV_ID!r} in gymnasium.registry)\n"
        f"env = gymnasium.make({ENV_ID!r}, max_episode_time=0.1)\n"
        "print(type(env.unwrapped).__name__)\n"
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["False", "False", "True", "TetheredHoverEnv"]


def test_the_gymnasium_entry_point_registers_the_ids(monkeypatch):
    """``pyproject.toml``'s ``gymnasium.envs`` entry point names a function that registers
    ``ENV_ID`` with the registration ``envs`` itself uses."""
    import importlib
    import tomllib

    from tetherheli import _gym_registration

    pyproject = tomllib.loads((SRC.parent / "pyproject.toml").read_text())
    target = pyproject["project"]["entry-points"]["gymnasium.envs"]["tetherheli"]
    module, _, name = target.partition(":")
    register = getattr(importlib.import_module(module), name)
    assert register is _gym_registration.register_envs
    monkeypatch.delitem(gymnasium.registry, ENV_ID)
    register()
    assert gymnasium.spec(ENV_ID).max_episode_steps == MAX_EPISODE_STEPS
    assert gymnasium.spec(ENV_ID).entry_point == "tetherheli.envs.env:TetheredHoverEnv"
