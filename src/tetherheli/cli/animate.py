"""``tetherheli animate``: a 3-D animation (GIF/MP4) of the runs in a result folder."""

from __future__ import annotations

import argparse

from . import _common as c

__all__ = ["register", "run"]


def run(args: argparse.Namespace) -> int:
    """Render the animation (``viz.animation.animate``).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        The exit code, 0.
    """
    from ..viz.animation import animate

    stems, output = c.run_selection(args, "animation.gif")
    path = animate(
        args.result_dir,
        output,
        stems=stems,
        fps=args.fps,
        speed=args.speed,
        max_frames=args.max_frames,
        progress=not args.quiet,
    )
    print(f"wrote {path}")
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``animate`` to the sub-commands.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The command line's sub-command parsers.

    Returns
    -------
    None
    """
    p = sub.add_parser(
        "animate",
        help="3-D animation (GIF/MP4) of the runs in a result folder",
        parents=[c.result_runs()],
    )
    p.add_argument(
        "--out", metavar="FILE", help="output .gif or .mp4 (default RESULT_DIR/animation.gif)"
    )
    p.add_argument(
        "--fps", type=c.positive_float("--fps"), default=20.0, help="frames/s, at most 100"
    )
    p.add_argument(
        "--speed", type=c.positive_float("--speed"), default=1.0, help="playback speed-up"
    )
    p.add_argument(
        "--max-frames",
        type=c.count_arg("--max-frames", 1, 20_000),
        default=600,
        help="at most this many frames (a longer run is sampled more coarsely)",
    )
    p.set_defaults(func=run)
