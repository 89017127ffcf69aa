"""The drawing of a Gymnasium environment's episode (``render_mode``): each step's row of the
recorded episode (``episode_row``), the episode as the animation reads a saved run
(``episode_data``), its frame (``draw_frame``, ``tetherheli animate``'s scene) and the
"human" mode's Matplotlib window (``show_frame``, ``close_window``). The drawing is the viz
layer's (``viz.animation.frame_rgb``, ``viz.window``); it and Matplotlib load on first use.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from .sim.scenario import Scenario
from .status import status_message
from .wind import CompiledWind
from .wind.evaluate import air_force_on_base

__all__ = ["close_window", "draw_frame", "episode_data", "episode_row", "show_frame"]


def episode_row(
    t: float,
    y: np.ndarray,
    x: np.ndarray,
    wind: CompiledWind,
    gust_dt: float,
    tension: float,
    base: np.ndarray,
) -> np.ndarray:
    """One sample of the rendered episode (14,): t, q1..q9 (outputs y[:3], then x[:6]), the
    wind force on HO (``air_force_on_base`` over the packed ``base``, as ``simulate`` records
    it) and the tension."""
    row = np.empty(14)
    row[0] = t
    row[1:4] = y[:3]
    row[4:10] = x[:6]
    force = np.zeros(3)
    air_force_on_base(
        wind.program, wind.gust, gust_dt, wind.drag, base, t, 1, x[6], x[7], x[8], force
    )  # fmt: skip
    row[10:13] = force
    row[13] = tension
    return row


def episode_data(
    frames: Sequence[np.ndarray],
    scenario: Scenario,
    trim_position: np.ndarray,
    status: int,
    release_time: float,
) -> Any:
    """The recorded rows ``frames`` (``episode_row``'s) as a
    :class:`tetherheli.viz.animation.RunData` (stem "episode"), with the trim position, the
    scenario's helicopter and the episode's status (its message with ``release_time``)."""
    from ._version import __version__
    from .viz.animation import RunData

    rows = np.array(frames)
    return RunData(
        stem="episode",
        name=scenario.name,
        configuration=scenario.configuration,
        time=rows[:, 0],
        q=rows[:, 1:10],
        wind=rows[:, 10:13],
        tension=rows[:, 13],
        trim_position=trim_position,
        helicopter=scenario.params.helicopter,
        status=status,
        message=status_message(status, release_time),
        version=__version__,
    )


def draw_frame(run: Any) -> np.ndarray:
    """The animation's frame of ``run`` (``episode_data``'s) at its last sample."""
    from .viz.animation import frame_rgb

    return frame_rgb([run], float(run.time[-1]))


def show_frame(window: Any, frame: np.ndarray, fps: float, title: str) -> tuple:
    """Show ``frame`` in the "human" mode's Matplotlib window ``window`` ((figure, image), or
    None: opened here, named ``title``), then pause 1 / fps; returns the window
    (``viz.window.show_image``)."""
    from .viz.window import show_image

    return show_image(window, frame, fps, title)


def close_window(window: tuple) -> None:
    """Close the "human" mode's window (``show_frame``'s; ``viz.window.close_window``)."""
    from .viz import window as viz_window

    viz_window.close_window(window)
