"""The checks a Gymnasium environment makes before it builds anything: the render mode
(``RENDER_MODES``; "human" only where Matplotlib can open a window, ``RenderModeError``
otherwise), the scenario's keys it cannot fly (``check_env_scenario``, by the table
``SCENARIO_USE``), the names of its own arguments in the scenario's messages
(``argument_names``), ``reset``'s options (``check_reset_options``) and the memory its copies
would hold (``check_env_memory``, refused above the memory budget of
``tetherheli.resources``). ``tetherheli.envs.env`` re-exports the public names.
"""

from __future__ import annotations

import contextlib
import re
from collections.abc import Iterator, Mapping
from typing import Any

import gymnasium

from ..errors import ParameterError
from ..scenario.core import Scenario
from ..wind import Disturbance, compile_wind

__all__ = [
    "RENDER_MODES",
    "RESET_OPTIONS",
    "SCENARIO_USE",
    "RenderModeError",
    "argument_names",
    "check_display",
    "check_env_memory",
    "check_env_scenario",
    "check_reset_options",
    "display_backend",
]

#: What an environment does with each field (top-level key or table) of a ``Scenario``:
#: "flown" as ``simulate`` flies it (the same set-up, sample step and integrator), "argument"
#: (flown unless the environment's argument of the same meaning is given, which replaces it:
#: ``duration`` by ``max_episode_time``, ``wind`` by ``wind``), "label" (no bearing on the
#: flight), or "refused" where ``check_env_scenario`` refuses a value the environment cannot
#: fly (the key named). No field is left out (``tests/test_envs.py`` checks the list).
SCENARIO_USE: dict[str, str] = {
    "name": "label",
    "description": "label",
    "configuration": "flown",
    "duration": "argument",  # max_episode_time
    "q9": "flown",
    # controller 'paper' only; reference 'ground' over a moving base and base_feedforward
    # refused (Python controllers); tether_lqi and mpc are read by those controllers only
    "control": "refused",
    "limits": "flown",
    "wind": "argument",  # wind
    "params": "flown",
    "actuators": "flown",
    "sensors": "flown",
    "tether": "refused",  # model 'elastic' only; its other keys are the lumped chain's
    "seed": "refused",  # 0 with noisy sensors: reset(seed=...) seeds the episodes' noise
    "metrics_start": "refused",  # 0: an environment keeps no metrics
    "winch": "flown",
    "base": "flown",  # the moving base through the engine's packed form, as simulate
    "maneuver": "refused",  # type 'none' only; its other keys are a landing's
    "landing_gear": "refused",  # none: the environments fly no landing gear
    "trajectory": "refused",  # [reference] type 'hold' only (a moving one: simulate's)
}

#: The keys of ``reset(options=...)``: ``{"wind": Disturbance}``.
RESET_OPTIONS = ("wind",)

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
    """Whether Matplotlib's backend can open a window (interactive), and its name.

    Returns
    -------
    can_open : bool
        Whether the backend is interactive (a window can be shown).
    backend : str
        The backend's name (``matplotlib.get_backend()``).
    """
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
    (``runs.closed_loop.check_run_memory``, the rule ``simulate`` applies), its gust series
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
    from ..runs.closed_loop import check_run_memory

    gusts = 3 * 8 * (scenario.duration / gust_dt + 2)
    noisy = "" if scenario.sensors.is_perfect else " with noisy sensors"
    return check_run_memory(
        scenario, record=False, concurrent=copies, per_run_bytes=_COPY_BYTES + gusts,
        what=f"{copies} environment cop{'y' if copies == 1 else 'ies'}{noisy}: "
        f"max_episode_time = {scenario.duration:g} s at dt = {scenario.control.dt:g} s",
        hint="use fewer copies (num_envs) or a shorter max_episode_time",
    )  # fmt: skip


def check_env_scenario(scenario: Scenario) -> None:
    """Refuse (``ParameterError`` naming the key) a scenario an environment cannot fly as
    ``simulate`` would (the "refused" fields of ``SCENARIO_USE``): a controller other than
    the paper's compiled law, one that ``simulate`` flies in Python (a landing, the deck's
    feed-forward, a point of N held over a moving base: ``runs.setup.python_controlled``),
    the lumped tether, a seed of noisy sensors and a metrics window.

    Parameters
    ----------
    scenario : Scenario
        The scenario given to the environment.
    """
    from ..runs.setup import python_controlled

    c = scenario.control
    if c.controller != "paper":  # never substitute the paper's law
        raise ParameterError(
            "scenario.control.controller", c.controller, "'paper' (the environments fly the "
            "paper's controller; the action corrects or replaces it)"
        )  # fmt: skip
    if scenario.maneuver.type != "none":
        raise ParameterError(
            "scenario.maneuver.type", scenario.maneuver.type, "'none' (the environments "
            "hold the hover; a landing is flown by simulate)"
        )  # fmt: skip
    if scenario.landing_gear is not None:
        raise ParameterError(
            "scenario.landing_gear", "a table", "none (the environments fly no landing gear; "
            "simulate flies it)"
        )  # fmt: skip
    if scenario.trajectory.moving:
        raise ParameterError(
            "scenario.trajectory.type", scenario.trajectory.type, "'hold' (the environments "
            "hold the hover; a [reference] is flown by simulate)"
        )  # fmt: skip
    if c.base_feedforward:
        raise ParameterError(
            "scenario.control.base_feedforward", True, "false (the environments fly the "
            "paper's compiled controller; the deck's feed-forward is flown by simulate)"
        )  # fmt: skip
    if python_controlled(scenario):  # the reference: a point of N over a moving base
        raise ParameterError(
            "scenario.control.reference", c.reference, "'base' or unset over a moving base "
            "(the environments fly relative to the base; holding a point of N is flown by "
            "simulate)"
        )  # fmt: skip
    if scenario.tether.lumped:
        raise ParameterError(
            "scenario.tether.model", scenario.tether.model, "'elastic' (the environments "
            "fly eq 28's massless tether)"
        )  # fmt: skip
    if scenario.seed != 0 and not scenario.sensors.is_perfect:
        raise ParameterError(
            "scenario.seed", scenario.seed, "0 with noisy sensors (an episode's sensor noise "
            "is drawn from the generator reset(seed=...) seeds)"
        )  # fmt: skip
    if scenario.metrics_start != 0.0:
        raise ParameterError(
            "scenario.metrics_start", scenario.metrics_start, "0 (the environments keep no "
            "metrics: the reward covers every step)"
        )  # fmt: skip


@contextlib.contextmanager
def argument_names(names: Mapping[str, str]) -> Iterator[None]:
    """Name the environment's arguments in the scenario's messages: a ``ParameterError``
    raised inside about a scenario key of ``names`` (e.g. ``duration``) is raised again
    naming the argument the user wrote (``max_episode_time``), as its field and in its
    allowed text (a table's key of the same name, ``wind.duration``, is left alone).

    Parameters
    ----------
    names : mapping of str to str
        Scenario key -> the environment's argument that set it.

    Returns
    -------
    contextlib.AbstractContextManager
        The context (``contextlib.contextmanager``) in whose body the messages are renamed.
    """
    try:
        yield
    except ParameterError as exc:
        if not names:
            raise
        # a key alone, not a table's key of the same name (``wind.duration``)
        pattern = re.compile(r"(?<![\w.])(" + "|".join(map(re.escape, names)) + r")\b")
        allowed = pattern.sub(lambda m: names[m.group(1)], exc.allowed)
        field = names.get(exc.field, exc.field)
        raise type(exc)(field, exc.value, allowed, source=exc.source) from None


def check_reset_options(options: Any, name: str = "options") -> Disturbance | None:
    """The wind of ``reset(options=...)``: None or a dict whose keys are among
    ``RESET_OPTIONS``; ``options["wind"]`` a built-in ``Disturbance``. Anything else is a
    ``ParameterError`` naming ``options`` (or the unknown key).

    Parameters
    ----------
    options : object
        What ``reset`` was given.
    name : str, optional
        The argument's name in messages.

    Returns
    -------
    Disturbance or None
        The episode's wind, or None (draw one).
    """
    if options is None:
        return None
    allowed = f"None or a dict with keys among {list(RESET_OPTIONS)}"
    if not isinstance(options, Mapping):
        raise ParameterError(name, options, allowed)
    for key in options:
        if key not in RESET_OPTIONS:
            raise ParameterError(f"{name}[{key!r}]", options[key], f"no such key; {allowed}")
    wind = options.get("wind")
    if wind is None:
        return None
    if not isinstance(wind, Disturbance) or compile_wind(wind) is None:
        raise ParameterError(f"{name}['wind']", wind, "a built-in Disturbance")
    return wind
