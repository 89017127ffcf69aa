"""3-D animation of saved simulation runs: fuselage, rotor disc, tether, ground winch, wind.

The animation only reads results written by ``SimulationResult.save(directory, stem)``: one
``<stem>.csv`` (time series, SI units, angles in rad) and one ``<stem>.json`` (configuration,
trim, version, status) per run, read through ``tetherheli.sim.load_result``. Several runs of
one directory are overlaid in one scene, each helicopter in its own colour, so that the free
and the tethered responses to the same wind can be compared as in the paper's Sec. VI.

Geometry (paper Tables I-II, eqs 2-3, 43-45; see ``docs/notation.md``): N is the inertial frame
(n3 up) with the ground winch at its origin NO; HO, the helicopter's centre of mass, is at
(q1, q2, q3); the fuselage frame F follows from the body-1-2-3 Euler angles q4, q5, q6. The
reference point O lies at HO - dO-HO,3 f3; the rotor centre MRO at O + dO-MRO,3 f3, the tail
rotor TRO at O + dO-TRO,1 f1 and the tether attachment P at O + dO-P,3 f3; these positions
come from the code generated from the derivation (``model.kinematics``). Everything is drawn
at true scale; the camera is fixed around the trim point.

Rendering uses Matplotlib's Agg canvas directly (no pyplot, no display, no global backend
change). GIF files are written with Pillow; MP4 files need ffmpeg. Output files are written
atomically (``_io.atomic_path``): a temporary file in the target folder is renamed over the
target only when the whole file has been written.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import matplotlib as mpl
import numpy as np
from matplotlib import animation
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.cm import ScalarMappable
from matplotlib.colors import Normalize
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.ticker import MaxNLocator
from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection
from PIL import Image

from .._io import atomic_path, check_output_file, record_output_file
from .._validation import check_integer, check_number
from ..errors import ParameterError
from ..model.kinematics import HelicopterPoints, direction_cosines, helicopter_points
from ..params import HelicopterParams, Params
from ..progress import Progress
from ..resources import check_memory
from ..sim.result import _series_path, list_results, load_result

__all__ = [
    "HelicopterPoints",
    "RunData",
    "animate",
    "direction_cosines",
    "frame_rgb",
    "helicopter_points",
    "list_runs",
    "load_run",
    "render_frame",
    "run_colours",
]

#: Output formats ``animate`` can write: file suffix -> Matplotlib writer name.
FORMATS: dict[str, str] = {".gif": "pillow", ".mp4": "ffmpeg"}

#: colours of further runs of a configuration already drawn (the first free run is red and the
#: first tethered run blue, as in every figure: ``viz.plots.CONFIGURATION_COLOURS``)
_MORE_COLOURS = ("tab:purple", "tab:brown", "tab:pink", "tab:gray", "tab:olive", "tab:cyan")
_WIND_COLOUR = "darkorange"
_TENSION_CMAP = "viridis"
_SLACK = 1e-9  # [N] a tension at or below this is drawn as a slack tether
_WIND_ARROW = 1.0  # [m] drawn length of the largest wind force when auto-scaling
_ZOOM = 1.15  # the close-up box fills more of its panel than Matplotlib's default
_MARGIN = 0.3  # [m] free space around the drawn helicopter(s) in the close-up


# --- loading ------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class RunData:
    """One saved run, as much of it as the animation draws.

    Parameters
    ----------
    stem : str
        File stem in the result directory (``<stem>.csv``, ``<stem>.json``).
    name : str
        The scenario's name (configuration["name"]).
    configuration : {"free", "tethered"}
        The run's configuration.
    time : ndarray, shape (n,)
        Sample times [s], strictly increasing.
    q : ndarray, shape (n, 9)
        Generalized coordinates q1..q9: HO position q1..q3 [m], Euler angles q4..q6 [rad],
        tether angles q7, q8 [rad] and length q9 [m] (for a free run q7..q9 locate P as if a
        tether were there).
    wind : ndarray, shape (n, 3)
        Wind force on HO in N [N] (Fw1, Fw2, Fw3).
    tension : ndarray, shape (n,)
        Tether tension TC [N] (zero for a free run).
    trim_position : ndarray, shape (3,)
        HO at the run's trim point [m].
    helicopter : HelicopterParams
        The helicopter parameters of the run (for the point offsets).
    status : int
        0 if the run completed, else the simulator's failure code.
    message : str
        The simulator's status message.
    version : str
        The tetherheli version that wrote the run.
    """

    stem: str
    name: str
    configuration: Literal["free", "tethered"]
    time: np.ndarray
    q: np.ndarray
    wind: np.ndarray
    tension: np.ndarray
    trim_position: np.ndarray
    helicopter: HelicopterParams
    status: int
    message: str
    version: str

    def __post_init__(self) -> None:
        for name in ("time", "q", "wind", "tension", "trim_position"):
            getattr(self, name).setflags(write=False)

    @property
    def position(self) -> np.ndarray:
        """HO in N, (n, 3) [m]."""
        return self.q[:, 0:3]

    @property
    def angles(self) -> np.ndarray:
        """Euler angles q4, q5, q6, (n, 3) [rad]."""
        return self.q[:, 3:6]

    @property
    def tethered(self) -> bool:
        return self.configuration == "tethered"

    def points(self) -> HelicopterPoints:
        """The named points at every sample, each (n, 3) [m].

        Returns
        -------
        HelicopterPoints
            The helicopter's named points (``model.kinematics.helicopter_points``).
        """
        return helicopter_points(self.position, self.angles, self.helicopter)


#: The stems of the runs saved in a directory (``tetherheli.sim.list_results``).
list_runs = list_results


def load_run(directory: str | Path, stem: str | None = None) -> RunData:
    """Read one run saved by ``SimulationResult.save(directory, stem)``, through
    ``tetherheli.sim.load_result``, as much of it as the animation draws.

    Parameters
    ----------
    directory : path of the result directory
    stem : which run; None when the directory holds exactly one

    Returns
    -------
    RunData

    Raises
    ------
    ParameterError
        If the directory is missing or holds no (or, with ``stem=None``, several) runs, or a
        file is malformed or holds no samples (the message names the file and what is
        expected).
    """
    result = load_result(directory, stem)
    path = Path(directory)
    stem = stem if stem is not None else list_results(path)[0]
    if result.time.size == 0:
        series = _series_path(path, stem)  # the run's .csv or .parquet, as load_result read it
        raise ParameterError(
            series.suffix[1:], "no data rows", "at least one row of samples", source=str(series)
        )
    helicopter = Params.paper().helicopter
    params = result.configuration.get("params")
    if isinstance(params, dict) and isinstance(params.get("helicopter"), dict):
        helicopter = Params.from_mapping(
            {"helicopter": params["helicopter"]}, source=str(path / f"{stem}.json")
        ).helicopter
    return RunData(
        stem=stem,
        name=str(result.configuration.get("name", stem)),
        configuration=result.configuration["configuration"],
        time=result.time,
        q=np.column_stack([result.outputs[:, :3], result.states[:, :6]]),
        wind=result.wind,
        tension=result.tension,
        trim_position=result.trim_output[:3],
        helicopter=helicopter,
        status=result.status,
        message=result.message,
        version=result.version,
    )


def _load_runs(directory: str | Path, stems: Sequence[str] | None) -> list[RunData]:
    available = list_results(directory)
    if stems is None:
        if not available:
            load_result(directory)  # raises: no runs, naming what a result directory holds
        stems = available
    elif isinstance(stems, str) or len(stems) == 0:
        raise ParameterError("stems", stems, f"a non-empty list of run stems from {available}")
    return [load_run(directory, s) for s in stems]


# --- drawing ------------------------------------------------------------------------------


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
    from .plots import CONFIGURATION_COLOURS

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
            ax.text(0.0, 0.0, 0.0, "  winch NO", fontsize=8)
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
        background = np.array(self.fig.canvas.buffer_rgba())
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


# --- public entry points ------------------------------------------------------------------


#: Upper bounds of the rendering options: GIF frame delays are whole centiseconds (100 fps at
#: most); the frame count and resolution bound the time and memory of a render.
MAX_FPS = 100.0
MAX_FRAMES = 20_000
MAX_DPI = 600.0
_FIGURE_INCHES = (10.0, 6.0)


def _drawing_options(
    dpi: Any, rotor_radius: Any, wind_scale: Any
) -> tuple[float, float, float | None]:
    """The checked dpi, rotor radius [m] and wind scale [m/N] (None: automatic)."""
    return (
        check_number("dpi", dpi, low=0.0, low_open=True, high=MAX_DPI),
        check_number("rotor_radius", rotor_radius, low=0.0, low_open=True),
        None
        if wind_scale is None
        else check_number("wind_scale", wind_scale, low=0.0, low_open=True),
    )


def _output_path(output: str | Path, allowed: str) -> Path:
    out = Path(output)
    if out.is_dir():
        raise ParameterError("output", str(out), f"a file name ({allowed}), not a directory")
    if not out.parent.is_dir():
        raise ParameterError("output", str(out), "a path inside an existing directory")
    check_output_file(out, option="output")  # never replaces a file tetherheli did not write
    return out


def _check_render_memory(n_frames: int, dpi: float, gif: bool) -> None:
    """Refuse a render whose frames do not fit the memory budget: a GIF keeps every frame
    (1 byte per pixel after palettising, plus one RGBA frame being drawn); MP4 streams."""
    pixels = _FIGURE_INCHES[0] * dpi * _FIGURE_INCHES[1] * dpi
    needed = pixels * 4 * 3 + (n_frames * pixels if gif else 0)
    check_memory(
        f"animation of {n_frames} frames at dpi = {dpi:g}",
        needed,
        hint="lower --max-frames or the resolution, or write an .mp4 (streamed)",
    )


class _PalettePillowWriter(animation.PillowWriter):
    """Matplotlib's PillowWriter, keeping each grabbed frame palettised (1 byte per pixel).

    Pillow palettises every GIF frame on saving anyway (adaptive palette); doing it as each
    frame arrives gives the same file with half the peak memory (600 RGB frames of 800 x 480
    pixels are 0.7 GB). Falls back to the plain writer if its frame list is not found.
    """

    def grab_frame(self, **savefig_kwargs: Any) -> None:
        super().grab_frame(**savefig_kwargs)
        frames = getattr(self, "_frames", None)
        if isinstance(frames, list) and frames and frames[-1].mode == "RGB":
            frames[-1] = frames[-1].convert("P", palette=Image.Palette.ADAPTIVE)


def _writer(suffix: str, fps: float) -> animation.AbstractMovieWriter:
    if suffix == ".gif":
        return _PalettePillowWriter(fps=fps)
    return animation.writers[FORMATS[suffix]](fps=fps)


def animate(
    directory: str | Path,
    output: str | Path,
    *,
    stems: Sequence[str] | None = None,
    fps: float = 20.0,
    speed: float = 1.0,
    max_frames: int = 600,
    dpi: float = 80.0,
    rotor_radius: float = 0.9,
    wind_scale: float | None = None,
    progress: bool = False,
) -> Path:
    """Render saved runs as a 3-D animation (GIF, or MP4 when ffmpeg is installed).

    Parameters
    ----------
    directory : result directory written by ``SimulationResult.save``
    output : the file to write; its suffix picks the format: ``.gif`` (Pillow) or ``.mp4``
        (ffmpeg)
    stems : runs to draw, overlaid in one scene; None draws every run of the directory
    fps : playback frame rate [frames/s]
    speed : simulated seconds per second of playback (2.0 plays twice as fast)
    max_frames : at most this many frames; a longer run is sampled more coarsely and played
        at a lower frame rate so that ``speed`` still holds
    dpi : resolution of the 10 x 6 inch figure [pixels/inch]
    rotor_radius : radius of the drawn rotor disc [m]
    wind_scale : drawn length of the wind-force arrow per newton [m/N]; None scales the
        largest force of the runs to 1 m
    progress : show the frames drawn on stderr (``tetherheli.progress``)

    Returns
    -------
    Path of the written file. The file appears only once complete: it is written to a
    temporary file in the same folder and renamed; on any error nothing is left behind.

    Raises
    ------
    ParameterError
        For a missing or empty result directory, malformed result files, an unsupported
        output format (or MP4 without ffmpeg), or invalid options.
    """
    fps = check_number("fps", fps, low=0.0, low_open=True, high=MAX_FPS)
    speed = check_number("speed", speed, low=0.0, low_open=True)
    max_frames = check_integer("max_frames", max_frames, low=1, high=MAX_FRAMES)
    dpi, rotor_radius, wind_scale = _drawing_options(dpi, rotor_radius, wind_scale)
    allowed = "'.gif' (Pillow) or '.mp4' (needs ffmpeg)"
    out = _output_path(output, allowed)
    suffix = out.suffix.lower()
    if suffix not in FORMATS:
        raise ParameterError("output format", out.suffix or out.name, allowed)
    if not animation.writers.is_available(FORMATS[suffix]):
        raise ParameterError(
            "output format",
            out.suffix,
            "'.gif' (ffmpeg is not installed, so '.mp4' cannot be written)",
        )
    runs = _load_runs(directory, stems)
    times, playback = _frame_times(runs, fps, speed, max_frames)
    _check_render_memory(len(times), dpi, gif=suffix == ".gif")
    scene = _Scene(runs, times, rotor_radius=rotor_radius, wind_scale=wind_scale, dpi=dpi)
    writer = _writer(suffix, playback)
    with atomic_path(out) as tmp, mpl.rc_context({"savefig.bbox": None}):
        writer.setup(scene.fig, tmp, dpi=dpi)  # may round the figure size (ffmpeg)
        try:
            scene.freeze_background()
            with Progress("animate", len(times), "frames", enabled=progress) as bar:
                for k in range(len(times)):
                    scene.update(k)
                    writer.grab_frame()
                    bar.update(1)
        except BaseException:
            with contextlib.suppress(Exception):  # release ffmpeg; the file is discarded
                writer.finish()
            raise
        writer.finish()
    record_output_file(out, writer="animate")
    return out


def render_frame(
    directory: str | Path,
    output: str | Path,
    *,
    time: float,
    stems: Sequence[str] | None = None,
    dpi: float = 80.0,
    rotor_radius: float = 0.9,
    wind_scale: float | None = None,
) -> Path:
    """Save one frame of the animation as an image (PNG, PDF, SVG, ... by suffix).

    Parameters
    ----------
    directory, stems, dpi, rotor_radius, wind_scale : as for ``animate``
    output : image file to write (atomically)
    time : simulated time of the frame [s]; the nearest sample of each run is drawn

    Returns
    -------
    Path of the written image.

    Raises
    ------
    ParameterError
        As ``animate``, and for a time outside the runs or an unknown image format.
    """
    dpi, rotor_radius, wind_scale = _drawing_options(dpi, rotor_radius, wind_scale)
    out = _output_path(output, "an image file such as .png")
    formats = FigureCanvasAgg(Figure()).get_supported_filetypes()
    if out.suffix.lower().lstrip(".") not in formats:
        raise ParameterError(
            "output format", out.suffix or out.name, f"one of {sorted('.' + f for f in formats)}"
        )
    runs = _load_runs(directory, stems)
    t0 = min(float(r.time[0]) for r in runs)
    t1 = max(float(r.time[-1]) for r in runs)
    time = check_number("time", time, low=t0, high=t1, unit="s")
    scene = _Scene(
        runs, np.array([time]), rotor_radius=rotor_radius, wind_scale=wind_scale, dpi=dpi
    )
    scene.update(0)
    with atomic_path(out) as tmp:
        scene.fig.savefig(tmp, dpi=dpi)
    record_output_file(out, writer="animate")
    return out


def frame_rgb(
    runs: Sequence[RunData],
    time: float,
    *,
    dpi: float = 80.0,
    rotor_radius: float = 0.9,
    wind_scale: float | None = None,
) -> np.ndarray:
    """One frame of the animation's scene as an RGB image (what ``render_frame`` saves; the
    Gymnasium environment's ``render``).

    Parameters
    ----------
    runs : runs to draw, overlaid (``load_run``, or built from an episode)
    time : simulated time of the frame [s]; the nearest sample of each run is drawn
    dpi, rotor_radius, wind_scale : as for ``animate``

    Returns
    -------
    ndarray (H, W, 3) uint8
        The 10 x 6 inch figure at ``dpi`` (800 x 480 pixels at the default 80).
    """
    dpi, rotor_radius, wind_scale = _drawing_options(dpi, rotor_radius, wind_scale)
    if len(runs) == 0:
        raise ParameterError("runs", runs, "at least one run")
    scene = _Scene(
        runs, np.array([float(time)]), rotor_radius=rotor_radius, wind_scale=wind_scale, dpi=dpi
    )
    scene.update(0)
    scene.fig.canvas.draw()
    return np.array(scene.fig.canvas.buffer_rgba())[:, :, :3]
