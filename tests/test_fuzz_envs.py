"""Issue 43, items 10 and 13: a property-based fuzzer of the Gymnasium environments' arguments
(Hypothesis).

It builds ``TetheredHoverEnv``, ``TetheredHoverVectorEnv`` and (when Stable-Baselines3 is
installed) ``TetheredHoverSB3VecEnv`` from keyword arguments drawn inside, at and beyond each
one's range, non-finite numbers and wrong types, then resets them with ``options`` drawn the
same way (None, the documented ``{"wind": Disturbance}``, other types, unknown keys) and takes
a step. It asserts that each call either refuses in one line (a ``ParameterError`` naming the
argument the user wrote, ``field = value is invalid; allowed: ...``, or the memory budget's
``ResourceLimitError``) or gives observations that are finite float32 values inside the
observation space.

Bounded in CI: a fixed example budget, derandomized (the same examples on every run), no
deadline, a few seconds. ``TETHERHELI_FUZZ_EXAMPLES=2000`` runs longer (and random) on demand.
"""

from __future__ import annotations

import math
import os
import re
from typing import Any

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis")
pytest.importorskip("gymnasium")

from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from tetherheli.envs.env import WIND_KINDS, TetheredHoverEnv  # noqa: E402
from tetherheli.envs.vector import TetheredHoverVectorEnv  # noqa: E402
from tetherheli.errors import ParameterError, TetherheliError  # noqa: E402
from tetherheli.wind import DragModel, GaussMarkovTurbulence, NoWind, Pulse, Sine  # noqa: E402

_ON_DEMAND = int(os.environ.get("TETHERHELI_FUZZ_EXAMPLES", "0") or 0)


def _settings(examples: int) -> settings:
    return settings(
        max_examples=_ON_DEMAND or examples,
        derandomize=not _ON_DEMAND,
        deadline=None,
        suppress_health_check=[HealthCheck.too_slow],
        database=None,
    )


#: A refusal: "field = value is invalid; allowed: ..." on one line.
REFUSAL = re.compile(r"^(?P<field>[\w.\[\]'-]+) = .* is invalid; allowed: ")

#: The constructor's arguments (the names the user writes).
ARGUMENTS = (
    "wind", "residual", "action_scale", "max_episode_time", "max_wind_force", "max_mean_wind",
    "turbulence", "drag", "gust_dt", "effort_weight", "termination_penalty", "render_mode",
)  # fmt: skip

PULSE = Pulse(0.02, 0.05, 15.0, (0.6, 0.8, 0.0))

_WRONG = st.sampled_from([None, "x", b"1", [], {}, {"a": 1}, (1, 2), object(), True, 1j])


def _number(low: float = 0.0) -> st.SearchStrategy:
    """Numbers inside, at and beyond a bound, huge, tiny and non-finite ones."""
    return st.one_of(
        st.sampled_from([low - 1.0, low, low + 1e-9, low + 0.5, 1e300, -1e300, 1e-300]),
        st.floats(allow_nan=True, allow_infinity=True, width=64),
        st.integers(-(10**6), 10**6),
    )


def _arguments() -> dict[str, st.SearchStrategy]:
    kinds = st.sampled_from([*WIND_KINDS, "gale", ""])
    return {
        "wind": st.one_of(
            kinds,
            st.lists(kinds, max_size=3),
            st.lists(kinds, max_size=2).map(tuple),
            st.sampled_from([PULSE, NoWind(), Sine(5.0, 0.2, 0.0, (1.0, 0.0, 0.0)), 3]),
            _WRONG,
        ),
        "residual": st.one_of(st.booleans(), _WRONG, st.integers(0, 1)),
        "action_scale": st.one_of(
            st.lists(_number(), min_size=3, max_size=5),
            st.lists(st.floats(0.1, 30.0), min_size=4, max_size=4),
            _WRONG,
        ),
        "max_episode_time": st.one_of(
            st.sampled_from([0.01, 0.05, 0.1, 0.105, 0.0, -0.1, 1e12, math.nan, math.inf]),
            st.floats(-0.1, 0.2),
            _WRONG,
        ),
        "max_wind_force": st.one_of(_number(), st.floats(0.0, 30.0), _WRONG),
        "max_mean_wind": st.one_of(_number(), st.floats(0.0, 5.0), _WRONG),
        "turbulence": st.sampled_from([None, GaussMarkovTurbulence(), "dryden", 1.0]),
        "drag": st.sampled_from([None, DragModel(cd_area_m2=(0.3, 0.3, 0.5)), "cd", 0.3]),
        "gust_dt": st.one_of(_number(), st.floats(0.01, 0.2), _WRONG),
        "effort_weight": st.one_of(_number(), _WRONG),
        "termination_penalty": st.one_of(_number(), _WRONG),
        "render_mode": st.sampled_from([None, None, "rgb_array", "ansi", "human ", 3]),
    }


def _valid_arguments() -> dict[str, st.SearchStrategy]:
    """Values each argument allows, up to its extremes (strong winds, long gust steps)."""
    return {
        "wind": st.one_of(st.sampled_from(WIND_KINDS), st.just(PULSE)),
        "residual": st.booleans(),
        "action_scale": st.lists(st.floats(1e-3, 1e3), min_size=4, max_size=4),
        "max_episode_time": st.sampled_from([0.01, 0.05, 0.1]),
        "max_wind_force": st.floats(0.0, 1e6),
        "max_mean_wind": st.floats(0.0, 100.0),
        "turbulence": st.sampled_from([None, GaussMarkovTurbulence()]),
        "drag": st.sampled_from([None, DragModel(cd_area_m2=(1.0, 1.0, 1.0))]),
        "gust_dt": st.floats(0.005, 1.0),
        "effort_weight": st.floats(0.0, 1e6),
        "termination_penalty": st.floats(0.0, 1e6),
        "render_mode": st.sampled_from([None, "rgb_array"]),
    }


@st.composite
def env_arguments(draw) -> dict[str, Any]:
    """Some of the constructor's arguments, all valid in about half the examples; a short
    episode unless drawn otherwise."""
    strategies = _valid_arguments() if draw(st.booleans()) else _arguments()
    names = draw(st.lists(st.sampled_from(ARGUMENTS), max_size=4, unique=True))
    kwargs = {name: draw(strategies[name]) for name in names}
    kwargs.setdefault("max_episode_time", 0.05)
    return kwargs


_VALID_OPTIONS = st.sampled_from([None, {}, {"wind": None}, {"wind": PULSE}, {"wind": NoWind()}])
OPTIONS = st.one_of(
    _VALID_OPTIONS,
    _VALID_OPTIONS,
    st.sampled_from(["wind", ["wind"], 3, {"wind": "pulse"}, {"wnd": PULSE}, {1: 2}]),
    st.dictionaries(st.sampled_from(["wind", "seed", "gust"]), _WRONG, max_size=2),
)

#: What the runs met, by outcome (reported with ``-s``).
COUNTS: dict[str, int] = {}


def _count(key: str) -> None:
    COUNTS[key] = COUNTS.get(key, 0) + 1


def _assert_refusal(exc: BaseException, names: tuple[str, ...]) -> None:
    """One line; a ``ParameterError`` names a user-written field (an argument, a key of
    ``options``, the seed)."""
    message = str(exc)
    assert isinstance(exc, TetherheliError), repr(exc)
    assert "\n" not in message, message
    if isinstance(exc, ParameterError):
        match = REFUSAL.match(message)
        assert match, message
        root = re.split(r"[.\[]", exc.field)[0]
        assert root in names, message
        assert "duration" != exc.field, message


def _assert_observations(space: Any, obs: np.ndarray) -> None:
    assert obs.dtype == np.float32
    assert np.all(np.isfinite(obs)), obs
    assert space.contains(obs), obs


def _exercise(make, step_action, options: Any, names: tuple[str, ...]) -> None:
    """Build with ``make``, reset with ``options``, step once: each either refuses in one
    line or gives finite observations inside the observation space."""
    try:
        env = make()
    except Exception as exc:
        _assert_refusal(exc, names)
        _count(f"constructor refused: {getattr(exc, 'field', type(exc).__name__)}")
        return
    try:
        obs, _ = env.reset(seed=0, options=options)
    except Exception as exc:
        # the options, or a drawn wind without a trim at rest named by its bound
        _assert_refusal(exc, ("options", "seed", "wind", "max_mean_wind", "max_wind_force"))
        _count(f"reset refused: {getattr(exc, 'field', type(exc).__name__)}")
        return
    _assert_observations(env.observation_space, obs)
    obs, *_ = env.step(step_action)
    _assert_observations(env.observation_space, obs)
    _count("flown")
    env.close()


@_settings(150)
@given(kwargs=env_arguments(), options=OPTIONS)
def test_env_arguments_and_reset_options(kwargs, options):
    """``TetheredHoverEnv(**kwargs).reset(options=options)``: one line or a valid start."""
    _exercise(lambda: TetheredHoverEnv(**kwargs), np.zeros(4, dtype=np.float32), options, ARGUMENTS)


@_settings(40)
@given(kwargs=env_arguments(), options=OPTIONS, n=st.sampled_from([1, 2, 0, -1, 2.0, "2"]))
def test_vector_env_arguments_and_reset_options(kwargs, options, n):
    """The vector environment (``num_envs`` drawn too): one line or valid starts."""
    kwargs.pop("render_mode", None)  # the copies are not drawn (tested in test_envs_gym)
    action = np.zeros((n, 4)) if isinstance(n, int) and n > 0 else np.zeros((1, 4))
    _exercise(
        lambda: TetheredHoverVectorEnv(n, **kwargs), action, options, (*ARGUMENTS, "num_envs")
    )


@pytest.mark.extra("rl")
@_settings(20)
@given(kwargs=env_arguments(), n=st.sampled_from([1, 2, 0]))
def test_sb3_vec_env_arguments(kwargs, n):
    """Stable-Baselines3's ``VecEnv`` adapter: one line or valid starts (skipped without
    Stable-Baselines3)."""
    pytest.importorskip("stable_baselines3")
    from tetherheli.envs.sb3 import TetheredHoverSB3VecEnv

    kwargs.pop("render_mode", None)
    try:
        env = TetheredHoverSB3VecEnv(n, **kwargs)
    except Exception as exc:
        _assert_refusal(exc, (*ARGUMENTS, "num_envs"))
        return
    env.seed(0)  # the episodes' winds drawn from a fixed seed, as the other fuzzers' resets
    try:
        obs = env.reset()
    except Exception as exc:  # a drawn wind without a trim at rest, named by its bound
        _assert_refusal(exc, ("seed", "wind", "max_mean_wind", "max_wind_force"))
        return
    _assert_observations(env.venv.observation_space, obs)
    env.step_async(np.zeros((n, 4)))
    obs, *_ = env.step_wait()
    _assert_observations(env.venv.observation_space, obs)


def test_fuzzers_are_bounded_and_report():
    """The CI budget stays small and fixed (derandomized) unless asked for more."""
    if not _ON_DEMAND:
        assert _settings(150).max_examples == 150 and _settings(150).derandomize
    print("environment fuzz outcomes:", dict(sorted(COUNTS.items())))
