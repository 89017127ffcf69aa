"""Where a cold command's compilation goes (issue 24 item 5): Numba's compile events, per
compiled function, from an empty cache.

Runs one ``tetherheli`` command in this process with ``NUMBA_CACHE_DIR`` set to a fresh
empty folder (removed afterwards, with the command's output folder), and a listener on
``numba.core.event``'s ``numba:compile`` events. Prints the command's wall time, the sum of
the exclusive compile times, then the functions by exclusive time [s] (a function's own
compilation, its callees' taken out) with their inclusive time.

Run: python benchmarks/compile_events.py [--top 25] [--clock cpu] [COMMAND ...] (default
command: ``paper``; ``--out DIR`` is added, in a temporary folder). ``--clock cpu`` times
with the process's CPU time (``time.process_time``) instead of the wall clock: on a machine
shared with other work the wall clock counts the waits for a core too.
"""

from __future__ import annotations

import argparse
import collections
import os
import shutil
import sys
import tempfile
import time
from collections.abc import Callable


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--top", type=int, default=25, help="functions to list")
    parser.add_argument("--clock", choices=("wall", "cpu"), default="wall",
                        help="wall clock or the process's CPU time")  # fmt: skip
    parser.add_argument("command", nargs="*", default=["paper"], help="tetherheli command")
    options = parser.parse_args()
    scratch = tempfile.mkdtemp(prefix="compile-events-")
    # before the package is imported: its compiled functions choose their cache on import
    os.environ["NUMBA_CACHE_DIR"] = os.path.join(scratch, "cache")
    try:
        clock = time.perf_counter if options.clock == "wall" else time.process_time
        report(options.command, os.path.join(scratch, "out"), options.top, clock)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


def report(
    command: list[str], out: str, top: int, clock: Callable[[], float] = time.perf_counter
) -> None:
    """Run ``tetherheli COMMAND --out OUT`` under the listener and print its compile times,
    timed by ``clock``."""
    from numba.core import event

    stack: list[list[float]] = []
    exclusive: collections.Counter[str] = collections.Counter()
    inclusive: collections.Counter[str] = collections.Counter()

    class Listener(event.Listener):
        def on_start(self, ev: event.Event) -> None:
            stack.append([clock(), 0.0])

        def on_end(self, ev: event.Event) -> None:
            start, callees = stack.pop()
            spent = clock() - start
            dispatcher = ev.data["dispatcher"]
            name = f"{getattr(dispatcher.py_func, '__module__', '')}.{dispatcher.__qualname__}"
            exclusive[name] += spent - callees
            inclusive[name] += spent
            if stack:
                stack[-1][1] += spent

    event.register("numba:compile", Listener())
    from tetherheli.cli import main as cli

    start = clock()
    code = cli([*command, "--out", out])
    wall = clock() - start
    print(
        f"tetherheli {' '.join(command)}: exit {code}, {wall:.1f} s ({clock.__name__}), "
        f"compilation {sum(exclusive.values()):.1f} s (exclusive, summed)",
        file=sys.stderr,
    )
    for name, seconds in exclusive.most_common(top):
        print(f"{seconds:6.2f} s  ({inclusive[name]:6.2f} s inclusive)  {name}", file=sys.stderr)


if __name__ == "__main__":
    main()
