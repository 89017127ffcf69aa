"""3-D animation of saved simulation runs: fuselage, rotor disc, tether, winch on its deck, wind.

The animation only reads results written by ``SimulationResult.save(directory, stem)``: one
``<stem>.csv`` (time series, SI units, angles in rad) and one ``<stem>.json`` (configuration,
trim, version, status) per run, read through ``tetherheli.results.load_result``. Several runs of
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

This module renders and writes (``animate``, ``render_frame``, ``frame_rgb``); the runs are
read by ``viz.run_data`` and drawn by ``viz.scene``, whose public names are re-exported here.
"""

from __future__ import annotations

import contextlib
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import matplotlib as mpl
import numpy as np
from matplotlib import animation
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from PIL import Image

from .._io import atomic_path, check_output_file, record_output_file
from .._validation import check_integer, check_number
from ..errors import ParameterError
from ..model.kinematics import HelicopterPoints, direction_cosines, helicopter_points
from ..progress import Progress
from ..resources import check_memory
from .run_data import RunData, _load_runs, list_runs, load_run
from .scene import (
    _FIGURE_INCHES,
    _PAD_COLOUR,
    _WIND_COLOUR,
    _frame_times,
    _Scene,
    run_colours,
)

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


#: Upper bounds of the rendering options: GIF frame delays are whole centiseconds (100 fps at
#: most); the frame count and resolution bound the time and memory of a render.
MAX_FPS = 100.0
MAX_FRAMES = 20_000
MAX_DPI = 600.0


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
        return _PalettePillowWriter(fps=fps)  # type: ignore[arg-type]  # stubs: int; float works
    return animation.writers[FORMATS[suffix]](fps=fps)  # type: ignore[arg-type]  # (as above)


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
    if suffix == ".gif":
        _write_gif(scene, out, playback, progress=progress)
        record_output_file(out, writer="animate")
        return out
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


def _gif_palette(scene: _Scene) -> Image.Image:
    """One palette for every frame of a GIF, so that each frame is only mapped to it (a
    table look-up) instead of getting a palette of its own: the drawn colours kept exactly
    (the runs', the wind's, black, white, greys and 64 steps of the tension colour map),
    the rest from the first, middle and last frames (Pillow's median cut)."""
    from matplotlib.colors import to_rgb

    n = len(scene.times)
    named = [*scene.colours, _WIND_COLOUR, _PAD_COLOUR, "black", "white", "0.5", "0.85"]
    fixed = [to_rgb(c) for c in named] + [scene.cmap(x)[:3] for x in np.linspace(0, 1, 64)]
    fixed_rgb = (np.array(fixed) * 255).round().astype(np.uint8)
    samples = [_rgb(scene.render(k)) for k in sorted({0, n // 2, n - 1})]
    strip = Image.fromarray(np.concatenate([np.asarray(im) for im in samples], axis=0))
    rest = strip.quantize(256 - len(fixed_rgb), method=Image.Quantize.MEDIANCUT)
    colours = np.asarray((rest.getpalette() or [])[: 3 * (256 - len(fixed_rgb))], dtype=np.uint8)
    palette = Image.new("P", (1, 1))
    palette.putpalette(np.concatenate([fixed_rgb.ravel(), colours]).tolist())
    return palette


def _rgb(rgba: np.ndarray) -> Image.Image:
    """An RGBA canvas buffer (H, W, 4) as an RGB image."""
    height, width = rgba.shape[:2]
    return Image.frombuffer("RGBA", (width, height), rgba.tobytes()).convert("RGB")


def _write_gif(scene: _Scene, out: Path, playback: float, *, progress: bool) -> None:
    """Render the scene's frames by blitting (``_Scene.render``), map each to one shared
    palette, and write them as a looping GIF, atomically."""
    scene.blit_background()
    palette = _gif_palette(scene)
    frames = []
    with Progress("animate", len(scene.times), "frames", enabled=progress) as bar:
        for k in range(len(scene.times)):
            rgb = _rgb(scene.render(k))
            frames.append(rgb.quantize(palette=palette, dither=Image.Dither.NONE))
            bar.update(1)
    with atomic_path(out) as tmp:
        frames[0].save(
            tmp,
            format="GIF",
            save_all=True,
            append_images=frames[1:],
            duration=int(1000 / playback),
            loop=0,
        )


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
    return np.array(scene.fig.canvas.buffer_rgba())[:, :, :3]  # type: ignore[attr-defined]  # Agg
