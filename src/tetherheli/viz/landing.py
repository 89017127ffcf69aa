"""The landing's figure (``[maneuver] type = "tethered_landing"``): what a descent to a
moving deck shows, in place of the hover's Figs. 6-9.

Panels over a shared time axis, each drawn when the run records its series: HO's height
above the pad (q3, the recorded outputs being relative to the base) with the landing gear
``gear_height`` below it and the deck at zero; the deck's heave (``base_n3``) and, over a
ship, its roll and pitch; the tension at P (TC) and at the winch (``TC_ground``, a lumped
tether's); the paid-out length LN; the gear's penetration and force (``gear_penetration*``,
``gear_force*``). The touchdown (``SimulationResult.touchdown``) is a vertical line on every
panel and a point on the gear's line; the settling, when recorded, a dotted line.

Every line carries a ``gid`` naming its series (``LANDING_SERIES``), for tests and tools that
read a figure's data.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

from ..results.files import BASE_POSITION_COLUMNS, DECK_ATTITUDE_COLUMNS, TENSION_GROUND_COLUMN
from ..results.landing import GEAR_FORCE, GEAR_PENETRATION, SETTLED_TIME, gear_columns
from ..results.result import SimulationResult
from .figure import _finish, _Plotter, _stacked, _style

__all__ = ["LANDING_SERIES", "figure_landing"]

#: the ``gid`` of each line of the landing figure -> what it draws [unit]
LANDING_SERIES = {
    "height_HO": "HO's height above the pad, q3 [m]",
    "height_gear": "the landing gear's height above the pad, q3 - gear_height [m]",
    "deck_heave": "the deck's heave, base_n3 [m]",
    "deck_roll": "the deck's roll [deg]",
    "deck_pitch": "the deck's pitch [deg]",
    "tension_P": "the tension at P, TC [N]",
    "tension_winch": "the tension at the winch, TC_ground [N]",
    "length": "the paid-out length LN [m]",
    "gear_penetration": "the gear's penetration into the deck [m]",
    "gear_force": "the gear's force [N]",
    "touchdown": "the touchdown's time [s] (a vertical line)",
    "settled": "the settling's time [s] (a vertical line)",
}
#: more runs than one: the colours after the first
_MORE = ("tab:green", "tab:purple", "tab:brown", "tab:olive", "tab:cyan", "tab:gray")


def _panels(runs: list[SimulationResult]) -> list[str]:
    """The panels the runs' records fill, in order."""

    def any_has(test: Any) -> bool:
        return any(test(r) for r in runs)

    panels = ["height"]
    if any_has(lambda r: BASE_POSITION_COLUMNS[2] in r.extra):
        panels.append("heave")
    if any_has(lambda r: all(c in r.extra for c in DECK_ATTITUDE_COLUMNS[:2])):
        panels.append("attitude")
    panels += ["tension", "length"]
    if any_has(lambda r: gear_columns(r.extra, GEAR_PENETRATION)):
        panels.append("penetration")
    if any_has(lambda r: gear_columns(r.extra, GEAR_FORCE)):
        panels.append("force")
    return panels


_LABELS = {
    "height": "height above\nthe pad [m]",
    "heave": "deck heave\nbase_n3 [m]",
    "attitude": "deck roll,\npitch [deg]",
    "tension": "tension [N]",
    "length": "paid-out\nlength LN [m]",
    "penetration": "gear pene-\ntration [m]",
    "force": "gear force [N]",
}


def figure_landing(
    runs: list[SimulationResult], title: str = "", *, fig: Figure | None = None
) -> Figure:
    """A landing's figure: height above the pad, the deck's motion, the tension, the
    paid-out length and the gear's contact against time, the touchdown and the settling
    marked (into ``fig`` if given).

    Parameters
    ----------
    runs : list of SimulationResult
        The runs to overlay (landings; the first in its configuration's colour, further
        ones in other colours).
    title : str, optional
        The figure's title (default none).
    fig : matplotlib.figure.Figure, optional
        The figure to draw into (cleared); default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn; its lines' ``gid`` name their series (``LANDING_SERIES``).
    """
    panels = _panels(runs)
    fig, axes = _stacked(len(panels), (7.5, 1.75 * len(panels) + 1.0), fig)
    ax = dict(zip(panels, axes, strict=True))
    plot = _Plotter()
    for i, r in enumerate(runs):
        st = _style(r)
        if i:
            st["color"] = _MORE[(i - 1) % len(_MORE)]
        if len(runs) > 1:
            st["label"] = r.name
        colour = st["color"]
        gear_height = float((r.configuration.get("maneuver") or {}).get("gear_height", 0.0))
        t = r.time
        plot(ax["height"], t, r.outputs[:, 2], gid="height_HO", **st)
        gear = dict(color=colour, lw=0.9, ls="--", gid="height_gear")
        plot(ax["height"], t, r.outputs[:, 2] - gear_height, **gear)
        if "heave" in ax and BASE_POSITION_COLUMNS[2] in r.extra:
            plot(ax["heave"], t, r.extra[BASE_POSITION_COLUMNS[2]], color=colour, lw=1.1,
                 gid="deck_heave")  # fmt: skip
        if "attitude" in ax and all(c in r.extra for c in DECK_ATTITUDE_COLUMNS[:2]):
            for column, ls in zip(DECK_ATTITUDE_COLUMNS[:2], ("-", ":"), strict=True):
                plot(ax["attitude"], t, np.degrees(r.extra[column]), color=colour, lw=1.1,
                     ls=ls, gid=column)  # fmt: skip
        plot(ax["tension"], t, r.tension, color=colour, lw=1.1, gid="tension_P")
        if TENSION_GROUND_COLUMN in r.extra:
            plot(ax["tension"], t, r.extra[TENSION_GROUND_COLUMN], color=colour, lw=0.9,
                 ls="--", gid="tension_winch")  # fmt: skip
        plot(ax["length"], t, r.winch_length, color=colour, lw=1.1, gid="length")
        for panel, kind in (("penetration", GEAR_PENETRATION), ("force", GEAR_FORCE)):
            for values in gear_columns(r.extra, kind).values() if panel in ax else ():
                plot(ax[panel], t, values, color=colour, lw=1.0, gid=kind)
        _mark(axes, ax["height"], r, colour)
    for panel, a in ax.items():
        a.set_ylabel(_LABELS[panel], fontsize=9)
    ax["height"].axhline(0.0, color="0.4", lw=0.8)  # the deck
    _legends(ax)
    return _finish(fig, axes, title, plot.dropped)


def _mark(axes: np.ndarray, height: Any, r: SimulationResult, colour: str) -> None:
    """The touchdown (a vertical line on every panel, a point where the gear meets the deck)
    and the settling (dotted) of run ``r``."""
    td = r.touchdown
    if td is None:
        return
    t = float(td["time"])
    for a in axes:
        a.axvline(t, color=colour, lw=0.9, ls="-.", alpha=0.8, gid="touchdown")
    height.plot([t], [0.0], marker="v", color=colour, ms=7, ls="",
                gid="touchdown_point")  # fmt: skip
    height.annotate(f"touchdown {t:.3g} s", (t, 0.0), xytext=(4, 6),
                    textcoords="offset points", fontsize=7, color=colour)  # fmt: skip
    settled = td.get(SETTLED_TIME)
    if settled is not None:
        for a in axes:
            a.axvline(float(settled), color=colour, lw=0.9, ls=":", gid="settled")


def _legends(ax: dict[str, Any]) -> None:
    """Small legends naming the panels' several series (the runs' legend is ``_finish``'s,
    on the first panel)."""
    from matplotlib.lines import Line2D

    def legend(panel: str, entries: list[tuple[str, str]]) -> None:
        handles = [Line2D([], [], color="0.3", ls=ls, label=text) for ls, text in entries]
        ax[panel].legend(handles=handles, loc="lower left", fontsize=7)

    if "attitude" in ax:
        legend("attitude", [("-", "roll"), (":", "pitch")])
    if any(line.get_gid() == "tension_winch" for line in ax["tension"].get_lines()):
        legend("tension", [("-", "at P (TC)"), ("--", "at the winch")])
    ax["height"].add_artist(
        ax["height"].legend(
            handles=[Line2D([], [], color="0.3", label="HO"),
                     Line2D([], [], color="0.3", ls="--", label="gear"),
                     Line2D([], [], color="0.3", ls="-.", label="touchdown")],
            loc="center right", fontsize=7,
        )
    )  # fmt: skip
