"""The MPC (``[control] controller = "mpc"``) on the paper's runs 1 and 2, tethered, with eq 40's
cyclic limit as saturation: OSQP's time per sample and the issue-14 goal.

Run: PYTHONPATH=src python benchmarks/bench_mpc.py [--tune EVALUATIONS] [--tension T_REF]
     PYTHONPATH=src python benchmarks/bench_mpc.py --pareto OUT [--pareto-csv FILE]
     PYTHONPATH=src python benchmarks/bench_mpc.py --robust N [--tension T_REF]

Timing (pinned to one CPU): each sample's OSQP update + solve, as wall-clock time and as the
thread's CPU time (which a loaded machine does not inflate), median, 99th percentile and
maximum against the 10 ms sample time; the whole MPC run's wall time against the paper
controller's compiled run of the same scenario (each timed on a second run: the first
compiles). The samples where OSQP stopped short (``mpc_fallback``) are counted.

Goal (``tune_tether_lqi.goal``, the same objective and penalties as the tethered LQI's
search): peak and RMS of q1 in sim 1 and of q2 in sim 2 against the free helicopter under the
paper's controller, as reductions 100 (1 - ratio) %; the RMS effort of each rotor input
against the paper's tethered controller (and the tethered LQI's) on the same saturated runs;
the tension range. ``--tune N`` runs a Nelder-Mead of N evaluations (each two 60 s runs) on
the log10 of four factors applied to ``start_settings()`` (the tethered LQI's weights and a
0.1 s time constant; ``--start`` the factors' first values): the disturbance estimate's
time constant, the position weights (q1 = q2 and their integrators), the cyclic input
weights (tMR1 = tMR2) and the tail-rotor weight (first steps: 0.3 decade down, down, up,
up); it prints the best as a ``[control.mpc]``
table. Deterministic: the same command prints the same numbers (the times aside).

``--pareto OUT`` maps the trade-off between the goal's two sides: a grid of designs (the
operating tension T_ref of the tether, ``PARETO_TENSIONS``, times common factors on the
position weights, ``PARETO_POSITION``, and on the cyclic input weights, ``PARETO_CYCLIC``,
applied to the shipped ``MPCSettings``), each flown on both eq-40 runs; per design the worst of
the four reductions and the worst of the eight effort ratios. A design is admissible when both
runs complete without an OSQP fallback, the tension stays within ``TENSION_RANGE`` (taut with
margin; the default drum winch's torque limit 2.5 N m at its 0.05 m radius holds 50 N), the
tether's moment about HO stays below the cyclic limit (eq 40, measured:
``analysis.tether_moment``) and the goal's altitude and off-axis bounds hold. The MPC's own
soft tension bounds are set to ``TENSION_RANGE`` on every design. Writes OUT/mpc_pareto.csv
(every design), OUT/mpc_pareto.md (the front and the answer) and OUT/mpc_pareto.png
(``viz.plots.figure_pareto``), whole at the end by the commands' output rules (OUT is
checked before anything flies: ``cli._script.claim``); ``--pareto-csv FILE`` redraws those
from a written CSV without flying. ``--tension T`` flies the report and timing at the
operating tension T [N]. Every argument is checked before anything runs (one line, exit 2).
"""

from __future__ import annotations

import dataclasses
import math
import os
import time

import numpy as np
from scipy.optimize import minimize
from tune_tether_lqi import MAX_OFF_AXIS, MAX_Q3, goal, references

from tetherheli import simulate
from tetherheli.cli._common import count_arg, number_arg
from tetherheli.cli._script import claim, run_script, script_parser
from tetherheli.errors import TetherheliError
from tetherheli.names import INPUT
from tetherheli.runs.mpc_setup import mpc_controller
from tetherheli.runs.setup import engine_setup
from tetherheli.scenario import Scenario
from tetherheli.scenario.core import MPCSettings, TetherLQISettings
from tetherheli.studies.controllers import fly, with_controller
from tetherheli.studies.sweep import scenario_cyclic_limit

STEP = 0.3  # the initial simplex's edge [decades]
#: the --pareto grid: operating tensions T_ref [N], log10 factors on the position weights
#: (q1 = q2 and their integrators) and on the cyclic input weights (tMR1 = tMR2)
PARETO_TENSIONS = (20.0, 25.0, 30.0, 35.0, 40.0, 45.0, 50.0)
PARETO_POSITION = (-1.0, -0.5, 0.0, 0.5)
PARETO_CYCLIC = (-0.5, 0.0, 0.5)
#: the admissible tension [N]: T_ref / 2 of the paper's 25 N (taut with margin) to the 50 N
#: that the default drum winch holds (``WinchSettings``: torque limit 2.5 N m, radius 0.05 m)
TENSION_RANGE = (12.5, 50.0)
PARETO_COLUMNS = (
    "T_ref", "log10_position", "log10_cyclic", "worst_reduction", "worst_effort",
    "red_peak_q1_sim1", "red_rms_q1_sim1", "red_peak_q2_sim2", "red_rms_q2_sim2",
    *(f"effort_{i}_sim{n}" for n in (1, 2) for i in INPUT),
    "tension_min", "tension_max", "peak_tether_moment", "cyclic_limit", "peak_q3",
    "peak_off_axis", "fallbacks", "trim_fMR3", "completed", "admissible",
)  # fmt: skip
#: The files ``--pareto`` writes into OUT.
PARETO_FILES = ("mpc_pareto.csv", "mpc_pareto.md", "mpc_pareto.png")
#: The largest CSV ``--pareto-csv`` reads [bytes] (one that ``--pareto`` wrote: ~30 KB).
PARETO_CSV_MAX_BYTES = 10 * 2**20
#: The bounds of ``--start``'s log10 factors [decades].
START_DECADES = 3.0


def start_settings() -> MPCSettings:
    """Where ``--tune`` starts: the tethered LQI's shipped weights, a disturbance estimate of
    time constant 0.1 s, the other keys at their defaults (fixed, so that the search is
    reproducible whatever the shipped defaults are)."""
    w = TetherLQISettings()
    return MPCSettings(Qy=w.Qy, q_tension=w.q_tension, Ru=w.Ru, disturbance_time_constant=0.1)


def with_mpc(scenario: Scenario, settings: MPCSettings) -> Scenario:
    """``scenario`` flown by the MPC with ``settings``."""
    s = with_controller(scenario, "mpc")
    return s.replace(control=dataclasses.replace(s.control, mpc=settings))


def tuned(p: np.ndarray, base: MPCSettings) -> MPCSettings:
    """``base`` with the four factors 10**p (module docstring) applied."""
    f = 10.0 ** np.asarray(p)
    Qy = list(base.Qy)
    for i in (0, 1, 4, 5):
        Qy[i] *= f[1]
    Ru = list(base.Ru)
    Ru[1] *= f[2]
    Ru[2] *= f[2]
    Ru[3] *= f[3]
    return dataclasses.replace(
        base,
        disturbance_time_constant=base.disturbance_time_constant * f[0],
        Qy=tuple(float(f"{v:.6g}") for v in Qy),
        Ru=tuple(float(f"{v:.6g}") for v in Ru),
    )


def timing(sims: dict, settings: MPCSettings) -> None:
    for n, (_, _, _, scenario) in sims.items():
        s = with_mpc(scenario, settings)
        c = mpc_controller(s, engine_setup(s))
        t0 = time.perf_counter()
        r = simulate(s, controller=c)
        wall = time.perf_counter() - t0
        simulate(scenario)  # compiled already; the second run is timed
        t0 = time.perf_counter()
        simulate(scenario)
        paper = time.perf_counter() - t0
        dt_ms = 1e3 * s.control.dt
        print(f"sim {n}: {r.message}; {r.time.size} samples, OSQP fell back on "
              f"{int(r.extra['mpc_fallback'].sum())}, iterations median "
              f"{np.median(c.iterations):.0f} max {max(c.iterations)}")  # fmt: skip
        for what, t in (("wall", c.solve_times), ("CPU", c.solve_cpu_times)):
            ms = 1e3 * np.array(t)
            print(f"  solve time per sample ({what}) [ms]: median {np.median(ms):.3f}, 99th "
                  f"percentile {np.percentile(ms, 99):.3f}, max {ms.max():.3f} (sample time "
                  f"{dt_ms:g} ms; over it: {np.count_nonzero(ms > dt_ms)})")  # fmt: skip
        print(f"  whole run: MPC {wall:.2f} s ({1e6 * wall / r.time.size:.0f} us/sample), "
              f"paper controller compiled {paper:.3f} s: {wall / paper:.0f}x")  # fmt: skip


def gyroscopic_estimate(scenario: Scenario, result, window: tuple[float, float]) -> tuple:
    """The cyclic torque a position hold needs against the wind over ``window`` [s] (the
    README's "Why"): the thrust leans by F / fMR3, and a lean rate needs the rotor's
    gyroscopic torque h times it (h = 2 I_MR11 |omega_MR|, eqs 21, 24), so RMS h F' / fMR3 with
    F the recorded wind force along its axis. Returns (estimate, flown RMS of the cyclic input
    that turns the thrust towards F: tMR1 for a wind along n1, tMR2 along n2) [N m]."""
    hp = scenario.params.helicopter
    h = 2.0 * hp.I_MR11 * abs(hp.omega_MR)
    u_trim = engine_setup(scenario).trim.u_total
    fMR3 = float(u_trim[0])
    axis = int(np.argmax(np.abs(result.wind).max(axis=0)))
    k = (result.time >= window[0]) & (result.time <= window[1])
    rate = np.gradient(result.wind[:, axis], result.time)[k]
    flown = result.inputs[k, 1 + axis] - u_trim[1 + axis]
    return h * float(np.sqrt(np.mean(rate**2))) / fMR3, float(np.sqrt(np.mean(flown**2)))


#: the paper's sine wind (Sec. VI: from t = 30 s to the end of the 60 s runs) [s]
SINE_WINDOW = (30.0, 60.0)


def report(sims: dict, settings: MPCSettings, what: str) -> float:
    flown = {}
    runs = {}

    def fly_mpc(s: Scenario) -> dict:
        s = with_mpc(s, settings)
        runs[s.name], flown[s.name] = fly(s)
        return flown[s.name]

    score, info = goal(sims, fly_mpc)
    _, lqi = goal(sims, lambda s: fly(with_controller(s, "tether_lqi"))[1])
    print(f"{what}: score {score:.4f} (worst of the four ratios; + penalties)")
    print("reductions vs free [%] (sim1 peak, RMS q1; sim2 peak, RMS q2):",
          np.round(100 * (1 - np.array(info["ratios"])), 1),
          "; tether_lqi:", np.round(100 * (1 - np.array(lqi["ratios"])), 1))  # fmt: skip
    for label, eff in (("mpc", info["effort"]), ("tether_lqi", lqi["effort"])):
        print(f"effort of {label} / paper tethered ({', '.join(INPUT)}; sim1 | sim2):",
              np.round(eff[:4], 3), "|", np.round(eff[4:], 3))  # fmt: skip
    print("tension range [N] (sim1 min max, sim2 min max):", np.round(info["tension"], 2))
    for n, (axis, _, _, scenario) in sims.items():
        m = flown[scenario.name]
        print(f"sim {n}: peak q3 {m['peak_q3']:.3f} m, off-axis peak q{2 - axis} "
              f"{m[f'peak_q{2 - axis}']:.3f} m, peak cyclic {m['peak_cyclic']:.3f} / "
              f"{scenario_cyclic_limit(scenario):.3f} N m")  # fmt: skip
        est, rms = gyroscopic_estimate(scenario, runs[scenario.name], SINE_WINDOW)
        print(f"sim {n}, {SINE_WINDOW[0]:g}-{SINE_WINDOW[1]:g} s (the sine): RMS d{INPUT[1 + axis]}"
              f" {rms:.3f} N m; gyroscopic estimate h RMS(F') / fMR3 {est:.3f} N m")  # fmt: skip
    return score


def at_tension(scenario: Scenario, T_ref: float) -> Scenario:
    """``scenario`` with the operating tension (Sec. VI's T_ref) T_ref [N]: it starts from the
    trim at that tension and the controller regulates about it."""
    return scenario.replace(params=scenario.params.replace({"tension_control.T_ref": T_ref}))


def pareto_design(log_position: float, log_cyclic: float) -> MPCSettings:
    """The shipped ``MPCSettings`` with the position and cyclic weights scaled by 10**log and
    the soft tension bounds at ``TENSION_RANGE``."""
    s = tuned(np.array([0.0, log_position, log_cyclic, 0.0]), MPCSettings())
    return dataclasses.replace(s, tension_bounds=TENSION_RANGE)


def evaluate(sims: dict, settings: MPCSettings, T_ref: float) -> dict:
    """One design of ``--pareto`` (module docstring): a row of ``PARETO_COLUMNS`` but the
    design's own columns (NaN where a run failed)."""
    from tetherheli.analysis import tether_moment

    runs = []

    def flown(scenario: Scenario) -> dict:
        s = at_tension(with_mpc(scenario, settings), T_ref)
        r, m = fly(s)
        runs.append((s, r, m))
        return m

    _, info = goal(sims, flown)
    row = dict.fromkeys(PARETO_COLUMNS[3:], math.nan)
    row.update(completed=len(info["ratios"]) == 4, admissible=False)
    row["fallbacks"] = sum(int(r.extra["mpc_fallback"].sum()) for _, r, _ in runs)
    if not row["completed"]:
        return row
    red = 100.0 * (1.0 - np.array(info["ratios"]))
    row.update(zip(PARETO_COLUMNS[5:9], red, strict=True))
    row.update(zip(PARETO_COLUMNS[9:17], info["effort"], strict=True))
    row["worst_reduction"], row["worst_effort"] = float(red.min()), float(max(info["effort"]))
    row["tension_min"], row["tension_max"] = min(info["tension"]), max(info["tension"])
    row["peak_tether_moment"] = max(tether_moment(r, s.params).peak for s, r, _ in runs)
    row["cyclic_limit"] = min(scenario_cyclic_limit(s) for s, _, _ in runs)
    row["peak_q3"] = max(m["peak_q3"] for _, _, m in runs)
    row["peak_off_axis"] = max(
        m[f"peak_q{2 - axis}"] for (axis, *_), (_, _, m) in zip(sims.values(), runs, strict=True)
    )
    row["trim_fMR3"] = float(engine_setup(runs[0][0]).trim.u_total[0])
    row["admissible"] = bool(
        row["fallbacks"] == 0
        and TENSION_RANGE[0] <= row["tension_min"]
        and row["tension_max"] <= TENSION_RANGE[1]
        and row["peak_tether_moment"] <= row["cyclic_limit"]
        and row["peak_q3"] <= MAX_Q3
        and row["peak_off_axis"] <= MAX_OFF_AXIS
    )
    return row


def pareto_rows(sims: dict) -> list[dict]:
    """Every design of the ``--pareto`` grid, flown (printed as it goes)."""
    rows = []
    grid = [(T, p, c) for T in PARETO_TENSIONS for p in PARETO_POSITION for c in PARETO_CYCLIC]
    for k, (T, p, c) in enumerate(grid):
        row = {"T_ref": T, "log10_position": p, "log10_cyclic": c}
        row.update(evaluate(sims, pareto_design(p, c), T))
        rows.append(row)
        print(f"[{k + 1}/{len(grid)}] T_ref {T:g} N, position 10^{p:g}, cyclic 10^{c:g}: "
              f"worst reduction {row['worst_reduction']:.1f} %, worst effort "
              f"{row['worst_effort']:.3f}, tension {row['tension_min']:.1f}-"
              f"{row['tension_max']:.1f} N, admissible {row['admissible']}",
              flush=True)  # fmt: skip
    return rows


def references_on_front(sims: dict) -> dict[str, tuple[float, float]]:
    """(worst effort ratio, worst reduction [%]) of the paper's tethered controller (effort
    ratio 1 by definition) and of the tethered LQI, both at the paper's 25 N."""
    out = {}
    red = [100.0 * (1.0 - p[f"{k}_q{a + 1}"] / f[f"{k}_q{a + 1}"])
           for a, f, p, _ in sims.values() for k in ("peak", "rms")]  # fmt: skip
    out["paper, tethered (25 N)"] = (1.0, min(red))
    _, lqi = goal(sims, lambda s: fly(with_controller(s, "tether_lqi"))[1])
    out["tether_lqi (25 N)"] = (max(lqi["effort"]), float(100.0 * (1.0 - max(lqi["ratios"]))))
    return out


def _fmt(v: float, digits: int) -> str:
    return f"{v:.{digits}f}" if math.isfinite(v) else "-"


def pareto_markdown(rows: list[dict], refs: dict[str, tuple[float, float]]) -> str:
    """The front and the answer (``--pareto``'s mpc_pareto.md)."""
    from tetherheli.analysis import pareto_front

    e = np.array([r["worst_effort"] for r in rows], dtype=float)
    red = np.array([r["worst_reduction"] for r in rows], dtype=float)
    ok = np.array([bool(r["admissible"]) for r in rows])
    front = pareto_front(np.where(ok, e, np.nan), np.where(ok, red, np.nan))
    head = ("| T_ref [N] | position x | cyclic x | worst reduction [%] | worst effort | "
            "tension [N] | peak tether moment [N m] | hover fMR3 [N] | "
            "worst effort x fMR3 [N] |")  # fmt: skip
    lines = ["# The MPC's effort-performance trade-off (benchmarks/bench_mpc.py --pareto)", "",
             f"{len(rows)} designs, {int(ok.sum())} admissible; references: "
             + "; ".join(f"{k}: effort {v[0]:.3f}, reduction {v[1]:.1f} %"
                         for k, v in refs.items()),
             "", "## The Pareto front (admissible designs)", "", head,
             "|---:|---:|---:|---:|---:|---|---:|---:|---:|"]  # fmt: skip

    def line(r: dict) -> str:
        return (f"| {r['T_ref']:g} | {10 ** r['log10_position']:.3g} | "
                f"{10 ** r['log10_cyclic']:.3g} | {_fmt(r['worst_reduction'], 1)} | "
                f"{_fmt(r['worst_effort'], 3)} | {_fmt(r['tension_min'], 1)}-"
                f"{_fmt(r['tension_max'], 1)} | {_fmt(r['peak_tether_moment'], 2)} | "
                f"{_fmt(r['trim_fMR3'], 2)} | "
                f"{_fmt(r['worst_effort'] * r['trim_fMR3'], 1)} |")  # fmt: skip

    for i in np.flatnonzero(front)[np.argsort(e[front])]:
        lines.append(line(rows[i]))
    lines += ["", "## Per operating tension: the least worst effort at >= 50 % and the best "
              "reduction at effort <= 1 (admissible designs)", "", head,
              "|---:|---:|---:|---:|---:|---|---:|---:|---:|"]  # fmt: skip
    answers = []
    for T in sorted({r["T_ref"] for r in rows}):
        at = [i for i, r in enumerate(rows) if r["T_ref"] == T and ok[i]]
        half = [i for i in at if red[i] >= 50.0]
        cheap = [i for i in at if e[i] <= 1.0]
        for pick in (min(half, key=lambda i: e[i], default=None),
                     max(cheap, key=lambda i: red[i], default=None)):  # fmt: skip
            if pick is not None and pick not in answers:
                answers.append(pick)
                lines.append(line(rows[pick]))
    both = [i for i in np.flatnonzero(ok) if red[i] >= 50.0 and e[i] <= 1.0]
    half = [i for i in np.flatnonzero(ok) if red[i] >= 50.0]
    cheap = [i for i in np.flatnonzero(ok) if e[i] <= 1.0]
    lines += ["", "## Answer", ""]
    lines.append(f"- designs meeting the goal (>= 50 %, effort <= 1, admissible): {len(both)}")
    if cheap:
        i = max(cheap, key=lambda i: red[i])
        lines.append(f"- best worst reduction at effort <= 1: {red[i]:.1f} % "
                     f"(T_ref {rows[i]['T_ref']:g} N, effort {e[i]:.3f})")  # fmt: skip
    if half:
        i = min(half, key=lambda i: e[i])
        lines.append(f"- least worst effort at >= 50 %: {e[i]:.3f} "
                     f"(T_ref {rows[i]['T_ref']:g} N, reduction {red[i]:.1f} %)")  # fmt: skip
    for T in sorted({r["T_ref"] for r in rows}):
        at = [i for i in half if rows[i]["T_ref"] == T]
        if at:
            i = min(at, key=lambda i: e[i])
            lines.append(f"- at T_ref {T:g} N: least worst effort at >= 50 %: {e[i]:.3f} "
                         f"(reduction {red[i]:.1f} %)")  # fmt: skip
    return "\n".join(lines) + "\n"


def write_pareto(
    out: str, rows: list[dict], refs: dict[str, tuple[float, float]], force: bool = False
) -> None:
    """OUT/mpc_pareto.csv, .md and .png (``tetherheli._io.output_directory``: written whole,
    never over a file tetherheli did not write; ``force``: beside foreign files)."""
    import csv

    from tetherheli._io import output_directory
    from tetherheli.viz.plots import figure_pareto, save_figure

    with output_directory(out, writer="bench_mpc --pareto", option="--pareto", force=force) as tmp:
        with open(tmp / "mpc_pareto.csv", "w", newline="", encoding="utf-8") as fh:
            w = csv.DictWriter(fh, fieldnames=PARETO_COLUMNS)
            w.writeheader()
            w.writerows(rows)
            fh.write(
                "# references: "
                + "; ".join(f"{k}={v[0]!r},{v[1]!r}" for k, v in refs.items())
                + "\n"
            )
        (tmp / "mpc_pareto.md").write_text(pareto_markdown(rows, refs), encoding="utf-8")
        fig = figure_pareto(
            [r["worst_effort"] for r in rows], [r["worst_reduction"] for r in rows],
            [bool(r["admissible"]) for r in rows], [r["T_ref"] for r in rows],
            "operating tension T_ref [N]", references=refs,
        )  # fmt: skip
        fig.axes[0].set_title("MPC designs on the paper's runs 1 and 2 (eq 40 saturation)",
                              fontsize=9)  # fmt: skip
        save_figure(fig, tmp / "mpc_pareto.png")
    print(pareto_markdown(rows, refs))


def read_pareto(path: str) -> tuple[list[dict], dict[str, tuple[float, float]]]:
    """The rows and references of a CSV that ``--pareto`` wrote.

    Raises
    ------
    TetherheliError
        One line naming the file and the row or line at fault (never its content): too
        large, not UTF-8, other columns, a cell that is not a number.
    """
    import csv

    def refuse(what: str) -> TetherheliError:
        return TetherheliError(
            f"--pareto-csv {path}: {what}; allowed: a CSV that bench_mpc.py --pareto wrote"
        )

    if os.path.getsize(path) > PARETO_CSV_MAX_BYTES:
        raise refuse(f"larger than {PARETO_CSV_MAX_BYTES // 2**20} MiB")
    try:
        with open(path, encoding="utf-8") as fh:
            text = fh.read().splitlines()
    except UnicodeDecodeError:
        raise refuse("not UTF-8 text") from None
    refs = {}
    for n, ln in enumerate(text, 1):
        if ln.startswith("# references: "):
            for item in ln[len("# references: ") :].split("; "):
                name, _, xy = item.rpartition("=")
                try:
                    x, y = (float(v) for v in xy.split(","))
                except ValueError:
                    raise refuse(f"line {n}: a reference that is not two numbers") from None
                refs[name] = (x, y)
    rows = []
    reader = csv.DictReader([ln for ln in text if not ln.startswith("#")])
    if tuple(reader.fieldnames or ()) != PARETO_COLUMNS:
        raise refuse("other columns than PARETO_COLUMNS")
    for n, r in enumerate(reader, 1):
        row = {}
        for k, v in r.items():
            if k in ("completed", "admissible"):
                if v not in ("True", "False"):
                    raise refuse(f"row {n}: {k} is not True or False")
                row[k] = v == "True"
                continue
            try:
                row[k] = float(v)
            except (TypeError, ValueError):
                raise refuse(f"row {n}: {k} is not a number") from None
        rows.append(row)
    if not rows:
        raise refuse("no designs")
    return rows, refs


def robust(runs: int, tension: float | None) -> None:
    """``--robust N``: the MPC (the shipped weights; at ``tension`` [N] with the tension
    bounds ``TENSION_RANGE``) on the first N draws of the two Monte Carlo files with eq 40's
    saturation, designed on the nominal plant (``studies.robust.montecarlo_compare``):
    failures, paired reductions against the free helicopter (median / 5th percentile) and the
    median RMS effort of each rotor input."""
    from tetherheli.compare import markdown_reductions
    from tetherheli.studies.montecarlo import load_montecarlo
    from tetherheli.studies.robust import montecarlo_compare

    settings = MPCSettings()
    if tension is not None:
        settings = dataclasses.replace(settings, tension_bounds=TENSION_RANGE)
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenarios")
    results = []
    for name in ("montecarlo_paper_sim1", "montecarlo_turbulence"):
        base, config = load_montecarlo(os.path.join(root, f"{name}.toml"))
        base = with_mpc(base, settings)
        if tension is not None:
            base = at_tension(base, tension)
        mc = montecarlo_compare(base, config, ("mpc",), runs=runs, eq40=True)
        results.append(mc)
        for lab in mc.labels:
            eff = [np.nanmedian(mc.values[lab][f"rms_d{u}"]) for u in INPUT]
            print(f"{name} {lab}: failed {mc.failures(lab)}/{mc.runs}; median RMS effort "
                  f"({', '.join(INPUT)}) " + ", ".join(f"{e:.3f}" for e in eff))  # fmt: skip
    print(markdown_reductions(tuple(results)))


def _start(text: str) -> np.ndarray:
    """``--start``: four comma-separated log10 factors within +-``START_DECADES``."""
    import argparse

    try:
        p = np.array([float(v) for v in text.split(",")])
    except ValueError:
        p = np.array([])
    if p.shape != (4,) or not np.all(np.abs(p) <= START_DECADES):
        raise argparse.ArgumentTypeError(
            f"--start = {text!r}: allowed: four comma-separated numbers in "
            f"[-{START_DECADES:g}, {START_DECADES:g}]"
        )
    return p


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark (module docstring).

    Parameters
    ----------
    argv : list of str, optional
        The arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        0 done, 2 a wrong argument or output folder (one line, nothing run or written).
    """
    return run_script(__file__, _bench, argv)


def _bench(argv: list[str]) -> int:
    parser = script_parser(__file__, __doc__)
    parser.add_argument("--tune", type=count_arg("--tune", 0, 10_000), default=0,
                        metavar="EVALUATIONS")  # fmt: skip
    parser.add_argument("--start", type=_start, default=_start("0,0,0,0"),
                        help="log10 factors the search starts at (default 0,0,0,0)")  # fmt: skip
    parser.add_argument("--pareto", metavar="OUT", help="map the trade-off into directory OUT")
    parser.add_argument("--pareto-csv", metavar="FILE", help="with --pareto: redraw from FILE")
    parser.add_argument("--force", action="store_true",
                        help="with --pareto: write beside files tetherheli did not write "
                        "(they are kept)")  # fmt: skip
    parser.add_argument("--tension", type=number_arg("--tension", *TENSION_RANGE),
                        metavar="T_REF",
                        help="report at the operating tension T_REF [N] (tension bounds "
                        f"{TENSION_RANGE})")  # fmt: skip
    parser.add_argument("--robust", type=count_arg("--robust", 1, 1000), metavar="N",
                        help="only: the MPC (at --tension) on the first N draws of the "
                        "sim-1 and turbulence Monte Carlos, eq 40")  # fmt: skip
    args = parser.parse_args(argv)
    if args.robust:
        robust(args.robust, args.tension)
        return 0
    if args.pareto_csv and not args.pareto:
        parser.error("--pareto-csv needs --pareto OUT")
    if args.pareto:  # before anything flies
        claim(args.pareto, option="--pareto", force=args.force, names=PARETO_FILES)
    if args.pareto and args.pareto_csv:
        write_pareto(args.pareto, *read_pareto(args.pareto_csv), force=args.force)
        return 0
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})  # one core
    sims = references()
    if args.pareto:
        refs = references_on_front(sims)
        write_pareto(args.pareto, pareto_rows(sims), refs, force=args.force)
        return 0
    base = MPCSettings()
    if args.tension is not None:
        base = dataclasses.replace(base, tension_bounds=TENSION_RANGE)
        sims = {n: (a, f, p, at_tension(s, args.tension)) for n, (a, f, p, s) in sims.items()}
    if args.tune > 0:
        base = start_settings()
        best = {"f": math.inf, "p": np.zeros(4)}

        def objective(p: np.ndarray) -> float:
            f, _ = goal(sims, lambda s: fly(with_mpc(s, tuned(p, base)))[1])
            if f < best["f"]:
                best.update(f=f, p=np.array(p))
                print(f"best {f:.4f} at", ",".join(f"{v:.3f}" for v in p), flush=True)
            return f

        p0 = args.start
        simplex = np.vstack([p0, p0 + STEP * np.diag([-1.0, -1.0, 1.0, 1.0])])
        minimize(objective, p0, method="Nelder-Mead", options={
            "maxfev": args.tune, "initial_simplex": simplex, "xatol": 1e-3})  # fmt: skip
        base = tuned(best["p"], base)
        print("log10 factors:", ",".join(f"{v:.4f}" for v in best["p"]))
        print("[control.mpc]")
        for f in ("disturbance_time_constant", "Qy", "Ru"):
            v = getattr(base, f)
            print(f"{f} = " + (f"[{', '.join(f'{x:.6g}' for x in v)}]" if isinstance(v, tuple)
                               else f"{v:.6g}"))  # fmt: skip
    what = "the tuned settings" if args.tune else "the shipped defaults"
    if args.tension is not None:
        what += f" at T_ref = {args.tension:g} N (tether_lqi too), tension bounds {TENSION_RANGE}"
    report(sims, base, what)
    timing(sims, base)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
