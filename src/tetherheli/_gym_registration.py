"""The Gymnasium ids of the package, registered without importing the compiled stack.

:func:`register_envs` is the ``gymnasium.envs`` entry point of ``pyproject.toml`` and runs on
``import tetherheli`` when Gymnasium is installed: it imports Gymnasium alone and registers
string entry points, so NumPy's, Numba's and the engine's import cost is paid only by
``gymnasium.make``. (Gymnasium 0.26-0.29 call the entry point when they are imported;
Gymnasium 1.x no longer loads plugins, so the registration on ``import tetherheli`` is what
makes ``gymnasium.make(ENV_ID)`` work there.)
"""

from __future__ import annotations

#: Gymnasium id of :class:`tetherheli.envs.env.TetheredHoverEnv`.
ENV_ID = "tetherheli/TetheredHover-v0"

#: ``max_episode_steps`` of the registration: the default episode (30 s,
#: ``envs.DEFAULT_EPISODE_TIME``) at the default sample time (10 ms, ``Scenario().control.dt``);
#: a test checks it against both.
MAX_EPISODE_STEPS = 3000


def register_envs() -> None:
    """Register ``ENV_ID`` ("tetherheli/TetheredHover-v0") with Gymnasium (idempotent; done
    on ``import tetherheli`` and ``import tetherheli.envs.env``, and by Gymnasium's entry point).

    Keyword arguments of ``gymnasium.make`` go to :class:`tetherheli.envs.env.TetheredHoverEnv`.
    The registration has ``max_episode_steps = MAX_EPISODE_STEPS`` (3000: 30 s at 10 ms), so
    ``make`` adds Gymnasium's ``TimeLimit`` wrapper, which agrees with the environment's own
    truncation at the defaults; an episode ends at whichever comes first, so a longer
    ``max_episode_time`` needs ``max_episode_steps`` too (``gymnasium.make(ENV_ID,
    max_episode_time=60, max_episode_steps=6000)``). The vector entry point is
    :class:`tetherheli.envs.vector.TetheredHoverVectorEnv`
    (``gymnasium.make_vec(ENV_ID, num_envs=N, vectorization_mode="vector_entry_point")``),
    which truncates at the same step.
    """
    import gymnasium

    if ENV_ID not in gymnasium.registry:
        gymnasium.register(
            id=ENV_ID,
            entry_point="tetherheli.envs.env:TetheredHoverEnv",
            vector_entry_point="tetherheli.envs.vector:TetheredHoverVectorEnv",
            max_episode_steps=MAX_EPISODE_STEPS,
        )
