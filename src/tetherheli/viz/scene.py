"""The drawing of an animation's frames: the helicopter's wireframe, rotor disc, tether
(coloured by tension), ground winch and wind arrow of each run in a 3-D scene with a close-up
(``_Scene``), the runs' colours (``run_colours``) and the frame times. ``viz.animation``
renders and writes the frames.
"""

from __future__ import annotations

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
_TENSION_CMAP = "viridis"
_SLACK = 1e-9  # [N] a tension at or below this is drawn as a slack tether
_WIND_ARROW = 1.0  # [m] drawn length of the largest wind force when auto-scaling
_ZOOM = 1.15  # the close-up box fills more of its panel than Matplotlib's default
_MARGIN = 0.3  # [m] free space around the drawn helicopter(s) in the close-up
_FIGURE_INCHES = (10.0, 6.0)  # [in] the animation's figure


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


def _shape(run: RunData, index: np.ndarray, rotor_radius: float) -> _Shape:
    pts = helicopter_points(run.position[index], run.angles[index], run.helicopter)
    h = run.helicopter
    tmpl = _wireframe(h, rotor_radius)
    rim = _circle(np.array([0.0, 0.0, h.d_O_MRO3]), rotor_radius, (0, 1), 73)
    tail = _circle(np.array([h.d_O_TRO1, 0.0, 0.0]), 0.16, (0, 2), 25)

    def place(local: np.ndarray) -> np.ndarray:
        flat = local.reshape(-1, 3)
        out = pts.N_p_O[:, None, :] + np.einsum("mij,kj->mki", pts.N_R_F, flat)
        return out.reshape((len(index), *local.shape))

    return _Shape(place(tmpl), place(rim), place(tail), pts.N_p_HO, pts.N_p_P)


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
        trims = np.array([r.trim_position for r in runs])
        close_lo, close_hi = trims.min(axis=0), trims.max(axis=0)
        for r in runs:
            s = _shape(r, np.arange(len(r.time)), rotor_radius)
            for pts in (s.segments, s.rotor, s.tail):
                flat = pts.reshape(-1, 3)
                close_lo = np.minimum(close_lo, flat.min(axis=0))
                close_hi = np.maximum(close_hi, flat.max(axis=0))
        close_lo, close_hi = close_lo - _MARGIN, close_hi + _MARGIN

        self.fig = Figure(figsize=_FIGURE_INCHES, dpi=dpi)
        FigureCanvasAgg(self.fig)
        top = 0.92 - 0.035 * len(runs)  # the run lines sit above the panels
        bottom = 0.1
        self.views: list[_View] = []
        if self.tethered:
            lo = np.minimum(close_lo, [-1.0, -1.0, 0.0])
            hi = np.maximum(close_hi, [1.0, 1.0, 0.0])
            ax = self.fig.add_axes((0.0, bottom, 0.36, top - bottom), projection="3d")
            self.views.append(_View(ax, lo, hi, close_up=False))
            self._decorate(ax, "whole scene", bins=3)
            ground = [
                [(lo[0], lo[1], 0.0), (hi[0], lo[1], 0.0), (hi[0], hi[1], 0.0), (lo[0], hi[1], 0.0)]
            ]
            ax.add_collection(
                Poly3DCollection(ground, facecolor="0.85", edgecolor="0.6", alpha=0.5),
                autolim=False,
            )
            ax.plot([0.0], [0.0], [0.0], marker="s", markersize=8, color="black")
            ax.text(0.0, 0.0, 0.0, "  winch NO", fontsize=8)  # type: ignore[arg-type]  # Axes3D
            cax = self.fig.add_axes((0.925, 0.25, 0.012, 0.5))
            self.fig.colorbar(
                ScalarMappable(self.norm, self.cmap), cax=cax, label="tether tension TC [N]"
            )
            rect = (0.33, bottom, 0.58, top - bottom)
        else:
            rect = (0.05, bottom, 0.90, top - bottom)
        ax = self.fig.add_axes(rect, projection="3d")
        self.views.append(_View(ax, close_lo, close_hi, close_up=True))
        self._decorate(ax, "close-up around the trim point", bins=5)
        ax.plot(*trims.T, marker="x", markersize=8, linestyle="", color="black")

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

        self.clock = self.fig.text(0.02, 0.95, "", fontsize=12, family="monospace")
        self.labels = [
            self.fig.text(0.21, 0.955 - 0.035 * i, "", fontsize=9, color=c, family="monospace")
            for i, c in enumerate(self.colours)
        ]
        self._legend()

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
        handles.append(Line2D([], [], color="black", marker="x", linestyle="", label="trim point"))
        self.fig.legend(
            handles=handles,
            loc="lower center",
            ncols=min(len(handles), 4),
            fontsize=8,
            frameon=False,
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

    def update(self, k: int) -> None:
        """Draw frame k (time ``times[k]``)."""
        t = self.times[k]
        self.clock.set_text(f"t = {t:6.2f} s")
        for i, (r, s, idx) in enumerate(zip(self.runs, self.shapes, self.index, strict=True)):
            j = idx[k]
            tension = float(r.tension[j])
            wind = float(np.linalg.norm(r.wind[j]))
            dev = float(np.linalg.norm(r.position[j] - r.trim_position))
            text = f"{r.stem:<16s} |Fw| = {wind:5.1f} N  |HO - trim| = {dev:5.2f} m"
            if r.tethered:
                text += f"  TC = {tension:6.1f} N"
            if j == len(r.time) - 1 and r.status != 0:
                text += f"  (stopped: {r.message})"
            self.labels[i].set_text(text)
            trail = r.position[: j + 1]
            arrow = self._wind_segments(s.HO[k], r.wind[j])
            for view, per_run in zip(self.views, self.artists, strict=True):
                a = per_run[i]
                a.body.set_segments(s.segments[k])
                a.disc.set_verts([s.rotor[k]])
                a.tail.set_data_3d(*s.tail[k].T)
                a.trail.set_data_3d(*trail.T)
                a.wind.set_segments(arrow)
                if a.tether is not None:
                    self._draw_tether(a, view, s.P[k], tension)

    def _moving(self) -> list[Any]:
        """The artists that change from frame to frame."""
        out: list[Any] = [self.clock, *self.labels]
        for per_run in self.artists:
            for a in per_run:
                out += [a.body, a.disc, a.tail, a.trail, a.wind]
                out += [x for x in (a.tether, a.P) if x is not None]
        return out

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

    def _draw_tether(self, a: _RunArtists, view: _View, P: np.ndarray, tension: float) -> None:
        """Straight tether NO-P, coloured by tension (dashed grey when slack)."""
        assert a.tether is not None and a.P is not None  # drawn for tethered runs only
        origin = np.zeros(3)
        if view.close_up:  # only the part inside the close-up box
            part = _clip_segment(origin, P, view.lo, view.hi)
            ends = np.array(part) if part is not None else np.empty((0, 3))
        else:
            ends = np.array([origin, P])
        a.tether.set_data_3d(*ends.T)
        if tension <= _SLACK:
            a.tether.set_color("0.5")
            a.tether.set_linestyle("--")
        else:
            a.tether.set_color(self.cmap(self.norm(tension)))
            a.tether.set_linestyle("-")
        a.P.set_data_3d([P[0]], [P[1]], [P[2]])
