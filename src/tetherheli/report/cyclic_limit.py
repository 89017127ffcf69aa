"""The cyclic-limit search's output folder (``tetherheli sweep --find-min
actuators.cyclic_limit``): the study (``studies.cyclic_limit``) returns a ``LimitSearch``;
this writes its table, its figure (``viz.plots.figure_limit_search``) and its summary."""

from __future__ import annotations

from pathlib import Path

from ..names import METRIC_UNITS
from ..studies.cyclic_limit import LimitSearch
from ..viz.plots import figure_limit_search
from .sweep import write_sweep_folder

__all__ = ["write_limit_search"]


def write_limit_search(
    result: LimitSearch,
    out_dir: str | Path,
    *,
    command: str,
    inputs: tuple[str | Path, ...] = (),
    force: bool = False,
    figure_format: str = "png",
    data_format: str = "csv",
) -> None:
    """Table (``sweep.<data_format>``, csv or parquet: every run), plot
    (``sweep.<figure_format>``: png, pdf or svg) and summary.json of a search, written whole
    or not at all (``sweep.write_sweep_folder``).

    Parameters
    ----------
    result : LimitSearch
        The search.
    out_dir, command, inputs, force, figure_format, data_format
        As for ``report.sweep.write_sweep``.

    Returns
    -------
    None
    """
    write_sweep_folder(
        out_dir,
        draw=lambda: figure_limit_search(result),
        header=("cyclic_limit_Nm", "metric", "meets", "status"),
        rows=[
            [repr(v), repr(m), str(int(ok)), s]
            for v, m, ok, s in zip(
                result.values.tolist(),
                result.metric.tolist(),
                result.meets,
                result.statuses,
                strict=True,
            )
        ],
        summary=result.as_dict(),
        command=command,
        inputs=inputs,
        force=force,
        figure_format=figure_format,
        data_format=data_format,
        units={"cyclic_limit_Nm": "N m", "metric": METRIC_UNITS.get(result.metric_name, "")},
    )
