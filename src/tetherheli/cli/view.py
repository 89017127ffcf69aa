"""``tetherheli view``: a 3-D replay of the runs in a result folder, as one HTML file."""

from __future__ import annotations

import argparse

from . import _common as c

__all__ = ["register", "run"]


def run(args: argparse.Namespace) -> int:
    """Write the replay (``viz.replay.write_replay``).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        The exit code, 0.
    """
    from ..viz.replay import write_replay

    stems, output = c.run_selection(args, "replay.html")
    path = write_replay(
        args.result_dir,
        output,
        stems=stems,
        fps=args.fps,
        max_frames=args.max_frames,
        title=args.title,
    )
    print(f"wrote {path}")
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``view`` to the sub-commands.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The command line's sub-command parsers.

    Returns
    -------
    None
    """
    from ..viz.formats import REPLAY_FPS, REPLAY_MAX_FRAMES

    p = sub.add_parser(
        "view",
        help="3-D replay of the runs in a result folder: one HTML file that opens offline",
        parents=[c.result_runs()],
    )
    p.add_argument(
        "--out", metavar="FILE", help="output .html file (default RESULT_DIR/replay.html)"
    )
    p.add_argument(
        "--fps",
        type=c.positive_float("--fps"),
        default=REPLAY_FPS,
        help=f"frames kept per second of simulated time (default {REPLAY_FPS:g}; the "
        "recorded sample nearest each frame)",
    )
    p.add_argument(
        "--max-frames",
        type=c.count_arg("--max-frames", 1, REPLAY_MAX_FRAMES),
        default=REPLAY_MAX_FRAMES,
        help="at most this many frames (a longer run is sampled more coarsely)",
    )
    p.add_argument("--title", help="the page's title (default: the folder's name)")
    p.set_defaults(func=run)
