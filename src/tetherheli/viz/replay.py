"""A 3-D replay of saved runs as one self-contained HTML file (``tetherheli view``).

The page shows each run's helicopter (a simple body with its attitude, rotor disc and tail
rotor), its tether coloured by tension (the lumped chain's recorded nodes when present, else
the straight line winch - P), the deck and its pad following the recorded base motion
(``base_n1..3``) and, over a ship, tilting with its roll, pitch and yaw, the wind force as
an arrow at HO and the path of HO, with a time slider, play/pause and a speed choice; all
the runs of a folder are overlaid, in the animation's colours (``viz.scene.run_colours``).
The 3-D library, three.js r170 (MIT licence, ``replay_assets/three.LICENSE``), and the
data are inlined, so the file opens from disk with no network. The URL may name a time:
``replay.html#t=12.5`` shows t = 12.5 s, paused.

The data are the recorded samples nearest to frames ``1 / fps`` seconds of simulated time
apart (``fps`` = 25 by default): the file stays small (some 60 kB per run and simulated
minute) whatever the control rate. Numbers are strict JSON (a non-finite value is null).
"""

from __future__ import annotations

import html
import json
import re
from collections.abc import Sequence
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib import colormaps
from matplotlib.colors import to_hex
from scipy.spatial.transform import Rotation

from .._io import atomic_write_text, record_output_file
from .._validation import check_integer, check_number
from .._version import __version__
from ..model.kinematics import helicopter_points
from .formats import REPLAY_FPS, REPLAY_MAX_FRAMES
from .run_data import RunData, _load_runs
from .scene import _SLACK, _TENSION_CMAP, _frame_times, _nearest, run_colours

__all__ = ["REPLAY_FPS", "REPLAY_MAX_FRAMES", "replay_data", "replay_html", "write_replay"]
#: Drawn radius of the main rotor disc [m] (as the animation's) and of the tail rotor [m].
_ROTOR_RADIUS = 0.9
_TAIL_RADIUS = 0.16
#: Decimals kept of positions [m] (0.1 mm), of the attitude quaternions and of forces [N].
_DIGITS = {"length": 4, "quaternion": 5, "force": 3}
_ASSETS = "replay_assets"


def _numbers(values: np.ndarray, digits: int) -> list[float | None]:
    """``values`` flattened to a list of rounded floats, a non-finite value as None (strict
    JSON has no NaN or Infinity)."""
    flat = np.asarray(values, dtype=float).ravel()
    rounded = np.round(flat, digits)
    return [float(v) if np.isfinite(v) else None for v in rounded]


def _run_frames(run: RunData, index: np.ndarray) -> dict[str, Any]:
    """One run's drawn state at the samples ``index`` (one per frame), flattened."""
    length, quat, force = _DIGITS["length"], _DIGITS["quaternion"], _DIGITS["force"]
    base = run.base[index]
    pts = helicopter_points(run.position[index], run.angles[index], run.helicopter)
    rotation = pts.N_R_F
    finite = np.all(np.isfinite(rotation), axis=(1, 2))
    quaternions = np.full((len(index), 4), np.nan)
    if np.any(finite):  # scalar last (x, y, z, w), as three.js reads them
        quaternions[finite] = Rotation.from_matrix(rotation[finite]).as_quat()
    frames: dict[str, Any] = {
        "O": _numbers(pts.N_p_O + base, length),
        "quaternion": _numbers(quaternions, quat),
        "HO": _numbers(pts.N_p_HO + base, length),
        "P": _numbers(pts.N_p_P + base, length),
        "base": _numbers(base, length),
        "tension": _numbers(run.tension[index], force),
        "wind": _numbers(run.wind[index], force),
        "deviation": _numbers(np.linalg.norm(run.position[index] - run.trim_position, axis=1), 3),
        "nodes": None,
        "node_count": 0,
        "deck_quaternion": None,
    }
    if run.deck_attitude is not None:  # over a ship: the deck's tilt (scalar last)
        deck = Rotation.from_matrix(np.asarray(run.deck_rotation)[index]).as_quat()
        frames["deck_quaternion"] = _numbers(deck, quat)
    if run.nodes is not None:
        nodes = run.nodes[index] + base[:, None, :]
        frames["nodes"] = _numbers(nodes, length)
        frames["node_count"] = int(nodes.shape[1])
    return frames


def replay_data(
    runs: Sequence[RunData],
    *,
    fps: float = REPLAY_FPS,
    max_frames: int = REPLAY_MAX_FRAMES,
    title: str = "tetherheli replay",
) -> dict[str, Any]:
    """What the replay page draws: the frame times and each run's state at them.

    Parameters
    ----------
    runs : sequence of RunData
        The runs, overlaid (``viz.run_data.load_run``).
    fps : float
        Frames per second of simulated time [1/s] (at most 1000).
    max_frames : int
        At most this many frames; a longer span is sampled more coarsely.
    title : str
        The page's title.

    Returns
    -------
    dict
        Strict-JSON data (no NaN or Infinity): ``time`` [s], the tension scale [N], the wind
        arrow's scale [m/N], the scene's bounds [m] and per run its colour, status and frames
        (positions in N [m], attitude quaternions, tension [N], wind force [N]).
    """
    fps = check_number("fps", fps, low=0.0, low_open=True, high=1000.0)
    max_frames = check_integer("max_frames", max_frames, low=1, high=REPLAY_MAX_FRAMES)
    times, _ = _frame_times(runs, fps, 1.0, max_frames)
    colours = run_colours(runs)
    taut = np.concatenate([r.tension[r.tension > _SLACK] for r in runs])
    tension_max = max(float(np.max(taut)), 2.0 * float(np.median(taut))) if taut.size else 1.0
    wind_max = max(float(np.max(np.linalg.norm(r.wind, axis=1))) for r in runs)
    cmap = colormaps[_TENSION_CMAP]
    out_runs, lo, hi = [], np.full(3, np.inf), np.full(3, -np.inf)
    for run, colour in zip(runs, colours, strict=True):
        index = _nearest(run.time, times)
        frames = _run_frames(run, index)
        for key in ("HO", "P", "base") + (("nodes",) if run.nodes is not None else ()):
            pts = np.array(frames[key], dtype=float).reshape(-1, 3)
            if key == "P" and not run.tethered:
                continue
            lo = np.fmin(lo, np.nanmin(pts, axis=0))
            hi = np.fmax(hi, np.nanmax(pts, axis=0))
        h = run.helicopter
        out_runs.append(
            {
                "stem": run.stem,
                "name": run.name,
                "configuration": run.configuration,
                "tethered": run.tethered,
                "colour": to_hex(colour),
                "status": int(run.status),
                "message": run.message,
                "end_time": float(run.time[-1]),
                "geometry": {
                    "rotor_radius": _ROTOR_RADIUS,
                    "tail_radius": _TAIL_RADIUS,
                    "mast": float(h.d_O_MRO3),
                    "tail": float(h.d_O_TRO1),
                    "hook": float(h.d_O_P3),
                },
                "frames": frames,
            }
        )
    margin = _ROTOR_RADIUS + 0.5
    lo = np.where(np.isfinite(lo), lo, 0.0) - margin
    hi = np.where(np.isfinite(hi), hi, 0.0) + margin
    return {
        "title": title,
        "generator": f"tetherheli {__version__}",
        "fps": float(fps),
        "time": _numbers(times, 6),
        "tension_max": tension_max,
        "tension_colours": [to_hex(cmap(x)) for x in np.linspace(0.0, 1.0, 9)],
        "wind_scale": 1.0 / wind_max if wind_max > 0.0 else 0.0,
        "bounds": {"lo": _numbers(lo, 3), "hi": _numbers(hi, 3)},
        "runs": out_runs,
    }


def _asset(name: str) -> str:
    return resources.files(__package__).joinpath(_ASSETS, name).read_text(encoding="utf-8")


def _script_json(value: Any) -> str:
    """``value`` as strict JSON safe inside a ``<script>`` element (every '<' escaped, so
    no ``</script>`` or ``<!--`` can end or change it)."""
    text = json.dumps(value, allow_nan=False, separators=(",", ":"), ensure_ascii=True)
    return text.replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")


def replay_html(data: dict[str, Any]) -> str:
    """The replay page of ``data`` (``replay_data``): one HTML file with three.js, the
    viewer's script and the data inlined.

    Parameters
    ----------
    data : dict
        The replay's data (strict JSON).

    Returns
    -------
    str
        The HTML text.
    """
    page = _asset("replay.html")
    parts = {
        "__TITLE__": html.escape(str(data["title"])),
        "__GENERATOR__": html.escape(str(data["generator"])),
        "__DATA__": _script_json(data),
        "__THREE__": _script_json(_asset("three.module.min.js")),
        "__VIEWER__": _asset("replay.js"),
    }
    # one pass: a placeholder's text inside the data (a run's name) is never replaced
    return re.sub("|".join(parts), lambda m: parts[m.group(0)], page)


def write_replay(
    directory: str | Path,
    output: str | Path,
    *,
    stems: Sequence[str] | None = None,
    fps: float = REPLAY_FPS,
    max_frames: int = REPLAY_MAX_FRAMES,
    title: str | None = None,
) -> Path:
    """Write the 3-D replay of the runs saved in ``directory`` as one HTML file.

    Parameters
    ----------
    directory : str or pathlib.Path
        A result folder written by ``tetherheli paper`` or ``simulate`` (one or several runs).
    output : str or pathlib.Path
        The ``.html`` file to write (whole or not at all; never over a file tetherheli did
        not write).
    stems : sequence of str, optional
        The runs to draw (default: all of the folder).
    fps : float
        Frames per second of simulated time [1/s] (default 25).
    max_frames : int
        At most this many frames.
    title : str, optional
        The page's title (default: the folder's name).

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    ParameterError
        A missing or empty folder, malformed runs, a bad option or an output that is not an
        ``.html`` file name.
    """
    from ..errors import ParameterError
    from .animation import _output_path

    out = _output_path(output, "an .html file")
    if out.suffix.lower() not in (".html", ".htm"):
        raise ParameterError("output", str(out), "a file name ending in .html")
    fps = check_number("fps", fps, low=0.0, low_open=True, high=1000.0)
    max_frames = check_integer("max_frames", max_frames, low=1, high=REPLAY_MAX_FRAMES)
    runs = _load_runs(directory, stems)
    name = title if title is not None else f"tetherheli replay: {Path(directory).resolve().name}"
    text = replay_html(replay_data(runs, fps=fps, max_frames=max_frames, title=name))
    atomic_write_text(out, text)
    record_output_file(out, writer="view")
    return out
