"""The drawing of an animation's frames: the helicopter's wireframe, rotor disc, tether
(coloured by tension), winch and wind arrow of each run in a 3-D scene with a close-up
(``_Scene``), the runs' colours (``run_colours``) and the frame times. ``viz.animation``
renders and writes the frames.

The deck is a square plane around the winch with the pad (a ring) marked: over a moving
base it follows the recorded base position (its heave included) and, over a ship, tilts
with the recorded roll, pitch and yaw (``RunData.deck_rotation``), in place of a still
ground; for a landing the close-up shows it too.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import matplotlib as mpl
import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.cm import ScalarMappable
from matplotlib.colors import Normalize
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.ticker import MaxNLocator
from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

from ..model.kinematics import helicopter_points
from ..params import HelicopterParams
from .run_data import RunData

__all__ = ["run_colours"]

#: colours of further runs of a configuration already drawn (the first free run is red and the
#: first tethered run blue, as in every figure: ``viz.plots.CONFIGURATION_COLOURS``)
_MORE_COLOURS = ("tab:purple", "tab:brown", "tab:pink", "tab:gray", "tab:olive", "tab:cyan")
_WIND_COLOUR = "darkorange"
_PAD_COLOUR = "gold"
_TENSION_CMAP = "viridis"
_SLACK = 1e-9  # [N] a tension at or below this is drawn as a slack tether
_WIND_ARROW = 1.0  # [m] drawn length of the largest wind force when auto-scaling
_ZOOM = 1.15  # the close-up box fills more of its panel than Matplotlib's default
_MARGIN = 0.3  # [m] free space around the drawn helicopter(s) in the close-up
_FIGURE_INCHES = (10.0, 6.0)  # [in] the animation's figure
_DECK = 1.5  # [m] half the side of the drawn deck around the winch
_CLOSE_DECK = 0.9  # [m] half the side of the deck drawn in a landing's close-up
_PAD = 0.5  # [m] radius of the drawn pad (a ring around the winch)
_LABEL_X = 0.2  # the run lines start here (figure fraction), right of the clock
_LABEL_POINTS = 8.5  # [pt] their font size
_MONO_WIDTH = 0.6  # a monospace character's advance over its font size


def run_colours(runs: Sequence[RunData]) -> list[str]:
    """The colour of each run: the first free run red and the first tethered run blue
    (``viz.plots.CONFIGURATION_COLOURS``, the figures' colours), any further run one of
    ``_MORE_COLOURS`` in turn.

    Parameters
    ----------
    runs : sequence of RunData
        The runs drawn together.

    Returns
    -------
    list of str
        One Matplotlib colour per run.
    """
    from .figure import CONFIGURATION_COLOURS

    colours, used, extra = [], set(), 0
    for r in runs:
        c = CONFIGURATION_COLOURS.get(r.configuration)
        if c is None or c in used:
            c = _MORE_COLOURS[extra % len(_MORE_COLOURS)]
            extra += 1
        used.add(c)
        colours.append(c)
    return colours


def _wireframe(h: HelicopterParams, rotor_radius: float) -> np.ndarray:
    """Line segments of a simple helicopter in F components relative to O, (s, 2, 3) [m]."""
    x0, x1, y, z0, z1 = -0.30, 0.40, 0.13, -0.24, 0.04
    corners = np.array([[x, yy, z] for x in (x0, x1) for yy in (-y, y) for z in (z0, z1)])
    segs = []
    for i in range(8):
        for j in range(i + 1, 8):
            if np.count_nonzero(corners[i] != corners[j]) == 1:  # box edges
                segs.append((corners[i], corners[j]))
    nose = np.array([0.62, 0.0, -0.12])
    segs += [(c, nose) for c in corners if c[0] == x1]
    mrO = np.array([0.0, 0.0, h.d_O_MRO3])
    trO = np.array([h.d_O_TRO1, 0.0, 0.0])
    segs.append((np.array([0.0, 0.0, z1]), mrO))  # rotor mast
    segs.append((np.array([x0, 0.0, 0.0]), trO))  # tail boom
    segs.append((trO, trO + np.array([-0.08, 0.0, 0.22])))  # fin
    segs.append((np.array([0.0, 0.0, z0]), np.array([0.0, 0.0, min(h.d_O_P3, z0)])))  # hook
    zs = z0 - 0.06
    for s in (-0.2, 0.2):  # skids and struts
        segs.append((np.array([-0.34, s, zs]), np.array([0.36, s, zs])))
        segs.append((np.array([0.36, s, zs]), np.array([0.44, s, zs + 0.05])))
        for x in (-0.15, 0.22):
            segs.append((np.array([x, s, zs]), np.array([x, 0.6 * s, z0])))
    for a in (0.25 * np.pi, 0.75 * np.pi):  # two blades across the disc
        d = rotor_radius * np.array([np.cos(a), np.sin(a), 0.0])
        segs.append((mrO - d, mrO + d))
    return np.array(segs, dtype=float)


def _circle(centre: np.ndarray, radius: float, plane: tuple[int, int], n: int) -> np.ndarray:
    a = np.linspace(0.0, 2.0 * np.pi, n)
    pts = np.tile(centre, (n, 1))
    pts[:, plane[0]] += radius * np.cos(a)
    pts[:, plane[1]] += radius * np.sin(a)
    return pts


@dataclass(frozen=True, eq=False)
class _Shape:
    """One run's drawn geometry at a set of samples, all in N [m]."""

    segments: np.ndarray  # (m, s, 2, 3) fuselage wireframe
    rotor: np.ndarray  # (m, k, 3) rotor disc rim
    tail: np.ndarray  # (m, j, 3) tail-rotor rim
    HO: np.ndarray  # (m, 3)
    P: np.ndarray  # (m, 3)
    base: np.ndarray  # (m, 3) the winch's base (the deck's pad)
    nodes: np.ndarray | None  # (m, N + 1, 3) a lumped chain's recorded nodes, or None
    deck: np.ndarray  # (m, 3, 3) the deck's rotation from N (the identity: level)

    def deck_plane(self, k: int, half: float) -> np.ndarray:
        """The deck's corners at frame k, a square of half side ``half`` [m] around the
        winch, tilted with the deck, (4, 3) [m]."""
        square = half * np.array([[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0],
                                  [-1.0, 1.0, 0.0]])  # fmt: skip
        return self.base[k] + square @ self.deck[k].T

    def pad_ring(self, k: int) -> np.ndarray:
        """The pad's ring at frame k (radius ``_PAD`` around the winch, on the deck), (j, 3)."""
        ring = _circle(np.zeros(3), _PAD, (0, 1), 49)
        return self.base[k] + ring @ self.deck[k].T


def _shape(run: RunData, index: np.ndarray, rotor_radius: float) -> _Shape:
    """The run's geometry at the samples ``index``, in N: over a moving base the recorded
    positions (relative to it) plus the base's position (``RunData.base``)."""
    base = run.base[index]
    pts = helicopter_points(run.position[index] + base, run.angles[index], run.helicopter)
    h = run.helicopter
    tmpl = _wireframe(h, rotor_radius)
    rim = _circle(np.array([0.0, 0.0, h.d_O_MRO3]), rotor_radius, (0, 1), 73)
    tail = _circle(np.array([h.d_O_TRO1, 0.0, 0.0]), 0.16, (0, 2), 25)

    def place(local: np.ndarray) -> np.ndarray:
        flat = local.reshape(-1, 3)
        out = pts.N_p_O[:, None, :] + np.einsum("mij,kj->mki", pts.N_R_F, flat)
        return out.reshape((len(index), *local.shape))

    nodes = None if run.nodes is None else run.nodes[index] + base[:, None, :]
    deck = np.asarray(run.deck_rotation)[index]
    return _Shape(place(tmpl), place(rim), place(tail), pts.N_p_HO, pts.N_p_P, base, nodes, deck)


def _frame_times(runs: Sequence[RunData], fps: float, speed: float, max_frames: int):
    """Frame times [s] and the playback rate [frames/s] that keeps the requested speed."""
    t0 = min(float(r.time[0]) for r in runs)
    t1 = max(float(r.time[-1]) for r in runs)
    step = speed / fps
    n = math.floor((t1 - t0) / step + 1e-9) + 1
    if n > max_frames:
        n = max_frames
        step = (t1 - t0) / (n - 1) if n > 1 else 1.0
    times = t0 + step * np.arange(n)
    playback = speed / step if n > 1 else fps
    return times, playback


def _nearest(time: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Index of the sample nearest to each t, held at the ends."""
    k = np.clip(np.searchsorted(time, t), 1, len(time) - 1) if len(time) > 1 else None
    if k is None:
        return np.zeros(len(t), dtype=int)
    return np.where(t - time[k - 1] <= time[k] - t, k - 1, k)


def _clip_segment(a: np.ndarray, b: np.ndarray, lo: np.ndarray, hi: np.ndarray):
    """The part of segment a-b inside the box [lo, hi] (Liang-Barsky), or None."""
    d = b - a
    u0, u1 = 0.0, 1.0
    for i in range(3):
        for p, q in ((-d[i], a[i] - lo[i]), (d[i], hi[i] - a[i])):
            if p == 0.0:
                if q < 0.0:
                    return None
            else:
                r = q / p
                if p < 0.0:
                    u0 = max(u0, r)
                else:
                    u1 = min(u1, r)
    if u0 > u1:
        return None
    return a + u0 * d, a + u1 * d


@dataclass(frozen=True, eq=False)
class _View:
    """One 3-D panel: its axes, fixed limits [m] and whether it is the close-up."""

    ax: Any
    lo: np.ndarray
    hi: np.ndarray
    close_up: bool


@dataclass(frozen=True, eq=False)
class _Deck:
    """A drawn deck: its plane, the pad's ring and the winch, of run ``run``'s base, a
    square of half side ``half`` [m]."""

    plate: Poly3DCollection
    pad: Any
    winch: Any
    run: int
    half: float


@dataclass(frozen=True, eq=False)
class _RunArtists:
    """The artists of one run in one panel."""

    body: Line3DCollection
    disc: Poly3DCollection
    tail: Any
    trail: Any
    wind: Line3DCollection
    tether: Any | None
    P: Any | None


class _Scene:
    """The figure and its artists; ``update(k)`` draws frame k (time ``times[k]``)."""

    def __init__(
        self,
        runs: Sequence[RunData],
        times: np.ndarray,
        *,
        rotor_radius: float,
        wind_scale: float | None,
        dpi: float,
    ) -> None:
        self.runs = list(runs)
        self.times = times
        self.index = [_nearest(r.time, times) for r in runs]
        self.shapes = [_shape(r, i, rotor_radius) for r, i in zip(runs, self.index, strict=True)]
        self.tethered = any(r.tethered for r in runs)
        self.moving_base = any(r.base_moves for r in runs)
        wind_max = max(float(np.max(np.linalg.norm(r.wind, axis=1))) for r in runs)
        if wind_scale is None:
            wind_scale = _WIND_ARROW / wind_max if wind_max > 0.0 else 0.0
        self.wind_scale = wind_scale
        # Tension colours from 0 to twice the typical tension (or the peak, if higher): the
        # nominal tension sits mid-scale, peaks show up bright, slack is drawn dashed grey.
        taut = np.concatenate([r.tension[r.tension > _SLACK] for r in runs])
        t_max = max(float(np.max(taut)), 2.0 * float(np.median(taut))) if taut.size else 1.0
        self.norm = Normalize(0.0, t_max)
        self.cmap = mpl.colormaps[_TENSION_CMAP]
        self.colours = run_colours(runs)

        # Camera: fixed limits from every sample of every run, not only the drawn frames. The
        # wind arrow may leave the box (including it would shrink the helicopter).
        trims = np.array([r.trim_position + r.base[0] for r in runs])
        close_lo, close_hi = trims.min(axis=0), trims.max(axis=0)
        base_lo, base_hi = np.zeros(3), np.zeros(3)
        for r in runs:
            base_lo = np.minimum(base_lo, r.base.min(axis=0))
            base_hi = np.maximum(base_hi, r.base.max(axis=0))
            s = _shape(r, np.arange(len(r.time)), rotor_radius)
            for pts in (s.segments, s.rotor, s.tail):
                flat = pts.reshape(-1, 3)
                close_lo = np.minimum(close_lo, flat.min(axis=0))
                close_hi = np.maximum(close_hi, flat.max(axis=0))
            if r.gear_height is not None:  # a landing: its close-up holds the deck
                half = np.array([_CLOSE_DECK, _CLOSE_DECK, 0.0])
                close_lo = np.minimum(close_lo, r.base.min(axis=0) - half)
                close_hi = np.maximum(close_hi, r.base.max(axis=0) + half)
        close_lo, close_hi = close_lo - _MARGIN, close_hi + _MARGIN

        self.fig = Figure(figsize=_FIGURE_INCHES, dpi=dpi)
        FigureCanvasAgg(self.fig)
        top = 0.93 - 0.032 * max(len(runs), 1)  # the run lines sit above the panels
        bottom = 0.13  # the legend's rows below
        self.views: list[_View] = []
        self.whole = self.tethered or self.moving_base
        if self.whole:
            deck = np.array([_DECK, _DECK, 0.0])
            lo = np.minimum(np.minimum(close_lo, base_lo - deck), [-1.0, -1.0, 0.0])
            hi = np.maximum(np.maximum(close_hi, base_hi + deck), [1.0, 1.0, 0.0])
            ax = self.fig.add_axes((0.0, bottom, 0.34, top - bottom), projection="3d")
            self.views.append(_View(ax, lo, hi, close_up=False))
            self._decorate(ax, "whole scene", bins=3)
            if not self.moving_base:  # a still ground; a moving deck is drawn per frame
                ground = [[(lo[0], lo[1], 0.0), (hi[0], lo[1], 0.0), (hi[0], hi[1], 0.0),
                           (lo[0], hi[1], 0.0)]]  # fmt: skip
                ax.add_collection(
                    Poly3DCollection(
                        ground, facecolor="0.85", edgecolor="0.6", alpha=0.5, gid="ground"
                    ),
                    autolim=False,
                )
        if self.tethered:
            cax = self.fig.add_axes((0.915, 0.28, 0.012, 0.44))
            bar = self.fig.colorbar(ScalarMappable(self.norm, self.cmap), cax=cax)
            bar.set_label("tether tension TC [N]", fontsize=8)
            bar.ax.tick_params(labelsize=7)
            rect = (0.31, bottom, 0.56, top - bottom)
        elif self.whole:
            rect = (0.31, bottom, 0.66, top - bottom)
        else:
            rect = (0.05, bottom, 0.90, top - bottom)
        ax = self.fig.add_axes(rect, projection="3d")
        self.views.append(_View(ax, close_lo, close_hi, close_up=True))
        self._decorate(ax, "close-up around the trim point", bins=5)
        # the trim points (relative to the base: they move with a moving deck)
        self.trim_marker: Any = ax.plot(
            *trims.T, marker="x", markersize=8, linestyle="", color="black"
        )[0]
        # the deck (a square around the winch, tilted with a ship's), its pad and the winch,
        # where the base is: in the whole scene, and in a landing's close-up
        self.decks: list[_Deck] = []
        self._deck_corners: list[np.ndarray] = []
        seen: list[tuple[np.ndarray, np.ndarray]] = []
        for i, r in enumerate(runs):
            rotation = np.asarray(r.deck_rotation)
            if any(np.array_equal(r.base, b) and np.array_equal(rotation, d) for b, d in seen):
                continue
            seen.append((r.base, rotation))
            if self.whole:
                self.decks.append(self._add_deck(self.views[0].ax, i, _DECK))
            if r.gear_height is not None:
                self.decks.append(self._add_deck(self.views[-1].ax, i, _CLOSE_DECK))

        self.artists = [
            [self._add_run(v.ax, r, c) for r, c in zip(runs, self.colours, strict=True)]
            for v in self.views
        ]
        for v in self.views:  # after adding artists, so that they cannot move the camera
            v.ax.set_xlim(v.lo[0], v.hi[0])
            v.ax.set_ylim(v.lo[1], v.hi[1])
            v.ax.set_zlim(v.lo[2], v.hi[2])
            zoom = _ZOOM if v.close_up else 1.0
            v.ax.set_box_aspect(tuple(np.maximum(v.hi - v.lo, 1e-6)), zoom=zoom)  # true scale

        self.clock = self.fig.text(
            0.015, 0.965, "", fontsize=11, family="monospace", va="top", ha="left"
        )
        self.labels = [
            self.fig.text(
                _LABEL_X, 0.965 - 0.032 * i, "", fontsize=_LABEL_POINTS, color=c,
                family="monospace", va="top", ha="left",
            )
            for i, c in enumerate(self.colours)
        ]  # fmt: skip
        # a run line never runs off the figure: at most this many characters
        room = (0.99 - _LABEL_X) * _FIGURE_INCHES[0] * 72.0
        self.label_chars = max(int(room / (_MONO_WIDTH * _LABEL_POINTS)), 20)
        self._legend()

    @staticmethod
    def _add_deck(ax: Any, i: int, half: float) -> _Deck:
        """The deck of run ``i`` in the axes ``ax``: a square of half side ``half`` [m], the
        pad's ring and the winch (drawn by ``update``)."""
        plate = Poly3DCollection([], facecolor="0.55", edgecolor="0.35", alpha=0.7,
                                 linewidths=0.8)  # fmt: skip
        ax.add_collection(plate, autolim=False)
        pad = ax.plot([], [], [], color=_PAD_COLOUR, linewidth=1.6)[0]
        winch = ax.plot([], [], [], marker="s", markersize=6, color="black", linestyle="")[0]
        return _Deck(plate, pad, winch, i, half)

    def deck_corners(self, j: int) -> np.ndarray:
        """The corners of deck ``j`` (of ``decks``) as last drawn by ``update``, (4, 3) [m].

        Parameters
        ----------
        j : int
            The deck's index in ``decks``.

        Returns
        -------
        numpy.ndarray
            The drawn square's corners in N [m].
        """
        return self._deck_corners[j]

    @staticmethod
    def _decorate(ax: Any, title: str, bins: int) -> None:
        for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
            axis.set_major_locator(MaxNLocator(bins))
        ax.set_xlabel("n1 [m]", fontsize=8, labelpad=-2)
        ax.set_ylabel("n2 [m]", fontsize=8, labelpad=-2)
        ax.set_zlabel("n3 [m]", fontsize=8, labelpad=-2)
        ax.tick_params(labelsize=7, pad=0)
        ax.view_init(elev=18.0, azim=-60.0)
        ax.set_title(title, fontsize=9, pad=0)

    @staticmethod
    def _add_run(ax: Any, run: RunData, colour: str) -> _RunArtists:
        def lines(**kw: Any) -> Line3DCollection:
            return ax.add_collection(Line3DCollection([], **kw), autolim=False)

        return _RunArtists(
            body=lines(colors=colour, linewidths=1.2),
            disc=ax.add_collection(
                Poly3DCollection(
                    [], facecolor=colour, edgecolor=colour, alpha=0.15, linewidths=0.8
                ),
                autolim=False,
            ),
            tail=ax.plot([], [], [], color=colour, linewidth=0.8)[0],
            trail=ax.plot([], [], [], color=colour, linewidth=0.8, alpha=0.5)[0],
            wind=lines(colors=_WIND_COLOUR, linewidths=2.0),
            tether=ax.plot([], [], [], linewidth=2.0)[0] if run.tethered else None,
            P=ax.plot([], [], [], marker="o", markersize=3, color="black")[0]
            if run.tethered
            else None,
        )

    def _legend(self) -> None:
        handles = [
            Line2D([], [], color=c, label=f"{r.stem} ({r.configuration})")
            for r, c in zip(self.runs, self.colours, strict=True)
        ]
        if self.tethered:
            handles.append(
                Line2D(
                    [], [], color=self.cmap(0.7), linewidth=2.0, label="tether (colour: tension)"
                )
            )
            handles.append(Line2D([], [], color="0.5", linestyle="--", label="slack tether"))
        if self.wind_scale > 0.0:
            handles.append(
                Line2D(
                    [],
                    [],
                    color=_WIND_COLOUR,
                    linewidth=2.0,
                    label=f"wind force on HO (1 m = {1.0 / self.wind_scale:.3g} N)",
                )
            )
        if self.whole:
            handles.append(
                Line2D(
                    [], [], color="0.55", marker="s", linestyle="", markersize=8,
                    label="deck, pad, winch" + (" (moving base)" if self.moving_base else " NO"),
                )
            )  # fmt: skip
        handles.append(Line2D([], [], color="black", marker="x", linestyle="", label="trim point"))
        self.fig.legend(
            handles=handles,
            loc="lower center",
            ncols=min(len(handles), 3),
            fontsize=7.5,
            frameon=False,
            bbox_to_anchor=(0.5, 0.0),
            borderaxespad=0.3,
            handlelength=1.6,
            columnspacing=1.2,
        )

    def _wind_segments(self, ho: np.ndarray, force: np.ndarray) -> list[np.ndarray]:
        """Shaft and head of the wind arrow starting at HO."""
        v = self.wind_scale * force
        length = float(np.linalg.norm(v))
        if length < 1e-6:
            return []
        tip = ho + v
        u = v / length
        side = np.cross(u, [0.0, 0.0, 1.0])
        if np.linalg.norm(side) < 1e-6:
            side = np.cross(u, [1.0, 0.0, 0.0])
        side /= np.linalg.norm(side)
        head = min(0.25, 0.4 * length)
        return [
            np.array([ho, tip]),
            np.array([tip, tip - head * (u + 0.5 * side)]),
            np.array([tip, tip - head * (u - 0.5 * side)]),
        ]

    def _label(self, r: RunData, j: int) -> str:
        """The run's line at its sample j, cut to ``label_chars`` characters."""
        wind = float(np.linalg.norm(r.wind[j]))
        if r.gear_height is None:  # a hover: the distance from its trim point
            dev = float(np.linalg.norm(r.position[j] - r.trim_position))
            text = f"{r.name}: |Fw| {wind:5.1f} N  |HO-trim| {dev:5.2f} m"
        else:  # a landing: the gear's height above the pad
            gear = float(r.position[j, 2]) - r.gear_height
            text = f"{r.name}: |Fw| {wind:5.1f} N  gear {gear:5.2f} m above the pad"
        if r.tethered:
            text += f"  TC {float(r.tension[j]):6.1f} N"
        if j == len(r.time) - 1 and r.status != 0:  # a landing ends at its touchdown
            text += f"  {'' if r.gear_height is not None else 'stopped: '}{r.message}"
        if len(text) > self.label_chars:
            text = text[: self.label_chars - 3] + "..."
        return text

    def update(self, k: int) -> None:
        """Draw frame k (time ``times[k]``)."""
        t = self.times[k]
        self.clock.set_text(f"t = {t:6.2f} s")
        self._deck_corners = []
        for d in self.decks:
            shape = self.shapes[d.run]
            corners = shape.deck_plane(k, d.half)
            self._deck_corners.append(corners)
            d.plate.set_verts([corners])
            d.pad.set_data_3d(*shape.pad_ring(k).T)
            b = shape.base[k]
            d.winch.set_data_3d([b[0]], [b[1]], [b[2]])
        if self.moving_base:
            trims = np.array(
                [r.trim_position + s.base[k] for r, s in zip(self.runs, self.shapes, strict=True)]
            )
            self.trim_marker.set_data_3d(*trims.T)
        for i, (r, s, idx) in enumerate(zip(self.runs, self.shapes, self.index, strict=True)):
            j = idx[k]
            tension = float(r.tension[j])
            self.labels[i].set_text(self._label(r, j))
            trail = r.world_position[: j + 1]
            arrow = self._wind_segments(s.HO[k], r.wind[j])
            chain = s.nodes[k] if s.nodes is not None else np.array([s.base[k], s.P[k]])
            for view, per_run in zip(self.views, self.artists, strict=True):
                a = per_run[i]
                a.body.set_segments(s.segments[k])
                a.disc.set_verts([s.rotor[k]])
                a.tail.set_data_3d(*s.tail[k].T)
                a.trail.set_data_3d(*trail.T)
                a.wind.set_segments(arrow)
                if a.tether is not None:
                    self._draw_tether(a, view, chain, tension)

    def _moving(self) -> list[Any]:
        """The artists that change from frame to frame, back to front."""
        out: list[Any] = [a for d in self.decks for a in (d.plate, d.pad, d.winch)]
        if self.moving_base:
            out.append(self.trim_marker)
        for per_run in self.artists:
            for a in per_run:
                out += [a.trail, *(x for x in (a.tether, a.P) if x is not None)]
                out += [a.body, a.disc, a.tail, a.wind]
        return [*out, self.clock, *self.labels]

    def blit_background(self) -> None:
        """Render everything that never changes once and keep the picture (blitting): each
        frame then restores it and draws only the moving artists (``render``). The camera
        is fixed, so the 3-D projections stay those of this drawing."""
        moving = self._moving()
        for artist in moving:
            artist.set_visible(False)
        canvas: Any = self.fig.canvas  # Agg's: it blits (copy_from_bbox, restore_region)
        canvas.draw()
        self._background = canvas.copy_from_bbox(self.fig.bbox)
        for artist in moving:
            artist.set_visible(True)

    def render(self, k: int) -> np.ndarray:
        """Frame k as an RGBA image (H, W, 4), over the background of ``blit_background``.

        Parameters
        ----------
        k : int
            The frame (time ``times[k]``).

        Returns
        -------
        numpy.ndarray
            The canvas's pixels (a view: copy or convert before the next frame).
        """
        self.update(k)
        canvas: Any = self.fig.canvas  # Agg's (``blit_background``)
        canvas.restore_region(self._background)
        for artist in self._moving():
            if hasattr(artist, "do_3d_projection"):
                artist.do_3d_projection()
            self.fig.draw_artist(artist)
        return np.asarray(canvas.buffer_rgba())

    def freeze_background(self) -> None:
        """Render everything that never changes once, as a picture behind the moving parts.

        Drawing tick labels, legend and colour bar took most of a frame's time; afterwards a
        frame draws only the moving artists over the stored picture. The camera is fixed, so
        the 3-D projection stays the same. Valid for output at the figure's own dpi.
        """
        moving = self._moving()
        for artist in moving:
            artist.set_visible(False)
        self.fig.canvas.draw()
        background = np.array(self.fig.canvas.buffer_rgba())  # type: ignore[attr-defined]  # Agg
        for artist in moving:
            artist.set_visible(True)
        keep = {id(a) for a in moving}
        for ax in self.fig.axes:
            if any(ax is v.ax for v in self.views):
                ax.set_axis_off()
                for child in ax.get_children():
                    if id(child) not in keep:
                        child.set_visible(False)
            else:
                ax.set_visible(False)  # the colour bar
        for legend in self.fig.legends:
            legend.set_visible(False)
        self.fig.figimage(background, zorder=-1)

    def _draw_tether(self, a: _RunArtists, view: _View, chain: np.ndarray, tension: float) -> None:
        """The tether from the winch to P (straight, or through a lumped chain's recorded
        nodes), coloured by tension (dashed grey when slack)."""
        assert a.tether is not None and a.P is not None  # drawn for tethered runs only
        P = chain[-1]
        if view.close_up:  # only the part inside the close-up box
            parts = [
                _clip_segment(a0, b0, view.lo, view.hi) for a0, b0 in itertools.pairwise(chain)
            ]
            kept = [p for p in parts if p is not None]
            ends = np.array([kept[0][0], *(p[1] for p in kept)]) if kept else np.empty((0, 3))
        else:
            ends = chain
        a.tether.set_data_3d(*ends.T)
        if tension <= _SLACK:
            a.tether.set_color("0.5")
            a.tether.set_linestyle("--")
        else:
            a.tether.set_color(self.cmap(self.norm(tension)))
            a.tether.set_linestyle("-")
        a.P.set_data_3d([P[0]], [P[1]], [P[2]])
