"""Running a Monte Carlo: chunks of draws written and verified on disk (resumable), and the
finished job (``MonteCarloJob``): its verified table, one chunk at a time, and its summary
statistics (``statistics``: failed runs in the tails, the paired reduction, bootstrap
intervals). The job's results folder (table, summary, figures) is ``report.montecarlo``'s."""

from __future__ import annotations

import csv
import hashlib
import io
import math
import os
import re
import stat
from array import array
from collections.abc import Collection, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..._io import (
    OutputPathError,
    atomic_write_text,
    check_output_file,
    check_real_folders,
    claim_output_directory,
    json_from_text,
    json_text,
    read_json,
    write_json,
)
from ..._validation import check_integer
from ..._version import __version__
from ...errors import ParameterError, TetherheliError
from ...names import METRIC_UNITS, MONTECARLO_METRICS
from ...progress import Progress
from ...resources import check_memory
from ...runs.batch import METRIC_NAMES, run_batch
from ...scenario.core import Scenario
from ...status import Status, is_success
from ...wind import Turbulence
from .config import CONFIGURATIONS, MAX_RUNS, MonteCarloConfig, _wind_parts, check_draw_names
from .draws import draw, draw_seed, free_reference

__all__ = [
    "INT_COLUMNS",
    "METRICS",
    "TEXT_COLUMNS",
    "MonteCarloColumns",
    "MonteCarloJob",
    "check_nominal_designs",
    "column_units",
    "paired_metric",
    "run_montecarlo_chunks",
]

#: The metrics of the table a Monte Carlo can plot (``report.montecarlo``'s ``metric=``):
#: every per-run metric of the table.
METRICS = MONTECARLO_METRICS

#: Columns of the results table that are text (the seed entropy can exceed 64 bits) or
#: integers in its Parquet form (``report.montecarlo``); every other column is a float64.
TEXT_COLUMNS = ("seed_entropy", "spawn_key", "configuration", "message", "reason")
INT_COLUMNS = ("run", "status")


#: Units of the results table's fixed columns ("": text or a count; "1": dimensionless)
_UNITS = {
    "run": "", "seed_entropy": "", "spawn_key": "", "amplitude_scale": "1",
    "direction_deg": "deg", "phase_rad": "rad", "start_shift_s": "s", "configuration": "",
    "status": "", "message": "", "reason": "", "release_time": "s", "release_tension": "N",
    **METRIC_UNITS,
}  # fmt: skip


def column_units(header: list[str]) -> dict[str, str]:
    """The unit of each column of a Monte Carlo results table: the draws' dispersions, the
    parameter factors ("1") and drawn values (the parameter's own unit, ``Params``), the run
    metrics (``names.METRIC_UNITS``), the release. Written into ``summary.json`` ("units") and
    into the Parquet schema's field metadata.

    Parameters
    ----------
    header : list of str
        The table's columns.

    Returns
    -------
    dict of str to str
        Column -> unit ("" for text and counts, "1" for dimensionless).
    """
    from ...params import Params

    docs = Params.field_docs()
    units = {}
    for c in header:
        kind, _, name = c.partition(":")
        if kind == "factor":
            units[c] = "1"
        elif kind == "value":
            found = re.search(r"\[([^\]]+)\]", docs.get(name, ""))
            units[c] = found.group(1) if found else "1"
        else:
            units[c] = _UNITS.get(c, "")
    return units


#: Memory of one draw's two scenarios besides their gust series (objects, parameters, wind
#: profiles), measured with tracemalloc on the shipped paper Monte Carlo: about 5 kB; margin kept.
_DRAW_BASE_BYTES = 16_384


def check_chunk_memory(base: Scenario, draws: int) -> int:
    """Estimate the bytes a chunk of ``draws`` draws holds at once (each draw's scenarios and
    its own gust series) and refuse it above the memory budget (``tetherheli.resources``);
    returns the estimate.

    Parameters
    ----------
    base : Scenario
        The Monte Carlo's base scenario (its turbulence's gust grids set each draw's size).
    draws : int
        The draws in the chunk.

    Returns
    -------
    int
        The estimated memory [bytes].

    Raises
    ------
    ResourceLimitError
        The estimate exceeds the memory budget.
    """
    gusts = sum(d.N_v_gust_grid.nbytes for d in _wind_parts(base.wind) if isinstance(d, Turbulence))
    needed = draws * (_DRAW_BASE_BYTES + gusts)
    check_memory(
        f"a Monte Carlo chunk of {draws} draws", needed, hint="lower --chunk-size (default 50)"
    )
    return needed


def _chunks(n: int, chunk_size: int) -> Iterator[tuple[int, int]]:
    """(first draw, end) of every chunk, lazily (no O(N) list)."""
    for lo in range(0, n, chunk_size):
        yield lo, min(n, lo + chunk_size)


def _chunk_path(part: Path, lo: int, hi: int) -> Path:
    """The chunk file of draws ``lo`` .. ``hi - 1``."""
    return part / f"chunk_{lo:09d}_{hi:09d}.csv"


def _columns(config: MonteCarloConfig) -> list[str]:
    cols = ["run", "seed_entropy", "spawn_key", "amplitude_scale", "direction_deg"]
    cols += ["phase_rad", "start_shift_s"]
    cols += [f"factor:{n}" for n, _ in config.params] + [f"value:{n}" for n, _ in config.params]
    cols += ["configuration", "status", "message", "reason", *METRIC_NAMES, *_RELEASE_COLUMNS]
    return cols


#: the tether release of a run (``BatchResult.release``): time [s], tension [N]; NaN if none
_RELEASE_COLUMNS = ("release_time", "release_tension")


def _fmt(v: object) -> str:
    return repr(float(v)) if isinstance(v, (float, np.floating)) else str(v)


def _run_chunk(
    base: Scenario,
    config: MonteCarloConfig,
    children: list,
    start: int,
    workers: int | None,
    client: Any,
    worker_timeout_s: float = 60.0,
) -> str:
    draws = [draw(base, config, ch, start + j) for j, ch in enumerate(children)]
    scenarios = [
        free_reference(d.scenario) if cfg == "free" else d.scenario.replace(configuration=cfg)
        for d in draws
        if d.scenario is not None
        for cfg in CONFIGURATIONS
    ]
    batch = run_batch(
        scenarios,
        workers=workers,
        design_params=base.params,
        client=client,
        record_setup_failures=True,
        worker_timeout_s=worker_timeout_s,
    )
    no_metrics = [math.nan] * (len(METRIC_NAMES) + 2)  # metrics and release of a failed draw
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    k = 0
    for d in draws:
        head = [
            d.index,
            d.entropy,
            ":".join(str(s) for s in d.spawn_key),
            d.amplitude_scale,
            d.direction_deg,
            d.phase_rad,
            d.start_shift_s,
            *(f for _, f in d.param_factors),
            *d.param_values,
        ]
        for cfg in CONFIGURATIONS:
            if d.scenario is None:  # impossible dispersed values: the draw's rows say why
                row = [*head, cfg, int(Status.SETUP), Status.SETUP.message, d.reason, *no_metrics]
            else:
                m = batch.metrics(k)
                release = (batch.release_time[k], batch.release_tension[k])
                metrics = (m[n] for n in METRIC_NAMES)
                st = int(batch.status[k])
                row = [*head, cfg, st, batch.message(k), batch.reasons[k], *metrics, *release]
                k += 1
            w.writerow([_fmt(v) for v in row])
    return buf.getvalue()


def _fingerprint(base: Scenario, config: MonteCarloConfig, chunk_size: int) -> dict[str, Any]:
    """What a chunk's rows depend on (the job's identity): the scenario, the bytes of every
    file it names (``Scenario.input_files``), the dispersions; not N (draw i does not depend
    on it), so a finished job can be extended with more runs in the same directory."""
    mc = config.to_dict()
    del mc["runs"]
    return {
        "scenario": base.to_dict(),
        "inputs": base.input_files,  # every file the scenario names: path -> SHA-256 of its bytes
        "montecarlo": mc,
        "chunk_size": chunk_size,
        "columns": _columns(config),  # chunks of another table layout are not reused
        "version": __version__,
    }


_CHUNK_END = re.compile(
    r"# tetherheli montecarlo chunk: draws (\d+)\.\.(\d+), (\d+) rows, sha256 ([0-9a-f]{64})"
)


def _seal(rows: str, lo: int, hi: int) -> str:
    """A chunk file's text: its rows (as results.csv gets them) and a last line with the draw
    range, the row count and the SHA-256 of the rows, checked by ``_chunk_rows``."""
    digest = hashlib.sha256(rows.encode("utf-8")).hexdigest()
    n = rows.count("\n")
    return f"{rows}# tetherheli montecarlo chunk: draws {lo}..{hi - 1}, {n} rows, sha256 {digest}\n"


class _BadChunk(Exception):
    """A chunk file that fails verification; the message says how."""


def _chunk_rows(path: Path, lo: int, hi: int, header: list[str], seed: int) -> str:
    """The verified rows of the chunk file of draws ``lo`` .. ``hi - 1`` of the job with root
    seed ``seed``: every row is the run it should be (draw index, seed entropy, spawn key and
    configuration, in the table's order), not only a sealed text.

    Raises
    ------
    _BadChunk
        Not a regular file (a link, a folder), unreadable, empty, truncated, garbled
        (checksum), rows or draws other than expected.
    """
    try:
        mode = os.lstat(path).st_mode
    except OSError as exc:
        raise _BadChunk(f"cannot be read ({exc.strerror or exc})") from None
    if not stat.S_ISREG(mode):
        kind = "a link" if stat.S_ISLNK(mode) else "a folder" if stat.S_ISDIR(mode) else "special"
        raise _BadChunk(f"is {kind}, not a chunk file")
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise _BadChunk(f"cannot be read ({exc.strerror or exc})") from None
    if not data:
        raise _BadChunk("is empty")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise _BadChunk("is garbled (not UTF-8 text)") from None
    head, _, last = text.removesuffix("\n").rpartition("\n")
    end = _CHUNK_END.fullmatch(last) if text.endswith("\n") else None
    if end is None:
        raise _BadChunk("has no checksum line (truncated, or written before checksums)")
    rows = head + "\n" if head else ""
    first, final, count, digest = end.groups()
    expected = len(CONFIGURATIONS) * (hi - lo)
    if (int(first), int(final)) != (lo, hi - 1):
        raise _BadChunk(f"holds draws {first}..{final}, not {lo}..{hi - 1}")
    if int(count) != expected:
        raise _BadChunk(f"says it has {count} rows, not {expected}")
    if hashlib.sha256(rows.encode("utf-8")).hexdigest() != digest:
        raise _BadChunk("is garbled (its checksum does not match)")
    table = list(csv.reader(io.StringIO(rows)))
    if len(table) != expected:
        raise _BadChunk(f"has {len(table)} rows, not {expected}")
    where = [header.index(c) for c in ("run", "seed_entropy", "spawn_key", "configuration")]
    for j, row in enumerate(table):
        i, cfg = lo + j // len(CONFIGURATIONS), CONFIGURATIONS[j % len(CONFIGURATIONS)]
        if len(row) != len(header) or [row[k] for k in where] != [str(i), str(seed), str(i), cfg]:
            raise _BadChunk(f"is garbled (row {j + 1} is not draw {i}'s {cfg} run)")
    return rows


def _make_way(path: Path) -> None:
    """Remove what stands where a chunk file is to be written again: a link (the link
    itself, never what it points to), an empty folder, a bad chunk file is replaced by the
    rename; a folder that holds files is refused (it may be a user's)."""
    if path.is_symlink():
        path.unlink()
    elif path.is_dir():
        try:
            path.rmdir()
        except OSError:
            raise OutputPathError(
                f"{path} is a folder that holds files, where a chunk file of the job belongs; "
                "allowed: move it away"
            ) from None


def check_nominal_designs(base: Scenario) -> None:
    """Refuse (``WeightsError``) weights that have no stabilising design on the nominal plant,
    on which every draw's free and tethered controller is designed: without this every run
    would be a set-up failure (``studies.controllers.check_design``).

    Parameters
    ----------
    base : Scenario
        The nominal scenario.
    """
    from ..controllers import check_design

    check_design(free_reference(base))
    check_design(base.replace(configuration="tethered"))


def run_montecarlo_chunks(
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
    outputs: Collection[str] = (),
) -> MonteCarloJob | None:
    """Run (or resume) the draws of a Monte Carlo into ``out/partial/``; the finished job's
    results folder is ``report.montecarlo.run_montecarlo``'s.

    ``out`` follows the rules of ``_io.output_directory``: not the current, home or root
    directory nor one holding the ``inputs``; a folder tetherheli did not create must be empty
    (or ``force``; its files are kept). It is claimed, and each of ``outputs`` checked, before
    the first run.

    Parameters
    ----------
    base : Scenario
        The nominal scenario (its configuration is ignored: every draw runs free and tethered).
    config : MonteCarloConfig
        Dispersions, N and seed.
    out : path
        Output directory; ``out/partial/`` holds finished chunks and is reused on a re-run
        with the same scenario, dispersions and chunk size.
    chunk_size : int
        Draws per chunk file.
    workers : int, optional
        Threads of ``run_batch``.
    max_chunks : int, optional
        Compute at most this many new chunks, then return None (the job stays resumable).
    progress : bool
        Progress on stderr (``tetherheli.progress``: a bar on a terminal, else one line at
        the end).
    client : distributed.Client, optional
        Run the chunks on this Dask cluster (``runs.batch.connect``); same table as in-process.
    worker_timeout_s : float
        With ``client``: how long the cluster may have no worker before ``ClusterError``.
    inputs : tuple of str or Path, optional
        The input files (the scenario), which ``out`` must not hold; recorded with the
        folder's marker.
    force : bool, optional
        Write into a non-empty folder tetherheli did not create (its files are kept).
    outputs : collection of str, optional
        The files the results folder will hold (``report.montecarlo.result_files``): each
        may replace only a file this command wrote, refused now, not after the runs.

    Returns
    -------
    MonteCarloJob or None
        The finished job, or None if stopped by ``max_chunks``.

    Raises
    ------
    ParameterError
        Bad arguments, ``out/partial`` belongs to a different job, or its ``job.json`` is
        unreadable.
    ClusterError
        With ``client``: the scheduler was lost, or no worker for ``worker_timeout_s``; the
        finished chunks are kept and the same call resumes the job.

    Notes
    -----
    A draw whose plant cannot be set up (no hover trim, actuator limits it cannot hover
    within) is a failed row (``Status.SETUP``, the error in ``reason``); the job goes
    on. On every call each finished chunk file is verified against its last line (draw range,
    row count, SHA-256) and by its rows (each the draw index, seed and configuration it should
    be); one that fails, or a link or an empty folder in its place, is named in one line on
    stderr and computed again. ``out/partial`` may not be a link.
    """
    if not isinstance(config, MonteCarloConfig):
        raise TypeError("config must be a MonteCarloConfig")
    check_nominal_designs(base)
    check_draw_names(base)
    check_integer("runs", config.runs, low=1, high=MAX_RUNS)
    chunk_size = check_integer("chunk_size", chunk_size, low=1, high=1_000_000)
    if max_chunks is not None:
        max_chunks = check_integer("max_chunks", max_chunks, low=0, high=MAX_RUNS)
    check_chunk_memory(base, min(chunk_size, config.runs))
    check_memory(  # the statistics hold the table's numeric columns at the end
        f"the results table of {config.runs} draws",
        2 * config.runs * MonteCarloColumns.ROW_BYTES,
        hint="run fewer draws",
    )
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise ParameterError("out", str(out), "a directory (new, or of the same job)")
    part = out / "partial"
    check_real_folders(out, "partial/job.json", shown=f"--out {out}")
    claim_output_directory(out, inputs=inputs, force=force, own=lambda rel: _is_job_file(out, rel))
    for name in outputs:  # refused now, not after the runs
        check_output_file(out / name)
    part.mkdir(parents=True, exist_ok=True)
    fp = _fingerprint(base, config, chunk_size)
    fp_path = part / "job.json"
    if fp_path.exists():
        try:
            recorded = read_json(fp_path)
        except (OSError, ValueError) as exc:  # ValueError: not UTF-8, not JSON
            reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            raise ParameterError(
                "file",
                str(fp_path),
                f"the job record of a Monte Carlo in this folder ({reason}); delete {part} "
                "to start the job over",
            ) from None
        if recorded != json_from_text(json_text(fp)):
            _refuse_changed_inputs(recorded, fp["inputs"], out, part)
            raise ParameterError(
                "out",
                str(out),
                "a new directory, or one of the same job (partial/job.json differs)",
            )
    else:
        write_json(fp_path, fp)
    n = config.runs
    header = _columns(config)
    computed = 0
    with Progress("montecarlo", n, "draws", enabled=progress) as bar:
        for lo, hi in _chunks(n, chunk_size):
            path = _chunk_path(part, lo, hi)
            if os.path.lexists(path):
                try:
                    _chunk_rows(path, lo, hi, header, config.seed)
                except _BadChunk as exc:
                    _make_way(path)
                    bar.note(f"tetherheli: {path} {exc}; computing it again")
                else:
                    bar.update_to(hi)
                    continue
            if max_chunks is not None and computed >= max_chunks:
                return None
            children = [draw_seed(config.seed, i) for i in range(lo, hi)]
            rows = _run_chunk(base, config, children, lo, workers, client, worker_timeout_s)
            atomic_write_text(path, _seal(rows, lo, hi))
            computed += 1
            bar.update_to(hi)
    return MonteCarloJob(base, config, out, chunk_size, tuple(header))


def _refuse_changed_inputs(recorded: Any, inputs: dict[str, str], out: Path, part: Path) -> None:
    """Refuse, in one line naming the file, to resume the job recorded in ``part`` (its
    ``job.json`` read as ``recorded``) over an input file whose bytes changed since it started,
    or over another file than it started with; nothing when the inputs are the same."""
    before = recorded.get("inputs") if isinstance(recorded, dict) else None
    if not isinstance(before, dict) or before == inputs:
        return
    for path, digest in inputs.items():
        if path in before and before[path] != digest:
            raise ParameterError(
                "base.file", path, f"the bytes the job in {out} started with (the file changed "
                f"since); restore it, or delete {part} to start the job over",
            )  # fmt: skip
    gone = sorted(set(before) - set(inputs))
    named = sorted(set(inputs) - set(before))
    raise ParameterError(
        "base.file", named[0] if named else "", f"the file the job in {out} started with "
        f"({gone[0] if gone else 'none'}); name it again, or delete {part} to start the job "
        "over",
    )  # fmt: skip


def _is_job_file(out: Path, rel: str) -> bool:
    """A file of a Monte Carlo job's own ``partial/`` folder (one with its ``job.json``)."""
    return rel.startswith("partial/") and (out / "partial" / "job.json").is_file()


@dataclass(frozen=True)
class MonteCarloJob:
    """A finished Monte Carlo (``run_montecarlo_chunks``): its table lives in the verified
    chunk files of ``out/partial/``, read one chunk at a time (``chunks``), so that a job
    of any N is summarized in bounded memory (``MonteCarloColumns``, ``summarize``).

    Parameters
    ----------
    base : Scenario
        The nominal scenario.
    config : MonteCarloConfig
        Dispersions, N and seed.
    out : Path
        The job's output directory (its chunks in ``out/partial/``).
    chunk_size : int
        Draws per chunk file.
    header : tuple of str
        The results table's columns (units: ``column_units``).
    """

    base: Scenario
    config: MonteCarloConfig
    out: Path
    chunk_size: int
    header: tuple[str, ...]

    def owns(self, rel: str) -> bool:
        """Whether ``rel`` (a path relative to ``out``) is a file of the job's own
        ``partial/`` folder (``_io.output_directory``'s ``own``).

        Parameters
        ----------
        rel : str
            A path relative to ``out``, with "/" separators.

        Returns
        -------
        bool
        """
        return _is_job_file(self.out, rel)

    def chunks(self, columns: MonteCarloColumns | None = None) -> Iterator[str]:
        """The table's rows (CSV text without its header), one verified chunk at a time, in
        draw order; each is added to ``columns`` first, if given.

        Parameters
        ----------
        columns : MonteCarloColumns, optional
            Collects the numeric columns while the table is read.

        Returns
        -------
        iterator of str
            Each chunk's rows, as results.csv holds them (read when the iterator gets there).

        Raises
        ------
        TetherheliError
            A chunk file changed since the job verified it (another process).
        """
        part, header = self.out / "partial", list(self.header)
        for lo, hi in _chunks(self.config.runs, self.chunk_size):
            path = _chunk_path(part, lo, hi)
            try:
                text = _chunk_rows(path, lo, hi, header, self.config.seed)
            except _BadChunk as exc:
                raise TetherheliError(
                    f"{path} {exc} after it was verified (changed by another process?); "
                    "run the same command again"
                ) from None
            if columns is not None:
                columns.add(text)
            yield text

    def summarize(self, columns: dict[str, np.ndarray]) -> dict[str, Any]:
        """The job's summary (summary.json): per configuration the counts, percentiles with
        failed runs in the tail and their bootstrap intervals; the paired reduction by the
        tether; the configuration, version, N, seed and the columns' units.

        Parameters
        ----------
        columns : dict of str to ndarray
            The table's columns (``MonteCarloColumns.arrays``).

        Returns
        -------
        dict
            Plain data (JSON: a percentile among the failed runs is None).
        """
        return _summarize(self.base, self.config, columns)


class MonteCarloColumns:
    """The configuration, status and metric columns of the results table, collected while it
    is written: 8 bytes a number and 1 a configuration (``ROW_BYTES`` a row with the final
    arrays), not Python objects; the table is not read back.

    Parameters
    ----------
    header : sequence of str
        The table's columns (``MonteCarloJob.header``).
    """

    _NUMERIC = ("status", *METRIC_NAMES, "release_time")
    #: bytes a row of the table holds here: the numbers, the configuration code, and the
    #: configuration names of ``arrays`` (numpy '<U8', 32 bytes)
    ROW_BYTES = 8 * len(_NUMERIC) + 1 + 32

    def __init__(self, header: Sequence[str]) -> None:
        header = list(header)
        self._where = {k: header.index(k) for k in ("configuration", *self._NUMERIC)}
        self._cols = {k: array("d") for k in self._NUMERIC}
        self._configuration = array("b")

    def add(self, chunk_text: str) -> None:
        """Collect a chunk's rows.

        Parameters
        ----------
        chunk_text : str
            CSV rows of the table, without its header.

        Returns
        -------
        None
        """
        for row in csv.reader(io.StringIO(chunk_text)):
            self._configuration.append(CONFIGURATIONS.index(row[self._where["configuration"]]))
            for k in self._NUMERIC:
                self._cols[k].append(float(row[self._where[k]]))

    def arrays(self) -> dict[str, np.ndarray]:
        """The collected columns: "configuration" (names), "status", the metrics and
        "release_time", each of shape (rows,).

        Returns
        -------
        dict of str to ndarray
        """
        out = {k: np.frombuffer(self._cols[k], dtype=float) for k in self._NUMERIC}
        codes = np.frombuffer(self._configuration, dtype=np.int8)
        out["configuration"] = np.array(CONFIGURATIONS)[codes]
        return out


_PCTS = (1, 5, 25, 50, 75, 95, 99)
#: the metrics of summary.json, and the side a failed run counts on (+inf: smaller is better)
_SUMMARY_METRICS = {m: -math.inf if m == "tension_min" else math.inf for m in METRICS}
#: the metrics whose paired reduction by the tether summary.json reports: the deviations
_REDUCTION_METRICS = tuple(m for m in METRICS if m.startswith(("peak_", "rms_")))


def _json_number(v: float) -> float | None:
    """A finite number, or None (JSON null) for a percentile among the failed runs."""
    return float(v) if math.isfinite(v) else None


def _percentile_entry(sample: np.ndarray, seed: int) -> dict[str, Any]:
    """Percentiles of ``sample`` (failures as +-inf) with their bootstrap intervals."""
    from .statistics import bootstrap_interval, tail_percentile

    values = tail_percentile(sample, _PCTS)
    low, high = bootstrap_interval(sample, _PCTS, seed)
    return {f"p{p}": _json_number(v) for p, v in zip(_PCTS, values, strict=True)} | {
        "ci95": {
            f"p{p}": [_json_number(lo), _json_number(hi)]
            for p, lo, hi in zip(_PCTS, low, high, strict=True)
        }
    }


def _paired(columns: dict[str, np.ndarray]) -> dict[str, np.ndarray] | None:
    """Each draw's free and tethered rows side by side: ``<metric>`` (n, 2) and ``ok`` (n, 2)
    (the table holds draw i's free row, then its tethered row); None for a table of another
    layout (a hand-made one)."""
    cfg = columns["configuration"]
    if cfg.size % 2 or not (
        np.all(cfg[0::2] == CONFIGURATIONS[0]) and np.all(cfg[1::2] == CONFIGURATIONS[1])
    ):
        return None
    pairs = {m: columns[m].reshape(-1, 2) for m in METRIC_NAMES}
    pairs["ok"] = is_success(columns["status"]).reshape(-1, 2)
    return pairs


def _summarize(
    base: Scenario, config: MonteCarloConfig, columns: dict[str, np.ndarray]
) -> dict[str, Any]:
    from .statistics import BOOTSTRAP_RESAMPLES, CONFIDENCE, paired_reduction, with_failures

    stats: dict[str, Any] = {}
    for c, cfg in enumerate(CONFIGURATIONS):
        sel = columns["configuration"] == cfg
        ok = sel & is_success(columns["status"])
        entry: dict[str, Any] = {
            "runs": int(sel.sum()),
            "completed": int(ok.sum()),
            "failed": int(sel.sum() - ok.sum()),
            "tether_released": int((sel & np.isfinite(columns["release_time"])).sum()),
        }
        for k, (m, worst) in enumerate(_SUMMARY_METRICS.items()):
            v = columns[m][ok]
            if v.size:  # no completed run: the counts say it all
                sample = with_failures(columns[m][sel], ok[sel], worst)
                entry[m] = {"mean": float(v.mean()), "max": float(v.max())}
                entry[m] |= _percentile_entry(sample, config.seed + 100 * c + k)
        stats[cfg] = entry
    pairs = _paired(columns)
    reduction: dict[str, Any] = {}
    failed_draws = None
    for k, m in enumerate(_REDUCTION_METRICS if pairs is not None else ()):
        assert pairs is not None  # (the loop is empty without pairs)
        free_ok, teth_ok = pairs["ok"][:, 0], pairs["ok"][:, 1]
        r = paired_reduction(pairs[m][:, 0], pairs[m][:, 1], free_ok, teth_ok)
        done = np.isfinite(r) & free_ok & teth_ok
        referenced = r[free_ok]  # a draw whose free run failed has no reduction
        reduction[m] = {
            "draws": int(r.size),
            "draws_with_reference": int(referenced.size),
            "both_completed": int(done.sum()),
            "mean_both_completed": float(r[done].mean()) if done.any() else None,
        }
        if referenced.size >= 2:  # the bootstrap needs two draws
            reduction[m] |= _percentile_entry(referenced, config.seed + 1000 + k)
        else:  # no reduction to speak of: every percentile and interval null
            reduction[m] |= {f"p{p}": None for p in _PCTS}
            reduction[m]["ci95"] = {f"p{p}": [None, None] for p in _PCTS}
        failed_draws = {
            "free_only": int((~free_ok & teth_ok).sum()),
            "tethered_only": int((free_ok & ~teth_ok).sum()),
            "both": int((~free_ok & ~teth_ok).sum()),
        }
    return {
        "description": "Monte Carlo: per-configuration percentiles over all runs, a failed "
        "run counted as the worst value (+inf; -inf for tension_min), so a percentile among "
        "the failures is null; mean and max over completed runs; the paired per-draw "
        "reduction 100 (free - tethered) / free [%] over the draws whose free run completed "
        "(a failed tethered run: -inf; a failed free run is no reference: its draw has no "
        "reduction and is counted in failed_draws); ci95: bootstrap confidence intervals",
        "version": __version__,
        "N": config.runs,
        "seed": config.seed,
        "bootstrap": {
            "method": "scipy.stats.bootstrap, percentile method, resampling draws",
            "resamples": BOOTSTRAP_RESAMPLES,
            "confidence": CONFIDENCE,
            "seed": "root seed + 100 configuration + metric index (+ 1000 for reductions)",
        },
        "montecarlo": config.to_dict(),
        "scenario": base.to_dict(),
        "controller": "LQI gain designed on the nominal parameters; plant dispersed",
        "units": column_units(_columns(config)),
        "failed_draws": failed_draws,
        "statistics": stats,
        "reduction_percent": reduction,
    }


def paired_metric(
    columns: dict[str, np.ndarray], metric: str
) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """Each draw's ``metric`` and completion per configuration, side by side by draw (what the
    Monte Carlo's figures draw, ``viz.plots.figure_montecarlo`` and ``figure_paired``).

    Parameters
    ----------
    columns : dict of str to ndarray
        A job's table columns (``MonteCarloColumns.arrays``: draw i's free row, then its
        tethered row).
    metric : str
        One of ``METRICS``.

    Returns
    -------
    values : dict of str to ndarray
        Configuration -> the metric per draw, shape (N,).
    ok : dict of str to ndarray
        Configuration -> whether the draw's run succeeded (``status.is_success``), shape (N,).
    """
    pairs = _paired(columns)
    if pairs is None:
        raise ValueError("columns: not a Monte Carlo job's table (free and tethered rows)")
    values = {cfg: pairs[metric][:, c] for c, cfg in enumerate(CONFIGURATIONS)}
    ok = {cfg: pairs["ok"][:, c] for c, cfg in enumerate(CONFIGURATIONS)}
    return values, ok
