"""Rerun the commands behind the README's tables and print each table in the README's Markdown.

Run from the repository root (the package importable, e.g. ``pip install -e .``):

    python docs/regenerate_tables.py                     # every cheap table
    python docs/regenerate_tables.py --only cyclic_limit # one table
    python docs/regenerate_tables.py --expensive         # also the Monte Carlo tables and speed
    python docs/regenerate_tables.py --figures docs/img  # also write the README's figures

Each table is printed after the command(s) that made it, so the output can be pasted into the
README or compared with it. The commands write into a temporary folder (``--workdir`` keeps
them). The figures are gathered aside and written once every table is done: into the
checkout's ``docs/`` (the project's own files, ``cli._script.write_docs_file``), or into any
other folder by the commands' output rules (``--force`` to write beside foreign files); the
place is checked before anything runs. Tables (``--only`` NAME, repeatable):

- claim: "Our measurement of the paper's claim" and the tension ranges (``tetherheli paper``)
- turbulence: the hover-turbulence pair (``tetherheli simulate``)
- cyclic_limit: the smallest cyclic limit per paper run (``tetherheli sweep --find-min``)
- sensing: GPS against the tether (``tetherheli sensing``)
- eq40: the tension sweep saturated at the paper's 20% rule (``tetherheli sweep``)
- release: the transient after a tether release (Python: ``studies.release``)
- statuses: docs/tutorials/statuses.md's table of run statuses (``status.markdown_table``)
- montecarlo, montecarlo_turbulence, speed: expensive, only with ``--expensive`` or ``--only``
"""

from __future__ import annotations

import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

from tetherheli.cli._script import claim, docs_file, run_script, script_parser, write_docs_file

ROOT = Path(__file__).resolve().parents[1]
SCENARIOS = ROOT / "scenarios"

#: the paper's 20% rule, 0.2 x 123.7633 N x 0.2045951 m (``studies.sweep.paper_cyclic_limit``)
PAPER_CYCLIC_LIMIT = "5.0643"


def tetherheli(*args: str) -> str:
    """Run ``tetherheli ARGS`` (this interpreter), echo the command, return its stdout."""
    shown = "tetherheli " + " ".join(str(a).replace(str(ROOT) + "/", "") for a in args)
    print(f"$ {shown}", flush=True)
    done = subprocess.run(
        [sys.executable, "-m", "tetherheli", *map(str, args)], capture_output=True, text=True
    )
    if done.returncode not in (0, 1):  # 1: some runs failed, still a table
        sys.stderr.write(done.stderr)
        raise SystemExit(f"failed ({done.returncode}): {shown}")
    return done.stdout


def _json(path: Path) -> dict:
    return json.loads(path.read_text())


def table_claim(work: Path, figures: Path | None) -> None:
    out = work / "paper_out"
    tetherheli("paper", "--out", out, "--force")
    d = _json(out / "summary.json")
    runs, red = d["runs"], d["reduction_percent"]
    print("\n| metric | free | tethered | reduction |\n|---|---:|---:|---:|")
    rows = (
        ("simulation 1 (wind along n1), q1 peak [m]", "sim1", "peak_abs_dev", "q1", "sim1_q1_peak"),
        ("simulation 1, q1 RMS [m]", "sim1", "rms_dev", "q1", "sim1_q1_rms"),
        ("simulation 2 (wind along n2), q2 peak [m]", "sim2", "peak_abs_dev", "q2", "sim2_q2_peak"),
        ("simulation 2, q2 RMS [m]", "sim2", "rms_dev", "q2", "sim2_q2_rms"),
    )
    for label, sim, group, q, key in rows:
        f, t = runs[f"{sim}_free"][group][q], runs[f"{sim}_tethered"][group][q]
        print(f"| {label} | {f:.4f} | {t:.4f} | {red[key]:.1f}% |")
    for sim in ("sim1", "sim2"):
        r = runs[f"{sim}_tethered"]
        print(f"\ntension of {sim} tethered: {r['tension_min']:.2f}-{r['tension_max']:.2f} N")
    if figures:
        shutil.copy(out / "fig6_sim1_outputs.png", figures / "fig6_sim1_outputs.png")


def table_turbulence(work: Path, figures: Path | None) -> None:
    out = work / "turb_out"
    tetherheli(
        "simulate",
        SCENARIOS / "turbulence_hover_free.toml",
        SCENARIOS / "turbulence_hover_tethered.toml",
        "--out",
        out,
        "--force",
    )
    runs = _json(out / "summary.json")["runs"]
    f = runs["turbulence_hover_free"]["metrics"]
    t = runs["turbulence_hover_tethered"]["metrics"]
    print("\n| over 120 s | free | tethered | reduction |\n|---|---:|---:|---:|")
    for label, group, q, fmt in (
        ("q1 RMS deviation [m]", "rms_dev", "q1", ".4f"),
        ("q1 peak deviation [m]", "peak_abs_dev", "q1", ".3f"),
        ("q2 RMS deviation [m]", "rms_dev", "q2", ".4f"),
        ("q3 RMS deviation [m]", "rms_dev", "q3", ".4f"),
    ):
        a, b = f[group][q], t[group][q]
        print(f"| {label} | {a:{fmt}} | {b:{fmt}} | {100 * (a - b) / a:.0f}% |")
    if figures:
        shutil.copy(out / "outputs.png", figures / "turbulence_hover.png")


def table_cyclic_limit(work: Path, figures: Path | None) -> None:
    cells = {}
    for sim, metric in (("sim1", "peak_q1"), ("sim2", "peak_q2")):
        for cfg in ("free", "tethered"):
            out = work / f"findmin_{sim}_{cfg}"
            tetherheli(
                "sweep",
                SCENARIOS / f"paper_{sim}_{cfg}.toml",
                "--find-min",
                "actuators.cyclic_limit",
                "--values",
                "1:8:71",
                "--metric",
                metric,
                "--within",
                "0.10",
                "--tol",
                "0.005",
                "--out",
                out,
                "--force",
            )
            d = _json(out / "summary.json")
            cells[sim, cfg] = f"{d['interval']} ({metric} {d['reference_metric']:.2f} m)"
    print("\n| smallest cyclic limit, peak within 10% of unlimited (unlimited peak) | free | "
          "tethered |\n|---|---:|---:|")  # fmt: skip
    for sim, label in (("sim1", "simulation 1 (wind along n1)"), ("sim2", "simulation 2 (n2)")):
        print(f"| {label} | {cells[sim, 'free']} | {cells[sim, 'tethered']} |")


def table_sensing(work: Path, figures: Path | None) -> None:
    out = work / "sensing_out"
    tetherheli("sensing", "--out", out, "--force")
    runs = _json(out / "summary.json")["runs"]
    print(f"\n(raw rows of {out.name}/summary.json; the README's table takes these values)")
    print(
        "| run | source | estimate error RMS q1 / q2 / q3 [m] "
        "| true deviation RMS q1 / q2 / q3 [m] |"
    )
    print("|---|---|---:|---:|")

    def triple(v: dict | None) -> str:
        return " / ".join(f"{x:.3f}" for x in v.values()) if v else "n/a"

    for name, row in runs.items():
        src = row.get("position_source", "")
        est, dev = row.get("estimate_error_rms"), row.get("true_deviation_rms")
        print(f"| {name} | {src} | {triple(est)} | {triple(dev)} |")
    if figures and (out / "sensing.png").exists():
        shutil.copy(out / "sensing.png", figures / "sensing.png")


def table_eq40(work: Path, figures: Path | None) -> None:
    out = work / "sweep_out"
    tetherheli(
        "sweep",
        SCENARIOS / "paper_sim1_tethered.toml",
        "--param",
        "tension_control.T_ref",
        "--values",
        "0,10,20,25,30,40,50,60,70,80",
        "--cyclic-limit",
        PAPER_CYCLIC_LIMIT,
        "--metric",
        "rms_q1",
        "--out",
        out,
        "--force",
    )
    d = _json(out / "summary.json")
    print(
        f"\ncyclic authority {d['cyclic_limit_Nm']} N m ({d['cyclic_limit_source']}); "
        f"eq 40 bound {d['tension_bound_eq40']:.2f} N"
    )
    print(
        "\n| Tref [N] | run | RMS q1 [m] | peak tether moment [N m] | eq 40 worst case "
        "[N m] | largest tether-shaft angle [deg] |\n|---:|---|---:|---:|---:|---:|"
    )
    for i, v in enumerate(d["values"]):
        m, mom = d["metric_values"][i], d["peak_tether_moment_Nm"][i]
        worst, angle = d["eq40_worst_case_moment_Nm"][i], d["peak_tether_angle_deg"][i]

        def f(x: float | None, fmt: str) -> str:
            return "-" if x is None else format(x, fmt)

        print(
            f"| {v:g} | {d['statuses'][i]} | {f(m, '.3f')} | {f(mom, '.2f')} | "
            f"{f(worst, '.2f')} | {f(angle, '.1f')} |"
        )
    if figures:
        shutil.copy(out / "sweep.png", figures / "sweep_tref.png")


def table_release(work: Path, figures: Path | None) -> None:
    from tetherheli.scenario.core import ActuatorSettings, paper_scenario
    from tetherheli.studies.release import release_comparison

    print("$ python: release_comparison(paper simulation 1 tethered, breaking_tension = 25.05 N)")
    s = paper_scenario(1, "tethered").replace(actuators=ActuatorSettings(breaking_tension=25.05))
    c = release_comparison(s)
    print("\n| after the release | u0\\|T kept (before) | switched to u0\\|F |\n|---|---:|---:|")
    for label, kept, switched in c.rows():
        print(f"| {label} | {kept} | {switched} |")
    if figures:
        from tetherheli.viz.plots import figure_release, save_figure

        save_figure(figure_release(c), figures / "release.png")


def table_statuses(work: Path, figures: Path | None) -> None:
    """docs/tutorials/statuses.md's table of every run status (``status.markdown_table``)."""
    from tetherheli.status import markdown_table

    print("$ python: tetherheli.status.markdown_table()")
    print(markdown_table())


def table_montecarlo(work: Path, figures: Path | None) -> None:
    import numpy as np

    from tetherheli.runs import simulate
    from tetherheli.studies.montecarlo import draw, draw_seed, load_montecarlo
    from tetherheli.studies.montecarlo.draws import free_reference

    path = SCENARIOS / "montecarlo_paper_sim1.toml"
    out = work / "mc_out"
    tetherheli("montecarlo", path, "--runs", "1000", "--seed", "20261122", "--out", out, "--quiet")
    summary = _json(out / "summary.json")
    stats = summary["statistics"]
    print("\n| 1000 draws | free | tethered |\n|---|---:|---:|")
    for label, p in (("median", "p50"), ("95th percentile", "p95")):
        f, t = stats["free"]["peak_q1"][p], stats["tethered"]["peak_q1"][p]
        (fl, fh), (tl, th) = (
            stats["free"]["peak_q1"]["ci95"][p],
            stats["tethered"]["peak_q1"]["ci95"][p],
        )
        print(
            f"| peak q1 deviation, {label} [m] [95% CI] | {f:.3f} [{fl:.3f}, {fh:.3f}] | "
            f"{t:.3f} [{tl:.3f}, {th:.3f}] |"
        )
    print(f"| runs that failed | {stats['free']['failed']} | {stats['tethered']['failed']} |")
    r = summary["reduction_percent"]["peak_q1"]
    for label, p in (("median", "p50"), ("5th percentile", "p5")):
        lo, hi = r["ci95"][p]
        print(f"paired reduction of peak q1, {label}: {r[p]:.1f} % [95% CI {lo:.1f}, {hi:.1f}]")
    print(f"failed draws: {summary['failed_draws']}")
    base, config = load_montecarlo(path)
    with open(out / "results.csv", newline="") as fh:
        for row in csv.DictReader(fh):
            if row["status"] == "0":
                continue
            i = int(row["run"])
            d = draw(base, config, draw_seed(20261122, i), i)
            free = row["configuration"] == "free"
            r = simulate(free_reference(d.scenario) if free else d.scenario)
            force = np.linalg.norm(r.wind, axis=1)
            print(
                f"failed draw {i} ({row['configuration']}): amplitude scale "
                f"{float(row['amplitude_scale']):.2f}, {row['message']} at t = {r.end_time:g} s "
                f"(wind force then {force[-1]:.1f} N; the pulse is at 10-11 s, the sine from 30 s)"
            )
    if figures:
        shutil.copy(out / "peak_q1_hist.png", figures / "montecarlo_peak_q1_hist.png")
        shutil.copy(out / "peak_q1_paired.png", figures / "montecarlo_peak_q1_paired.png")


def table_montecarlo_turbulence(work: Path, figures: Path | None) -> None:
    out = work / "mct_out"
    tetherheli("montecarlo", SCENARIOS / "montecarlo_turbulence.toml", "--out", out, "--quiet")
    summary = _json(out / "summary.json")
    f, t = summary["statistics"]["free"], summary["statistics"]["tethered"]
    n = f["runs"]
    print(
        f"\n| {n} draws: median (95th percentile) | free | tethered | "
        "paired reduction per draw: median [95% CI] (5th percentile) |"
    )
    print("|---|---:|---:|---:|")
    for label, m in (
        ("q1 RMS deviation [m]", "rms_q1"),
        ("q1 peak deviation [m]", "peak_q1"),
        ("q2 RMS deviation [m]", "rms_q2"),
    ):
        a, b = f[m], t[m]
        r = summary["reduction_percent"][m]
        lo, hi = r["ci95"]["p50"]
        print(
            f"| {label} | {a['p50']:.3f} ({a['p95']:.3f}) | {b['p50']:.3f} ({b['p95']:.3f}) | "
            f"{r['p50']:.0f}% [{lo:.0f}, {hi:.0f}] ({r['p5']:.0f}%) |"
        )


def table_speed(work: Path, figures: Path | None) -> None:
    for bench in ("bench_derivative.py", "bench_closed_loop.py"):
        print(f"$ python benchmarks/{bench}")
        done = subprocess.run(
            [sys.executable, str(ROOT / "benchmarks" / bench)], capture_output=True, text=True
        )
        print(done.stdout)
    print("(the README gives the range over several such runs)")


#: The figures each table writes with ``--figures`` (``sensing``'s only when drawn).
FIGURES: dict[str, tuple[str, ...]] = {
    "claim": ("fig6_sim1_outputs.png",),
    "turbulence": ("turbulence_hover.png",),
    "sensing": ("sensing.png",),
    "eq40": ("sweep_tref.png",),
    "release": ("release.png",),
    "montecarlo": ("montecarlo_peak_q1_hist.png", "montecarlo_peak_q1_paired.png"),
}

TABLES: dict[str, tuple[Callable[[Path, Path | None], None], bool]] = {
    # name: (function, expensive)
    "claim": (table_claim, False),
    "turbulence": (table_turbulence, False),
    "cyclic_limit": (table_cyclic_limit, False),
    "sensing": (table_sensing, False),
    "eq40": (table_eq40, False),
    "release": (table_release, False),
    "statuses": (table_statuses, False),
    "montecarlo": (table_montecarlo, True),
    "montecarlo_turbulence": (table_montecarlo_turbulence, True),
    "speed": (table_speed, True),
}


def docs_folder(path: str) -> str | None:
    """``path`` relative to the checkout when it lies in its ``docs/`` (not following links:
    ``docs_file`` refuses a link on the way), else None."""
    rel = os.path.relpath(os.path.abspath(path), ROOT)
    parts = Path(rel).parts
    return Path(rel).as_posix() if parts and parts[0] == "docs" else None


def check_figures(path: str, names: list[str], force: bool) -> None:
    """Before any table runs: the figures ``names`` may be written into ``path`` (the
    checkout's docs: ``docs_file``; elsewhere: ``cli._script.claim``)."""
    rel = docs_folder(path)
    if rel is None:
        claim(path, option="--figures", force=force, names=names)
        return
    for name in names:
        docs_file(ROOT, f"{rel}/{name}")


def publish_figures(staged: Path, path: str, force: bool) -> None:
    """Write the figures gathered in ``staged`` into ``path``, by the rule of
    ``check_figures``: whole, never through a link or over a file tetherheli did not write."""
    from tetherheli._io import output_directory

    names = sorted(p.name for p in staged.iterdir())
    rel = docs_folder(path)
    if rel is not None:
        for name in names:
            write_docs_file(ROOT, f"{rel}/{name}", (staged / name).read_bytes())
    else:
        writer = "regenerate_tables.py --figures"
        with output_directory(path, writer=writer, option="--figures", force=force) as tmp:
            for name in names:
                shutil.copyfile(staged / name, tmp / name)
    for name in names:
        print(f"wrote {Path(path) / name}")


def main(argv: list[str] | None = None) -> int:
    """Print the tables (module docstring).

    Parameters
    ----------
    argv : list of str, optional
        The arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        0 done, 2 a wrong argument or figures' folder (one line, nothing run or written).
    """
    return run_script(__file__, _tables, argv)


def _tables(argv: list[str]) -> int:
    parser = script_parser(__file__, __doc__)
    parser.add_argument("--only", action="append", choices=sorted(TABLES), help="a table")
    parser.add_argument("--expensive", action="store_true", help="also the expensive tables")
    parser.add_argument("--workdir", help="keep the commands' output here (default: temporary)")
    parser.add_argument("--figures", help="also write the README's figures into this folder")
    parser.add_argument(
        "--force", action="store_true",
        help="with --figures outside docs/: write beside files tetherheli did not write",
    )  # fmt: skip
    args = parser.parse_args(argv)
    names = args.only or [n for n, (_, costly) in TABLES.items() if args.expensive or not costly]
    if args.figures:
        check_figures(args.figures, [f for n in names for f in FIGURES.get(n, ())], args.force)
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(args.workdir) if args.workdir else Path(tmp) / "work"
        work.mkdir(parents=True, exist_ok=True)
        staged = Path(tmp) / "figures" if args.figures else None
        if staged is not None:
            staged.mkdir()
        for name in names:
            print(f"\n## {name}\n", flush=True)
            t0 = time.perf_counter()
            TABLES[name][0](work, staged)
            print(f"\n({name}: {time.perf_counter() - t0:.0f} s)", flush=True)
        if staged is not None:
            publish_figures(staged, args.figures, args.force)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
