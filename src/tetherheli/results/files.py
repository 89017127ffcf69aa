"""The files of a saved run: its columns (names, units, descriptions, the CSV's order), the
formats (CSV, Parquet), their writing, and the reading and checking of a saved run.

``results.result`` holds the ``SimulationResult`` these files store and re-exports the public
names below; ``load_result`` builds one from ``read_result_fields``.
"""

from __future__ import annotations

import csv
import io
import json
import re
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .._io import atomic_open, atomic_path, atomic_write_text, json_text, read_json
from ..errors import ParameterError
from ..names import (
    INPUT,
    INPUT_UNITS,
    OUTPUT,
    OUTPUT_UNITS,
    TETHERED_STATE,
    TETHERED_STATE_UNITS,
    WIND,
)
from ..status import Status

__all__ = [
    "BASE_POSITION_COLUMNS",
    "BASE_VELOCITY_COLUMNS",
    "DECK_ATTITUDE_COLUMNS",
    "DECK_RATE_COLUMNS",
    "DRUM_COLUMNS",
    "EXTRA_UNITS",
    "GEAR_CONTACT_PREFIX",
    "GEAR_FORCE_COLUMN",
    "GEAR_PENETRATION_PREFIX",
    "RESULT_COLUMNS",
    "RESULT_DESCRIPTIONS",
    "RESULT_FORMATS",
    "RESULT_UNITS",
    "TABLE_FORMATS",
    "TENSION_GROUND_COLUMN",
    "WINCH_LIMITS",
    "check_result_format",
    "list_results",
    "read_result_fields",
    "table_csv",
    "write_csv",
    "write_parquet",
    "write_table",
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
#: A moving base's extra columns ([base]): the winch point's position and velocity
#: in N at each sample; over a moving base the states and outputs are relative to it, so HO in
#: N is (q1, q2, q3) + (base_n1, base_n2, base_n3).
BASE_POSITION_COLUMNS: tuple[str, ...] = ("base_n1", "base_n2", "base_n3")
BASE_VELOCITY_COLUMNS: tuple[str, ...] = ("base_v1", "base_v2", "base_v3")
#: A ship's extra columns ([base] motion = "ship", ``base.ship.ShipBase.attitude``): the
#: deck's roll, pitch and yaw (small rotations about the ship's x, y, z) and their rates.
DECK_ATTITUDE_COLUMNS: tuple[str, ...] = ("deck_roll", "deck_pitch", "deck_yaw")
DECK_RATE_COLUMNS: tuple[str, ...] = ("deck_roll_rate", "deck_pitch_rate", "deck_yaw_rate")
#: A landing gear's extra columns ([landing_gear], a landing's run): the deck's total normal
#: force on the gear, and per gear point i its penetration and contact flag (1: in contact).
GEAR_FORCE_COLUMN = "gear_force"
GEAR_PENETRATION_PREFIX = "gear_penetration"
GEAR_CONTACT_PREFIX = "gear_contact"
EXTRA_UNITS: dict[str, str] = {
    GEAR_FORCE_COLUMN: "N",
    **{f"{GEAR_PENETRATION_PREFIX}{i}": "m" for i in range(16)},
    "drum_speed": "rad/s",
    "motor_torque": "N m",
    **dict.fromkeys(BASE_POSITION_COLUMNS, "m"),
    **dict.fromkeys(BASE_VELOCITY_COLUMNS, "m/s"),
    **dict.fromkeys(DECK_ATTITUDE_COLUMNS, "rad"),
    **dict.fromkeys(DECK_RATE_COLUMNS, "rad/s"),
}
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
    **{f"base_n{i}": f"position of the winch's base in N, axis n{i}" for i in (1, 2, 3)},
    **{f"base_v{i}": f"velocity of the winch's base in N, axis n{i}" for i in (1, 2, 3)},
    **{name: f"the ship's {name.removeprefix('deck_')} (about its {axis} axis, small angle)"
       for name, axis in zip(DECK_ATTITUDE_COLUMNS, "xyz", strict=True)},
    **{name: f"the rate of the ship's {name.removeprefix('deck_').removesuffix('_rate')}"
       for name in DECK_RATE_COLUMNS},
}  # fmt: skip
#: File formats of a saved run's time series (``SimulationResult.save``): ``<stem>.csv`` (the
#: default, text), ``<stem>.parquet`` (Apache Parquet through pandas + pyarrow, the ``data``
#: extra) or ``<stem>.mcap`` (MCAP: the signals and a 3-D scene for Foxglove, through the
#: ``mcap`` package, the ``replay`` extra; ``results.mcap``); ``load_result`` reads each.
RESULT_FORMATS = ("csv", "parquet", "mcap")
#: The formats of a table of many runs' results (``montecarlo --format``): no MCAP.
TABLE_FORMATS = ("csv", "parquet")
#: Extra columns named ``<output>_est`` (the controller's estimate) carry the output's unit.
_ESTIMATE_SUFFIX = "_est"
_RESULT_HINT = (
    "<stem>.csv (or .parquet, .mcap) + <stem>.json result pairs written by SimulationResult.save"
)


def check_result_format(fmt: str, formats: tuple[str, ...] = RESULT_FORMATS) -> str:
    """``fmt`` if it is one of ``formats`` whose packages are installed (Parquet needs pandas
    and pyarrow, MCAP the ``mcap`` package), else a one-line ``ParameterError``: checked
    before a run, not after it.

    Parameters
    ----------
    fmt : str
        The requested result format (``RESULT_FORMATS``, e.g. "csv" or "parquet").
    formats : tuple of str, optional
        The formats allowed here (``TABLE_FORMATS`` for a table of many runs).

    Returns
    -------
    str
        ``fmt``, unchanged.

    Raises
    ------
    ParameterError
        An unknown format, or one whose packages are not installed.
    """
    if fmt not in formats:
        raise ParameterError("format", fmt, f"one of {formats}")
    needs = {"parquet": ("pandas", "pyarrow"), "mcap": ("mcap",)}.get(fmt, ())
    try:
        for module in needs:
            _optional(module)
    except ImportError as exc:
        raise ParameterError("format", fmt, f"'csv' here ({exc})") from None
    return fmt


def _optional(module: str) -> Any:
    """Import an optional dependency, or raise a one-line error naming the package."""
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError:
        extra = "replay" if module == "mcap" else "data"
        raise ImportError(
            f"{module} is needed for this format and is not installed: "
            f"pip install {module} (or tetherheli[{extra}])"
        ) from None


def write_csv(path: str | Path, columns: dict[str, np.ndarray]) -> Path:
    """Write named columns (``SimulationResult.columns``) as CSV, atomically: a header row,
    then every value as its ``repr`` (a float read back exactly), streamed in blocks of rows
    (a long run is not held a second time as text).

    Parameters
    ----------
    path : str or pathlib.Path
        The file to write.
    columns : dict of str to numpy.ndarray
        Column name -> samples, all of one length.

    Returns
    -------
    pathlib.Path
        The file written.
    """
    values = list(columns.values())
    n = values[0].size if values else 0
    with atomic_open(Path(path)) as fh:
        writer = csv.writer(fh, lineterminator="\n")
        writer.writerow(columns.keys())
        for start in range(0, n, _CSV_BLOCK_ROWS):
            block = np.column_stack([c[start : start + _CSV_BLOCK_ROWS] for c in values])
            writer.writerows([repr(float(v)) for v in row] for row in block)
    return Path(path)


def write_parquet(
    path: str | Path, df: Any, units: dict[str, str], descriptions: dict[str, str]
) -> Path:
    """Write a table as Apache Parquet, atomically, each Arrow field carrying its ``units``
    and ``description`` in its metadata and the DataFrame's ``attrs`` kept where
    ``pandas.read_parquet`` restores them (needs pandas and pyarrow).

    Parameters
    ----------
    path : str or pathlib.Path
        The file to write.
    df : pandas.DataFrame
        The columns (``t`` first, as a column, not the index).
    units, descriptions : dict of str to str
        Column name -> unit, and -> description (every column named).

    Returns
    -------
    pathlib.Path
        The file written.
    """
    pa = _optional("pyarrow")
    import pyarrow.parquet as pq

    table = pa.Table.from_pandas(df, preserve_index=False)
    fields = [
        f.with_metadata({"units": units[f.name], "description": descriptions[f.name]})
        for f in table.schema
    ]
    # pandas.DataFrame.to_parquet keeps df.attrs under this key; read_parquet restores them
    metadata = {**(table.schema.metadata or {}), b"PANDAS_ATTRS": json_text(df.attrs, indent=None)}
    table = pa.Table.from_arrays(table.columns, schema=pa.schema(fields, metadata=metadata))
    with atomic_path(Path(path)) as tmp:
        pq.write_table(table, tmp)
    return Path(path)


# --- a study's table: CSV or Parquet from one header and its rows ------------------------------

_INT = re.compile(r"[+-]?[0-9]+")


def table_csv(header: Sequence[str], rows: Iterable[Sequence[Any]]) -> str:
    """A table as CSV text: the header, then each row (None as an empty cell, a float as its
    ``repr``: read back exactly; a cell with a comma or a quote quoted).

    Parameters
    ----------
    header : sequence of str
        The column names.
    rows : iterable of sequences
        The rows, one value per column.

    Returns
    -------
    str
        The CSV text, "\\n" line ends.
    """
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(header)
    writer.writerows(rows)
    return buf.getvalue()


def _float(cell: str) -> float | None:
    if "_" in cell or cell != cell.strip():
        return None
    try:
        return float(cell)
    except ValueError:
        return None


def _arrow_column(pa: Any, cells: list[str]) -> Any:
    """A column's cells as an Arrow array: int64 when every non-empty cell is an integer,
    float64 when every one is a number (nan and inf included), else string; in a numeric
    column an empty cell is null."""
    given = [v for v in cells if v != ""]
    if given and all(_INT.fullmatch(v) and -(2**63) <= int(v) < 2**63 for v in given):
        return pa.array([int(v) if v != "" else None for v in cells], type=pa.int64())
    if given and all(_float(v) is not None for v in given):
        return pa.array([_float(v) if v != "" else None for v in cells], type=pa.float64())
    return pa.array(cells, type=pa.string())


def write_table(
    path: str | Path,
    header: Sequence[str],
    rows: Iterable[Sequence[Any]],
    *,
    units: dict[str, str] | None = None,
) -> Path:
    """Write a study's table, atomically, in the format its suffix names: ``.csv``
    (``table_csv``) or ``.parquet`` (Apache Parquet through pyarrow, the ``data`` extra). The
    one writer of the commands' tables (sweep.csv, compare.csv, the tether study's).

    The Parquet columns hold the CSV's cells typed: int64 where every non-empty cell is an
    integer, float64 where every one is a number, string otherwise (an empty cell of a
    numeric column is null); a column's unit, when ``units`` names it, is its Arrow field's
    ``units`` metadata (``pyarrow.parquet.read_schema(path).field(name).metadata``).

    Parameters
    ----------
    path : str or pathlib.Path
        The file to write: ``<stem>.csv`` or ``<stem>.parquet``.
    header : sequence of str
        The column names.
    rows : iterable of sequences
        The rows, one value per column (None: an empty cell).
    units : dict of str to str, optional
        Column name -> unit, for the columns whose unit is known.

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    ParameterError
        A suffix other than .csv or .parquet.
    ImportError
        Parquet without pyarrow (``check_result_format`` says so before a run).
    """
    path = Path(path)
    check_result_format(path.suffix[1:])
    return _write_table(path, header, rows, units=units)


def _write_table(
    path: Path,
    header: Sequence[str],
    rows: Iterable[Sequence[Any]],
    *,
    units: dict[str, str] | None = None,
) -> Path:
    """``write_table`` of a path whose suffix the caller checked (``check_result_format``
    at a writer's entry)."""
    fmt = path.suffix[1:]
    if fmt == "csv":
        atomic_write_text(path, table_csv(header, rows))
        return path
    pa = _optional("pyarrow")
    import pyarrow.parquet as pq

    # the CSV's own cells, so that the two formats hold the same table
    head, *cells = csv.reader(io.StringIO(table_csv(header, rows)))
    if any(len(r) != len(head) for r in cells):
        raise ValueError(f"a row of {path.name} does not have {len(head)} values")
    columns = [_arrow_column(pa, [r[j] for r in cells]) for j in range(len(header))]
    units = units or {}
    fields = [
        pa.field(name, col.type, metadata={"units": units[name]} if name in units else None)
        for name, col in zip(header, columns, strict=True)
    ]
    table = pa.Table.from_arrays(columns, schema=pa.schema(fields))
    with atomic_path(path) as tmp:
        pq.write_table(table, tmp)
    return path


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
        data = read_json(path)
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

    A run is a ``<stem>.csv``, ``<stem>.parquet`` or ``<stem>.mcap`` with a ``<stem>.json``
    beside it whose JSON object has a ``configuration`` table (as ``SimulationResult.save``
    writes), in the directory or one folder below it (``<name>/<stem>``, as ``tetherheli
    simulate`` writes several runs); other files are ignored.

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
    """The time-series file of a run: ``<stem>.csv``, ``.parquet`` or ``.mcap``, only one."""
    found = [path / f"{stem}.{fmt}" for fmt in RESULT_FORMATS if (path / f"{stem}.{fmt}").is_file()]
    if len(found) != 1:
        names = " and ".join(p.name for p in found)
        raise ParameterError(
            "run", stem, f"one time-series file per run, not both {names}", source=str(path)
        )
    return found[0]


def _read_table(path: Path) -> tuple[list[str], np.ndarray]:
    """The header and the values (rows x columns) of a run's time-series file."""
    if path.suffix == ".mcap":
        _optional("mcap")
        from .mcap import read_mcap_table

        return read_mcap_table(path)
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
    """The time series' columns by name (``<stem>.csv``, ``.parquet`` or ``.mcap``): every one of
    ``RESULT_COLUMNS`` present and finite, times increasing."""
    header, values = _read_table(path)
    src = str(path)
    kind = path.suffix[1:]
    csv_file = kind == "csv"
    _check_header(header, "csv header" if csv_file else f"{kind} columns", src)
    cols = {name: values[:, j] for j, name in enumerate(header)}
    for name in RESULT_COLUMNS:
        bad = np.flatnonzero(~np.isfinite(cols[name]))
        if bad.size:
            where = f"csv line {bad[0] + 2}" if csv_file else f"{kind} row {bad[0]}"
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


#: a landing's touchdown record (``SimulationResult.touchdown``): its numbers, then the limits
TOUCHDOWN_FIELDS = ("time", "vertical_speed", "offset", "attitude")


def _touchdown(meta: dict[str, Any], source: str) -> dict[str, Any] | None:
    info = meta.get("touchdown")
    if info is None:
        return None
    try:
        out: dict[str, Any] = {name: float(info[name]) for name in TOUCHDOWN_FIELDS}
        reasons = info.get("reasons", [])
        if not isinstance(reasons, list) or not all(isinstance(r, str) for r in reasons):
            raise TypeError
        out["reasons"] = list(reasons)
        if "settled" in info:  # a landing on its gear (``runs.landing.Touchdown.settle``)
            if not isinstance(info["settled"], bool) or isinstance(info["bounces"], bool):
                raise TypeError
            out["settled"] = info["settled"]
            out["max_penetration"] = float(info["max_penetration"])
            out["bounces"] = int(info["bounces"])
    except (KeyError, TypeError, ValueError):
        raise ParameterError(
            "touchdown", info, "null or a table with numbers time [s], vertical_speed [m/s], "
            "offset [m], attitude [rad], a list of reasons and, on landing gear, settled "
            "(true or false), max_penetration [m] and bounces", source=source,
        ) from None  # fmt: skip
    return out


def read_result_fields(directory: str | Path, stem: str | None = None) -> dict[str, Any]:
    """The fields of a saved run (``load_result``, which documents the arguments and errors):
    the keyword arguments of ``SimulationResult``, every file checked.

    Parameters
    ----------
    directory : str or pathlib.Path
        The result directory, or the path of one run's file.
    stem : str, optional
        Which run; None when the directory holds exactly one.

    Returns
    -------
    dict of str to object
        ``SimulationResult``'s fields by name.
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
    return dict(
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
        touchdown=_touchdown(meta, source),
    )
