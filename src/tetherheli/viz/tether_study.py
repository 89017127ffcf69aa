"""Figures of the tether study (``studies.tether_study``, ``studies.tether_sensing``): they
only read its rows and return Matplotlib ``Figure`` objects built without pyplot (as
``viz.plots``; ``plots.save_figure`` writes them)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from .figure import _new_figure

__all__ = ["figure_study_reduction", "figure_study_sensing", "figure_study_static"]

_CABLE_STYLE = ("o-", "s-", "^-", "D-", "v-")


def _series(rows: Sequence[dict[str, Any]], cable: str, key: str) -> tuple[np.ndarray, ...]:
    sel = [r for r in rows if r["cable"] == cable]
    x = np.array([r["length_m"] for r in sel], dtype=float)
    y = np.array([np.nan if r.get(key) is None else r[key] for r in sel], dtype=float)
    return x, y


def figure_study_reduction(
    rows: Sequence[dict[str, Any]], labels: dict[str, str], *, fig: Figure | None = None
) -> Figure:
    """The paper's metric against tether length, one line per cable: the reduction
    100 (free - tethered) / free [%] of the peak (solid) and RMS (dashed) deviation along the
    wind in simulations 1 (q1) and 2 (q2), and of the RMS q1, q2 in turbulence.

    Parameters
    ----------
    rows : sequence of dict
        ``tether_study.dynamic_rows``'s rows.
    labels : dict of str to str
        Cable key -> legend text.
    fig : Figure, optional
        An empty figure to draw into.

    Returns
    -------
    Figure
    """
    fig = _new_figure(fig, (12.0, 4.0))
    axes = fig.subplots(1, 3, sharey=True)
    panels = (
        ("Simulation 1 (wind along n1): q1", ("sim1_peak_q1", "sim1_rms_q1")),
        ("Simulation 2 (wind along n2): q2", ("sim2_peak_q2", "sim2_rms_q2")),
        ("Turbulence: RMS q1 (solid), RMS q2 (dashed)", ("turbulence_rms_q1", "turbulence_rms_q2")),
    )
    for ax, (title, (solid, dashed)) in zip(axes, panels, strict=True):
        for k, (key, label) in enumerate(labels.items()):
            style = _CABLE_STYLE[k % len(_CABLE_STYLE)]
            x, y = _series(rows, key, f"{solid}_reduction_pct")
            (line,) = ax.plot(x, y, style, label=label)
            x, y = _series(rows, key, f"{dashed}_reduction_pct")
            ax.plot(x, y, style.replace("-", "--"), color=line.get_color(), mfc="none")
        ax.axhline(0.0, color="k", lw=0.8)
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("tether length q9 [m]")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("reduction by the tether [%]\n(solid: peak, dashed: RMS)")
    axes[0].legend(fontsize=8)
    return fig


def figure_study_static(
    rows: Sequence[dict[str, Any]],
    labels: dict[str, str],
    max_thrust_N: float,
    *,
    fig: Figure | None = None,
) -> Figure:
    """The static half against length, one line per cable: the ground tension that keeps
    the paper's 25 N at P; the main rotor's extra thrust with 25 N at the winch and the
    margin to the maximum thrust; the lateral stiffness at P against the massless tether's.

    Parameters
    ----------
    rows : sequence of dict
        ``tether_study.static_rows``'s rows.
    labels : dict of str to str
        Cable key -> legend text.
    max_thrust_N : float
        The maximum thrust [N] (its margin is drawn).
    fig : Figure, optional
        An empty figure to draw into.

    Returns
    -------
    Figure
    """
    fig = _new_figure(fig, (12.0, 4.0))
    ax0, ax1, ax2 = fig.subplots(1, 3)
    for k, (key, label) in enumerate(labels.items()):
        style = _CABLE_STYLE[k % len(_CABLE_STYLE)]
        x, y = _series(rows, key, "ground_tension_for_top_N")
        ax0.plot(x, y, style, label=label)
        x, y = _series(rows, key, "extra_lift_N")
        (line,) = ax1.plot(x, y, style, label=f"{key}: extra fMR3")
        x, y = _series(rows, key, "lift_margin_N")
        ax1.plot(x, y, style.replace("-", "--"), color=line.get_color(), mfc="none")
        x, y = _series(rows, key, "k_lateral_N_m")
        ax2.plot(x, y, style, label=label)
    x = np.unique([r["length_m"] for r in rows])
    x_fine = np.linspace(x.min(), x.max(), 200)
    ax2.plot(x_fine, 25.0 / x_fine, "k:", label="massless, T / q9")
    ax0.set_title("ground tension for 25 N at P", fontsize=9)
    ax0.set_ylabel("T_ground [N]")
    ax1.set_title(
        f"25 N at the winch: extra fMR3 (solid), margin to {max_thrust_N:.0f} N (dashed)",
        fontsize=9,
    )
    ax1.set_ylabel("[N]")
    ax2.set_title("quasi-static lateral stiffness at P (25 N at the winch)", fontsize=9)
    ax2.set_ylabel("k [N/m]")
    ax2.set_yscale("log")
    for ax in (ax0, ax1, ax2):
        ax.set_xlabel("tether length q9 [m]")
        ax.grid(alpha=0.3)
    ax0.axhline(0.0, color="k", lw=0.8)
    ax0.legend(fontsize=8)
    ax2.legend(fontsize=8)
    return fig


def figure_study_sensing(
    rows: Sequence[dict[str, Any]],
    labels: dict[str, str],
    *,
    fig: Figure | None = None,
) -> Figure:
    """The horizontal error of P's estimate against length: one column per cable, one row
    per elevation of P; Sec. IV-F (solid) and the catenary estimator with the wind known to
    +-1 m/s (dashed), one colour per wind speed.

    Parameters
    ----------
    rows : sequence of dict
        ``tether_sensing.sensing_study``'s rows.
    labels : dict of str to str
        Cable key -> column title.
    fig : Figure, optional
        An empty figure to draw into.

    Returns
    -------
    Figure
    """
    elevations = sorted({r["elevation_deg"] for r in rows}, reverse=True)
    winds = sorted({r["wind_m_s"] for r in rows})
    fig = _new_figure(fig, (4.0 * len(labels), 3.3 * len(elevations)))
    axes = np.atleast_2d(fig.subplots(len(elevations), len(labels), squeeze=False))
    for i, el in enumerate(elevations):
        for j, (key, label) in enumerate(labels.items()):
            ax = axes[i, j]
            for k, w in enumerate(winds):
                sel = [
                    r
                    for r in rows
                    if r["cable"] == key and r["elevation_deg"] == el and r["wind_m_s"] == w
                ]
                x = np.array([r["length_m"] for r in sel], dtype=float)
                for est, ls in (("ivf", "-"), ("catenary_wind_1ms", "--")):
                    y = np.array([r[est] for r in sel], dtype=float)
                    y = np.where(y > 1e-4, y, np.nan)  # log axis: exact zeros are not drawn
                    lab = f"{w:g} m/s" if est == "ivf" else None
                    ax.plot(x, y, ls, marker="o", ms=3, color=f"C{k}", label=lab)
            ax.set_yscale("log")
            ax.set_title(f"{label}\nP at {el:g} deg elevation", fontsize=9)
            ax.set_xlabel("distance winch-P [m]")
            ax.grid(alpha=0.3, which="both")
        axes[i, 0].set_ylabel("horizontal error [m]\n(solid: IV-F, dashed: catenary +-1 m/s)")
    axes[0, 0].legend(title="wind", fontsize=8)
    return fig
