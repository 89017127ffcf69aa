"""The paper's job (Sec. VI): four runs, Figs. 6-9, time series, report.md, summary.json.

``run_paper(out_dir)`` is what ``tetherheli paper --out DIR`` does; ``write_run`` serves
``tetherheli simulate``. Output directories are written whole or not at all.
"""

from __future__ import annotations

import dataclasses
import platform
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from .._io import atomic_write_text, claim_output_directory, output_directory, write_json
from .._version import __version__, dependency_versions, git_commit
from ..analysis import metric_samples, reduction_percent, run_metrics
from ..errors import ParameterError
from ..names import POSITION
from ..results import SimulationResult
from ..results.result import check_result_format
from ..runs import simulate
from ..scenario.core import (
    MPC_QY_GNSS,
    Scenario,
    check_distinct_names,
    paper_scenario,
    scenario_toml,
)
from ..viz.formats import figures_for_files

__all__ = [
    "PAPER_CLAIM_PERCENT",
    "paper_summary",
    "run_paper",
    "run_status",
    "write_run",
]

#: Sec. VI: "the disturbance effect ... is reduced up to a 30% from the response of the free
#: system".
PAPER_CLAIM_PERCENT = 30.0
#: Written beside every run ``simulate`` writes: its scenario, for ``tetherheli simulate``
#: (``load_scenario``) to run it again.
SCENARIO_FILE = "scenario.toml"
RUN_KEYS = ("sim1_free", "sim1_tethered", "sim2_free", "sim2_tethered")


def run_status(result: SimulationResult) -> dict[str, Any]:
    """How a run ended, as plain data: status code, message, whether it completed, the time
    of its last recorded sample [s] (where a failed run stopped) and its tether release.

    Parameters
    ----------
    result : SimulationResult
        The run.

    Returns
    -------
    dict of str to Any
        ``status`` (int), ``message`` (str), ``completed`` (bool), ``end_time`` [s] and
        ``tether_release`` (``SimulationResult.release_info``).
    """
    return {
        "status": result.status,
        "message": result.message,
        "completed": result.ok,
        "end_time": result.end_time,
        "tether_release": result.release_info(),
    }


def _metrics_or_none(result: SimulationResult) -> dict[str, Any] | None:
    """``run_metrics`` over the recorded samples (up to a failure), None without samples in
    the metrics' window."""
    return run_metrics(result).as_dict() if metric_samples(result) else None


#: summary.json's reductions: key -> (simulation, output, metric group of ``RunMetrics``)
_REDUCTIONS = {
    "sim1_q1_peak": ("sim1", "q1", "peak_abs_dev"),
    "sim1_q1_rms": ("sim1", "q1", "rms_dev"),
    "sim2_q2_peak": ("sim2", "q2", "peak_abs_dev"),
    "sim2_q2_rms": ("sim2", "q2", "rms_dev"),
}


def paper_summary(
    results: dict[str, SimulationResult], *, dt: float, pulse_duration: float
) -> dict[str, Any]:
    """summary.json's content from the four runs (keys as documented in the README).

    ``statuses`` says how every run ended; the metrics of a failed run cover its samples up
    to the failure, and a reduction involving a failed run is None (it cannot be computed).

    Parameters
    ----------
    results : dict of str to SimulationResult
        The four runs, keyed "sim1_free", "sim1_tethered", "sim2_free", "sim2_tethered".
    dt : float
        Control sample time the runs used [s].
    pulse_duration : float
        Duration of the wind pulse [s].

    Returns
    -------
    dict of str to Any
        summary.json's content: ``dt``, ``pulse_duration``, ``runs`` (``run_metrics`` of
        each run, None without samples), ``reduction_percent`` (tethered against free [%],
        None if either run failed) and ``statuses`` (``run_status``).
    """
    metrics = {k: _metrics_or_none(results[k]) for k in RUN_KEYS}
    red: dict[str, float | None] = {}
    for key, (sim, q, group) in _REDUCTIONS.items():
        free, tethered = results[f"{sim}_free"], results[f"{sim}_tethered"]
        if free.ok and tethered.ok:
            red[key] = reduction_percent(
                metrics[f"{sim}_free"][group][q],  # type: ignore[index]
                metrics[f"{sim}_tethered"][group][q],  # type: ignore[index]
            )
        else:
            red[key] = None
    return {
        "dt": dt,
        "pulse_duration": pulse_duration,
        "runs": metrics,
        "reduction_percent": red,
        "statuses": {k: run_status(results[k]) for k in RUN_KEYS},
    }


def _manifest(command: str, scenarios: dict[str, Scenario]) -> dict[str, Any]:
    return {
        "tetherheli_version": __version__,
        "command": command,
        "python": sys.version.split()[0],
        "numpy": np.__version__,
        "versions": dependency_versions(),
        "git_commit": git_commit(),
        "platform": platform.platform(),
        "scenarios": {k: s.to_dict() for k, s in scenarios.items()},
    }


def _claim_sentence(reductions: dict[str, float | None]) -> str:
    red = [v for v in reductions.values() if v is not None]
    if not red:
        return (
            "No reduction can be computed: a run of each simulation failed (see Failed runs), "
            "so the paper's claim is not checked."
        )
    best = max(red)
    worst = min(red)
    if len(red) < len(reductions):
        best_note = " (only the simulations whose runs both completed are compared)"
    else:
        best_note = ""
    if best >= PAPER_CLAIM_PERCENT:
        verdict = (
            f'The paper\'s "up to 30%" is matched or exceeded here: the largest '
            f"reduction is {best:.1f}%."
        )
    elif best > 0:
        verdict = (
            f"The reductions measured here ({worst:.1f}% to {best:.1f}%) fall short of "
            f'the paper\'s "up to 30%".'
        )
    else:
        verdict = "The tether did not reduce the disturbance effect in these runs."
    return (
        verdict + best_note + " The paper does not define its metric (peak or RMS) nor the pulse "
        "duration or the controller's sample time, so the comparison is indicative only."
    )


def _fmt(value: float | None, spec: str, suffix: str = "") -> str:
    """A number for the report, "n/a" where it could not be computed."""
    return "n/a" if value is None else f"{value:{spec}}{suffix}"


def _report_md(
    summary: dict[str, Any], command: str, data_format: str = "csv", figure_format: str = "png"
) -> str:
    red = summary["reduction_percent"]
    runs = summary["runs"]
    statuses = summary["statuses"]
    failed = [k for k in RUN_KEYS if not statuses[k]["completed"]]
    lines = [
        "# tetherheli: the paper's wind-disturbance simulations (Sec. VI)",
        "",
        f"Produced by `{command}` with tetherheli {__version__}.",
        "",
    ]
    if failed:
        lines += ["## Failed runs", ""]
        for k in failed:
            st = statuses[k]
            lines.append(f"- **{k}** failed at t = {st['end_time']:g} s: {st['message']}.")
        lines += [
            "",
            "Their metrics below cover the run up to the failure; a reduction that involves a "
            "failed run is n/a. Their figures draw them up to the failure.",
            "",
        ]
    released = [k for k in RUN_KEYS if statuses[k]["tether_release"] is not None]
    for k in released:
        ev = statuses[k]["tether_release"]
        lines += [
            f"- {k}: tether released at t = {ev['time']:g} s (tension {ev['tension']:.6g} N).",
            "",
        ]
    lines += [
        "## Set-up",
        "",
        "- Plant: the tethered model (eqs 10-12, 29-35, 37); the free configuration is the same "
        "plant with the tether removed (TC = 0, no winch, no feed-forward).",
        f"- Controller: LQI designed on the free model (Table IV hover) with the paper's Qy, Ru, "
        f"sampled every dt = {summary['dt']:g} s (zero-order hold; the paper does not give dt); "
        "feed-forward of eq 55 and PI tension control of eq 56 (KP = 1, KI = 0.1, "
        "Tref = 25 N) in the tethered runs.",
        "- Integration: fixed-step RK4, two steps per sample (checked against an adaptive "
        "DOP853 reference to better than 1e-6 m in the test suite).",
        f"- Wind on HO: 20 N pulse at t = 10 s lasting **{summary['pulse_duration']:g} s "
        "(an assumption: the paper does not state the duration)**, then "
        "20 sin(2 pi 0.1 t) N from t = 30 s; along n1 (simulation 1) or n2 (simulation 2).",
        "- Metrics: deviation from each run's own trim over the whole 60 s run; peak = max |dev|, "
        "RMS = sqrt(mean(dev^2)); reduction = 100 (free - tethered) / free.",
        "",
        "## Reduction of the disturbance effect by the tether",
        "",
        "| metric | free | tethered | reduction |",
        "|---|---:|---:|---:|",
    ]
    for key, (sim, q, kind) in _REDUCTIONS.items():
        free, teth = runs[f"{sim}_free"], runs[f"{sim}_tethered"]
        f = _fmt(free[kind][q] if free else None, ".4f")
        t = _fmt(teth[kind][q] if teth else None, ".4f")
        label = f"{sim} {q} {'peak' if kind == 'peak_abs_dev' else 'RMS'} [m]"
        lines.append(f"| {label} | {f} | {t} | {_fmt(red[key], '.1f', '%')} |")
    lines += [
        "",
        _claim_sentence(red),
        "",
        "## All runs",
        "",
        "| run | peak q1 [m] | peak q2 [m] | peak q3 [m] | peak q4 [deg] | peak q5 [deg] "
        "| RMS q1 [m] | RMS q2 [m] | RMS q3 [m] | TC min [N] | TC max [N] |",
        "|---|" + "---:|" * 10,
    ]
    for k in RUN_KEYS:
        r = runs[k]
        name = k if statuses[k]["completed"] else f"{k} (failed at {statuses[k]['end_time']:g} s)"
        if r is None:
            lines.append(f"| {name} |" + " n/a |" * 10)
            continue
        pk, rm = r["peak_abs_dev"], r["rms_dev"]
        lines.append(
            f"| {name} | {pk['q1']:.4f} | {pk['q2']:.4f} | {pk['q3']:.4f} | {pk['q4_deg']:.3f} | "
            f"{pk['q5_deg']:.3f} | {rm['q1']:.4f} | {rm['q2']:.4f} | {rm['q3']:.4f} | "
            f"{r['tension_min']:.3f} | {r['tension_max']:.3f} |"
        )
    lines += [
        "",
        "## Figures",
        "",
        "Simulation 1 (wind along n1): outputs and attitude (the paper's Fig. 6), tension and "
        "inputs (Fig. 7).",
        "",
        f"![Fig. 6](fig6_sim1_outputs.{figure_format})",
        "",
        f"![Fig. 7](fig7_sim1_inputs.{figure_format})",
        "",
        "Simulation 2 (wind along n2): Figs. 8 and 9.",
        "",
        f"![Fig. 8](fig8_sim2_outputs.{figure_format})",
        "",
        f"![Fig. 9](fig9_sim2_inputs.{figure_format})",
        "",
        f"Time series: `<run>.{data_format}` (SI units) with `<run>.json` (configuration, "
        "trim, version); `summary.json` holds the metrics above; `manifest.json` the full "
        "configuration.",
        "",
    ]
    return "\n".join(lines)


@figures_for_files()
def run_paper(
    out_dir: str | Path,
    *,
    dt: float = 0.01,
    pulse_duration: float = 1.0,
    command: str = "tetherheli paper",
    force: bool = False,
    data_format: str = "csv",
    figure_format: str = "png",
    progress: bool = False,
) -> dict[str, Any]:
    """Run the four simulations of Sec. VI and write the paper's outputs into ``out_dir``
    (``_io.output_directory``: refused before any run if it holds files tetherheli did not
    write, unless ``force``; those are kept). The time series are ``<run>.csv``, or
    ``<run>.parquet`` or ``<run>.mcap`` with ``data_format`` "parquet" or "mcap"
    (``results.result.RESULT_FORMATS``); the
    figures are ``figure_format`` files (png, pdf or svg); ``progress`` shows the runs done on
    stderr (``tetherheli.progress``).

    A run that fails (e.g. with a coarse ``dt``) is recorded, not raised: its status is in
    summary.json's ``statuses`` and in report.md, its reductions are None ("n/a"), and the
    figures draw it up to the failure. The caller decides the exit code (the CLI: 1).

    Parameters
    ----------
    out_dir : str or pathlib.Path
        The output directory (created if missing).
    dt : float
        Control sample time [s].
    pulse_duration : float
        Duration of the wind pulse [s].
    command : str
        The command line recorded in summary.json and report.md.
    force : bool
        Write into a directory that holds files tetherheli did not write (they are kept).
    data_format : {"csv", "parquet", "mcap"}
        Format of the time series.
    figure_format : {"png", "pdf", "svg"}
        Format of the figures.
    progress : bool
        Show the runs done on stderr.

    Returns
    -------
    dict of str to Any
        summary.json's content (``paper_summary``).
    """
    from ..progress import Progress
    from ..viz.figure import _save_figure  # the formats: checked at the entry
    from ..viz.formats import check_figure_format
    from ..viz.plots import figure_inputs, figure_outputs

    check_result_format(data_format)
    figure_format = check_figure_format(figure_format)
    claim_output_directory(out_dir, force=force)
    scenarios = {
        f"sim{sim}_{cfg}": paper_scenario(sim, cfg, pulse_duration=pulse_duration, dt=dt)
        for sim in (1, 2)
        for cfg in ("free", "tethered")
    }
    results = {}
    with Progress("paper", len(scenarios), "runs", enabled=progress) as bar:
        for k, s in scenarios.items():
            results[k] = simulate(s)
            bar.update(1)
    summary = paper_summary(results, dt=dt, pulse_duration=pulse_duration)
    with output_directory(out_dir, writer="paper", force=force) as tmp:
        for k, r in results.items():
            r._save(tmp, k, format=data_format)
        for sim, (fo, fi) in ((1, ("fig6", "fig7")), (2, ("fig8", "fig9"))):
            pair = [results[f"sim{sim}_free"], results[f"sim{sim}_tethered"]]
            axis = "n1" if sim == 1 else "n2"
            _save_figure(
                figure_outputs(
                    pair, f"Simulation {sim}: wind along {axis} (paper Fig. {6 if sim == 1 else 8})"
                ),
                tmp / f"{fo}_sim{sim}_outputs.{figure_format}",
            )
            _save_figure(
                figure_inputs(
                    pair,
                    f"Simulation {sim}: tension and inputs (paper Fig. {7 if sim == 1 else 9})",
                ),
                tmp / f"{fi}_sim{sim}_inputs.{figure_format}",
            )
        write_json(tmp / "summary.json", summary)
        write_json(tmp / "manifest.json", _manifest(command, scenarios))
        atomic_write_text(
            tmp / "report.md", _report_md(summary, command, data_format, figure_format)
        )
    return summary


def write_run(
    result: SimulationResult,
    out_dir: str | Path,
    *,
    command: str = "tetherheli simulate",
    inputs: tuple[str | Path, ...] = (),
    force: bool = False,
    data_format: str = "csv",
    figure_format: str = "png",
) -> dict[str, Any]:
    """Write one run (time series as ``data_format``, "csv", "parquet" or "mcap"; figures as
    ``figure_format`` files: png, pdf or svg; metrics, report) into ``out_dir``
    (``_io.output_directory``: the user's files there are kept, never replaced).

    Parameters
    ----------
    result : SimulationResult
        The run.
    out_dir : str or pathlib.Path
        The output directory (created if missing).
    command : str
        The command line recorded in summary.json and report.md.
    inputs : tuple of str or pathlib.Path
        Input files (scenarios) the output directory records as read.
    force : bool
        Write into a directory that holds files tetherheli did not write (they are kept).
    data_format : {"csv", "parquet", "mcap"}
        Format of the time series.
    figure_format : {"png", "pdf", "svg"}
        Format of the figures.

    Returns
    -------
    dict of str to Any
        summary.json's content: the run's name, status, message, tether release, metrics
        (``run_metrics``; empty without samples), tetherheli version and command.
    """
    from ..viz.formats import check_figure_format

    check_result_format(data_format)
    figure_format = check_figure_format(figure_format)
    return _write_run(result, out_dir, command, inputs, force, data_format, figure_format)


def _write_run(
    result: SimulationResult,
    out_dir: str | Path,
    command: str,
    inputs: tuple[str | Path, ...],
    force: bool,
    data_format: str,
    figure_format: str,
) -> dict[str, Any]:
    """``write_run`` of formats the caller checked (``tetherheli simulate``, before its runs)."""
    with output_directory(out_dir, writer="simulate", inputs=inputs, force=force) as tmp:
        return _write_run_files(result, tmp, command, data_format, figure_format)


@figures_for_files()
def _write_run_files(
    result: SimulationResult,
    directory: Path,
    command: str,
    data_format: str = "csv",
    figure_format: str = "png",
) -> dict[str, Any]:
    from ..viz.figure import _save_figure  # the formats: checked at the entry

    ext = figure_format
    directory.mkdir(exist_ok=True)
    metrics: dict[str, Any] = run_metrics(result).as_dict() if metric_samples(result) else {}
    landing = result.landing_metrics()  # a descent's headline; its hover metrics stay below
    info = {
        "name": result.name,
        "status": result.status,
        "message": result.message,
        "tether_release": result.release_info(),
        **({"landing": landing} if landing else {}),
        "metrics": metrics,
        "tetherheli_version": __version__,
        "command": command,
    }
    deck = result.deck_motion()  # over a ship: the STANAG 4154 deck-motion figures
    if deck:
        info["deck_motion"] = deck
    result._save(directory, result.name, format=data_format)
    if result.configuration.get("wind", {}).get("type") != "custom":  # else not re-runnable
        atomic_write_text(directory / SCENARIO_FILE, scenario_toml(result.configuration))
    figures = _run_figures(result) if result.time.size > 1 else {}
    for stem, draw in figures.items():
        _save_figure(draw([result], result.name), directory / f"{stem}.{ext}")
    write_json(directory / "summary.json", info)
    lines = [
        f"# {result.name}",
        "",
        f"Status: {result.message}.",
        "",
    ]
    if result.released:
        lines += [f"Event: {result.release_note()}.", ""]
    lines += [
        f"Produced by `{command}` with tetherheli {__version__}.",
        "",
    ]
    if landing:  # a descent: the touchdown's figures, not the hover's deviations
        from ..results.landing import landing_rows

        lines += ["| landing | value |", "|---|---:|"]
        lines += [f"| {k} | {v} |" for k, v in landing_rows(landing)]
        lines.append("")
    elif metrics:
        lines += ["| metric | value |", "|---|---:|"]
        for group in ("peak_abs_dev", "rms_dev"):
            for k, v in metrics[group].items():
                lines.append(f"| {group} {k} | {v:.5g} |")
        lines += [
            f"| tension min [N] | {metrics['tension_min']:.5g} |",
            f"| tension max [N] | {metrics['tension_max']:.5g} |",
            "",
        ]
    for stem in figures:
        lines += [f"![{stem}]({stem}.{ext})", ""]
    atomic_write_text(directory / "report.md", "\n".join(lines))
    return info


def _run_figures(result: SimulationResult) -> dict[str, Callable[..., Any]]:
    """A run's figures, file stem -> drawing function: a landing's figure
    (``viz.plots.figure_landing``) for a descent, else the hover's outputs and inputs
    (Figs. 6-9's layout)."""
    from ..viz.plots import figure_inputs, figure_landing, figure_outputs

    if result.landing_metrics():
        return {"landing": figure_landing}
    return {"outputs": figure_outputs, "inputs": figure_inputs}


def write_comparison(
    results: list[SimulationResult],
    out_dir: str | Path,
    *,
    command: str,
    inputs: tuple[str | Path, ...] = (),
    force: bool = False,
    data_format: str = "csv",
    figure_format: str = "png",
) -> dict[str, Any]:
    """Several runs: each in ``out_dir/<name>/`` as ``write_run`` writes it, overlaid in
    ``outputs.<figure_format>`` and ``inputs.<figure_format>`` (png, pdf or svg), with their
    metrics side by side in ``summary.json`` and ``report.md``.

    Parameters
    ----------
    results : list of SimulationResult
        The runs, with distinct scenario names.
    out_dir, command, inputs, force, data_format, figure_format
        As for ``write_run``.

    Returns
    -------
    dict of str to Any
        summary.json's content: version, command and every run's ``write_run`` summary.
    """
    from ..viz.formats import check_figure_format

    check_result_format(data_format)
    figure_format = check_figure_format(figure_format)
    check_distinct_names(r.name for r in results)  # each run its own folder
    return _write_comparison(results, out_dir, command, inputs, force, data_format, figure_format)


@figures_for_files()
def _write_comparison(
    results: list[SimulationResult],
    out_dir: str | Path,
    command: str,
    inputs: tuple[str | Path, ...],
    force: bool,
    data_format: str,
    ext: str,
) -> dict[str, Any]:
    """``write_comparison`` of formats the caller checked (``tetherheli simulate``, before its
    runs) and of runs with distinct names."""
    from ..viz.figure import _save_figure

    with output_directory(out_dir, writer="simulate", inputs=inputs, force=force) as tmp:
        infos = {
            r.name: _write_run_files(r, tmp / r.name, command, data_format, ext) for r in results
        }
        plotted = [r for r in results if r.time.size > 1]
        figures: dict[str, list[SimulationResult]] = {}  # landings and hovers apart
        for r in plotted:
            for stem in _run_figures(r):
                figures.setdefault(stem, []).append(r)
        if plotted:
            title = " vs ".join(r.name for r in plotted)
            for stem, runs in figures.items():
                draw = _run_figures(runs[0])[stem]
                _save_figure(draw(runs, " vs ".join(r.name for r in runs)), tmp / f"{stem}.{ext}")
        summary = {"tetherheli_version": __version__, "command": command, "runs": infos}
        write_json(tmp / "summary.json", summary)
        lines = [f"# {title if plotted else 'comparison'}", "", f"Produced by `{command}`.", ""]
        lines += ["| metric | " + " | ".join(infos) + " |"]
        lines += ["|---|" + "---:|" * len(infos)]
        rows: list[tuple[str, Callable[..., str]]] = [("status", lambda i: i["message"])]
        for group in ("peak_abs_dev", "rms_dev"):
            for k in POSITION:
                rows.append(
                    (f"{group} {k} [m]", lambda i, g=group, k=k: f"{i['metrics'][g][k]:.4g}")
                )
        for name, get in rows:  # a landing's hover deviations are not its figures
            cells = [
                get(i) if name == "status" or (i["metrics"] and "landing" not in i) else "-"
                for i in infos.values()
            ]
            lines.append(f"| {name} | " + " | ".join(cells) + " |")
        landings = [i.get("landing") for i in infos.values()]
        for key in _COMPARED_LANDING if any(landings) else ():
            cells = [_fmt(m.get(key), ".4g") if m else "-" for m in landings]
            lines.append(f"| {key} | " + " | ".join(cells) + " |")
        for stem in figures:
            lines += ["", f"![{stem}]({stem}.{ext})"]
        atomic_write_text(tmp / "report.md", "\n".join(lines) + "\n")
    return summary


#: a comparison's rows of the landings' figures (``results.landing.landing_metrics``)
_COMPARED_LANDING = (
    "touchdown_time",
    "touchdown_vertical_speed",
    "touchdown_horizontal_speed",
    "touchdown_offset",
    "touchdown_attitude_deg",
    "touchdown_tension",
)


#: the GNSS outage of the shipped sensing runs with one [s]: 20 s in the sine phase
SENSING_OUTAGE = (30.0, 50.0)
#: the shipped sensing runs: name suffix -> (controller's position source, GNSS outage)
SENSING_RUNS = {
    "gps": ("gps", ()),
    "tether": ("tether", ()),
    "gps_outage": ("gps", SENSING_OUTAGE),
    "tether_outage": ("tether", SENSING_OUTAGE),
}


def sensing_scenario(source: str) -> Scenario:
    """Paper simulation 1, tethered, seed 1, with the sensors as they are flown
    (``SensorConfig.flown``: consumer GNSS, MEMS IMU, laser altimeter, joint encoders, load
    cell) and the controller's position from the GNSS or the tether; ``source`` is a key of
    ``SENSING_RUNS`` ("gps", "tether", and both with a 20 s GNSS outage).

    Parameters
    ----------
    source : str
        A key of ``SENSING_RUNS``.

    Returns
    -------
    Scenario
        The scenario, named ``sensing_<source>``.
    """
    from ..sensing.config import SensorConfig

    if source not in SENSING_RUNS:
        raise ParameterError("source", source, f"one of {sorted(SENSING_RUNS)}")
    position, outage = SENSING_RUNS[source]
    base = paper_scenario(1, "tethered")
    label = (
        "a consumer GNSS"
        if position == "gps"
        else "the tether (encoders + altimeter + IMU, Sec. IV-F)"
    )
    lost = f", GNSS lost {outage[0]:g}-{outage[1]:g} s" if outage else ""
    control = base.control
    if position == "gps":  # the MPC's weights when it flies these files (MPC_QY_GNSS)
        control = dataclasses.replace(control, mpc=dataclasses.replace(control.mpc, Qy=MPC_QY_GNSS))
    return base.replace(
        name=f"sensing_{source}",
        sensors=SensorConfig.flown(position, gps_outage=outage),
        seed=1,
        description=f"Paper simulation 1, tethered, position from {label}{lost}.",
        control=control,
    )


@figures_for_files()
def run_sensing(
    out_dir: str | Path,
    *,
    scenarios: tuple[str | Path, ...] | None = None,
    command: str = "tetherheli sensing",
    force: bool = False,
    figure_format: str = "png",
    data_format: str = "csv",
) -> dict[str, Any]:
    """The tether as a GPS-free position sensor (Sec. IV-F): fly the shipped
    ``sensing_*`` scenarios (``SENSING_RUNS``, or the given ones), compare the controller's
    position-estimate error and the true deviation from trim, and run the Kalman filter
    (``studies.estimation.estimate_run``) fusing the IMU with the GNSS, the tether or both on each
    run's recorded sensors (its error RMS over the run and, with a GNSS outage, over it).

    A failed run is recorded, not raised: its row holds its status (``run_status``), its
    RMS figures cover the samples up to the failure (None without samples), and the plot
    draws it up to the failure (``sensing.<figure_format>``: png, pdf or svg). The caller
    decides the exit code (the CLI: 1).

    Parameters
    ----------
    out_dir : str or pathlib.Path
        The output directory (created if missing).
    scenarios : tuple of str or pathlib.Path, optional
        Scenario files to fly instead of the shipped ``sensing_*`` ones.
    command : str
        The command line recorded in summary.json and report.md.
    force : bool
        Write into a directory that holds files tetherheli did not write (they are kept).
    figure_format : {"png", "pdf", "svg"}
        Format of the figures.
    data_format : {"csv", "parquet"}
        Format of the time series (``results.result.RESULT_FORMATS``, default "csv").

    Returns
    -------
    dict of str to dict
        Per run name: its status (``run_status``), GNSS outage, position-estimate error RMS
        and true deviation RMS along n1, n2, n3 [m], and the Kalman filters' error RMS and
        final 1-sigma [m].
    """
    from ..scenario import load_scenario
    from ..sensing.estimation import FUSIONS
    from ..studies.estimation import estimate_run
    from ..viz.figure import _save_figure  # the formats: checked at the entry
    from ..viz.formats import check_figure_format
    from ..viz.plots import figure_sensing

    figure_format = check_figure_format(figure_format)
    check_result_format(data_format)
    claim_output_directory(out_dir, inputs=scenarios or (), force=force)
    if scenarios:
        runs = [load_scenario(p) for p in scenarios]
    else:  # the shipped scenarios/sensing_*.toml, built here (a test checks equality)
        runs = [sensing_scenario(key) for key in SENSING_RUNS]
    check_distinct_names(s.name for s in runs)  # each run its own files
    for s in runs:
        if s.sensors.is_perfect:
            raise ParameterError("sensors", s.name, "a scenario with noisy sensors ([sensors])")
    results = {s.name: simulate(s) for s in runs}
    estimates: dict[str, dict[str, Any]] = {}
    table: dict[str, Any] = {}

    def rms(a: np.ndarray) -> dict[str, float] | None:
        if not a.shape[0]:
            return None
        return dict(zip(POSITION, np.sqrt(np.mean(a**2, axis=0)).tolist(), strict=True))

    for s in runs:
        r = results[s.name]
        est = np.column_stack([r.extra[f"q{i}_est"] for i in (1, 2, 3)])
        err = est - r.outputs[:, :3]
        dev = r.outputs[:, :3] - r.trim_output[:3]
        outage = list(s.sensors.gps_outage) or None
        fusions = FUSIONS if s.configuration == "tethered" else ("gnss",)
        estimates[s.name] = {f: estimate_run(r, s, f) for f in fusions} if r.time.size else {}
        table[s.name] = {
            "position_source": s.sensors.position_source,
            **run_status(r),
            "gps_outage": outage,
            # over the recorded samples: up to the failure for a failed run
            "estimate_error_rms": rms(err),
            "true_deviation_rms": rms(dev),
            "kalman_error_rms": {f: e.error_rms() for f, e in estimates[s.name].items()},
            # the filter's own 1-sigma at the last sample: what it expects its error to be
            "kalman_final_std": {f: rms(e.position_std[-1:]) for f, e in estimates[s.name].items()},
            "kalman_error_rms_outage": (
                {f: e.error_rms(outage) for f, e in estimates[s.name].items()} if outage else None
            ),
        }
    fig = figure_sensing(results, estimates)
    with output_directory(out_dir, writer="sensing", inputs=scenarios or (), force=force) as tmp:
        for name, r in results.items():
            r._save(tmp, name, format=data_format)
        _save_figure(fig, tmp / f"sensing.{figure_format}")
        info = {
            "tetherheli_version": __version__,
            "command": command,
            "failed": [name for name, r in results.items() if not r.ok],
            "runs": table,
        }
        write_json(tmp / "summary.json", info)
    return table
