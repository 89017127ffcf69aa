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

from ..scenario.core import Scenario
from ..status import status_message
from ..wind import CompiledWind
from ..wind.evaluate import air_force_on_base

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
    it) and the tension.

    Parameters
    ----------
    t : float
        The sample's time [s].
    y : numpy.ndarray, shape (4,)
        The outputs [q1, q2, q3 in m, q6 in rad].
    x : numpy.ndarray, shape (13,)
        The tethered state [q4..q9, u1..u6, LN] (relative to the base): q4..q8 [rad], q9 [m],
        u1..u3 [m/s].
    wind : CompiledWind
        The episode's wind in the engine's form (``wind.compiled``).
    gust_dt : float
        The gust table's step [s] (0: no table).
    tension : float
        The tether tension [N].
    base : numpy.ndarray, shape (rows, BASE_COLUMNS)
        The base motion's packed form (``layout.BASE_*``).

    Returns
    -------
    numpy.ndarray, shape (14,)
        t [s], q1..q9 [m, rad], the wind force on HO in N [N] and the tension [N].
    """
    row = np.empty(14)
    row[0] = t
    row[1:4] = y[:3]
    row[4:10] = x[:6]
    force = np.zeros(3)
    air_force_on_base(
        wind.program, wind.gust, gust_dt, wind.drag, base, t, 1, (x[6], x[7], x[8]), force
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
    scenario's helicopter and the episode's status (its message with ``release_time``).

    Parameters
    ----------
    frames : sequence of numpy.ndarray, shape (14,)
        The episode's rows (``episode_row``'s), one per sample.
    scenario : Scenario
        The episode's scenario (its name, configuration and helicopter).
    trim_position : numpy.ndarray, shape (3,)
        The trim's position of HO in N [m].
    status : int
        The episode's ``Status`` code.
    release_time : float
        The tether release time [s] (NaN: none).

    Returns
    -------
    tetherheli.viz.animation.RunData
        The episode as the animation's run.
    """
    from .._version import __version__
    from ..viz.animation import RunData

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
    """The animation's frame of ``run`` (``episode_data``'s) at its last sample.

    Parameters
    ----------
    run : tetherheli.viz.animation.RunData
        The episode so far (``episode_data``'s).

    Returns
    -------
    numpy.ndarray, shape (H, W, 3), uint8
        The RGB frame (``viz.animation.frame_rgb``).
    """
    from ..viz.animation import frame_rgb

    return frame_rgb([run], float(run.time[-1]))


def show_frame(window: Any, frame: np.ndarray, fps: float, title: str) -> tuple:
    """Show ``frame`` in the "human" mode's Matplotlib window ``window`` ((figure, image), or
    None: opened here, named ``title``), then pause 1 / fps; returns the window
    (``viz.window.show_image``).

    Parameters
    ----------
    window : tuple of (Figure, AxesImage), or None
        The window of an earlier call; None: open one.
    frame : numpy.ndarray, shape (H, W, 3), uint8
        The RGB frame (``draw_frame``'s).
    fps : float
        Frames per second [1/s].
    title : str
        The window's name, when one is opened.

    Returns
    -------
    tuple of (Figure, AxesImage)
        The window, for the next call.
    """
    from ..viz.window import show_image

    return show_image(window, frame, fps, title)


def close_window(window: tuple) -> None:
    """Close the "human" mode's window (``show_frame``'s; ``viz.window.close_window``).

    Parameters
    ----------
    window : tuple of (Figure, AxesImage)
        The window ``show_frame`` returned.
    """
    from ..viz import window as viz_window

    viz_window.close_window(window)
