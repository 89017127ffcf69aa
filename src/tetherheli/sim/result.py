"""The result of a closed-loop run: a frozen object that plotting and export only read."""

from __future__ import annotations

import csv
import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .._io import (
    OutputPathError,
    atomic_open,
    atomic_path,
    atomic_write_bytes,
    atomic_write_text,
)
from ..errors import ParameterError
from ..names import (
    INPUT,
    INPUT_UNITS,
    OUTPUT,
    OUTPUT_UNITS,
    POSITION,
    TETHERED_STATE,
    TETHERED_STATE_UNITS,
    WIND,
)
from ..status import FALLBACK_COLUMN, Status, ran_to_end, release_sentence, status_message

__all__ = [
    "DRUM_COLUMNS",
    "EXTRA_UNITS",
    "RESULT_COLUMNS",
    "RESULT_DESCRIPTIONS",
    "RESULT_FORMATS",
    "RESULT_UNITS",
    "SimulationResult",
    "atomic_write_bytes",
    "atomic_write_text",
    "check_result_format",
    "list_results",
    "load_result",
    "winch_limit_info",
]

STATE_NAMES, STATE_UNITS = TETHERED_STATE, TETHERED_STATE_UNITS
INPUT_NAMES, OUTPUT_NAMES = INPUT, OUTPUT
_CSV_BLOCK_ROWS = 4096
_FEEDFORWARD = ("C1_ffwd", "C2_ffwd")  # columns 1 and 2 of the feed-forward (eq 55)
_WIND = WIND
#: The columns of every result CSV, in order (``SimulationResult.columns``; extra signals such
#: as sensor estimates follow them).
RESULT_COLUMNS: tuple[str, ...] = (
    "t",
    *STATE_NAMES,
    *OUTPUT_NAMES[:3],
    *INPUT_NAMES,
    *_FEEDFORWARD,
    "TC",
    "RC",
    *_WIND,
)
#: The unit of every column of ``RESULT_COLUMNS`` (from ``names``; the feed-forward columns are
#: torques about F1, F2 like tMR1, tMR2 (eq 55), the wind columns a force on HO).
RESULT_UNITS: dict[str, str] = {
    "t": "s",
    **dict(zip(STATE_NAMES, STATE_UNITS, strict=True)),
    **dict(zip(OUTPUT_NAMES, OUTPUT_UNITS, strict=True)),
    **dict(zip(INPUT_NAMES, INPUT_UNITS, strict=True)),
    **dict(zip(_FEEDFORWARD, INPUT_UNITS[1:3], strict=True)),
    "TC": "N",
    "RC": "m/s",
    **dict.fromkeys(_WIND, "N"),
}
#: The extra column of a lumped tether's run (``[tether] model = "lumped"``): the tension at
#: the winch, which the load cell measures (``TC`` is the tension at P); a massless run has
#: one tension and writes no such column (``SimulationResult.tension_ground``).
TENSION_GROUND_COLUMN = "TC_ground"
RESULT_UNITS[TENSION_GROUND_COLUMN] = "N"
#: The drum winch's extra columns (``[winch] model = "drum"``): the drum's speed at each sample
#: and the motor torque averaged over the sample that follows it, with their units.
DRUM_COLUMNS: tuple[str, ...] = ("drum_speed", "motor_torque")
EXTRA_UNITS: dict[str, str] = {"drum_speed": "rad/s", "motor_torque": "N m"}
#: What each column means (docs/notation.md), written with its unit into a Parquet file's
#: Arrow field metadata (``SimulationResult.to_parquet``); an estimate ``<name>_est`` is
#: "estimate of" its signal's description.
RESULT_DESCRIPTIONS: dict[str, str] = {
    "t": "time since the start of the run",
    "q1": "position of HO in N, axis n1 (eq 4)",
    "q2": "position of HO in N, axis n2 (eq 4)",
    "q3": "position of HO in N, axis n3 (eq 4)",
    "q4": "roll of F, body-1-2-3 Euler angle (Table I)",
    "q5": "pitch of F, body-1-2-3 Euler angle (Table I)",
    "q6": "yaw of F, body-1-2-3 Euler angle (Table I)",
    "q7": "tether angle q7",
    "q8": "tether angle q8",
    "q9": "tether length q9",
    "u1": "velocity of HO in N, component 1 (eq 7)",
    "u2": "velocity of HO in N, component 2 (eq 7)",
    "u3": "velocity of HO in N, component 3 (eq 7)",
    "u4": "angular velocity of F in N, in F, component 1 (eq 8)",
    "u5": "angular velocity of F in N, in F, component 2 (eq 8)",
    "u6": "angular velocity of F in N, in F, component 3 (eq 8)",
    "LN": "tether natural length (eqs 28, 37)",
    "fMR3": "main rotor thrust fMR,3 (input, eq 42)",
    "tMR1": "main rotor torque tMR,1 (input, eq 42)",
    "tMR2": "main rotor torque tMR,2 (input, eq 42)",
    "fTR2": "tail rotor force fTR,2 (input, eq 42)",
    "C1_ffwd": "tension feed-forward torque about F1 (eq 55)",
    "C2_ffwd": "tension feed-forward torque about F2 (eq 55)",
    "TC": "tether tension at P (eq 28)",
    "RC": "reel rate dLN/dt (eq 37)",
    "Fw1": "wind force on HO, component 1",
    "Fw2": "wind force on HO, component 2",
    "Fw3": "wind force on HO, component 3",
    TENSION_GROUND_COLUMN: "tether tension at the winch (the load cell)",
    "drum_speed": "drum speed of the winch",
    "motor_torque": "winch motor torque, averaged over the following sample",
}
#: File formats of a saved run's time series (``SimulationResult.save``): ``<stem>.csv`` (the
#: default, text) or ``<stem>.parquet`` (Apache Parquet through pandas + pyarrow, the
#: ``data`` extra); ``load_result`` reads either.
RESULT_FORMATS = ("csv", "parquet")
#: Extra columns named ``<output>_est`` (the controller's estimate) carry the output's unit.
_ESTIMATE_SUFFIX = "_est"
_RESULT_HINT = (
    "<stem>.csv (or .parquet) + <stem>.json result pairs written by SimulationResult.save"
)


def check_result_format(fmt: str) -> str:
    """``fmt`` if it is one of ``RESULT_FORMATS`` whose packages are installed (Parquet needs
    pandas and pyarrow), else a one-line ``ParameterError``: checked before a run, not after
    it.

    Parameters
    ----------
    fmt : str
        The requested result format (``RESULT_FORMATS``, e.g. "csv" or "parquet").

    Returns
    -------
    str
        ``fmt``, unchanged.

    Raises
    ------
    ParameterError
        An unknown format, or Parquet without pandas and pyarrow.
    """
    if fmt not in RESULT_FORMATS:
        raise ParameterError("format", fmt, f"one of {RESULT_FORMATS}")
    if fmt == "parquet":
        try:
            _optional("pandas")
            _optional("pyarrow")
        except ImportError as exc:
            raise ParameterError("format", fmt, f"'csv' here ({exc})") from None
    return fmt


@dataclass(frozen=True)
class SimulationResult:
    """A sampled closed-loop run (one row per control sample t_k = k dt).

    ``simulate`` builds it; plotting and export only read it.

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
        0 on success, else a failure code; ``message`` says which.
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
        """True when the run completed without hitting a stop condition."""
        return self.status == Status.OK

    @property
    def message(self) -> str:
        """What happened: the status, with the tether release and the fraction of samples a
        solver's fallback flew (``status.solver_status``) if there were any."""
        fallbacks = self.extra.get(FALLBACK_COLUMN)
        fraction = None if fallbacks is None or fallbacks.size == 0 else float(fallbacks.mean())
        return status_message(self.status, self.release_time, fraction, self.winch_limit)

    @property
    def released(self) -> bool:
        """True when the safety device released the tether during the run."""
        return self.release_time is not None

    @property
    def end_time(self) -> float:
        """Where the run ended [s]: the last sample of a completed run; for a failed run the
        control sample at which the failure was detected (the first one not recorded: its
        state failed the checks, or the integration towards it failed)."""
        dt = self.configuration.get("control", {}).get("dt")
        if ran_to_end(self.status) or dt is None:
            return float(self.time[-1]) if self.time.size else 0.0
        return self.time.size * float(dt)

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
        cols = self.columns()
        columns = list(cols.values())
        with atomic_open(Path(path)) as fh:
            writer = csv.writer(fh, lineterminator="\n")
            writer.writerow(cols.keys())
            for start in range(0, self.time.size, _CSV_BLOCK_ROWS):
                block = np.column_stack([c[start : start + _CSV_BLOCK_ROWS] for c in columns])
                writer.writerows([repr(float(v)) for v in row] for row in block)
        return Path(path)

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
        pa = _optional("pyarrow")
        import pyarrow.parquet as pq

        df = self.to_dataframe().reset_index()
        table = pa.Table.from_pandas(df, preserve_index=False)
        units, descriptions = self.column_units(), self.column_descriptions()
        fields = [
            f.with_metadata({"units": units[f.name], "description": descriptions[f.name]})
            for f in table.schema
        ]
        # pandas.DataFrame.to_parquet keeps df.attrs under this key; read_parquet restores them
        metadata = {**(table.schema.metadata or {}), b"PANDAS_ATTRS": json.dumps(df.attrs)}
        table = pa.Table.from_arrays(table.columns, schema=pa.schema(fields, metadata=metadata))
        with atomic_path(Path(path)) as tmp:
            pq.write_table(table, tmp)
        return Path(path)

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
        """Write the time series ``<stem>.csv`` (or ``<stem>.parquet``) and ``<stem>.json``
        (configuration, trim, version) into directory; ``load_result(directory, stem)`` reads
        them back.

        Parameters
        ----------
        directory : str or pathlib.Path
            The directory (created with its parents if missing).
        stem : str, optional
            The files' stem (default: the scenario's name).
        format : {"csv", "parquet"}, optional
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
        else:
            self.to_csv(series)
        meta_path = directory / f"{stem}.json"
        atomic_write_text(meta_path, json.dumps(self.metadata(), indent=2) + "\n")
        return {format: series, "json": meta_path}


def _optional(module: str) -> Any:
    """Import an optional dependency, or raise a one-line error naming the package."""
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError:
        raise ImportError(
            f"{module} is needed for this format and is not installed: "
            f"pip install {module} (or tetherheli[data])"
        ) from None


# --- reading saved results ---------------------------------------------------------------------


def _result_directory(directory: str | Path) -> Path:
    path = Path(directory)
    if not path.is_dir():
        raise ParameterError(
            "directory", str(path), f"an existing directory holding {_RESULT_HINT}"
        )
    return path


def _read_metadata(path: Path) -> dict[str, Any]:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ParameterError(
            "metadata", path.name, f"readable JSON ({exc})", source=str(path)
        ) from None
    if not isinstance(data, dict) or not isinstance(data.get("configuration"), dict):
        raise ParameterError(
            "metadata", path.name, "a JSON object with a 'configuration' table", source=str(path)
        )
    return data


def _is_result(json_path: Path) -> bool:
    try:
        _read_metadata(json_path)
    except ParameterError:
        return False
    return True


def list_results(directory: str | Path) -> list[str]:
    """Stems of the saved runs in a directory, sorted.

    A run is a ``<stem>.csv`` or ``<stem>.parquet`` with a ``<stem>.json`` beside it whose
    JSON object has a ``configuration`` table (as ``SimulationResult.save`` writes), in the
    directory or one folder below it (``<name>/<stem>``, as ``tetherheli simulate`` writes
    several runs); other files are ignored.

    Parameters
    ----------
    directory : str or pathlib.Path
        The result directory.

    Returns
    -------
    list of str
        The stems (``<name>/<stem>`` for a run one folder below).

    Raises
    ------
    ParameterError
        If the directory does not exist.
    """
    path = _result_directory(directory)
    stems = set()
    for fmt in RESULT_FORMATS:
        for series in [*path.glob(f"*.{fmt}"), *path.glob(f"*/*.{fmt}")]:
            json_path = series.with_suffix(".json")
            if json_path.is_file() and _is_result(json_path):
                stems.add(series.relative_to(path).with_suffix("").as_posix())
    return sorted(stems)


def _series_path(path: Path, stem: str) -> Path:
    """The time-series file of a run: ``<stem>.csv`` or ``<stem>.parquet``, not both."""
    found = [path / f"{stem}.{fmt}" for fmt in RESULT_FORMATS if (path / f"{stem}.{fmt}").is_file()]
    if len(found) != 1:
        names = " and ".join(p.name for p in found)
        raise ParameterError(
            "run", stem, f"one time-series file per run, not both {names}", source=str(path)
        )
    return found[0]


def _read_table(path: Path) -> tuple[list[str], np.ndarray]:
    """The header and the values (rows x columns) of a run's time-series file."""
    if path.suffix == ".parquet":
        pd = _optional("pandas")
        _optional("pyarrow")
        try:
            df = pd.read_parquet(path, engine="pyarrow")
            return [str(c) for c in df.columns], df.to_numpy(dtype=float)
        except (OSError, ValueError, TypeError) as exc:
            reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            raise ParameterError(
                "parquet", path.name, f"a Parquet table of numbers ({reason})", source=str(path)
            ) from None
    return _read_csv_table(path)


def _read_csv_table(path: Path) -> tuple[list[str], np.ndarray]:
    """The header and the values of a run CSV."""
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ParameterError(
            "csv", path.name, f"a readable UTF-8 CSV file ({exc})", source=str(path)
        ) from None
    rows = list(csv.reader(text.splitlines()))
    src = str(path)
    if not rows:
        raise ParameterError("csv", "empty file", "a header row and data rows", source=src)
    header = [h.strip() for h in rows[0]]
    _check_header(header, "csv header", src)
    body = [r for r in rows[1:] if r]
    values = np.empty((len(body), len(header)))
    for k, row in enumerate(body):
        if len(row) != len(header):
            raise ParameterError(
                f"csv line {k + 2}", f"{len(row)} fields", f"{len(header)} fields", source=src
            )
        try:
            values[k] = [float(v) for v in row]
        except ValueError:
            raise ParameterError(
                f"csv line {k + 2}", ",".join(row)[:60], "numbers", source=src
            ) from None
    return header, values


def _read_columns(path: Path) -> dict[str, np.ndarray]:
    """The time series' columns by name (``<stem>.csv`` or ``.parquet``): every one of
    ``RESULT_COLUMNS`` present and finite, times increasing."""
    header, values = _read_table(path)
    src = str(path)
    csv_file = path.suffix == ".csv"
    _check_header(header, "csv header" if csv_file else "parquet columns", src)
    cols = {name: values[:, j] for j, name in enumerate(header)}
    for name in RESULT_COLUMNS:
        bad = np.flatnonzero(~np.isfinite(cols[name]))
        if bad.size:
            where = f"csv line {bad[0] + 2}" if csv_file else f"parquet row {bad[0]}"
            raise ParameterError(
                f"{where} column {name}",
                cols[name][bad[0]],
                "a finite number",
                source=src,
            )
    if np.any(np.diff(cols["t"]) <= 0.0):
        raise ParameterError("column t", "not increasing", "strictly increasing times", source=src)
    return cols


def _check_header(header: list[str], field: str, source: str) -> None:
    missing = [c for c in RESULT_COLUMNS if c not in header]
    if missing:
        raise ParameterError(
            field, ",".join(missing), f"columns {', '.join(RESULT_COLUMNS)}", source=source
        )


def _trim(meta: dict[str, Any], part: str, names: tuple[str, ...], source: str) -> np.ndarray:
    table = meta.get("trim", {}).get(part) if isinstance(meta.get("trim"), dict) else None
    try:
        return np.array([float(table[k]) for k in names])  # type: ignore[index]
    except (KeyError, TypeError, ValueError):
        raise ParameterError(
            f"trim.{part}", table, f"a table of numbers {', '.join(names)}", source=source
        ) from None


def _release(meta: dict[str, Any], source: str) -> tuple[float | None, float | None]:
    info = meta.get("tether_release")
    if info is None:
        return None, None
    try:
        return float(info["time"]), float(info["tension"])
    except (KeyError, TypeError, ValueError):
        raise ParameterError(
            "tether_release", info, "null or a table with numbers time, tension", source=source
        ) from None


#: ``winch_limit``'s codes (``layout.HELD_LIMIT_WHICH``) and the ``[winch]`` keys they name
WINCH_LIMITS = {-1: "min_length", 1: "max_length"}


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


def _winch_limit(meta: dict[str, Any], source: str) -> dict[str, Any] | None:
    info = meta.get("winch_limit")
    if info is None:
        return None
    try:
        out = {"time": float(info["time"]), "limit": info["limit"], "length": float(info["length"])}
    except (KeyError, TypeError, ValueError):
        out = None
    if out is None or out["limit"] not in WINCH_LIMITS.values():
        raise ParameterError(
            "winch_limit", info, "null or a table with time [s], limit ('min_length' or "
            "'max_length') and length [m]", source=source,
        )  # fmt: skip
    return out


def load_result(directory: str | Path, stem: str | None = None) -> SimulationResult:
    """Read a run saved by ``SimulationResult.save(directory, stem)``.

    Parameters
    ----------
    directory : str or pathlib.Path
        The result directory, or the path of one run's ``<stem>.csv``, ``<stem>.parquet`` or
        ``<stem>.json`` (then ``stem`` is that file's).
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
    given = Path(directory)
    if stem is None and given.is_file() and given.suffix[1:] in (*RESULT_FORMATS, "json"):
        directory, stem = given.parent, given.stem
    path = _result_directory(directory)
    stems = list_results(path)
    if stem is None:
        if not stems:
            raise ParameterError("directory", str(path), f"a directory with {_RESULT_HINT}")
        if len(stems) > 1:
            raise ParameterError(
                "stem", None, f"one of {stems} (the directory holds several)", source=str(path)
            )
        stem = stems[0]
    elif stem not in stems:  # a name, never a path of the user's choosing
        raise ParameterError("stem", stem, f"one of {stems}", source=str(path))
    json_path = path / f"{stem}.json"
    source = str(json_path)
    meta = _read_metadata(json_path)
    configuration = meta["configuration"]
    kind = configuration.get("configuration")
    if kind not in ("free", "tethered"):
        raise ParameterError(
            "configuration.configuration", kind, "'free' or 'tethered'", source=source
        )
    status = meta.get("status", int(Status.OK))
    if isinstance(status, bool) or not isinstance(status, int):
        raise ParameterError("status", status, "an integer status code", source=source)
    trim_state = _trim(meta, "state", STATE_NAMES, source)
    trim_input = _trim(meta, "input", INPUT_NAMES, source)
    trim_output = _trim(meta, "output", OUTPUT_NAMES, source)
    release_time, release_tension = _release(meta, source)
    cols = _read_columns(_series_path(path, stem))
    n = cols["t"].size
    cols = {name: np.ascontiguousarray(v) for name, v in cols.items()}
    states = np.column_stack([cols[name] for name in STATE_NAMES])
    feedforward = np.zeros((n, 4))
    for i, name in enumerate(_FEEDFORWARD, start=1):
        feedforward[:, i] = cols[name]
    q6 = states[:, STATE_NAMES.index(OUTPUT_NAMES[3])]
    return SimulationResult(
        time=cols["t"],
        states=states,
        outputs=np.column_stack([*(cols[name] for name in OUTPUT_NAMES[:3]), q6]),
        inputs=np.column_stack([cols[name] for name in INPUT_NAMES]),
        feedforward=feedforward,
        tension=cols["TC"],
        reel_rate=cols["RC"],
        wind=np.column_stack([cols[name] for name in _WIND]),
        trim_state=trim_state,
        trim_input=trim_input,
        trim_output=trim_output,
        status=status,
        configuration=configuration,
        version=str(meta.get("tetherheli_version", "unknown")),
        method=str(meta.get("method", "rk4")),
        extra={name: v for name, v in cols.items() if name not in RESULT_COLUMNS},
        release_time=release_time,
        release_tension=release_tension,
        winch_limit=_winch_limit(meta, source),
    )
