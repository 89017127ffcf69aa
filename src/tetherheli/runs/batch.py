"""Many closed-loop runs at once, keeping only per-run summaries (memory-bounded).

``run_batch(scenarios)`` runs every scenario with the compiled engine and keeps, per run, the
on-line summary of ``engine.SUMMARY_FIELDS`` (peaks, sums of squares, tension range, number
of samples) and the status: memory is O(N + workers x LANES x samples of sensor noise),
never O(N x samples). Each run is packed by the same set-up as ``simulate``
(``setup.engine_setup``: trim, gain, wind, actuators, sensor noise).

By default the runs go in blocks of ``layout.LANES`` through the lane engine
(``lanes.run_lanes``): each sample runs every lane's sensors, controller, actuators, checks
and metrics at once (``lane_sample.lane_sample``, on the single run's scalar kernels), then
integrates all lanes at once (``lanes.rk4_lanes``), both as vectorised loops over the lanes.
A lane performs the operations of a single run in the same order, so a batch's numbers
equal ``simulate``'s bit for bit (a test checks it over dispersed runs with actuators,
sensors, turbulence, releases and failures). With
``lanes=False`` every run goes alone through ``engine.run_closed_loop``.

Blocks (or single runs) are spread over threads; ``run_block`` and ``run_unrecorded`` call
compiled code that releases the GIL (``lanes.run_lanes``, ``engine``'s closed loops) for the
whole block or run, so two threads run in parallel. The Python side of a run (trim,
packing, about 0.15 ms) holds the GIL. With a ``dask.distributed`` client the runs are
split into equal tasks and run on the cluster's workers instead (``connect``).

Runs are sorted by (parameters, control settings, q9), and the LQI gain (``paper_gain``,
cached) is designed once per distinct set. With ``design_params`` every run's gain is
designed on those parameters instead (the Monte Carlo's "controller designed on nominal
parameters, plant dispersed"); the trim operating point (initial state, references, trim
inputs) stays the run's own plant trim.

A batch of N scenarios gives the numbers of N calls of ``simulate`` (same engine, same
arithmetic), see ``BatchResult.metrics`` and ``summary_metrics``. A run whose set-up fails (no
hover trim, actuator limits it cannot hover within) raises, or with
``record_setup_failures=True`` is recorded as ``Status.SETUP`` with the error in
``BatchResult.reasons`` and the batch goes on (the Monte Carlo's dispersed plants).
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validation import check_integer
from ..control.registry import controller_entry
from ..engine import lanes
from ..engine import loop as engine
from ..engine.lanes import lane_program_into
from ..engine.summary import summarize
from ..errors import ClusterError, ParameterError, TetherheliError
from ..layout import (
    LANES,
    SUMMARY_RELEASE_TENSION,
    SUMMARY_RELEASE_TIME,
    SUMMARY_WINCH_LIMIT,
    SUMMARY_WINCH_LIMIT_TIME,
    WIND_COLUMNS,
    Signals,
)
from ..names import METRIC_NAMES
from ..params import Params
from ..results.result import WINCH_LIMITS
from ..scenario.core import Scenario
from ..status import Status, finite_status, is_success, status_message
from ..wind import compile_wind
from .closed_loop import check_run_memory
from .setup import EngineSetup, engine_setup, python_controlled

__all__ = [
    "METRIC_NAMES",
    "BatchResult",
    "connect",
    "disconnect",
    "run_batch",
    "run_block",
    "run_unrecorded",
    "summary_metrics",
]

_N_SUMMARY = len(engine.SUMMARY_FIELDS)
_I = {name: i for i, name in enumerate(engine.SUMMARY_FIELDS)}


def run_unrecorded(engine_args, summary):
    """``engine.run_closed_loop(*engine_args, ...)`` without recording (1-row dummy outputs),
    GIL released; ``engine_args`` is ``EngineSetup.engine_args``.

    Parameters
    ----------
    engine_args : tuple
        ``EngineSetup.engine_args``: the compiled engine's arguments for one run.
    summary : numpy.ndarray, shape (len(engine.SUMMARY_FIELDS),)
        Filled with the run's on-line metrics.

    Returns
    -------
    status : int
        ``Status`` of the run (0: completed).
    samples_done : int
        Samples the run completed (``n_samples + 1`` if completed).
    """
    return engine.run_closed_loop(*engine_args, False, _NO_SIGNALS, summary)


#: one-row signals for the unrecorded runs, never written (``record`` is False)
_NO_SIGNALS = Signals.zeros(1)


def run_block(block_args: tuple, summary: np.ndarray, status: np.ndarray, done: np.ndarray) -> None:
    """``lanes.run_lanes(*block_args, (summary, status, done))``, which releases the GIL;
    ``block_args`` is ``batch.lane_block``'s. (A compiled wrapper would re-optimise the whole
    lane engine inside it: 10 s of the first compile.)

    Parameters
    ----------
    block_args : tuple
        ``batch.lane_block``'s arguments for a block of ``layout.LANES`` runs.
    summary : numpy.ndarray, shape (LANES, len(engine.SUMMARY_FIELDS))
        Filled with each lane's on-line metrics.
    status : numpy.ndarray of int, shape (LANES,)
        Filled with each lane's ``Status``.
    done : numpy.ndarray of int, shape (LANES,)
        Filled with each lane's samples done.

    Returns
    -------
    None
        The results are written into ``summary``, ``status`` and ``done``.
    """
    lanes.run_lanes(*block_args, (summary, status, done))


def summary_metrics(summary: np.ndarray) -> dict[str, float]:
    """Metrics of one run from its engine summary, as ``analysis.run_metrics`` defines them.

    Parameters
    ----------
    summary : numpy.ndarray
        Shape ``(len(engine.SUMMARY_FIELDS),)``.

    Returns
    -------
    dict
        ``METRIC_NAMES`` -> value: peaks of |q1|, |q2|, |q3| deviations [m], of q4, q5 [deg],
        RMS deviations ``sqrt(sumsq / n_samples)`` [m], tension range [N], sample count.
        NaN for a run with no sample.
    """
    s = np.asarray(summary, dtype=float)
    n = float(s[_I["n_samples"]])
    if n <= 0.0:
        return {k: math.nan for k in METRIC_NAMES[:-1]} | {"n_samples": 0.0}
    return {
        "peak_q1": float(s[_I["peak_q1"]]),
        "peak_q2": float(s[_I["peak_q2"]]),
        "peak_q3": float(s[_I["peak_q3"]]),
        "peak_q4_deg": math.degrees(float(s[_I["peak_q4"]])),
        "peak_q5_deg": math.degrees(float(s[_I["peak_q5"]])),
        "rms_q1": math.sqrt(float(s[_I["sumsq_q1"]]) / n),
        "rms_q2": math.sqrt(float(s[_I["sumsq_q2"]]) / n),
        "rms_q3": math.sqrt(float(s[_I["sumsq_q3"]]) / n),
        "tension_min": float(s[_I["tension_min"]]),
        "tension_max": float(s[_I["tension_max"]]),
        "n_samples": n,
    }


@dataclass(frozen=True)
class BatchResult:
    """Per-run summaries of a batch.

    A run whose tether the safety device released is still ``ok`` (it completed, free); its
    ``release`` and ``message`` say when.

    Parameters
    ----------
    summaries : numpy.ndarray
        ``(N, len(engine.SUMMARY_FIELDS))``, columns ``engine.SUMMARY_FIELDS``.
    status : numpy.ndarray
        ``(N,)`` int, ``Status`` (0: completed).
    samples_done : numpy.ndarray
        ``(N,)`` int, samples recorded before the run ended (``n_samples + 1`` if completed).
    reasons : tuple of str
        ``(N,)``: why a run could not be set up (``Status.SETUP``), else "".
    """

    summaries: np.ndarray
    status: np.ndarray
    samples_done: np.ndarray
    reasons: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if not self.reasons:
            object.__setattr__(self, "reasons", ("",) * len(self))

    def __len__(self) -> int:
        return int(self.status.shape[0])

    @property
    def ok(self) -> np.ndarray:
        """``(N,)`` bool: the run succeeded (``status.is_success``: completed, or landed)."""
        return is_success(self.status)

    @property
    def release_time(self) -> np.ndarray:
        """``(N,)`` the time [s] at which each run's tether was released (NaN: never)."""
        return self.summaries[:, SUMMARY_RELEASE_TIME]

    @property
    def release_tension(self) -> np.ndarray:
        """``(N,)`` the tension [N] that released each run's tether (NaN: never)."""
        return self.summaries[:, SUMMARY_RELEASE_TENSION]

    def release(self, i: int) -> tuple[float, float] | None:
        """Run ``i``'s tether release, (time [s], tension [N]), or None.

        Parameters
        ----------
        i : int
            Run index, 0 <= i < N.

        Returns
        -------
        tuple of 2 floats or None
            (release time [s], release tension [N]); None if the tether was never released.
        """
        t = float(self.release_time[i])
        return None if math.isnan(t) else (t, float(self.release_tension[i]))

    def message(self, i: int) -> str:
        """Run ``i``'s status message, with its tether release (``status_message``).

        Parameters
        ----------
        i : int
            Run index, 0 <= i < N.

        Returns
        -------
        str
            One line, e.g. "completed" or why the run stopped.
        """
        return status_message(
            int(self.status[i]), float(self.release_time[i]), winch_limit=self.winch_limit(i)
        )

    def winch_limit(self, i: int) -> dict[str, Any] | None:
        """Run ``i``'s first stop of the reel at a payout limit (``[winch] min_length``,
        ``max_length``), ``{"time", "limit"}`` (s, the key's name), or None.

        Parameters
        ----------
        i : int
            Run index, 0 <= i < N.

        Returns
        -------
        dict or None
            When the natural length reached the limit and which; None if none was reached.
        """
        t = float(self.summaries[i, SUMMARY_WINCH_LIMIT_TIME])
        if math.isnan(t):
            return None
        which = int(self.summaries[i, SUMMARY_WINCH_LIMIT])
        return {"time": t, "limit": WINCH_LIMITS[which]}

    def messages(self) -> list[str]:
        """The status message of every run (a tether release included).

        Returns
        -------
        list of str, length N
            ``message(i)`` for every run.
        """
        return [self.message(i) for i in range(len(self))]

    def metrics(self, i: int) -> dict[str, float]:
        """``summary_metrics`` of run ``i``.

        Parameters
        ----------
        i : int
            Run index, 0 <= i < N.

        Returns
        -------
        dict of str to float
            Metric name (``METRIC_NAMES``) to value, units as ``summary_metrics``.
        """
        return summary_metrics(self.summaries[i])


def _default_workers() -> int:
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def _check(scenario: Scenario) -> None:
    """A run_batch scenario: a Scenario whose wind the compiled engine can run."""
    if not isinstance(scenario, Scenario):
        raise TypeError(f"scenario must be a tetherheli Scenario, not {type(scenario).__name__}")
    wind = compile_wind(scenario.wind)
    if wind is None:
        raise ParameterError(
            f"{scenario.name}.wind",
            type(scenario.wind).__name__,
            "built-in disturbances only (run_batch uses the compiled engine)",
        )
    if scenario.landing_gear is not None and not python_controlled(scenario):
        raise ParameterError(f"{scenario.name}.landing_gear", "a table", "absent in run_batch "
                             "outside a landing (the lanes fly no landing gear)")  # fmt: skip


def _python_run(
    scenario: Scenario, setup: EngineSetup, design_params: Params | None, summary: np.ndarray
) -> tuple[int, int]:
    """A run whose controller is a Python ``Controller`` (``control.mpc``, designed on
    ``design_params`` when given; a landing's ``control.landing``), flown by ``simulate``'s
    loop; ``summary`` receives the
    engine's on-line metrics of it (``engine.SUMMARY_FIELDS``, from the recorded samples at
    or after ``metrics_start``). Returns (status, samples done)."""
    from .closed_loop import _simulate
    from .mpc_setup import mpc_controller

    # the MPC designed on ``design_params``; the other Python controllers are simulate's own
    # (``runs.landing``, ``control.deck``)
    mpc = not controller_entry(scenario.control.controller).compiled
    controller = mpc_controller(scenario, setup, design_params) if mpc else None
    # its memory checked by run_batch, as a recorded run (``check_run_memory``)
    result = _simulate(scenario, controller=controller, design_params=design_params)
    # the engine's own accumulation over the recorded samples (one definition of the metrics)
    summarize(
        np.ascontiguousarray(result.states), np.ascontiguousarray(result.trim_state),
        np.ascontiguousarray(result.outputs), np.ascontiguousarray(result.trim_output),
        np.ascontiguousarray(result.tension), min(scenario.metrics_first_sample,
        result.time.size), summary,
    )  # fmt: skip
    release = (result.release_time, result.release_tension)
    summary[_I["release_time"]] = math.nan if release[0] is None else release[0]
    summary[_I["release_tension"]] = math.nan if release[1] is None else release[1]
    limit = result.winch_limit
    summary[_I["winch_limit_time"]] = math.nan if limit is None else limit["time"]
    codes = {name: code for code, name in WINCH_LIMITS.items()}
    summary[_I["winch_limit"]] = math.nan if limit is None else codes[limit["limit"]]
    return result.status, result.time.size


def connect(address: str, timeout_s: float = 10.0) -> Any:
    """A ``dask.distributed.Client`` of the scheduler at ``address`` (e.g. "tcp://host:8786").

    Parameters
    ----------
    address : str
        Scheduler address, ``protocol://host:port``.
    timeout_s : float
        How long to wait for the scheduler [s].

    Returns
    -------
    distributed.Client
        The connected client; close it with ``disconnect``.

    Raises
    ------
    ParameterError
        dask.distributed is not installed, the address is malformed, or no scheduler answers
        within ``timeout_s``.
    """
    if not isinstance(address, str) or "://" not in address:
        raise ParameterError("scheduler", address, "an address like tcp://host:8786")
    try:
        from distributed import Client
    except ImportError:
        raise ParameterError(
            "scheduler", address, "dask.distributed installed (pip install 'tetherheli[dask]')"
        ) from None
    try:
        return Client(address, timeout=f"{timeout_s}s", set_as_default=False)
    except (OSError, TimeoutError, ValueError) as exc:
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise ParameterError(
            "scheduler", address, f"a reachable dask.distributed scheduler ({reason})"
        ) from None


def disconnect(client: Any) -> None:
    """Close a client of ``connect``. If its scheduler was lost, the close interrupts the
    client's attempts to reconnect, which distributed logs as tracebacks: the client is gone,
    so its loggers are silenced first (the reason was reported as one ``ClusterError``).

    Parameters
    ----------
    client : distributed.Client
        A client returned by ``connect``.
    """
    if client.status != "running":
        import logging

        for name in ("distributed", "distributed.client", "distributed.core"):
            logging.getLogger(name).setLevel(logging.CRITICAL + 1)
    client.close()


def _run_part(
    scenarios: list[Scenario],
    design_params: Params | None,
    record_setup_failures: bool = False,
    lanes: bool = True,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple[str, ...]]:
    """One Dask task: a serial batch on the worker (the worker's threads run tasks in parallel;
    the engine releases the GIL)."""
    r = run_batch(
        scenarios,
        workers=1,
        design_params=design_params,
        record_setup_failures=record_setup_failures,
        lanes=lanes,
    )
    return r.summaries, r.status, r.samples_done, r.reasons


def _run_on_cluster(
    client: Any,
    scenarios: list[Scenario],
    design_params: Params | None,
    record_setup_failures: bool,
    worker_timeout_s: float,
    lanes: bool,
) -> list[tuple[list[int], tuple]]:
    """The batch as equal Dask tasks: ``(indices, _run_part result)`` per task. A lost
    scheduler, or no worker for ``worker_timeout_s`` seconds, raises ``ClusterError`` (one
    line) instead of tracebacks or waiting forever."""
    import asyncio
    import concurrent.futures
    import time

    from distributed.client import FutureCancelledError, FuturesCancelledError

    where = getattr(getattr(client, "scheduler", None), "address", None) or "the scheduler"
    lost = (
        OSError,
        TimeoutError,
        asyncio.CancelledError,
        concurrent.futures.CancelledError,
        FutureCancelledError,
        FuturesCancelledError,
    )
    try:
        n = len(scenarios)
        n_threads = max(1, sum(client.nthreads().values()))
        size = max(1, -(-n // (4 * n_threads)))
        parts = [list(range(i, min(n, i + size))) for i in range(0, n, size)]
        futures = client.map(
            _run_part,
            [[scenarios[i] for i in idx] for idx in parts],
            design_params=design_params,
            record_setup_failures=record_setup_failures,
            lanes=lanes,
            pure=False,
        )
        idle_since = None
        next_check = time.monotonic()
        while not all(f.done() for f in futures):
            time.sleep(0.02)
            if client.status != "running":
                raise ClusterError(f"lost the connection to the Dask scheduler {where}")
            now = time.monotonic()
            if now < next_check:
                continue
            next_check = now + 1.0
            if client.nthreads():
                idle_since = None
            elif idle_since is None:
                idle_since = now
            elif now - idle_since > worker_timeout_s:
                raise ClusterError(
                    f"no Dask worker connected to {where} for {worker_timeout_s:g} s "
                    "(start workers: dask worker ADDRESS, or raise --worker-timeout)"
                )
        return list(zip(parts, client.gather(futures), strict=True))
    except lost as exc:
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise ClusterError(f"lost the Dask scheduler {where} ({reason})") from None


def run_batch(
    scenarios: Sequence[Scenario],
    *,
    workers: int | None = None,
    design_params: Params | None = None,
    client: Any = None,
    record_setup_failures: bool = False,
    worker_timeout_s: float = 60.0,
    lanes: bool = True,
    on_done: Callable[[int], None] | None = None,
) -> BatchResult:
    """Run many scenarios with the compiled engine, keeping per-run summaries only.

    Parameters
    ----------
    scenarios : sequence of Scenario
        The runs; their winds must be built-in disturbances (``compile_wind`` not None).
    workers : int, optional
        Number of threads in this process (default: the CPUs available to it); 1 runs
        serially. Ignored with ``client``.
    design_params : Params, optional
        Parameters the LQI gain is designed on for every run (default: each run's own
        parameters). The plant and its trim always use the scenario's parameters.
    client : distributed.Client, optional
        Run on this Dask cluster instead (see ``connect``); the runs are split into tasks of
        equal size, and the result is the same as in-process.
    record_setup_failures : bool
        A run whose set-up raises a ``TetherheliError`` (no hover trim, actuator limits it
        cannot hover within) gets ``Status.SETUP`` and the error's message in
        ``reasons`` instead of stopping the batch.
    worker_timeout_s : float
        With ``client``: how long the cluster may have no worker before ``ClusterError``.
    lanes : bool
        Advance the runs in blocks of ``layout.LANES`` (``lanes.run_lanes``, the default);
        False runs them one at a time (``engine.run_closed_loop``). Both give the same
        numbers bit for bit. Runs with a lumped tether or a moving base always run one at a
        time.
    on_done : callable, optional
        Called with the number of runs just finished, as they finish (progress,
        ``tetherheli.progress``); the counts add up to ``len(scenarios)``.

    Returns
    -------
    BatchResult
        In the order of ``scenarios``.

    Raises
    ------
    ParameterError
        ``workers`` < 1 or a custom (non-compilable) disturbance.
    ClusterError
        With ``client``: the scheduler was lost, or no worker for ``worker_timeout_s``.
    """
    scenarios = list(scenarios)
    if workers is None:
        workers = _default_workers()
    workers = check_integer("workers", workers, low=1)
    n = len(scenarios)
    summaries = np.zeros((n, _N_SUMMARY))
    # no release event until a run records one (a run that is never set up has none)
    summaries[:, [SUMMARY_RELEASE_TIME, SUMMARY_RELEASE_TENSION]] = np.nan
    summaries[:, [SUMMARY_WINCH_LIMIT_TIME, SUMMARY_WINCH_LIMIT]] = np.nan
    status = np.zeros(n, dtype=np.int64)
    done = np.zeros(n, dtype=np.int64)
    reasons = [""] * n
    if n == 0:
        return BatchResult(summaries, status, done)
    for s in scenarios:  # fail fast, before any work is sent anywhere
        _check(s)  # a run of a Python controller is recorded (``simulate``'s loop)
        check_run_memory(s, record=python_controlled(s), concurrent=min(workers, n))
    if client is not None:
        for idx, (sm, st, dn, why) in _run_on_cluster(
            client, scenarios, design_params, record_setup_failures, worker_timeout_s, lanes
        ):
            summaries[idx], status[idx], done[idx] = sm, st, dn
            for i, r in zip(idx, why, strict=True):
                reasons[i] = r
            if on_done is not None:
                on_done(len(idx))
        return _finished(summaries, status, done, reasons)
    # group by (params, control, q9) so each group's gain is designed once (paper_gain caches)
    order = sorted(
        range(n),
        key=lambda i: hash((scenarios[i].params, scenarios[i].control, scenarios[i].q9)),
    )

    def set_up(i: int) -> EngineSetup | None:
        """Run i's set-up, or None with its failure recorded (``record_setup_failures``)."""
        try:
            return engine_setup(scenarios[i], design_params)  # checked by ``_check``
        except TetherheliError as exc:
            if not record_setup_failures:
                raise
            status[i] = Status.SETUP
            reasons[i] = str(exc).splitlines()[0]
            return None

    def run_one(i: int) -> None:
        if python_controlled(scenarios[i]):  # the MPC, or simulate's own Python controllers
            return run_python(i)
        setup = set_up(i)
        if setup is not None:
            st, k = run_unrecorded(setup.engine_args(scenarios[i].n_samples), summaries[i])
            status[i] = st
            done[i] = k

    def run_python(i: int) -> None:
        """A run of a Python controller (the MPC): ``simulate``'s loop, then its summary."""
        setup = set_up(i)
        if setup is not None:
            status[i], done[i] = _python_run(scenarios[i], setup, design_params, summaries[i])

    def run_lane_block(block: list[int]) -> None:
        if not controller_entry(scenarios[block[0]].control.controller).compiled:
            for i in block:
                run_python(i)
            return
        ready = [(i, s) for i in block if (s := set_up(i)) is not None]
        if not ready:
            return
        index = [i for i, _ in ready]
        args = lane_block([s for _, s in ready], [scenarios[i].n_samples for i in index])
        block_summary = np.empty((LANES, _N_SUMMARY))
        block_status = np.empty(LANES, dtype=np.int64)
        block_done = np.empty(LANES, dtype=np.int64)
        run_block(args, block_summary, block_status, block_done)
        m = len(index)
        summaries[index], status[index], done[index] = (
            block_summary[:m],
            block_status[:m],
            block_done[:m],
        )

    if lanes:
        # a block's runs share the RK4 steps per sample and the controller (whose law's arrays
        # are stacked: ``layout.LAW_GAIN``); runs of equal length finish together
        def block_key(i: int) -> tuple[int, str]:
            return scenarios[i].control.substeps, scenarios[i].control.controller

        order.sort(key=lambda i: (block_key(i), scenarios[i].n_samples))
        blocks: list[list[int]] = []

        # no lane engine for chains nor for a moving base: those runs go one at a time
        def single(i: int) -> bool:
            s = scenarios[i]
            return s.tether.lumped or not s.base_motion.fixed or s.maneuver.landing

        alone = [i for i in order if single(i)]
        for i in (i for i in order if not single(i)):
            last = blocks[-1] if blocks else None
            same = last and block_key(last[0]) == block_key(i)
            if same and last and len(last) < LANES:  # (last: narrowed for the type checker)
                last.append(i)
            else:
                blocks.append([i])
        tasks: list[Any] = [*blocks, *alone]  # run indices, and blocks of them
        task: Callable[[Any], None]

        def task(t: int | list[int]) -> None:
            run_lane_block(t) if isinstance(t, list) else run_one(t)

    else:
        tasks, task = order, run_one

    def size(t: int | list[int]) -> int:
        return len(t) if isinstance(t, list) else 1

    if workers == 1 or len(tasks) == 1:
        for t in tasks:
            task(t)
            if on_done is not None:
                on_done(size(t))
    else:
        with ThreadPoolExecutor(max_workers=workers) as pool:
            futures = [(pool.submit(task, t), size(t)) for t in tasks]
            for fut, m in futures:
                fut.result()
                if on_done is not None:
                    on_done(m)
    return _finished(summaries, status, done, reasons)


#: the summary's metrics (the fields before ``n_samples`` in ``engine.SUMMARY_FIELDS``): finite
#: in every successful run; the event slots (release, payout limit) hold NaN for "none"
_METRIC_FIELDS = _I["n_samples"]


def _finished(
    summaries: np.ndarray, status: np.ndarray, done: np.ndarray, reasons: Sequence[str]
) -> BatchResult:
    """The batch's result; a successful run whose metrics are not finite is NONFINITE
    (``status.finite_status``: never completed)."""
    for i in range(status.shape[0]):
        status[i] = finite_status(int(status[i]), summaries[i, :_METRIC_FIELDS])
    return BatchResult(summaries, status, done, tuple(reasons))


# --- a block of runs packed for the lanes (``lanes.run_lanes``'s leading arguments) -------


def _stack(arrays: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Arrays (rows, ...) of different row counts stacked along a new lane axis, zero-padded
    to the longest (their dtype kept); returns (stacked (B, rows_max, ...), rows in use (B,))."""
    rows = np.array([a.shape[0] for a in arrays], dtype=np.int64)
    shape = (len(arrays), max(1, int(rows.max())), *arrays[0].shape[1:])
    stacked = np.zeros(shape, dtype=arrays[0].dtype)
    for j, a in enumerate(arrays):
        stacked[j, : a.shape[0]] = a
    return stacked, rows


def lane_block(setups: Sequence[EngineSetup], n_samples: Sequence[int]) -> tuple:
    """The leading arguments of ``lanes.run_lanes`` for a block of up to ``LANES`` runs:
    lane j holds ``setups[j].engine_args(n_samples[j])``, the single run's own packing, with
    a lane axis in front (built-in winds only; every run must take the same RK4 steps per
    sample). Lanes beyond the runs are padding: copies of the first run with n_samples = -1
    (never run). Wind programs are padded with rows of zero force and laid out flat (row,
    column, lane); tables of other lengths are zero-padded with their rows in use.

    Parameters
    ----------
    setups : sequence of EngineSetup
        1 to ``LANES`` runs with built-in winds.
    n_samples : sequence of int
        Control samples of each run.

    Returns
    -------
    tuple
        The arguments of ``lanes.run_lanes`` before its outputs, each with a leading lane
        axis of length ``LANES``.
    """
    if not 0 < len(setups) <= LANES or len(n_samples) != len(setups):
        raise ValueError(f"lane_block: 1 to {LANES} runs, each with its n_samples")
    pad = LANES - len(setups)
    runs = [s.engine_args(n) for s, n in zip(setups, n_samples, strict=True)]
    runs += [runs[0]] * pad
    counts = np.array([*n_samples, *([-1] * pad)], dtype=np.int64)
    if any(s.chain[0].shape[0] > 0 for s in setups):
        raise ValueError("lane_block: lumped tethers run alone (engine.run_closed_loop)")
    x_init, _, cfg, ctrl, c, law, wind, act, sensors, _ = zip(*runs, strict=True)
    program, gust, drag, _base = zip(*wind, strict=True)  # the lanes fly a still base
    n_rows = max(p.shape[0] for p in program)
    programs = np.empty((n_rows, WIND_COLUMNS, LANES))
    for j, p in enumerate(program):
        lane_program_into(programs, j, p)
    noise, source, arm, scratch, schedule, ring = zip(*sensors, strict=True)
    return (
        np.stack(x_init),
        counts,
        np.stack(cfg),
        np.stack(ctrl),
        np.stack(c),
        tuple(np.ascontiguousarray(np.stack(part)) for part in zip(*law, strict=True)),
        (programs.ravel(), n_rows, *_stack(list(gust)), np.stack(drag)),
        np.stack(act),
        (
            *_stack(list(noise)),
            np.array(source, dtype=np.int64),
            np.array(arm, dtype=float),
            np.stack(scratch),
            *_stack(list(schedule)),
            *_stack(list(ring)),
        ),
    )
