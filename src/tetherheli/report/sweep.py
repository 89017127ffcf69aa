"""A parameter sweep's output folder (``tetherheli sweep``): the study (``studies.sweep``)
returns a ``SweepResult``; this writes its table, its figure (``viz.plots.figure_sweep``) and
its summary."""

from __future__ import annotations

import csv
import io
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .._io import atomic_write_text, output_directory, write_json
from .._version import __version__
from ..studies.sweep import SweepResult
from ..viz.formats import check_figure_format, figures_for_files
from ..viz.plots import figure_sweep, save_figure

__all__ = ["write_sweep", "write_sweep_folder"]


def write_sweep(
    result: SweepResult,
    out_dir: str | Path,
    *,
    command: str,
    inputs: tuple[str | Path, ...] = (),
    force: bool = False,
    figure_format: str = "png",
) -> None:
    """Table (CSV), plot (``sweep.<figure_format>``: png, pdf or svg) and summary.json of a
    sweep, written whole or not at all (``_io.output_directory``: the user's files in
    ``out_dir`` are kept, never replaced).

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
    )


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
) -> None:
    """A sweep's folder, written whole or not at all (``_io.output_directory``: the user's
    files in ``out_dir`` are kept, never replaced): ``sweep.<figure_format>``, ``sweep.csv``
    (``header``, then ``rows``) and ``summary.json`` (``summary`` with the version and the
    command). The one writer of ``write_sweep`` and ``cyclic_limit.write_limit_search``.

    Parameters
    ----------
    out_dir : str or Path
        The output folder.
    draw : callable
        Returns the figure; called once the format is checked, before anything is written.
    header : sequence of str
        The CSV's column names.
    rows : iterable of sequences of str
        The CSV's rows, each value already text (floats as ``repr``: read back exactly).
    summary : dict
        The study's plain data (``as_dict``), written to summary.json.
    command, inputs, force, figure_format
        As for ``write_sweep``.

    Returns
    -------
    None
    """
    figure_format = check_figure_format(figure_format)
    fig = draw()
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")  # quotes a status holding a comma
    writer.writerow(header)
    writer.writerows(rows)
    with output_directory(out_dir, writer="sweep", inputs=inputs, force=force) as tmp:
        save_figure(fig, tmp / f"sweep.{figure_format}")
        atomic_write_text(tmp / "sweep.csv", buf.getvalue())
        info = {**summary, "tetherheli_version": __version__, "command": command}
        write_json(tmp / "summary.json", info)
