"""A parameter sweep's output folder (``tetherheli sweep``): the study (``studies.sweep``)
returns a ``SweepResult``; this writes its table, its figure (``viz.plots.figure_sweep``) and
its summary."""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .._io import output_directory, write_json
from .._version import __version__
from ..names import METRIC_UNITS
from ..results.files import _write_table, check_result_format
from ..studies.sweep import SweepResult, parameter_label
from ..viz.figure import _save_figure
from ..viz.formats import check_figure_format, figures_for_files
from ..viz.plots import figure_sweep

__all__ = ["write_sweep", "write_sweep_folder"]


def write_sweep(
    result: SweepResult,
    out_dir: str | Path,
    *,
    command: str,
    inputs: tuple[str | Path, ...] = (),
    force: bool = False,
    figure_format: str = "png",
    data_format: str = "csv",
) -> None:
    """Table (``sweep.<data_format>``: csv or parquet), plot (``sweep.<figure_format>``: png,
    pdf or svg) and summary.json of a sweep, written whole or not at all
    (``_io.output_directory``: the user's files in ``out_dir`` are kept, never replaced).

    Parameters
    ----------
    result : SweepResult
        The sweep.
    out_dir : str or Path
        The output folder.
    command : str
        The command line, recorded in summary.json.
    inputs : tuple of str or Path, optional
        The input files, recorded with the folder's marker.
    force : bool, optional
        Replace this command's earlier output (default False).
    figure_format : str, optional
        "png" (default), "pdf" or "svg".
    data_format : str, optional
        "csv" (default) or "parquet" (``results.files.write_table``, units in the Arrow
        fields' metadata).

    Returns
    -------
    None
    """
    nan = np.full(result.values.size, np.nan)
    moment = nan if result.peak_tether_moment is None else result.peak_tether_moment
    angle = nan if result.peak_tether_angle_deg is None else result.peak_tether_angle_deg
    worst = nan if result.peak_worst_case_moment is None else result.peak_worst_case_moment
    header = (
        "value",
        "metric",
        "status",
        "peak_tether_moment_Nm",
        "peak_tether_angle_deg",
        "eq40_worst_case_moment_Nm",
    )
    rows = [
        [repr(row[0]), repr(row[1]), row[2], *(repr(v) for v in row[3:])]
        for row in zip(
            result.values.tolist(),
            result.metric.tolist(),
            result.statuses,
            moment.tolist(),
            angle.tolist(),
            worst.tolist(),
            strict=True,
        )
    ]
    write_sweep_folder(
        out_dir,
        draw=lambda: figure_sweep(result),
        header=header,
        rows=rows,
        summary=result.as_dict(),
        command=command,
        inputs=inputs,
        force=force,
        figure_format=figure_format,
        data_format=data_format,
        units={
            "value": _label_unit(parameter_label(result.parameter)),
            "metric": METRIC_UNITS.get(result.metric_name, ""),
            "peak_tether_moment_Nm": "N m",
            "peak_tether_angle_deg": "deg",
            "eq40_worst_case_moment_Nm": "N m",
        },
    )


def _label_unit(label: str) -> str:
    """The unit of an axis label "name [unit]" ("" without one)."""
    found = re.search(r"\[([^\]]*)\]\s*$", label)
    return found.group(1) if found else ""


@figures_for_files()
def write_sweep_folder(
    out_dir: str | Path,
    *,
    draw: Callable[[], Any],
    header: Sequence[str],
    rows: Iterable[Sequence[str]],
    summary: dict[str, Any],
    command: str,
    inputs: tuple[str | Path, ...] = (),
    force: bool = False,
    figure_format: str = "png",
    data_format: str = "csv",
    units: dict[str, str] | None = None,
) -> None:
    """A sweep's folder, written whole or not at all (``_io.output_directory``: the user's
    files in ``out_dir`` are kept, never replaced): ``sweep.<figure_format>``,
    ``sweep.<data_format>`` (``header``, then ``rows``) and ``summary.json`` (``summary``
    with the version and the command). The one writer of ``write_sweep`` and
    ``cyclic_limit.write_limit_search``.

    Parameters
    ----------
    out_dir : str or Path
        The output folder.
    draw : callable
        Returns the figure; called once the format is checked, before anything is written.
    header : sequence of str
        The CSV's column names.
    rows : iterable of sequences of str
        The table's rows, each value already text (floats as ``repr``: read back exactly).
    summary : dict
        The study's plain data (``as_dict``), written to summary.json.
    command, inputs, force, figure_format, data_format
        As for ``write_sweep``.
    units : dict of str to str, optional
        Column name -> unit (the Parquet fields' metadata; "" or missing: none).

    Returns
    -------
    None
    """
    figure_format = check_figure_format(figure_format)
    data_format = check_result_format(data_format)
    fig = draw()
    units = {k: v for k, v in (units or {}).items() if v}
    with output_directory(out_dir, writer="sweep", inputs=inputs, force=force) as tmp:
        _save_figure(fig, tmp / f"sweep.{figure_format}")
        # the CSV quotes a status holding a comma
        _write_table(tmp / f"sweep.{data_format}", header, rows, units=units)
        info = {**summary, "tetherheli_version": __version__, "command": command}
        write_json(tmp / "summary.json", info)
