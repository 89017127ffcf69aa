"""How much Python a run's set-up is (issue 44, item 2): the tetherheli functions called, by
module, the switches between modules and the checks, in ``simulate`` and in ``run_batch``.

Run: python benchmarks/setup_calls.py [--cold] [--duration 8] [--top 25] [--checks]

Flies ``simulate(paper_scenario(1, "tethered"))`` and ``run_batch`` of four dispersed copies
of it (``workers=1``), each once untraced first (the compiled code loaded or compiled, the
caches filled), then once under ``sys.setprofile``; ``--cold`` empties every ``functools``
cache of tetherheli before the traced run (the trims, gains and designs solved anew). Counts
every call of a Python function of tetherheli (a compiled function's body is not Python and
is not counted, its dispatch is), by module; a module switch is a call whose module differs
from the module of the previous tetherheli call; a check is a call of a function named
``check*``, ``_check*``, ``validate*`` or ``_validate*`` (``_validation``'s ``Key.check``
too). ``--checks`` lists the checks with their callers.
"""

from __future__ import annotations

import collections
import dataclasses
import functools
import sys
from collections.abc import Callable
from typing import Any

from tetherheli.cli._common import count_arg, number_arg
from tetherheli.cli._script import run_script, script_parser

_CHECK_PREFIXES = ("check", "_check", "validate", "_validate")


class Trace:
    """What ``sys.setprofile`` saw: calls by module, module switches, checks by caller."""

    def __init__(self) -> None:
        self.calls: collections.Counter[str] = collections.Counter()
        self.checks: collections.Counter[str] = collections.Counter()
        self.switches = 0
        self._last = ""

    def __call__(self, frame: Any, event: str, arg: Any) -> None:
        if event != "call":
            return
        module = frame.f_globals.get("__name__", "")
        if not module.startswith("tetherheli"):
            return
        self.calls[module] += 1
        if module != self._last:
            self.switches += self._last != ""
            self._last = module
        name = frame.f_code.co_name
        caller = frame.f_back
        outer = caller.f_globals.get("__name__")
        if name.startswith(_CHECK_PREFIXES):
            where = f"{outer}:{caller.f_code.co_name}"
            self.checks[f"{module}:{name} <- {where}"] += 1


def empty_caches() -> None:
    """Empty every ``functools`` cache of tetherheli (trims, gains, designs)."""
    for name, module in list(sys.modules.items()):
        if name.startswith("tetherheli"):
            for value in list(vars(module).values()):
                if isinstance(value, functools._lru_cache_wrapper):
                    value.cache_clear()


def traced(job: Callable[[], object], *, cold: bool) -> Trace:
    """Run ``job`` once untraced, then once under the tracer (its caches emptied first when
    ``cold``)."""
    job()
    if cold:
        empty_caches()
    trace = Trace()
    previous = sys.getprofile()
    sys.setprofile(trace)
    try:
        job()
    finally:
        sys.setprofile(previous)
    return trace


def report(title: str, trace: Trace, *, top: int, checks: bool) -> None:
    """Print a trace: totals, the modules by calls, the checks."""
    total = sum(trace.calls.values())
    print(
        f"{title}: {total} calls across {len(trace.calls)} modules, {trace.switches} module "
        f"switches, {sum(trace.checks.values())} checks"
    )
    for module, n in trace.calls.most_common(top):
        print(f"  {n:6d}  {module}")
    if checks:
        for where, n in sorted(trace.checks.items()):
            print(f"  check {n:4d}  {where}")


def main(argv: list[str] | None = None) -> int:
    """Trace a ``simulate`` and a ``run_batch`` of the paper's run 1 (tethered).

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status (0).
    """

    def work(arguments: list[str]) -> int:
        p = script_parser(__file__, __doc__)
        p.add_argument("--cold", action="store_true", help="empty the caches before tracing")
        p.add_argument(
            "--duration", type=number_arg("--duration", 0.01, 600.0), default=8.0, help="seconds"
        )
        p.add_argument(
            "--top", type=count_arg("--top", 1, 1000), default=25, help="modules to list"
        )
        p.add_argument("--checks", action="store_true", help="list the checks and callers")
        args = p.parse_args(arguments)
        from tetherheli import paper_scenario, run_batch, simulate

        s = paper_scenario(1, "tethered").replace(duration=args.duration)
        params = s.params
        batch = [
            s.replace(params=params.replace(helicopter={"m_F": params.helicopter.m_F * f}))
            for f in (0.98, 0.99, 1.01, 1.02)
        ]
        mpc = s.replace(control=dataclasses.replace(s.control, controller="mpc"), duration=0.2)
        jobs: dict[str, Callable[[], object]] = {
            "simulate(paper_scenario(1, 'tethered'))": lambda: simulate(s),
            "run_batch(4 runs, workers=1)": lambda: run_batch(batch, workers=1),
            "simulate(the same, controller = 'mpc', 0.2 s)": lambda: simulate(mpc),
        }
        for title, job in jobs.items():
            trace = traced(job, cold=args.cold)
            report(title, trace, top=args.top, checks=args.checks)
        return 0

    return run_script(__file__, work, argv)


if __name__ == "__main__":
    sys.exit(main())
