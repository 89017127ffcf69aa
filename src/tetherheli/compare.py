"""Scenarios flown by several controllers, one table and one figure
(the command: ``tetherheli compare``, ``cli/compare.py``).

Each tethered scenario is flown once per controller (``[control] controller``, the weights of
its ``[control.tether_lqi]``); a free scenario is flown once (every controller flies the
paper's free law there), as the reference the tether is judged against. ``--eq40`` applies
eq 40's cyclic limit as saturation of tMR1, tMR2 (``controllers.eq40_saturated``). The
measures are ``controllers.CONTROLLER_METRICS``; the compute time is that of a second,
identical run (the first one compiles).

``--montecarlo FILE --runs N`` adds a Monte Carlo with plant dispersion (``studies.robust``):
the first N draws of FILE flown free and under every controller, all designed on the nominal
parameters; the table gets the median (p50) and 95th percentile (p95) of every measure,
failures in the failing tail and counted, and compare_montecarlo.md the paired reduction
against the free helicopter (median and 5th percentile over the draws).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from .control.registry import controller_entry
from .viz.formats import figures_for_files

__all__ = ["COLUMN_UNITS", "compare", "markdown_reductions", "write_compare"]


def _column_units() -> dict[str, str]:
    from .names import INPUT, INPUT_UNITS

    return {
        **{f"{k}_q{a}": "m" for k in ("peak", "rms") for a in (1, 2, 3)},
        "peak_attitude_deg": "deg",
        **{
            f"{k}_d{n}": u for k in ("rms", "peak") for n, u in zip(INPUT, INPUT_UNITS, strict=True)
        },
        "peak_cyclic": "N m",
        "cyclic_limit": "N m",
        "tension_min": "N",
        "tension_max": "N",
        "compute_us_per_sample": "us",
    }


#: The unit of each measure of the table (``controllers.CONTROLLER_METRICS``); the paired
#: reductions are in %.
COLUMN_UNITS: dict[str, str] = _column_units()


def compare(
    paths: list[str],
    controllers: tuple[str, ...],
    *,
    eq40: bool,
    workers: int | None = 1,
) -> list[dict[str, Any]]:
    """One row per (scenario, controller): ``scenario``, ``configuration``, ``controller``,
    ``status`` and ``controllers.CONTROLLER_METRICS``.

    Each run is flown twice and the second timed (the first compiles what it needs). A scenario
    is flown by those of ``controllers`` that fly its configuration (``control.registry``; a
    free one by the paper's alone when none of them does). With ``workers`` > 1 the runs fly
    side by side (``studies.robust.run_threads``): the same measures, but each compute time is
    taken with the other runs in flight.

    Parameters
    ----------
    paths : list of str
        Scenario TOML files.
    controllers : tuple of str
        Controller names (``studies.controllers.with_controller``), e.g. ``("paper",
        "tether_lqi")``.
    eq40 : bool
        Saturate tMR1, tMR2 at eq 40's cyclic limit (``eq40_saturated``).
    workers : int, optional
        Threads flying the runs (default 1: one after the other; None: the CPUs available).

    Returns
    -------
    list of dict of str to object
        One row per (scenario, controller); a run that could not be set up has its error's
        first line as ``status`` and ``completed`` False.
    """
    from .errors import TetherheliError, WeightsError, named_source
    from .scenario import load_scenario
    from .studies.controllers import check_design, eq40_saturated, fly, with_controller
    from .studies.robust import run_threads, thread_count

    runs: list[tuple[Any, str]] = []  # (scenario, controller) in table order
    for path in paths:
        base = load_scenario(path)
        if eq40:
            base = eq40_saturated(base)
        names = tuple(  # the controllers that fly this configuration (control.registry)
            n for n in controllers if base.configuration in controller_entry(n).configurations
        ) or ("paper",)
        for name in names:  # weights without a design are the file's error: refused, named
            named_source(path, check_design, with_controller(base, name))
        runs.extend((base, name) for name in names)
    rows: list[dict[str, Any]] = [{} for _ in runs]

    def fly_one(i: int) -> None:  # row i only
        base, name = runs[i]
        row: dict[str, Any] = {
            "scenario": base.name,
            "configuration": base.configuration,
            "controller": name,
        }
        try:
            scenario = with_controller(base, name)
            fly(scenario)  # a first run compiles what it needs: not part of the time
            result, metrics = fly(scenario)
            row["status"] = result.message
            row.update(metrics)
        except WeightsError:
            raise
        except TetherheliError as exc:
            row["status"] = str(exc).splitlines()[0]
            row["completed"] = False
        row["runs"] = 1
        row["failures"] = 0 if row["completed"] else 1
        rows[i] = row

    longest = max(runs, key=lambda r: r[0].n_samples, default=None)
    threads = thread_count(workers, len(runs), longest[0] if longest else None)
    run_threads(fly_one, len(runs), threads)
    return rows


@figures_for_files()
def write_compare(
    rows: list[dict[str, Any]],
    out_dir: str | Path,
    *,
    command: str,
    inputs: tuple[str, ...],
    force: bool = False,
    montecarlo: tuple[Any, ...] = (),
    figure_format: str = "png",
    data_format: str = "csv",
) -> None:
    """compare.csv or compare.parquet (every measure, ``data_format``; ``write_table``, units
    in the Parquet fields' metadata), compare.md (the main columns), compare.png and
    summary.json, written whole or not at all (``_io.output_directory``); with Monte Carlo
    comparisons also compare_montecarlo.md (the paired reductions), compare_montecarlo.png
    (``viz.study_figures.figure_compare_spread``) and their per-draw values in summary.json.
    The figures are drawn by ``viz.study_figures`` (compare.png: ``figure_compare``).

    Parameters
    ----------
    rows : list of dict of str to object
        ``compare``'s rows.
    out_dir : str or Path
        The output folder.
    command : str
        The command line, recorded in summary.json.
    inputs : tuple of str
        The input files, recorded with the folder's marker.
    force : bool, optional
        Replace this command's earlier output in ``out_dir`` (default False).
    montecarlo : tuple of MonteCarloComparison, optional
        The Monte Carlo comparisons (``studies.robust.montecarlo_compare``) whose rows are
        in ``rows``.
    figure_format : {"png", "pdf", "svg"}, optional
        File format of the figures (default "png").
    data_format : {"csv", "parquet"}, optional
        File format of the table (default "csv").

    Returns
    -------
    None
    """
    from . import __version__
    from ._io import atomic_write_text, output_directory, write_json
    from .results.files import _write_table, check_result_format
    from .studies.controllers import CONTROLLER_METRICS
    from .studies.robust import REDUCED
    from .viz.figure import _save_figure
    from .viz.formats import check_figure_format
    from .viz.plots import figure_compare, figure_compare_spread

    reductions = [f"reduction_{m}_{p}" for m in REDUCED for p in ("p50", "p5")]
    columns = [
        "scenario", "configuration", "controller", "status", "runs", "failures",
        *CONTROLLER_METRICS, *(reductions if montecarlo else ()),
    ]  # fmt: skip
    data_format = check_result_format(data_format)
    figure_format = check_figure_format(figure_format)
    table = [[r.get(c, "") for c in columns] for r in rows]
    units = {c: u for c in columns if (u := COLUMN_UNITS.get(c)) is not None}
    units.update({c: "%" for c in reductions if c in columns})
    # drawn by viz (``viz.figure.new_figure``: the backend left alone)
    fig = figure_compare([r for r in rows if r.get("runs", 1) == 1] or rows)
    fig_mc = figure_compare_spread(_spreads(montecarlo)) if montecarlo else None
    with output_directory(out_dir, writer="compare", inputs=inputs, force=force) as tmp:
        _save_figure(fig, tmp / f"compare.{figure_format}")
        _write_table(tmp / f"compare.{data_format}", columns, table, units=units)
        atomic_write_text(tmp / "compare.md", markdown_table(rows))
        info = {
            "rows": [{k: _json_number(v) for k, v in r.items()} for r in rows],
            "tetherheli_version": __version__,
            "command": command,
        }
        if montecarlo:
            assert fig_mc is not None  # drawn above when there is a Monte Carlo
            _save_figure(fig_mc, tmp / f"compare_montecarlo.{figure_format}")
            atomic_write_text(tmp / "compare_montecarlo.md", markdown_reductions(montecarlo))
            info["montecarlo"] = [mc.as_dict() for mc in montecarlo]
        write_json(tmp / "summary.json", info)


def _json_number(v: Any) -> Any:
    """+-inf (a percentile among failures) and NaN as null in JSON."""
    return None if isinstance(v, float) and not math.isfinite(v) else v


def markdown_reductions(montecarlo: tuple[Any, ...]) -> str:
    """The paired reduction of the deviations against the free helicopter per controller
    (``MonteCarloComparison.reduction``): median and 5th percentile over the draws [%],
    failures as -inf; and the failure counts.

    Parameters
    ----------
    montecarlo : tuple of MonteCarloComparison
        The Monte Carlo comparisons.

    Returns
    -------
    str
        A Markdown table.
    """
    from .studies.robust import FREE, REDUCED

    head = "| Monte Carlo | controller | failed (free) | failed |"
    head += "".join(f" {m} red. p50 / p5 [%] |" for m in REDUCED) + "\n"
    head += "|" + "---|" * (4 + len(REDUCED)) + "\n"
    lines = []
    for mc in montecarlo:
        for lab in mc.labels:
            if lab == FREE:
                continue
            cells = [
                f"{mc.scenario_name} (N={mc.runs})",
                lab,
                f"{mc.failures(FREE)}/{mc.runs}",
                f"{mc.failures(lab)}/{mc.runs} ({100.0 * mc.failures(lab) / mc.runs:.1f}%)",
            ]
            for m in REDUCED:
                r50, r5 = mc.reduction_percentiles(lab, m)
                cells.append(" / ".join("n/a" if math.isnan(v) else f"{v:.1f}" for v in (r50, r5)))
            lines.append("| " + " | ".join(cells) + " |")
    return head + "\n".join(lines) + "\n"


def _spreads(montecarlo: tuple[Any, ...]) -> list[Any]:
    """The Monte Carlo comparisons as ``compare_montecarlo.png`` draws them
    (``viz.study_figures.ControllerSpread``): per run kind its failures and the completed
    draws' peak and RMS q1."""
    from .viz.plots import ControllerSpread

    return [
        ControllerSpread(
            scenario_name=mc.scenario_name,
            runs=mc.runs,
            labels=tuple(mc.labels),
            failures={lab: mc.failures(lab) for lab in mc.labels},
            completed={
                lab: {m: mc.values[lab][m][mc.ok[lab]] for m in ("peak_q1", "rms_q1")}
                for lab in mc.labels
            },
        )
        for mc in montecarlo
    ]


#: The columns of ``markdown_table``.
_MD_COLUMNS = 17


def markdown_table(rows: list[dict[str, Any]]) -> str:
    """The comparison's main columns as a Markdown table (lengths [m], attitude [deg],
    efforts [N, N m, N m, N], tension [N], failed runs out of those flown, compute time [us]).
    A Monte Carlo's rows are percentiles over its draws ("inf": among the failures).

    Parameters
    ----------
    rows : list of dict
        The comparison's rows, one per scenario and controller (``compare``'s): "scenario",
        "controller", "configuration", the metrics ("peak_q1", "rms_dfMR3", ...,
        "compute_us_per_sample") and "completed" or "failures" and "runs"; a row without
        metrics (no run completed) shows its name and failures only.

    Returns
    -------
    str
        The Markdown table, one line per row, ending in a newline.
    """
    head = (
        "| scenario | controller | peak q1 | peak q2 | peak q3 | RMS q1 | RMS q2 | RMS q3 "
        "| peak att. | RMS dfMR3 | RMS dtMR1 | RMS dtMR2 | RMS dfTR2 | peak cyclic / limit "
        "| tension | failed | us/sample |\n"
    )
    head += "|" + "---|" * _MD_COLUMNS + "\n"
    lines = []
    for r in rows:
        failed = f"{r.get('failures', 0 if r.get('completed') else 1)}/{r.get('runs', 1)}"
        if "peak_q1" not in r:
            cells = [r["scenario"], r["controller"], *([""] * (_MD_COLUMNS - 4)), failed, ""]
            lines.append("| " + " | ".join(cells) + " |")
            continue
        lim = r["cyclic_limit"]
        cyc = f"{r['peak_cyclic']:.2f} / {lim:.2f}" if lim == lim else f"{r['peak_cyclic']:.2f}"
        tension = (
            f"{r['tension_min']:.1f}-{r['tension_max']:.1f}"
            if r["configuration"] == "tethered"
            else "-"
        )
        cells = [
            r["scenario"], r["controller"],
            *(f"{r[k]:.3f}" for k in ("peak_q1", "peak_q2", "peak_q3", "rms_q1", "rms_q2",
                                      "rms_q3")),
            f"{r['peak_attitude_deg']:.2f}",
            *(f"{r[k]:.3f}" for k in ("rms_dfMR3", "rms_dtMR1", "rms_dtMR2", "rms_dfTR2")),
            cyc, tension, failed,
            f"{r['compute_us_per_sample']:.1f}",
        ]  # fmt: skip
        lines.append("| " + " | ".join(cells) + " |")
    return head + "\n".join(lines) + "\n"
