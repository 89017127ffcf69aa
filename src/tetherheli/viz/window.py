"""A frame shown in a Matplotlib window: the Gymnasium environment's "human" render mode
(``envs``, through ``env_render``). The only module of the package that draws through
pyplot, imported on first use (``show_image``), never at import time; the backend is
Matplotlib's choice.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["close_window", "show_image"]


def show_image(window: Any, image: np.ndarray, fps: float, title: str) -> tuple[Any, Any]:
    """Show ``image`` in the window ``window`` ((figure, image artist), or None or a window
    since closed: a 10 x 6 inch one is opened, named ``title``), then pause 1 / ``fps`` s
    (pyplot's event loop runs meanwhile).

    Parameters
    ----------
    window : tuple of (Figure, AxesImage), or None
        The window of an earlier call.
    image : numpy.ndarray, shape (H, W, 3), uint8
        The RGB image (``viz.animation.frame_rgb``'s frame).
    fps : float
        Frames per second [1/s].
    title : str
        The window's name, when one is opened.

    Returns
    -------
    tuple of (Figure, AxesImage)
        The window, for the next call and ``close_window``.
    """
    import matplotlib.pyplot as plt

    if window is None or not plt.fignum_exists(window[0].number):
        fig = plt.figure(title, figsize=(10, 6))
        ax = fig.add_axes((0.0, 0.0, 1.0, 1.0))
        ax.set_axis_off()
        window = (fig, ax.imshow(image))
    else:
        window[1].set_data(image)
    plt.pause(1.0 / fps)
    return window


def close_window(window: tuple[Any, Any]) -> None:
    """Close a window of ``show_image``.

    Parameters
    ----------
    window : tuple of (Figure, AxesImage)
        ``show_image``'s window.
    """
    import matplotlib.pyplot as plt

    plt.close(window[0])
