"""Are two source trees' runs the same? Every recorded array of shipped scenarios, flown by
the paper's compiled law and by the MPC's Python loop, in this tree and in another.

Run: python benchmarks/results_ab.py --baseline OTHER/src [--duration 8] [NAME ...]

Each tree runs in its own process (its own ``PYTHONPATH`` and compile cache under
``$TMPDIR``); the default names are the paper's four runs and two sensed ones (Kalman
filter, GNSS outage). Prints, per run, the largest absolute difference over every recorded
array (time, states, outputs, inputs, tension, reel rate, wind and the extra columns: the
MPC's estimate, iterations, fallbacks) and whether all are bit-identical (else which
differ); a scenario that refuses a controller (a landing: the paper's only) is flown by the
others; exits 1 when a run differs by more than ``--tolerance`` (default 1e-12) or records
other arrays.
"""

from __future__ import annotations

import argparse
import hashlib
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

NAMES = (
    "paper_sim1_tethered", "paper_sim1_free", "paper_sim2_tethered", "paper_sim2_free",
    "sensing_gps", "sensing_tether_outage",
)  # fmt: skip

_PROBE = """
import dataclasses, sys, numpy as np
from tetherheli.errors import ParameterError
from tetherheli.shipped import shipped_scenario
from tetherheli import simulate
out = {}
for name in sys.argv[3:]:
    base = shipped_scenario(name).replace(duration=float(sys.argv[2]))
    for law in ("paper", "mpc"):
        try:
            s = base.replace(control=dataclasses.replace(base.control, controller=law))
        except ParameterError as exc:  # e.g. a landing flies the paper's law only
            print(f"{name}/{law}: not flown ({exc})", file=sys.stderr)
            continue
        r = simulate(s)
        arrays = {k: getattr(r, k) for k in
                  ("time", "states", "outputs", "inputs", "tension", "reel_rate", "wind")}
        arrays.update(r.extra)
        for k, v in arrays.items():
            out[f"{name}/{law}/{k}"] = np.asarray(v)
        out[f"{name}/{law}/status"] = np.asarray(str(r.status))
np.savez(sys.argv[1], **out)
"""


def _run(src: Path, target: Path, duration: float, names: list[str]) -> dict[str, np.ndarray]:
    tag = hashlib.sha1(str(src.resolve()).encode()).hexdigest()[:12]
    cache = Path(tempfile.gettempdir()) / f"tetherheli-ab-{tag}"  # one compile cache per tree
    env = {**os.environ, "PYTHONPATH": str(src), "NUMBA_CACHE_DIR": str(cache)}
    cmd = [sys.executable, "-c", _PROBE, str(target), str(duration), *names]
    subprocess.run(cmd, env=env, check=True)
    with np.load(target) as data:
        return {k: data[k] for k in data.files}


def main(argv: list[str] | None = None) -> int:
    """Compare the runs of this tree and ``--baseline``; 0 when equal within the tolerance.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status: 0 equal, 1 different.
    """
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--baseline", type=Path, required=True, help="the other tree's src/")
    p.add_argument("--duration", type=float, default=8.0, help="seconds of each run")
    p.add_argument("--tolerance", type=float, default=1e-12, help="largest allowed difference")
    p.add_argument("names", nargs="*", default=list(NAMES), help="shipped scenario names")
    args = p.parse_args(argv)
    here = Path(__file__).resolve().parents[1] / "src"
    with tempfile.TemporaryDirectory() as tmp:
        new = _run(here, Path(tmp) / "new.npz", args.duration, args.names)
        old = _run(args.baseline, Path(tmp) / "old.npz", args.duration, args.names)
    if set(new) != set(old):
        print(f"the trees record different arrays: {sorted(set(new) ^ set(old))}")
        return 1
    failed = False
    for run in sorted({k.rsplit("/", 1)[0] for k in new}):
        keys = [k for k in new if k.startswith(run + "/")]
        worst, identical, differing = 0.0, True, []
        for k in keys:
            a, b = new[k], old[k]
            if a.shape != b.shape:
                worst, identical = float("inf"), False
                differing.append(k.rsplit("/", 1)[1])
                continue
            same = bool(np.array_equal(a, b, equal_nan=a.dtype.kind == "f"))
            identical &= same
            if not same:
                differing.append(k.rsplit("/", 1)[1])
            if a.dtype.kind == "f" and a.size:
                diff = np.abs(a - b)
                worst = max(worst, float(np.nanmax(diff)) if np.isfinite(diff).any() else 0.0)
        failed |= worst > args.tolerance or not np.array_equal(
            new[run + "/status"], old[run + "/status"]
        )
        which = "bit-identical" if identical else "differs: " + ", ".join(differing)
        print(f"{run:32s} {worst:.3g}  {which}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
