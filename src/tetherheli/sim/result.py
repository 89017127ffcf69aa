"""The result of a closed-loop run: a frozen object that plotting and export only read."""

from __future__ import annotations

import csv
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .._io import atomic_open, atomic_write_bytes, atomic_write_text
from ..names import (
    INPUT,
    INPUT_UNITS,
    OUTPUT,
    OUTPUT_UNITS,
    POSITION,
    TETHERED_STATE,
    TETHERED_STATE_UNITS,
)
from ..status import Status, release_sentence, status_message

__all__ = ["SimulationResult", "atomic_write_bytes", "atomic_write_text"]

STATE_NAMES, STATE_UNITS = TETHERED_STATE, TETHERED_STATE_UNITS
INPUT_NAMES, OUTPUT_NAMES = INPUT, OUTPUT
_CSV_BLOCK_ROWS = 4096


@dataclass(frozen=True)
class SimulationResult:
    """A sampled closed-loop run (one row per control sample t_k = k dt).

    Attributes
    ----------
    time : (n,) [s]
    states : (n, 13) tethered-coordinate state [q4..q9, u1..u6, LN] (see ``STATE_NAMES``);
        for the free configuration q7..q9 locate P as if a tether were there
    outputs : (n, 4) [q1, q2, q3, q6] [m, m, m, rad] (eqs 43-45)
    inputs : (n, 4) applied [fMR3, tMR1, tMR2, fTR2], including the feed-forward (eq 54)
    feedforward : (n, 4) C_f-fwd of eq 55 (zeros without tether or feed-forward)
    tension : (n,) tether tension TC [N]
    reel_rate : (n,) winch rate RC held over [t_k, t_k+1) [m/s] (eq 37)
    wind : (n, 3) wind force on HO in N [N]
    trim_state, trim_input, trim_output : the run's trim (its references)
    status : 0 on success, else a failure code; ``message`` says which
    configuration : the scenario as plain data; ``version`` the package version
    release_time, release_tension : the safety device released the tether at this control
        sample [s], the tension [N] having exceeded the breaking tension (None: not released);
        the run then continued free, and ``message`` says so
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
    def ok(self) -> bool:
        """True when the run completed without hitting a stop condition."""
        return self.status == Status.OK

    @property
    def message(self) -> str:
        """What happened: the status, with the tether release if there was one."""
        return status_message(self.status, self.release_time)

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
        if self.ok or dt is None:
            return float(self.time[-1]) if self.time.size else 0.0
        return self.time.size * float(dt)

    def release_info(self) -> dict[str, float] | None:
        """The tether release as plain data, ``{"time", "tension", "breaking_tension"}``
        [s, N, N], or None."""
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
        """One line on the tether release (``status.release_sentence``), or None."""
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
        """Deviations from the run's own trim: q1..q3 [m], q4, q5 [rad]."""
        d = {n: self.outputs[:, i] - self.trim_output[i] for i, n in enumerate(POSITION)}
        d["q4"] = self.states[:, 0] - self.trim_state[0]
        d["q5"] = self.states[:, 1] - self.trim_state[1]
        return d

    def columns(self) -> dict[str, np.ndarray]:
        """All sampled signals as named columns (name -> (n,))."""
        cols: dict[str, np.ndarray] = {"t": self.time}
        for i, n in enumerate(STATE_NAMES):
            cols[n] = self.states[:, i]
        for i, n in enumerate(OUTPUT_NAMES[:3]):
            cols[n] = self.outputs[:, i]
        for i, n in enumerate(INPUT_NAMES):
            cols[n] = self.inputs[:, i]
        cols["C1_ffwd"] = self.feedforward[:, 1]
        cols["C2_ffwd"] = self.feedforward[:, 2]
        cols["TC"] = self.tension
        cols["RC"] = self.reel_rate
        for i, n in enumerate(("Fw1", "Fw2", "Fw3")):
            cols[n] = self.wind[:, i]
        for n, v in self.extra.items():
            cols[n] = v
        return cols

    def to_csv(self, path: str | Path) -> Path:
        """Write the time series as CSV (SI units; header row), atomically, streamed in blocks
        of rows (a long run is not held a second time as text)."""
        cols = self.columns()
        columns = list(cols.values())
        with atomic_open(Path(path)) as fh:
            writer = csv.writer(fh, lineterminator="\n")
            writer.writerow(cols.keys())
            for start in range(0, self.time.size, _CSV_BLOCK_ROWS):
                block = np.column_stack([c[start : start + _CSV_BLOCK_ROWS] for c in columns])
                writer.writerows([repr(float(v)) for v in row] for row in block)
        return Path(path)

    def metadata(self) -> dict[str, Any]:
        """Configuration, version, status, trim: what is recorded next to the results."""
        return {
            "tetherheli_version": self.version,
            "status": self.status,
            "message": self.message,
            "tether_release": self.release_info(),
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

    def save(self, directory: str | Path, stem: str | None = None) -> dict[str, Path]:
        """Write ``<stem>.csv`` and ``<stem>.json`` (configuration + version) into directory."""
        directory = Path(directory)
        stem = stem or self.name
        csv_path = self.to_csv(directory / f"{stem}.csv")
        meta_path = directory / f"{stem}.json"
        atomic_write_text(meta_path, json.dumps(self.metadata(), indent=2) + "\n")
        return {"csv": csv_path, "json": meta_path}
