"""The tether study's output folder (``tetherheli tether-study``): the study
(``studies.tether_study``) returns a ``TetherStudy``; this writes its tables (Markdown and
CSV), its page study.md, its figures (``viz.tether_study``) and its summary."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from .._io import atomic_write_text, claim_output_directory, output_directory, write_json
from .._version import __version__
from ..names import METRIC_UNITS
from ..results.files import _write_table, check_result_format
from ..studies.tether_cables import STUDY_CABLES, StudyCable
from ..studies.tether_study import (
    DEFAULT_ELEVATIONS_DEG,
    DEFAULT_LENGTHS_M,
    DEFAULT_WINDS_M_S,
    TetherStudy,
    TetherStudyConfig,
    tether_study,
)
from ..viz.formats import figures_for_files

__all__ = ["run_tether_study", "sensing_table", "study_table", "write_tether_study"]


def run_tether_study(
    out: str,
    *,
    cables: Sequence[StudyCable] = STUDY_CABLES,
    lengths_m: Sequence[float] = DEFAULT_LENGTHS_M,
    winds_m_s: Sequence[float] = DEFAULT_WINDS_M_S,
    elevations_deg: Sequence[float] = DEFAULT_ELEVATIONS_DEG,
    model: str = "lumped",
    winch_gain: str = "paper",
    duration_s: float | None = None,
    max_thrust_N: float | None = None,
    workers: int | None = None,
    command: str = "",
    force: bool = False,
    progress: bool = True,
    figure_format: str = "png",
    data_format: str = "csv",
) -> dict[str, Any]:
    """Run the whole study (``studies.tether_study.tether_study``) and write it to ``out``
    (``write_tether_study``); the choices and ``out`` are checked before any work.

    Parameters
    ----------
    out : str
        The output folder.
    cables, lengths_m, winds_m_s, elevations_deg, model, winch_gain, duration_s, max_thrust_N
        The study's choices (``studies.tether_study.TetherStudyConfig``, with its defaults):
        the cables, hover heights q9 [m], the sensing half's steady winds [m/s] and
        elevations of P [deg], the dynamic half's tether model, winch gains and run length
        [s], the maximum fMR3 [N].
    workers : int, optional
        ``run_batch``'s threads.
    progress : bool, optional
        Progress on stderr.
    command, force, figure_format, data_format
        As for ``write_tether_study``.

    Returns
    -------
    dict
        The summary written to summary.json.
    """
    from ..viz.formats import check_figure_format

    config = TetherStudyConfig(
        cables=tuple(cables),
        lengths_m=tuple(lengths_m),
        winds_m_s=tuple(winds_m_s),
        elevations_deg=tuple(elevations_deg),
        model=model,
        winch_gain=winch_gain,
        duration_s=duration_s,
        max_thrust_N=max_thrust_N,
    )
    figure_format = check_figure_format(figure_format)
    data_format = check_result_format(data_format)
    claim_output_directory(out, force=force)
    result = tether_study(config, workers=workers, progress=progress)
    return _write(
        result, out, command=command, force=force, figure_format=figure_format,
        data_format=data_format,
    )  # fmt: skip


def write_tether_study(
    result: TetherStudy,
    out: str | Path,
    *,
    command: str = "",
    force: bool = False,
    figure_format: str = "png",
    data_format: str = "csv",
) -> dict[str, Any]:
    """Write the study to ``out``, whole or not at all (``_io.output_directory``): study.md
    (the main table and the hover limits), static, dynamic and sensing tables as
    ``<table>.<data_format>`` (csv or parquet, ``results.files.write_table``), sensing.md,
    reduction.png, static.png, sensing.png and summary.json (every row, the cables, the grids
    and every run's configuration).

    Parameters
    ----------
    result : TetherStudy
        The study.
    out : str or Path
        The output folder.
    command : str, optional
        The command line, recorded in summary.json.
    force : bool, optional
        Replace this command's earlier output in ``out``.
    figure_format : {"png", "pdf", "svg"}, optional
        File format of the three figures (default "png").
    data_format : {"csv", "parquet"}, optional
        File format of the three tables (default "csv"; Parquet with each column's unit in
        its Arrow field's metadata where the column's name gives it).

    Returns
    -------
    dict
        The summary written to summary.json.
    """
    from ..viz.formats import check_figure_format

    figure_format = check_figure_format(figure_format)
    data_format = check_result_format(data_format)
    return _write(
        result, out, command=command, force=force, figure_format=figure_format,
        data_format=data_format,
    )  # fmt: skip


@figures_for_files()
def _write(
    result: TetherStudy,
    out: str | Path,
    *,
    command: str,
    force: bool,
    figure_format: str,
    data_format: str = "csv",
) -> dict[str, Any]:
    """``write_tether_study`` with ``figure_format`` and ``data_format`` checked."""
    from ..viz.figure import _save_figure
    from ..viz.tether_study import (
        figure_study_reduction,
        figure_study_sensing,
        figure_study_static,
    )

    summary = {"command": command, "tetherheli_version": __version__, **result.as_dict()}
    labels = result.labels
    figures = {
        f"reduction.{figure_format}": figure_study_reduction(result.dynamic, labels),
        f"static.{figure_format}": figure_study_static(result.static, labels, result.max_thrust_N),
        f"sensing.{figure_format}": figure_study_sensing(result.sensing, labels),
    }
    with output_directory(out, writer="tether-study", force=force) as tmp:
        for name, fig in figures.items():
            _save_figure(fig, tmp / name)
        atomic_write_text(tmp / "study.md", _study_page(result))
        for name in ("static", "dynamic", "sensing"):
            _table(tmp / f"{name}.{data_format}", getattr(result, name))
        atomic_write_text(tmp / "sensing.md", sensing_table(result.sensing))
        write_json(tmp / "summary.json", summary, indent=1)
    return summary


def _study_page(result: TetherStudy) -> str:
    """study.md: the main table (``study_table``) and the hover limits."""
    c = result.config
    return (
        f"# Tether study ({c.model} tether, {c.winch_gain} winch gains in the dynamic runs)\n\n"
        + study_table(result.static, result.dynamic)
        + "\nHover limits (25 N at P: the ground tension reaches 0; 25 N at the winch: fMR3 "
        f"reaches {result.max_thrust_N:.2f} N):\n\n| cable | max q9, 25 N at P [m] "
        "| max q9, 25 N at winch [m] |\n|---|---:|---:|\n"
        + "".join(
            f"| {r['cable']} | {r['max_length_top_tension_m']:.1f} "
            f"| {_f(r['max_length_thrust_m'], '.1f')} |\n"
            for r in result.hover_limits
        )
    )


#: The units of the study's columns named by suffix (``lift_margin_N``, ``k_lateral_N_m``,
#: ``wind_m_s``, ...), longest suffix first.
_SUFFIX_UNITS = (
    ("_reduction_pct", "%"), ("_N_m", "N/m"), ("_m_s", "m/s"), ("_Nm", "N m"),
    ("_deg", "deg"), ("_N", "N"), ("_m", "m"), ("_s", "s"),
)  # fmt: skip
#: The sensing half's horizontal position errors of each estimate [m] (``tether_sensing``).
_SENSING_ERRORS = ("ivf", "catenary_wind_known", "catenary_wind_ignored", "catenary_wind_1ms")


def _unit(column: str) -> str | None:
    """A study column's unit: by its suffix, a sensing error's (m), or the metric's of a
    dynamic column ``<case>_<metric>_<free|tethered>``; None where the name does not say."""
    if column in _SENSING_ERRORS:
        return "m"
    for suffix, unit in _SUFFIX_UNITS:
        if column.endswith(suffix):
            return unit
    for metric, unit in METRIC_UNITS.items():
        if column.endswith((f"_{metric}_free", f"_{metric}_tethered")):
            return unit
    return None


def _table(path: Path, rows: Sequence[dict[str, Any]]) -> None:
    """One of the study's tables (``write_table``, its format checked by the writer's
    entry): a column per key of the first row."""
    columns = list(rows[0]) if rows else []
    units = {c: u for c in columns if (u := _unit(c)) is not None}
    _write_table(path, columns, [[r.get(c, "") for c in columns] for r in rows], units=units)


def _f(x: Any, spec: str) -> str:
    return "-" if x is None or (isinstance(x, float) and not math.isfinite(x)) else format(x, spec)


def study_table(static: Sequence[dict[str, Any]], dynamic: Sequence[dict[str, Any]]) -> str:
    """The study's main table (Markdown): per cable and length the ground tension for 25 N at
    P, the extra thrust and margin with 25 N at the winch, the lateral stiffness, and the
    reductions [%] of peak q1 (sim 1), peak q2 (sim 2) and RMS q1 (turbulence).

    Parameters
    ----------
    static, dynamic : sequence of dict
        ``static_rows`` and ``dynamic_rows`` on the same cables and lengths.

    Returns
    -------
    str
    """
    dyn = {(r["cable"], r["length_m"]): r for r in dynamic}
    head = (
        "| cable | q9 [m] | T_ground for 25 N at P [N] | T_P with 25 N at winch [N] "
        "| extra fMR3 [N] | thrust margin [N] | k_lat [N/m] (massless) "
        "| sim 1 peak q1 [%] | sim 2 peak q2 [%] | turbulence RMS q1 [%] |\n"
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n"
    )
    lines = []
    for r in static:
        d = dyn.get((r["cable"], r["length_m"]), {})
        lines.append(
            f"| {r['cable']} | {r['length_m']:g} | {_f(r['ground_tension_for_top_N'], '.2f')} "
            f"| {r['top_tension_N']:.2f} | {r['extra_lift_N']:.2f} | {r['lift_margin_N']:.2f} "
            f"| {r['k_lateral_N_m']:.3f} ({r['k_lateral_massless_N_m']:.3f}) "
            f"| {_f(d.get('sim1_peak_q1_reduction_pct'), '.1f')} "
            f"| {_f(d.get('sim2_peak_q2_reduction_pct'), '.1f')} "
            f"| {_f(d.get('turbulence_rms_q1_reduction_pct'), '.1f')} |"
        )
    return head + "\n".join(lines) + "\n"


def sensing_table(rows: Sequence[dict[str, Any]]) -> str:
    """The sensing half as a Markdown table: horizontal errors [m] of each estimate.

    Parameters
    ----------
    rows : sequence of dict
        ``tether_sensing.sensing_study``'s rows.

    Returns
    -------
    str
    """
    from ..studies.tether_sensing import ESTIMATES

    head = (
        "| cable | elevation [deg] | length [m] | wind [m/s] | winch-tangent angle [deg] | "
        + " | ".join(ESTIMATES)
        + " |\n|"
        + "---|" * (5 + len(ESTIMATES))
        + "\n"
    )
    lines = []
    for r in rows:
        if r["status"] != "ok":
            lines.append(
                f"| {r['cable']} | {r['elevation_deg']:g} | {r['length_m']:g} "
                f"| {r['wind_m_s']:g} | {r['status']} |" + " |" * len(ESTIMATES)
            )
            continue
        cells = " | ".join(f"{r[e]:.3f}" for e in ESTIMATES)
        lines.append(
            f"| {r['cable']} | {r['elevation_deg']:g} | {r['length_m']:g} | {r['wind_m_s']:g} "
            f"| {r['ground_angle_deg']:.2f} | {cells} |"
        )
    return head + "\n".join(lines) + "\n"
