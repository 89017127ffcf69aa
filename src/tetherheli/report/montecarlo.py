"""A Monte Carlo's results folder (``tetherheli montecarlo``): the study
(``studies.montecarlo.runner``) runs the draws into resumable chunks and returns the finished
``MonteCarloJob``; this writes its results table (CSV or Parquet), its summary and the
figures of one metric (``viz.plots.figure_montecarlo``, ``figure_paired``)."""

from __future__ import annotations

import csv
import io
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np

from .._io import (
    atomic_open,
    atomic_path,
    atomic_write_text,
    json_from_text,
    json_text,
    output_directory,
)
from ..errors import ParameterError
from ..results.result import TABLE_FORMATS, check_result_format
from ..scenario.core import Scenario
from ..studies.montecarlo.config import CONFIGURATIONS, MonteCarloConfig
from ..studies.montecarlo.runner import (
    INT_COLUMNS,
    METRICS,
    TEXT_COLUMNS,
    MonteCarloColumns,
    MonteCarloJob,
    column_units,
    paired_metric,
    run_montecarlo_chunks,
)
from ..viz.formats import figures_for_files

__all__ = ["FIGURE_KINDS", "RESULT_FILES", "result_files", "run_montecarlo"]

#: The figures of a metric: ``<metric>_<kind>.<format>`` (``viz.plots.figure_montecarlo``,
#: ``figure_paired``).
FIGURE_KINDS = ("hist", "cdf", "paired")


def result_files(
    metric: str = "peak_q1", figure_format: str = "png", table_format: str = "csv"
) -> tuple[str, ...]:
    """What a finished job writes beside ``partial/``: the results table in ``table_format``
    ("csv" or "parquet"), the summary and the figures of ``metric`` in ``figure_format``.

    Parameters
    ----------
    metric : str, optional
        The figures' metric (default "peak_q1").
    figure_format : str, optional
        "png" (default), "pdf" or "svg".
    table_format : str, optional
        "csv" (default) or "parquet".

    Returns
    -------
    tuple of str
        The file names.
    """
    figures = tuple(f"{metric}_{kind}.{figure_format}" for kind in FIGURE_KINDS)
    return (f"results.{table_format}", "summary.json", *figures)


#: What a finished job writes with the default metric and format.
RESULT_FILES = result_files()


def run_montecarlo(
    base: Scenario,
    config: MonteCarloConfig,
    out: str | Path,
    *,
    chunk_size: int = 50,
    workers: int | None = None,
    max_chunks: int | None = None,
    progress: bool = True,
    client: Any = None,
    worker_timeout_s: float = 60.0,
    inputs: tuple[str | Path, ...] = (),
    force: bool = False,
    table_format: str = "csv",
    metric: str = "peak_q1",
    figure_format: str = "png",
) -> dict[str, Any] | None:
    """Run (or resume) a Monte Carlo (``studies.montecarlo.runner.run_montecarlo_chunks``)
    and write its outputs to ``out``.

    ``out`` follows the rules of ``_io.output_directory``: not the current, home or root
    directory nor one holding the ``inputs``; a folder tetherheli did not create must be empty
    (or ``force``; its files are kept), and ``results.csv``, ``summary.json`` and the figures
    replace only files this command wrote.

    Parameters
    ----------
    base : Scenario
        The nominal scenario (every draw runs free and tethered).
    config : MonteCarloConfig
        Dispersions, N and seed.
    out : path
        Output directory, the job's chunks in its ``partial/`` (``run_montecarlo_chunks``).
    chunk_size, workers, max_chunks, progress, client, worker_timeout_s, inputs, force
        As for ``run_montecarlo_chunks``: draws per chunk file (default 50), ``run_batch``'s
        threads, at most this many new chunks before returning None, progress on stderr, a
        Dask cluster, how long it may have no worker, the input files ``out`` must not hold,
        write into a non-empty folder tetherheli did not create (its files are kept).
    table_format : {"csv", "parquet"}
        The results table: ``results.csv`` (default) or ``results.parquet`` (pyarrow; the
        same columns, text columns as strings, ``run`` and ``status`` as int64, the rest
        float64).
    metric : str
        The metric of the figures (one of ``METRICS``): histogram, CDF and the paired
        free-against-tethered scatter per draw.
    figure_format : str
        "png", "pdf" or "svg" (``viz.plots.FIGURE_FORMATS``).

    Returns
    -------
    dict or None
        The summary (also written to ``summary.json``), or None if stopped by ``max_chunks``.

    Raises
    ------
    ParameterError
        A bad metric or format, or as ``run_montecarlo_chunks`` raises it.
    ClusterError
        As ``run_montecarlo_chunks`` raises it (the same call resumes the job).

    Notes
    -----
    A draw whose plant cannot be set up is a failed row of the table, and a damaged chunk
    file is computed again (``run_montecarlo_chunks``). The results, summary and figures are
    built aside and swapped in whole (``_io.output_directory``); the figures of another
    metric or format stay.
    """
    from ..viz.formats import check_figure_format

    if metric not in METRICS:
        raise ParameterError("metric", metric, f"one of {list(METRICS)}")
    figure_format = check_figure_format(figure_format)
    files = result_files(metric, figure_format, check_result_format(table_format, TABLE_FORMATS))
    job = run_montecarlo_chunks(
        base,
        config,
        out,
        chunk_size=chunk_size,
        workers=workers,
        max_chunks=max_chunks,
        progress=progress,
        client=client,
        worker_timeout_s=worker_timeout_s,
        inputs=inputs,
        force=force,
        outputs=files,
    )
    if job is None:
        return None
    return _write_results(job, files, metric=metric, inputs=inputs, force=force)


def _write_results(
    job: MonteCarloJob,
    files: tuple[str, ...],
    *,
    metric: str,
    inputs: tuple[str | Path, ...],
    force: bool,
) -> dict[str, Any]:
    """The job's table, summary and figures (``files``, checked: ``result_files``), built
    aside and swapped in whole; streamed: one chunk in memory at a time."""
    columns = MonteCarloColumns(job.header)
    with output_directory(
        job.out,
        writer="montecarlo",
        inputs=inputs,
        force=force,
        own=job.owns,
        remove_earlier=False,
    ) as build:
        table, figures = build / files[0], [build / name for name in files[2:]]
        if table.suffix == ".parquet":
            _write_parquet(table, list(job.header), job.chunks(columns))
        else:
            with atomic_open(table) as fh:
                fh.write(",".join(job.header) + "\n")
                for text in job.chunks(columns):
                    fh.write(text)
        arrays = columns.arrays()
        text = json_text(job.summarize(arrays))
        atomic_write_text(build / "summary.json", text + "\n")
        summary: dict[str, Any] = json_from_text(text)
        _figures(figures, *paired_metric(arrays, metric), metric)
    return summary


def _write_parquet(path: Path, header: list[str], chunks: Iterable[str]) -> None:
    """The table as Parquet: text columns as strings, ``run`` and ``status`` as int64, the
    rest float64, each field with its unit (``column_units``) in its metadata."""
    import pyarrow.parquet as pq

    schema = _parquet_schema(header)
    with atomic_path(path) as tmp:
        with pq.ParquetWriter(tmp, schema) as writer:
            for text in chunks:
                writer.write_table(_parquet_chunk(text, schema))


def _parquet_schema(header: list[str]) -> Any:
    import pyarrow as pa

    def kind(c: str) -> Any:
        if c in TEXT_COLUMNS:
            return pa.string()
        return pa.int64() if c in INT_COLUMNS else pa.float64()

    units = column_units(header)
    return pa.schema([pa.field(c, kind(c), metadata={"units": units[c]}) for c in header])


def _parquet_chunk(rows_text: str, schema: Any) -> Any:
    """A chunk's CSV rows as a pyarrow table of ``schema`` (``_parquet_schema``)."""
    import pyarrow as pa

    rows = list(csv.reader(io.StringIO(rows_text)))
    columns = list(zip(*rows, strict=True)) if rows else [() for _ in schema]
    arrays = []
    for field, column in zip(schema, columns, strict=True):
        if field.type == pa.string():
            values: list[Any] = list(column)
        elif field.type == pa.int64():
            values = [int(v) for v in column]
        else:
            values = [float(v) for v in column]
        arrays.append(pa.array(values, type=field.type))
    return pa.Table.from_arrays(arrays, schema=schema)


@figures_for_files()
def _figures(
    paths: list[Path],
    values: dict[str, np.ndarray],
    ok: dict[str, np.ndarray],
    metric: str,
) -> None:
    """Histogram, CDF and paired scatter of ``metric`` (``FIGURE_KINDS``, in that order)."""
    # imported here, as the paper's report does: importing this module loads no Matplotlib
    from ..viz.figure import _save_figure  # the format: checked by run_montecarlo
    from ..viz.plots import figure_montecarlo, figure_paired

    hist, cdf, paired = paths
    _save_figure(figure_montecarlo(values, ok, "hist", metric=metric), hist)
    _save_figure(figure_montecarlo(values, ok, "cdf", metric=metric), cdf)
    free, tethered = CONFIGURATIONS
    fig = figure_paired(values[free], values[tethered], ok[free], ok[tethered], metric)
    _save_figure(fig, paired)
