"""The result of a closed-loop run: a frozen object that plotting and export only read.

Its files (columns, formats, reading and checking) are ``results.files``; the names
listed there are re-exported here, where users import them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .._io import OutputPathError, atomic_write_bytes, atomic_write_text, write_json
from ..names import INPUT, INPUT_UNITS, OUTPUT_UNITS, POSITION
from ..status import (
    FALLBACK_COLUMN,
    is_success,
    release_sentence,
    status_message,
    stopped,
)
from .files import (
    _ESTIMATE_SUFFIX,
    _FEEDFORWARD,
    _WIND,
    BASE_POSITION_COLUMNS,
    BASE_VELOCITY_COLUMNS,
    DECK_ATTITUDE_COLUMNS,
    DRUM_COLUMNS,
    EXTRA_UNITS,
    INPUT_NAMES,
    OUTPUT_NAMES,
    RESULT_COLUMNS,
    RESULT_DESCRIPTIONS,
    RESULT_FORMATS,
    RESULT_UNITS,
    STATE_NAMES,
    STATE_UNITS,
    TABLE_FORMATS,
    TENSION_GROUND_COLUMN,
    WINCH_LIMITS,
    _optional,
    check_result_format,
    list_results,
    read_result_fields,
    write_csv,
    write_parquet,
)

__all__ = [
    "DRUM_COLUMNS",
    "EXTRA_UNITS",
    "RESULT_COLUMNS",
    "RESULT_DESCRIPTIONS",
    "RESULT_FORMATS",
    "RESULT_UNITS",
    "TABLE_FORMATS",
    "TENSION_GROUND_COLUMN",
    "WINCH_LIMITS",
    "SimulationResult",
    "SummaryRepr",
    "atomic_write_bytes",
    "atomic_write_text",
    "check_result_format",
    "list_results",
    "load_result",
    "winch_limit_info",
]


class SummaryRepr:
    """A result's short summary as its ``repr`` (a few lines of text) and, in Jupyter, an
    HTML table (``_repr_html_``), from the class's ``_summary_rows``; never its arrays. A
    dataclass using it sets ``repr=False`` (else the dataclass writes its own)."""

    def _summary_rows(self) -> list[tuple[str, str]]:
        raise NotImplementedError

    def __repr__(self) -> str:
        rows = self._summary_rows()
        width = max((len(k) for k, _ in rows), default=0)
        lines = [f"  {k.ljust(width)}  {v}" for k, v in rows]
        return "\n".join([f"<{type(self).__name__}", *lines]) + ">"

    def _repr_html_(self) -> str:
        from html import escape

        body = "".join(
            f"<tr><th style='text-align:left'>{escape(k)}</th>"
            f"<td style='text-align:left'>{escape(v)}</td></tr>"
            for k, v in self._summary_rows()
        )
        return f"<table><caption>{escape(type(self).__name__)}</caption>{body}</table>"


def _number(value: float, unit: str = "") -> str:
    """``value`` with 4 significant digits and its unit, e.g. "0.03475 m"."""
    return f"{value:.4g}" + (f" {unit}" if unit else "")


@dataclass(frozen=True, repr=False)
class SimulationResult(SummaryRepr):
    """A sampled closed-loop run (one row per control sample t_k = k dt).

    ``simulate`` builds it; plotting and export only read it. Its ``repr`` (and, in
    Jupyter, an HTML table) is a summary: name, configuration, status, duration, samples
    and the peak deviations from trim (``peak_deviations``; a landing's touchdown figures
    instead, ``landing_metrics``), never the arrays.

    Parameters
    ----------
    time : numpy.ndarray, shape (n,)
        Sample times (s).
    states : numpy.ndarray, shape (n, 13)
        Tethered-coordinate state q4..q9, u1..u6, LN (see ``STATE_NAMES``); for the free
        configuration q7..q9 locate P as if a tether were there.
    outputs : numpy.ndarray, shape (n, 4)
        q1, q2, q3, q6 (m, m, m, rad; eqs 43-45).
    inputs : numpy.ndarray, shape (n, 4)
        Applied fMR3, tMR1, tMR2, fTR2, including the feed-forward (eq 54).
    feedforward : numpy.ndarray, shape (n, 4)
        C_f-fwd of eq 55 (zeros without tether or feed-forward).
    tension : numpy.ndarray, shape (n,)
        Tether tension TC (N).
    reel_rate : numpy.ndarray, shape (n,)
        Winch rate RC held over [t_k, t_k+1) (m/s, eq 37).
    wind : numpy.ndarray, shape (n, 3)
        Wind force on HO, N components (N).
    trim_state, trim_input, trim_output : numpy.ndarray
        The run's trim (its references), shapes (13,), (4,), (4,).
    status : int
        0 on success (10, "landed", for a landing), else a failure code; ``message`` says
        which (``tetherheli.status.Status``).
    configuration : dict
        The scenario as plain data (``Scenario.to_dict``).
    version : str
        The package version that ran it.
    method : str, optional
        The integrator, ``"rk4"`` (default) or ``"adaptive"``.
    extra : dict of str to numpy.ndarray, optional
        Further sampled columns (e.g. estimates ``<name>_est``).
    release_time, release_tension : float or None, optional
        The safety device released the tether at this control sample (s), the tension (N)
        having exceeded the breaking tension (None: not released); the run then continued
        free, and ``message`` says so.
    winch_limit : dict or None, optional
        The first stop of the reel at a payout limit (``winch_limit_info``): ``{"time",
        "limit", "length"}``, the time [s] the natural length reached the limit, which one
        ("min_length" or "max_length" of ``[winch]``) and its value [m]; None: no limit was
        reached. The run goes on with the length held (not a failure); ``message`` says so.
    touchdown : dict or None, optional
        A landing's touchdown (``[maneuver] type = "tethered_landing"``): ``{"time",
        "vertical_speed", "offset", "attitude", "reasons"}``, the time [s] the landing gear
        reached the deck (interpolated between samples), the vertical speed relative to the
        deck [m/s, > 0 downward], HO's horizontal distance from the pad [m], the fuselage's
        tilt [rad], and the limits it broke (empty for status LANDED); on landing gear also
        ``"settled"`` (every gear point in contact at the end of the settling),
        ``"max_penetration"`` [m] (the deepest gear point from the first contact on) and
        ``"bounces"`` (rises above ``scenario.tables.BOUNCE_HEIGHT_M``); None: no touchdown.
    """

    time: np.ndarray
    states: np.ndarray
    outputs: np.ndarray
    inputs: np.ndarray
    feedforward: np.ndarray
    tension: np.ndarray
    reel_rate: np.ndarray
    wind: np.ndarray
    trim_state: np.ndarray
    trim_input: np.ndarray
    trim_output: np.ndarray
    status: int
    configuration: dict[str, Any]
    version: str
    method: str = "rk4"
    extra: dict[str, np.ndarray] = field(default_factory=dict)
    release_time: float | None = None
    release_tension: float | None = None
    winch_limit: dict[str, Any] | None = None
    touchdown: dict[str, Any] | None = None

    def __post_init__(self) -> None:
        for name in (
            "time",
            "states",
            "outputs",
            "inputs",
            "feedforward",
            "tension",
            "reel_rate",
            "wind",
            "trim_state",
            "trim_input",
            "trim_output",
        ):
            getattr(self, name).setflags(write=False)

    @property
    def tension_ground(self) -> np.ndarray:
        """Tension at the winch [N] (the load cell's; ``TENSION_GROUND_COLUMN``): a lumped
        tether's ground end, else the tether's one tension ``tension``."""
        return self.extra.get(TENSION_GROUND_COLUMN, self.tension)

    @property
    def ok(self) -> bool:
        """True when the run succeeded: completed without a stop condition, or a landing
        that touched down within its limits (``status.is_success``)."""
        return bool(is_success(self.status))

    @property
    def message(self) -> str:
        """What happened: the status, with the tether release and the fraction of samples a
        solver's fallback flew (``status.solver_status``) if there were any."""
        fallbacks = self.extra.get(FALLBACK_COLUMN)
        fraction = None if fallbacks is None or fallbacks.size == 0 else float(fallbacks.mean())
        return status_message(
            self.status, self.release_time, fraction, self.winch_limit, self.touchdown
        )

    @property
    def released(self) -> bool:
        """True when the safety device released the tether during the run."""
        return self.release_time is not None

    @property
    def end_time(self) -> float:
        """Where the run ended [s]: its last recorded sample (the run's end, or a landing's
        touchdown); for a run stopped by a check (``status.stopped``) the control sample at
        which the failure was detected (the first one not recorded: its state failed the
        checks, or the integration towards it failed)."""
        dt = self.configuration.get("control", {}).get("dt")
        if not stopped(self.status) or dt is None:
            return float(self.time[-1]) if self.time.size else 0.0
        return self.time.size * float(dt)

    def limit_violations(self, *, rtol: float = 1e-9) -> list[str]:
        """The limits of the run's scenario that its recorded series break, checked sample by
        sample (empty for a run that kept them all): the engine's recorded series finite (a
        controller's own columns may hold NaN for "no value"); the applied
        inputs within ``[actuators] u_min``, ``u_max``; the reel rate within ``reel_rate_limit``
        and, for the ideal winch, its change within ``reel_acceleration_limit``; the natural
        length within ``[winch] min_length``, ``max_length``; the tension at most
        ``[limits] max_tension``. The engine enforces each; this is the independent check of
        the recorded results (the fuzzers' property: a success keeps every limit).

        Parameters
        ----------
        rtol : float, optional
            Relative tolerance on each bound (default 1e-9: rounding).

        Returns
        -------
        list of str
            One line per limit broken: the limit, the worst value and its time.
        """
        cfg = self.configuration
        out: list[str] = []

        def check(name: str, values: np.ndarray, low: float, high: float) -> None:
            if values.size == 0:
                return
            slack = rtol * max(1.0, abs(low) if math.isfinite(low) else 0.0,
                               abs(high) if math.isfinite(high) else 0.0)  # fmt: skip
            bad = (values < low - slack) | (values > high + slack)
            if bad.any():
                k = int(np.flatnonzero(bad)[0])
                out.append(
                    f"{name}: {float(values[k]):.6g} outside [{low:g}, {high:g}] at "
                    f"t = {float(self.time[k]):g} s"
                )

        base = (*BASE_POSITION_COLUMNS, *BASE_VELOCITY_COLUMNS)  # the engine's own columns
        for label, values in (
            ("states", self.states), ("outputs", self.outputs), ("inputs", self.inputs),
            ("tension", self.tension), ("reel_rate", self.reel_rate), ("wind", self.wind),
            *((name, self.extra[name]) for name in base if name in self.extra),
        ):  # fmt: skip
            if not np.isfinite(values).all():
                out.append(f"{label}: a recorded value is not finite")
        act = cfg.get("actuators", {})
        u_min = act.get("u_min", (-math.inf,) * 4)
        u_max = act.get("u_max", (math.inf,) * 4)
        for i, name in enumerate(INPUT):
            check(f"actuators.u_min/u_max ({name})", self.inputs[:, i], u_min[i], u_max[i])
        rate_limit = act.get("reel_rate_limit", math.inf)
        check("actuators.reel_rate_limit", self.reel_rate, -rate_limit, rate_limit)
        winch = cfg.get("winch", {})
        accel = act.get("reel_acceleration_limit", math.inf)
        dt = cfg.get("control", {}).get("dt")
        if winch.get("model", "ideal") == "ideal" and dt and self.reel_rate.size > 1:
            change = np.diff(self.reel_rate) / dt
            check("actuators.reel_acceleration_limit", change, -accel, accel)
        if cfg.get("configuration") == "tethered" and self.states.shape[1] > 12:
            low, high = winch.get("min_length", 0.0), winch.get("max_length", math.inf)
            check("winch.min_length/max_length (L_N)", self.states[:, 12], low, high)
        max_tension = cfg.get("limits", {}).get("max_tension", math.inf)
        check("limits.max_tension", self.tension, -math.inf, max_tension)
        return out

    def release_info(self) -> dict[str, float] | None:
        """The tether release as plain data.

        Returns
        -------
        dict or None
            ``{"time", "tension", "breaking_tension"}`` (s, N, N), or None without release.
        """
        if self.release_time is None or self.release_tension is None:
            return None
        return {
            "time": self.release_time,
            "tension": self.release_tension,
            "breaking_tension": self.breaking_tension,
        }

    @property
    def breaking_tension(self) -> float:
        """The breaking tension of the run's safety device [N] (inf: none)."""
        return float(self.configuration.get("actuators", {}).get("breaking_tension", np.inf))

    def release_note(self) -> str | None:
        """One line on the tether release (``status.release_sentence``).

        Returns
        -------
        str or None
            The sentence, or None without release.
        """
        info = self.release_info()
        if info is None:
            return None
        return release_sentence(info["time"], info["tension"], info["breaking_tension"])

    @property
    def winch_length(self) -> np.ndarray:
        """Tether natural length LN (n,) [m]."""
        return self.states[:, 12]

    @property
    def name(self) -> str:
        return str(self.configuration.get("name", "run"))

    def peak_deviations(self) -> dict[str, float]:
        """The largest |deviation from trim| of each of ``deviations`` over the samples the
        metrics cover (from ``metrics_start``; ``analysis.run_metrics`` has the same peaks
        from the engine's summary), q4 and q5 in degrees.

        Returns
        -------
        dict of str to float
            ``q1``, ``q2``, ``q3`` [m], ``q4_deg``, ``q5_deg`` [deg]; empty without a
            sample in the window.
        """
        from ..scenario.core import metrics_first_sample

        dt = self.configuration.get("control", {}).get("dt")
        start = self.configuration.get("metrics_start", 0.0)
        k0 = metrics_first_sample(start, dt) if dt else 0
        if self.time.size <= k0:
            return {}
        peaks = {k: float(np.max(np.abs(v[k0:]))) for k, v in self.deviations().items()}
        for k in ("q4", "q5"):
            peaks[f"{k}_deg"] = math.degrees(peaks.pop(k))
        return peaks

    def landing_metrics(self) -> dict[str, Any]:
        """A landing's figures of merit (``results.landing.landing_metrics``): the
        touchdown's time, speeds, offset, attitude and tension; empty for a run that is not a
        landing (``[maneuver] type = "tethered_landing"``).

        Returns
        -------
        dict of str to Any
            ``results.landing.landing_metrics``'s keys and units.
        """
        from .landing import landing_metrics

        return landing_metrics(self)

    def deck_motion(self) -> dict[str, float]:
        """The NATO STANAG 4154 deck-motion figures of a run over a ship (``[base] motion =
        "ship"``): RMS of the recorded ``deck_roll``, ``deck_pitch`` and of the pad's
        vertical velocity ``base_v3`` over all samples (``base.ship.deck_motion_rms``;
        the standard's limits 2.5 deg, 1.5 deg, 1.0 m/s).

        Returns
        -------
        dict of str to float
            ``deck_roll_rms`` [deg], ``deck_pitch_rms`` [deg], ``deck_heave_velocity_rms``
            [m/s]; empty without the deck's columns (no ship).
        """
        from ..base.ship import deck_motion_rms

        names = (*DECK_ATTITUDE_COLUMNS[:2], BASE_VELOCITY_COLUMNS[2])
        if not all(name in self.extra for name in names):
            return {}
        return deck_motion_rms(*(self.extra[name] for name in names))

    def _summary_rows(self) -> list[tuple[str, str]]:
        duration = float(self.time[-1] - self.time[0]) if self.time.size else 0.0
        dt = self.configuration.get("control", {}).get("dt", "?")
        rows = [
            ("name", self.name),
            ("configuration", str(self.configuration.get("configuration", "?"))),
            ("status", f"{int(self.status)} ({self.message})"),
            ("duration", f"{duration:g} s (ended at t = {self.end_time:g} s)"),
            ("samples", f"{self.time.size} (dt = {dt} s)"),
        ]
        landing = self.landing_metrics()  # a descent: its touchdown, not a hover's peaks
        peaks = [
            f"{k.removesuffix('_deg')} {_number(v, 'deg' if k.endswith('_deg') else 'm')}"
            for k, v in ({} if landing else self.peak_deviations()).items()
        ]
        if peaks:
            rows.append(("peak |deviation|", ", ".join(peaks)))
        if landing:
            from .landing import landing_rows

            rows += landing_rows(landing)
        deck = self.deck_motion()
        if deck:
            rows.append((
                "deck motion (RMS)",
                f"roll {_number(deck['deck_roll_rms'], 'deg')}, pitch "
                f"{_number(deck['deck_pitch_rms'], 'deg')}, heave velocity "
                f"{_number(deck['deck_heave_velocity_rms'], 'm/s')} (STANAG 4154: 2.5 deg, "
                "1.5 deg, 1 m/s)",
            ))  # fmt: skip
        return rows

    def deviations(self) -> dict[str, np.ndarray]:
        """Deviations from the run's own trim.

        Returns
        -------
        dict of str to numpy.ndarray
            ``q1``, ``q2``, ``q3`` (m), ``q4``, ``q5`` (rad), each of shape (n,).
        """
        d = {n: self.outputs[:, i] - self.trim_output[i] for i, n in enumerate(POSITION)}
        d["q4"] = self.states[:, 0] - self.trim_state[0]
        d["q5"] = self.states[:, 1] - self.trim_state[1]
        return d

    def columns(self) -> dict[str, np.ndarray]:
        """All sampled signals as named columns, in the order of the run's CSV.

        Returns
        -------
        dict of str to numpy.ndarray
            Column name (``t`` first) -> its samples, shape (n,).
        """
        cols: dict[str, np.ndarray] = {"t": self.time}
        for i, n in enumerate(STATE_NAMES):
            cols[n] = self.states[:, i]
        for i, n in enumerate(OUTPUT_NAMES[:3]):
            cols[n] = self.outputs[:, i]
        for i, n in enumerate(INPUT_NAMES):
            cols[n] = self.inputs[:, i]
        for i, n in enumerate(_FEEDFORWARD, start=1):
            cols[n] = self.feedforward[:, i]
        cols["TC"] = self.tension
        cols["RC"] = self.reel_rate
        for i, n in enumerate(_WIND):
            cols[n] = self.wind[:, i]
        for n, v in self.extra.items():
            cols[n] = v
        return cols

    def column_units(self) -> dict[str, str]:
        """The unit of each of ``columns()``.

        Returns
        -------
        dict of str to str
            Column name -> unit (``RESULT_UNITS``; an estimate ``<name>_est`` has its
            signal's unit; "" for an extra column of unknown unit).
        """
        units = {}
        for name in self.columns():
            base = name.removesuffix(_ESTIMATE_SUFFIX)
            units[name] = RESULT_UNITS.get(name, EXTRA_UNITS.get(name, RESULT_UNITS.get(base, "")))
        return units

    def column_descriptions(self) -> dict[str, str]:
        """What each of ``columns()`` means.

        Returns
        -------
        dict of str to str
            Column name -> description (``RESULT_DESCRIPTIONS``; "estimate of ..." for an
            estimate ``<name>_est``; "" for an extra column not described there).
        """
        out = {}
        for name in self.columns():
            base = name.removesuffix(_ESTIMATE_SUFFIX)
            if name in RESULT_DESCRIPTIONS:
                out[name] = RESULT_DESCRIPTIONS[name]
            elif base != name and base in RESULT_DESCRIPTIONS:
                out[name] = "estimate of " + RESULT_DESCRIPTIONS[base]
            else:
                out[name] = ""
        return out

    def to_dataframe(self) -> Any:
        """The sampled signals as a pandas DataFrame (``pip install tetherheli[data]``).

        Returns
        -------
        pandas.DataFrame
            Index ``t`` (s), one column per ``columns()`` entry after t (the run CSV's
            columns, in order), units in ``df.attrs["units"]``, and ``attrs`` ``scenario``
            (name), ``tetherheli_version``, ``status``, ``method``.
        """
        pd = _optional("pandas")
        cols = self.columns()
        index = pd.Index(np.array(cols.pop("t")), name="t")
        df = pd.DataFrame({n: np.array(v) for n, v in cols.items()}, index=index)
        df.attrs.update(self._attrs())
        return df

    def to_xarray(self) -> Any:
        """The sampled signals as an xarray Dataset (``pip install tetherheli[data]``).

        Returns
        -------
        xarray.Dataset
            Dimension ``t`` (s), one variable per column of ``columns()`` after t, each with
            its ``units`` attribute, and the dataset attributes of ``to_dataframe`` (units
            aside).
        """
        xr = _optional("xarray")
        cols = self.columns()
        units = self.column_units()
        t = np.array(cols.pop("t"))
        attrs = self._attrs()
        attrs.pop("units")
        return xr.Dataset(
            {n: ("t", np.array(v), {"units": units[n]}) for n, v in cols.items()},
            coords={"t": ("t", t, {"units": units["t"]})},
            attrs=attrs,
        )

    def _attrs(self) -> dict[str, Any]:
        return {
            "units": self.column_units(),
            "scenario": self.name,
            "tetherheli_version": self.version,
            "status": int(self.status),
            "method": self.method,
        }

    def to_csv(self, path: str | Path) -> Path:
        """Write the time series as CSV (SI units; header row), atomically, streamed in blocks
        of rows (a long run is not held a second time as text).

        Parameters
        ----------
        path : str or pathlib.Path
            The file to write.

        Returns
        -------
        pathlib.Path
            The file written.
        """
        return write_csv(path, self.columns())

    def to_parquet(self, path: str | Path) -> Path:
        """Write the time series as Apache Parquet, atomically: the columns of ``to_csv``
        (``t`` first), float64. Each Arrow field carries its ``units`` and ``description``
        in its metadata, readable by pyarrow alone
        (``pyarrow.parquet.read_schema(path).field("q1").metadata[b"units"]`` is ``b"m"``);
        pandas' ``df.attrs`` (units among them) round-trip through ``pandas.read_parquet``.
        Needs pandas and pyarrow (``pip install tetherheli[data]``).

        Parameters
        ----------
        path : str or pathlib.Path
            The file to write.

        Returns
        -------
        pathlib.Path
            The file written.
        """
        return write_parquet(
            path, self.to_dataframe().reset_index(), self.column_units(), self.column_descriptions()
        )

    def to_mcap(self, path: str | Path) -> Path:
        """Write the run as MCAP, atomically (``results.mcap``): every column of ``to_csv``
        as JSON ``/signals`` messages, the vehicle's and the base's frames as
        ``foxglove.FrameTransform`` on ``/tf`` and the deck, body, tether and wind as
        ``foxglove.SceneUpdate`` on ``/scene``, for Foxglove (or any MCAP reader). Needs the
        ``mcap`` package (``pip install tetherheli[replay]``).

        Parameters
        ----------
        path : str or pathlib.Path
            The file to write.

        Returns
        -------
        pathlib.Path
            The file written.
        """
        from .mcap import write_mcap

        return write_mcap(
            path,
            self.columns(),
            self.column_units(),
            self.column_descriptions(),
            self.configuration,
            tethered=self.configuration.get("configuration") == "tethered",
        )

    def metadata(self) -> dict[str, Any]:
        """What is recorded next to the results.

        Returns
        -------
        dict
            Version, status, message, tether release, winch limit, method, configuration,
            trim and units.
        """
        return {
            "tetherheli_version": self.version,
            "status": self.status,
            "message": self.message,
            "tether_release": self.release_info(),
            "winch_limit": self.winch_limit,
            "touchdown": self.touchdown,
            "method": self.method,
            "configuration": self.configuration,
            "trim": {
                "state": dict(zip(STATE_NAMES, map(float, self.trim_state), strict=True)),
                "input": dict(zip(INPUT_NAMES, map(float, self.trim_input), strict=True)),
                "output": dict(zip(OUTPUT_NAMES, map(float, self.trim_output), strict=True)),
            },
            "units": {
                **dict(zip(STATE_NAMES, STATE_UNITS, strict=True)),
                **dict(zip(INPUT_NAMES, INPUT_UNITS, strict=True)),
                **dict(zip(OUTPUT_NAMES, OUTPUT_UNITS, strict=True)),
                "t": "s",
                "TC": "N",
                "RC": "m/s",
                "Fw": "N",
            },
        }

    def save(
        self, directory: str | Path, stem: str | None = None, *, format: str = "csv"
    ) -> dict[str, Path]:
        """Write the time series ``<stem>.csv`` (or ``.parquet``, ``.mcap``) and ``<stem>.json``
        (configuration, trim, version) into directory; ``load_result(directory, stem)`` reads
        them back.

        Parameters
        ----------
        directory : str or pathlib.Path
            The directory (created with its parents if missing).
        stem : str, optional
            The files' stem (default: the scenario's name).
        format : {"csv", "parquet", "mcap"}, optional
            The time series' format (``RESULT_FORMATS``).

        Returns
        -------
        dict of str to pathlib.Path
            ``{format: path of the time series, "json": path of the metadata}``.

        Raises
        ------
        OutputPathError
            ``directory`` cannot be created (a file is in the way, no permission): one line
            naming it.
        """
        check_result_format(format)
        return self._save(directory, stem, format=format)

    def _save(
        self, directory: str | Path, stem: str | None = None, *, format: str = "csv"
    ) -> dict[str, Path]:
        # ``save`` of a format the caller checked (a writer, at its entry)
        directory = Path(directory)
        try:
            directory.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise OutputPathError(
                f"directory {str(directory)!r} cannot be created ({exc.strerror or exc}: "
                f"{exc.filename}); allowed: an existing directory or a path where one can be made"
            ) from None
        stem = stem or self.name
        series = directory / f"{stem}.{format}"
        if format == "parquet":
            self.to_parquet(series)
        elif format == "mcap":
            self.to_mcap(series)
        else:
            self.to_csv(series)
        meta_path = directory / f"{stem}.json"
        write_json(meta_path, self.metadata())
        return {format: series, "json": meta_path}


def winch_limit_info(time: float, which: float, winch: Any) -> dict[str, Any] | None:
    """The first stop of the reel at a payout limit as plain data (``SimulationResult``'s
    ``winch_limit``), from the engine's summary slots ``winch_limit_time``, ``winch_limit``.

    Parameters
    ----------
    time : float
        When the natural length reached the limit [s]; NaN: no limit reached.
    which : float
        -1 ``min_length``, +1 ``max_length`` (NaN: none).
    winch : WinchSettings
        The run's ``[winch]`` table (the limit's value).

    Returns
    -------
    dict or None
        ``{"time", "limit", "length"}`` (s, the key's name, m), or None.
    """
    if not math.isfinite(float(time)) or not math.isfinite(float(which)):
        return None
    limit = WINCH_LIMITS[int(which)]
    return {"time": float(time), "limit": limit, "length": float(getattr(winch, limit))}


def load_result(directory: str | Path, stem: str | None = None) -> SimulationResult:
    """Read a run saved by ``SimulationResult.save(directory, stem)``.

    Parameters
    ----------
    directory : str or pathlib.Path
        The result directory, or the path of one run's ``<stem>.csv``, ``<stem>.parquet``,
        ``<stem>.mcap`` or ``<stem>.json`` (then ``stem`` is that file's).
    stem : str, optional
        Which run (``list_results``); None when the directory holds exactly one.

    Returns
    -------
    SimulationResult
        Equal to the saved one in every array (the CSV holds each float exactly), trim,
        status, tether release, method, version and configuration. Columns 0 and 3 of
        ``feedforward`` are not saved and come back as zeros (eq 55's feed-forward acts on
        tMR,1 and tMR,2 only); CSV columns beyond ``RESULT_COLUMNS`` come back in ``extra``.

    Raises
    ------
    ParameterError
        If the directory is missing or holds no (or, with ``stem=None``, several) runs, or a
        file is malformed (one line naming the file and what is expected).
    """
    return SimulationResult(**read_result_fields(directory, stem))
