"""Stable-Baselines3 on the fast vector environment: ``TetheredHoverSB3VecEnv``.

Stable-Baselines3 does not take a :class:`gymnasium.vector.VectorEnv`; it takes its own
:class:`stable_baselines3.common.vec_env.VecEnv`, with another autoreset rule. This adapter
wraps :class:`tetherheli.envs.vector.TetheredHoverVectorEnv` (all copies in one compiled call
per step) and gives SB3's semantics:

- ``step_wait`` returns ``(obs, rewards, dones, infos)``; ``dones = terminated | truncated``;
- a copy whose episode ended is restarted *in the same step* (``TetheredHoverVectorEnv.restart``):
  its row of ``obs`` is the new episode's first observation, its episode's last observation is
  in ``infos[i]["terminal_observation"]`` and ``infos[i]["TimeLimit.truncated"]`` says whether
  the episode was cut by the time limit rather than ended by a failure, so no transition of
  the next-step autoreset (Gymnasium's) reaches the learner;
- ``infos`` is a list of one dict per copy with the single environment's info keys;
- ``seed(s)`` seeds copy i with s + i at the next reset, as SB3's ``DummyVecEnv`` does.

Needs ``pip install "tetherheli[rl]"`` (Gymnasium, Stable-Baselines3 and PyTorch; install the
CPU build of PyTorch first on a machine without a GPU, see ``docs/studies/gymnasium.md``).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np
from stable_baselines3.common.vec_env import VecEnv

from .vector import TetheredHoverVectorEnv

__all__ = ["TetheredHoverSB3VecEnv"]

#: the single environment's info keys that the adapter hands on, per copy
INFO_KEYS = ("time", "status", "message", "tether_release", "tension", "reel_rate")


class TetheredHoverSB3VecEnv(VecEnv):
    """``num_envs`` tethered-hover copies as a Stable-Baselines3 ``VecEnv``.

    Parameters
    ----------
    num_envs : int
        Number of copies, >= 1.
    scenario, **kwargs
        As for :class:`~tetherheli.envs.env.TetheredHoverEnv` (``max_episode_steps`` too, as for
        :class:`~tetherheli.envs.vector.TetheredHoverVectorEnv`).

    Attributes
    ----------
    venv : TetheredHoverVectorEnv
        The compiled vector environment underneath.
    """

    def __init__(self, num_envs: int = 1, scenario: Any = None, **kwargs: Any) -> None:
        self.venv = TetheredHoverVectorEnv(num_envs, scenario, **kwargs)
        super().__init__(
            self.venv.num_envs, self.venv.single_observation_space, self.venv.single_action_space
        )
        self._actions: np.ndarray | None = None

    # ------------------------------------------------------------------ VecEnv API

    def reset(self) -> np.ndarray:
        """Start an episode in every copy (seeded by the last :meth:`seed`, if any).

        Returns
        -------
        ndarray, shape (num_envs, 13), float32
            The first observations.
        """
        seeds = None if all(s is None for s in self._seeds) else list(self._seeds)
        obs, _ = self.venv.reset(seed=seeds)
        self._reset_seeds()
        self._reset_options()
        return obs

    def step_async(self, actions: np.ndarray) -> None:
        """Remember the actions (num_envs, 4) for :meth:`step_wait`."""
        self._actions = np.asarray(actions)

    def step_wait(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[dict[str, Any]]]:
        """Advance every copy one control sample; restart the copies whose episode ended.

        Returns
        -------
        obs : ndarray, shape (num_envs, 13), float32
        rewards : ndarray, shape (num_envs,), float32
        dones : ndarray, shape (num_envs,), bool
        infos : list of dict
            Per copy: the single environment's info keys, and for a finished episode
            ``terminal_observation`` and ``TimeLimit.truncated``.
        """
        if self._actions is None:
            raise RuntimeError("call step_async(actions) before step_wait()")
        obs, rewards, terminated, truncated, info = self.venv.step(self._actions)
        self._actions = None
        dones = terminated | truncated
        infos: list[dict[str, Any]] = [
            {key: info[key][i] for key in INFO_KEYS} for i in range(self.num_envs)
        ]
        if dones.any():
            for i in np.flatnonzero(dones):
                infos[i]["terminal_observation"] = obs[i].copy()
                infos[i]["TimeLimit.truncated"] = bool(truncated[i] and not terminated[i])
            obs = self.venv.restart(dones)
        return obs, rewards.astype(np.float32), dones, infos

    def close(self) -> None:
        """Nothing to release (no processes, no files)."""

    def get_attr(self, attr_name: str, indices: Any = None) -> list[Any]:
        """An attribute of the shared configuration (``venv.env``), once per copy asked."""
        return [getattr(self.venv.env, attr_name) for _ in self._indices(indices)]

    def set_attr(self, attr_name: str, value: Any, indices: Any = None) -> None:
        """Refused: the copies share one compiled configuration."""
        raise AttributeError(
            f"set_attr({attr_name!r}): the copies share one configuration; build a new "
            "TetheredHoverSB3VecEnv instead"
        )

    def env_method(
        self, method_name: str, *method_args: Any, indices: Any = None, **method_kwargs: Any
    ) -> list[Any]:
        """A method of the shared configuration (``venv.env``), once per copy asked."""
        method = getattr(self.venv.env, method_name)
        return [method(*method_args, **method_kwargs) for _ in self._indices(indices)]

    def env_is_wrapped(self, wrapper_class: type, indices: Any = None) -> list[bool]:
        """No copy is wrapped."""
        return [False for _ in self._indices(indices)]

    def get_images(self) -> Sequence[np.ndarray | None]:
        """The copies are not drawn."""
        return [None for _ in range(self.num_envs)]

    def _indices(self, indices: Any) -> Iterable[int]:
        if indices is None:
            return range(self.num_envs)
        if isinstance(indices, int):
            return [indices]
        return indices
