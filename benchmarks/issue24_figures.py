"""Every issue 24 figure re-measured in one run, as baseline -> candidate ratios (issue 24).

Run: python benchmarks/issue24_figures.py --baseline SRC [--rounds 2] [--skip-cold]
[--json PATH], where SRC is the ``src`` folder of the baseline tree (e.g. a ``git worktree
add /tmp/base <commit>``'s ``/tmp/base/src``); the candidate is this checkout's ``src``.
It orchestrates the existing benchmarks, each in a subprocess with the tree's PYTHONPATH:

- ``bench_ab.py --baseline SRC --rounds N``: the compiled engine's best time per 60 s
  paper run, the same with the tether as the sensor, and ``run_batch``'s throughput;
- ``bench_minimal_loop.py`` (candidate only: it imports modules a baseline may lack): the
  engine and ``run_batch`` against the minimal compiled loop and its ``prange`` batch
  (once untimed to compile, then timed);
- ``python -m tetherheli paper --out DIR`` wall time, cold (a fresh empty
  ``NUMBA_CACHE_DIR``) then warm (the same cache), N rounds alternating the trees, best;
- ``bench_vector_env.py --autoreset --rounds N`` (with ``--baseline`` only if the baseline
  tree has the vector environment).

Prints one table (figure, baseline, candidate, candidate / baseline) and the processor;
``--json PATH`` also writes it, whole, to a new file or one this script wrote before (the
commands' rule for an output file, checked before anything runs: ``cli._script.claim_file``).
Every argument is checked first (one line, exit 2). Timings vary with the machine and its
load; no test asserts them.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from tetherheli.cli._common import count_arg
from tetherheli.cli._script import claim_file, run_script, script_parser, write_file
from tetherheli.errors import TetherheliError

HERE = Path(__file__).resolve().parent
CANDIDATE = HERE.parent / "src"
NA = None  # a figure the tree cannot measure


def run(argv: list[str], src: Path, cache: str) -> str:
    env = {**os.environ, "PYTHONPATH": str(src), "NUMBA_CACHE_DIR": cache}
    done = subprocess.run(argv, env=env, capture_output=True, text=True, cwd=HERE.parent)
    if done.returncode:
        raise RuntimeError(f"{' '.join(argv)} failed:\n{done.stderr[-2000:]}")
    return done.stdout


def processor() -> str:
    model = re.search(
        r"Model name:\s*(.+)", subprocess.run(["lscpu"], capture_output=True, text=True).stdout
    )
    probe = (
        "import llvmlite.binding as l\n"
        "getattr(l, 'initialize_native_target', lambda: None)()\n"
        "print(l.get_host_cpu_name())"
    )
    host = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True)
    return f"{model.group(1) if model else '?'} (LLVM host CPU {host.stdout.strip() or '?'})"


def bench_ab(baseline: Path, rounds: int, cache: str) -> list[tuple]:
    out = run(
        [
            sys.executable,
            str(HERE / "bench_ab.py"),
            "--baseline",
            str(baseline),
            "--candidate",
            str(CANDIDATE),
            f"--rounds={rounds}",
        ],
        CANDIDATE,
        cache,
    )
    rows = []
    for label, key in [
        ("engine, 60 s paper run [ms]", "best engine time"),
        ("engine, tether as sensor [ms]", "best run with the tether"),
        ("run_batch of 400 [runs/s]", "best batch throughput"),
    ]:
        line = next(ln for ln in out.splitlines() if ln.startswith(key))
        a, b = re.findall(r"(?:baseline|candidate) ([\d.]+)", line)
        rows.append((label, float(a), float(b)))
    return rows


def minimal_loop(cache: str) -> list[tuple]:
    argv = [sys.executable, str(HERE / "bench_minimal_loop.py")]
    run([*argv, "--runs=8", "--repeat=1"], CANDIDATE, cache)  # compile outside the timed run
    out = run(argv, CANDIDATE, cache)
    m = json.loads(out[out.index("{") :])
    return [
        ("minimal loop: engine [ms]", NA, m["engine_ms"]),
        ("minimal loop: the loop itself [ms]", NA, m["minimal_ms"]),
        ("minimal loop: engine / loop", NA, m["engine_over_minimal"]),
        ("minimal loop: run_batch [runs/s]", NA, m["batch_runs_per_s"]),
        ("minimal loop: prange batch [runs/s]", NA, m["minimal_batch_runs_per_s"]),
        ("minimal loop: run_batch / prange batch", NA, m["batch_over_minimal_batch"]),
    ]


def paper(trees: dict[str, Path], rounds: int, skip_cold: bool) -> list[tuple]:
    best: dict[tuple[str, str], float] = {}
    caches = {name: tempfile.mkdtemp(prefix=f"fig-paper-{name}-") for name in trees}
    for r in range(rounds):
        for name in list(trees) if r % 2 == 0 else list(reversed(trees)):
            cache = caches[name] if skip_cold else tempfile.mkdtemp(prefix=f"fig-cold-{name}-")
            argv = [sys.executable, "-m", "tetherheli", "paper", "--out"]
            if skip_cold and r == 0:  # compile once, untimed
                run([*argv, tempfile.mkdtemp(prefix="fig-out-")], trees[name], cache)
            for kind in ("warm",) if skip_cold else ("cold", "warm"):
                t0 = time.perf_counter()
                run([*argv, tempfile.mkdtemp(prefix="fig-out-")], trees[name], cache)
                wall = time.perf_counter() - t0
                print(f"round {r + 1} {name:<9} paper {kind} {wall:6.1f} s", flush=True)
                best[name, kind] = min(best.get((name, kind), wall), wall)
    kinds = ("warm",) if skip_cold else ("cold", "warm")
    rows = [
        (f"tetherheli paper, {k} [s]", best["baseline", k], best["candidate", k]) for k in kinds
    ]
    if not skip_cold:
        rows.append(
            (
                "tetherheli paper, cold / warm",
                *(best[n, "cold"] / best[n, "warm"] for n in ("baseline", "candidate")),
            )
        )
    return rows


def vector_env(baseline: Path, rounds: int, cache: str) -> list[tuple]:
    has = (baseline / "tetherheli" / "vector_env.py").exists()
    argv = [
        sys.executable,
        str(HERE / "bench_vector_env.py"),
        "--autoreset",
        f"--rounds={rounds}",
        *(["--baseline", str(baseline)] if has else []),
    ]
    out = run(argv, CANDIDATE, cache)
    best = {}
    for ln in out.splitlines():
        if ln.startswith("best "):
            f = ln.split()
            best[f[1]] = [float(v.replace(",", "")) for v in f[3:7]]
    a = best.get("baseline", [NA] * 4)
    c = best["candidate"]
    labels = [
        "reset of 64 copies [ms]",
        "no-reset steps [steps/s]",
        "autoreset steps [steps/s]",
        "autoreset / no-reset",
    ]
    return [(f"vector env: {lab}", a[i], c[i]) for i, lab in enumerate(labels)]


def fmt(v: float | None) -> str:
    return "n/a" if v is None else f"{v:,.3f}" if v < 10 else f"{v:,.1f}"


def main(argv: list[str] | None = None) -> int:
    """Measure every figure (module docstring).

    Parameters
    ----------
    argv : list of str, optional
        The arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        0 done, 2 a wrong argument or output file (one line, nothing run or written).
    """
    return run_script(__file__, _figures, argv)


def _figures(argv: list[str]) -> int:
    parser = script_parser(__file__, __doc__)
    parser.add_argument("--baseline", type=Path, required=True, help="src folder of the baseline")
    parser.add_argument("--rounds", type=count_arg("--rounds", 1, 100), default=2)
    parser.add_argument("--skip-cold", action="store_true", help="no cold paper runs")
    parser.add_argument("--json", type=Path, help="also write the table as JSON here")
    opts = parser.parse_args(argv)
    baseline = opts.baseline.resolve()
    if not (baseline / "tetherheli" / "__init__.py").is_file():
        raise TetherheliError(
            f"--baseline {opts.baseline} holds no tetherheli package; allowed: the src folder "
            "of a tetherheli tree"
        )
    if opts.json:
        claim_file(opts.json, option="--json")  # before the minutes of measuring
    trees = {"baseline": baseline, "candidate": CANDIDATE}
    warm = tempfile.mkdtemp(prefix="fig-warm-")
    rows = bench_ab(baseline, opts.rounds, warm)
    rows += minimal_loop(warm)
    rows += paper(trees, opts.rounds, opts.skip_cold)
    rows += vector_env(baseline, opts.rounds, warm)
    cpu = processor()
    table = [
        {
            "figure": f,
            "baseline": a,
            "candidate": b,
            "ratio": None if a is None or b is None else b / a,
        }
        for f, a, b in rows
    ]
    print(f"\nprocessor: {cpu}; baseline {baseline}; candidate {CANDIDATE}")
    print(f"{'figure':<42} {'baseline':>10} {'candidate':>10} {'ratio':>7}")
    for t in table:
        print(
            f"{t['figure']:<42} {fmt(t['baseline']):>10} {fmt(t['candidate']):>10} "
            f"{fmt(t['ratio']):>7}"
        )
    print("ratio = candidate / baseline; n/a: the baseline tree cannot measure it")
    if opts.json:
        data = {"processor": cpu, "date": time.strftime("%Y-%m-%d"), "rounds": opts.rounds}
        text = json.dumps({**data, "rows": table}, indent=1)
        write_file(opts.json, text.encode("utf-8"), option="--json", writer="issue24_figures.py")
        print(f"wrote {opts.json}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
