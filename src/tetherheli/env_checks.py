"""The checks a Gymnasium environment makes before it builds anything: the render mode
(``RENDER_MODES``; "human" only where Matplotlib can open a window, ``RenderModeError``
otherwise) and the memory its copies would hold (``check_env_memory``, refused above the
memory budget of ``tetherheli.resources``). ``tetherheli.envs`` re-exports the public names.
"""

from __future__ import annotations

import gymnasium

from .errors import ParameterError
from .sim.scenario import Scenario

__all__ = [
    "RENDER_MODES",
    "RenderModeError",
    "check_display",
    "check_env_memory",
    "display_backend",
]

#: Render modes of :class:`TetheredHoverEnv` (``render_mode=None``, the default, draws nothing).
RENDER_MODES = ("human", "rgb_array")


class RenderModeError(ParameterError, gymnasium.error.UnsupportedMode):
    """A render mode the environment does not support (or "human" without a display): a
    ``ParameterError`` (one line) that is also Gymnasium's ``error.UnsupportedMode``.

    Parameters
    ----------
    field, value, allowed, source
        As for ``ParameterError``.
    """


def display_backend() -> tuple[bool, str]:
    """Whether Matplotlib's backend can open a window (interactive), and its name."""
    import matplotlib
    from matplotlib.backends import BackendFilter, backend_registry

    backend = matplotlib.get_backend()  # resolves the automatic choice (no window opened)
    interactive = backend.lower() in backend_registry.list_builtin(BackendFilter.INTERACTIVE)
    return interactive or (backend.startswith("module://") and "inline" not in backend), backend


def check_display() -> None:
    """Refuse ``render_mode="human"`` (``RenderModeError``) unless Matplotlib's backend is
    interactive, i.e. a window can be shown."""
    can_open, backend = display_backend()
    if not can_open:
        raise RenderModeError(
            "render_mode",
            "human",
            f"'rgb_array' or None here: no display (Matplotlib backend {backend!r} cannot "
            "open a window)",
        )


#: What one environment copy holds besides its per-sample tables: its state, settings and
#: loop arrays (about 300 floats with ``layout``'s sizes) and its Python objects (generator,
#: disturbance, infos), measured near 3 kB with tracemalloc; margin kept.
_COPY_BYTES = 8_192


def check_env_memory(scenario: Scenario, copies: int, gust_dt: float) -> int:
    """Estimate the bytes ``copies`` environment copies of ``scenario`` (an episode's
    duration and sensors) hold at once: each copy's sensor-noise table and schedule
    (``sim.closed_loop.check_run_memory``, the rule ``simulate`` applies), its gust series
    (3 floats per ``gust_dt``) and its state; refuse them (``ResourceLimitError``) above
    the memory budget (``tetherheli.resources``), before anything is allocated.

    Parameters
    ----------
    scenario : Scenario
        The episode's scenario (``duration`` = ``max_episode_time``).
    copies : int
        Environment copies (``num_envs``), >= 1.
    gust_dt : float
        The turbulence's gust step [s].

    Returns
    -------
    int
        The estimated bytes.

    Raises
    ------
    ResourceLimitError
        The estimate exceeds the budget.
    """
    from .sim.closed_loop import check_run_memory

    gusts = 3 * 8 * (scenario.duration / gust_dt + 2)
    noisy = "" if scenario.sensors.is_perfect else " with noisy sensors"
    return check_run_memory(
        scenario, record=False, concurrent=copies, per_run_bytes=_COPY_BYTES + gusts,
        what=f"{copies} environment cop{'y' if copies == 1 else 'ies'}{noisy}: "
        f"max_episode_time = {scenario.duration:g} s at dt = {scenario.control.dt:g} s",
        hint="use fewer copies (num_envs) or a shorter max_episode_time",
    )  # fmt: skip
