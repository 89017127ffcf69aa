"""A ship in six degrees of freedom as the winch's base (issue 46): response amplitude
operators (RAOs) times a JONSWAP sea, at the encounter frequencies of a ship under way.

Conventions (docs/studies/deck.md, "A ship in six degrees of freedom"):

- The ship's axes: x forward, y to port, z up, from its centre of motion (the reference
  point of the RAOs). The ship heads along n1, so its mean axes are N's (x = n1, y = n2,
  z = n3), and it moves at ``speed`` U along n1: the base's constant velocity (U, 0, 0).
- The six degrees of freedom: surge, sway, heave (translations of the centre of motion
  along x, y, z [m]), roll, pitch, yaw (small rotations about x, y, z [rad],
  right-handed: positive roll raises the port side, positive pitch puts the bow down,
  positive yaw turns the bow to port).
- The wave heading chi [deg]: where the long-crested waves come from, measured from the bow
  toward port: 0 head seas, 90 beam seas from port, 180 following seas.
- RAO phases: for the wave elevation a cos(w t + e) at the centre of motion, a degree of
  freedom's motion is |H| a cos(w t + e + phase) (the RAO H = |H| exp(i phase)); the same
  holds with sines, so the packed form's A sin(w t + p) takes p = e + phase.
- The encounter frequency (deep water, Lewis 1989, PNA vol III, eq 8.62; Faltinsen 1990,
  eq 2.1): w_e = w - k U cos(mu), k = w^2 / g, mu the angle between the ship's course and
  the waves' direction of travel (mu = 180 deg head seas); with chi = 180 deg - mu,
  w_e = w + w^2 U cos(chi) / g. In following seas (cos chi < 0) w_e falls to zero at
  w = g / (U |cos chi|) and is negative beyond (the waves overtake the ship): as the
  literature does, such a component is folded, sin(-|w_e| t + p) = sin(|w_e| t + pi - p),
  so every packed frequency is >= 0 and the variance of each motion is unchanged.
- Linear seakeeping, small angles: the pad at r (``pad``, ship's axes) moves by
  translation + rotation x r, each a sum of sinusoids, so b(t) = U t n1 + that sum, packed
  in the engine's sinusoid rows (``base.compiled``); the pad's mean position is the origin
  of N at t = 0.

The RAOs are those of a CSV file (``read_rao_csv``, ``RAO_HEADER``) or the default ship
(``default_raos``: a 50 m box hull by Capytaine, ``benchmarks/ship_raos.py``), at the wave
frequencies; the default ship's are for zero speed (an approximation at speed, fair for
Froude numbers up to about 0.3: 5 m/s is 0.23 for 50 m).
"""

from __future__ import annotations

import functools
import hashlib
import math
import re
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import NamedTuple

import numpy as np

from .._validation import Key
from ..errors import ParameterError
from .motion import (
    _CELL,
    _SHA256,
    MOTION_KEYS,
    BaseMotion,
    BaseParts,
    _checked,
    sea_components,
    sea_phases,
)

__all__ = [
    "DEFAULT_RAO_FILE",
    "RAO_COLUMNS",
    "RAO_DOFS",
    "RAO_HEADER",
    "RAO_MAX_BYTES",
    "RAO_MAX_ROWS",
    "RaoTable",
    "ShipBase",
    "deck_motion_rms",
    "default_raos",
    "encounter_frequency",
    "read_rao_csv",
    "write_rao_csv",
]

#: [m/s^2] gravity in the dispersion relation k = w^2 / g (deep water)
G = 9.81
#: the six degrees of freedom of the ship's centre of motion, in the RAO file's order
RAO_DOFS: tuple[str, ...] = ("surge", "sway", "heave", "roll", "pitch", "yaw")
#: the columns of an RAO file, in order: its header line is these names joined by commas
RAO_HEADER: tuple[str, ...] = (
    "frequency",
    "heading",
    *(f"{dof}_{part}" for dof in RAO_DOFS for part in ("amplitude", "phase")),
)
#: [rad/s] the highest wave frequency of an RAO file (wavelength 15 cm)
RAO_MAX_FREQUENCY = 20.0
#: the largest RAO amplitude: [m/m] of a translation, [rad/m] of a rotation
RAO_MAX_AMPLITUDE = 100.0
#: each column of an RAO file with its unit and range
RAO_COLUMNS: dict[str, Key] = {
    "frequency": Key("the wave frequency w (not the encounter frequency)", "rad/s", low=0.0,
                     low_open=True, high=RAO_MAX_FREQUENCY),
    "heading": Key("the wave heading chi: 0 head seas, 90 from port, 180 following", "deg",
                   low=0.0, high=180.0),
    **{
        f"{dof}_{part}": (
            Key(f"|H| of {dof} per metre of wave amplitude", "m/m" if i < 3 else "rad/m",
                low=0.0, high=RAO_MAX_AMPLITUDE)
            if part == "amplitude" else
            Key(f"the phase of {dof}: |H| a cos(w t + e + phase) for waves a cos(w t + e)",
                "rad", low=-2 * math.pi, high=2 * math.pi)
        )
        for i, dof in enumerate(RAO_DOFS)
        for part in ("amplitude", "phase")
    },
}  # fmt: skip
#: The largest RAO file [bytes] (checked before it is read) and its most rows
RAO_MAX_BYTES = 2_000_000
RAO_MAX_ROWS = 10_000
#: The default ship's RAOs (``benchmarks/ship_raos.py`` writes them), in the package
DEFAULT_RAO_FILE = "base/data/default_ship_raos.csv"
_RAO_ROW = re.compile(rb"[ \t]*" + _CELL + rb"[ \t]*")
_RAO_TEXT = "the header " + ",".join(RAO_HEADER)
_HEADER = ",".join(RAO_HEADER).encode()


class RaoTable(NamedTuple):
    """Response amplitude operators on a grid of wave frequencies and headings.

    Attributes
    ----------
    frequencies : numpy.ndarray, shape (m,)
        The wave frequencies [rad/s], strictly increasing, m >= 2.
    headings : numpy.ndarray, shape (h,)
        The wave headings [deg], strictly increasing, h >= 1.
    values : numpy.ndarray of complex, shape (m, h, 6)
        H = |H| exp(i phase) of ``RAO_DOFS`` ([m/m] translations, [rad/m] rotations).
    source : str
        The file's resolved path ("" for the default ship).
    sha256 : str
        The SHA-256 of the file's bytes.
    """

    frequencies: np.ndarray
    headings: np.ndarray
    values: np.ndarray
    source: str = ""
    sha256: str = ""

    def at(self, omega: np.ndarray, heading: float) -> np.ndarray:
        """The RAOs at wave frequencies ``omega`` and one heading, interpolated linearly in
        the complex values (between headings, then between frequencies); below the table's
        lowest frequency its first row's (long waves), above its highest zero (waves short
        against the hull average out).

        Parameters
        ----------
        omega : numpy.ndarray, shape (n,)
            Wave frequencies [rad/s].
        heading : float
            The wave heading [deg], within the table's headings.

        Returns
        -------
        numpy.ndarray of complex, shape (n, 6)
            H of ``RAO_DOFS`` at each frequency.
        """
        h = self.headings
        if h.size == 1:
            at_heading = self.values[:, 0, :]
        else:
            j = int(np.clip(np.searchsorted(h, heading) - 1, 0, h.size - 2))
            w = (heading - h[j]) / (h[j + 1] - h[j])
            at_heading = (1 - w) * self.values[:, j, :] + w * self.values[:, j + 1, :]
        omega = np.asarray(omega, dtype=float)
        out = np.empty((omega.size, 6), dtype=complex)
        for d in range(6):
            col = at_heading[:, d]
            re_ = np.interp(omega, self.frequencies, col.real, right=0.0)
            im_ = np.interp(omega, self.frequencies, col.imag, right=0.0)
            out[:, d] = re_ + 1j * im_
        return out


def encounter_frequency(omega: np.ndarray, speed: float, heading: float) -> np.ndarray:
    """The encounter frequency w_e = w + w^2 U cos(chi) / g of waves of frequency w met by a
    ship at speed U, chi the wave heading (0 head seas; deep water: Lewis 1989, PNA vol III,
    eq 8.62, with chi = 180 deg - mu). Not folded: negative where following waves overtake
    the ship.

    Parameters
    ----------
    omega : numpy.ndarray
        Wave frequencies w [rad/s].
    speed : float
        The ship's speed U [m/s].
    heading : float
        The wave heading chi [deg].

    Returns
    -------
    numpy.ndarray
        w_e [rad/s], the shape of ``omega``.
    """
    omega = np.asarray(omega, dtype=float)
    return omega + omega**2 * speed * math.cos(math.radians(heading)) / G


@dataclass(frozen=True)
class ShipBase(BaseMotion):
    """The winch on a ship's pad: six degrees of freedom from RAOs x a JONSWAP sea.

    The sea is ``SeaStateBase``'s (``sea_components``: ``components`` sinusoids evenly over
    [0.5, 4] w_p, 4 sqrt(m0) = Hs; ``sea_phases`` of ``seed``: its first set of phases);
    each wave component k of amplitude a_k, frequency w_k and phase e_k moves each degree of
    freedom by |H(w_k)| a_k sin(w_e,k t + e_k + phase(w_k)) at its encounter frequency
    (``encounter_frequency``, folded; module docstring for the conventions), and the pad by
    H_t + H_r x r (translation + rotation x r_pad, small angles).

    Parameters
    ----------
    significant_wave_height : float, optional
        Hs of the waves [m] (default 1), in (0, 20].
    peak_period : float, optional
        The JONSWAP peak period Tp [s] (default 8), in [1, 30].
    peak_enhancement : float, optional
        The JONSWAP gamma [-] (default 3.3), in [1, 7].
    seed : int, optional
        The seed of the wave phases (default 0).
    components : int, optional
        The wave components (default 128), at most ``SEA_STATE_MAX_COMPONENTS``.
    wave_heading : float, optional
        Where the waves come from [deg], from the bow toward port (default 0, head seas), in
        [0, 180] and within the RAO file's headings.
    speed : float, optional
        The ship's speed along n1 [m/s] (default 0), in [0, 25].
    pad : tuple of 3 float, optional
        The winch's point in the ship's axes from the centre of motion [m] (default the
        centre of motion).
    rao_file : str, optional
        A CSV of RAOs (``read_rao_csv``); empty (default): the default ship.
    rao_file_sha256 : str, optional
        The SHA-256 the file must have; empty: any (the file's is recorded).
    """

    significant_wave_height: float = 1.0
    peak_period: float = 8.0
    peak_enhancement: float = 3.3
    seed: int = 0
    components: int = 128
    wave_heading: float = 0.0
    speed: float = 0.0
    pad: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rao_file: str = ""
    rao_file_sha256: str = ""
    _waves: np.ndarray = field(init=False, repr=False, compare=False)
    _rotations: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        _checked(self, *MOTION_KEYS["ship"])
        self._derive()

    def _derive(self) -> None:
        """The pad's sinusoids (``_waves``) and the rotations' (``_rotations``) of the
        checked fields, the RAO file read; also run by ``_validation.trusted``."""
        if self.rao_file:
            table = read_rao_csv(self.rao_file, sha256=self.rao_file_sha256)
            object.__setattr__(self, "rao_file", table.source)
            object.__setattr__(self, "rao_file_sha256", table.sha256)
        elif self.rao_file_sha256:
            raise ParameterError("base.rao_file_sha256", self.rao_file_sha256,
                                 "empty with the default ship (rao_file unset)")  # fmt: skip
        else:
            table = default_raos()
        h = table.headings
        if not h[0] <= self.wave_heading <= h[-1]:
            raise ParameterError(
                "base.wave_heading", self.wave_heading,
                f"within the RAO file's headings [{h[0]:g}, {h[-1]:g}] deg",
                source=table.source or None,
            )  # fmt: skip
        omega, amp = sea_components(self.significant_wave_height, self.peak_period,
                                    self.peak_enhancement, self.components)  # fmt: skip
        phase = sea_phases(self.seed, 1, self.components)[0]
        raos = table.at(omega, self.wave_heading)  # (n, 6)
        we = encounter_frequency(omega, self.speed, self.wave_heading)
        # folded: sin(-|w| t + p) = sin(|w| t + pi - p)
        sign = np.where(we < 0.0, -1.0, 1.0)
        r = np.asarray(self.pad, dtype=float)
        rot = raos[:, 3:]
        pad = raos[:, :3] + np.cross(rot, r)  # H_t + H_r x r per component (small angles)

        def rows(h: np.ndarray, axis: int) -> np.ndarray:
            p = sign * (phase + np.angle(h)) + np.where(we < 0.0, math.pi, 0.0)
            return np.column_stack([np.full(omega.size, float(axis)), np.abs(h) * amp,
                                    np.abs(we), p])  # fmt: skip

        waves = np.concatenate([rows(pad[:, i], i) for i in range(3)])
        rotations = np.concatenate([rows(rot[:, i], i) for i in range(3)])
        for arr in (waves, rotations):
            arr.setflags(write=False)
        object.__setattr__(self, "_waves", waves)
        object.__setattr__(self, "_rotations", rotations)

    def parts(self) -> BaseParts:
        """The ship's parts: the pad's sinusoids and the speed.

        Returns
        -------
        BaseParts
            The velocity (``speed``, 0, 0) [m/s] and the waves (axis, amplitude [m], encounter
            frequency [rad/s], phase [rad]) of n1, n2, n3; no offset or spline.
        """
        return BaseParts(offset=np.zeros(3), velocity=np.array([self.speed, 0.0, 0.0]),
                         waves=self._waves)  # fmt: skip

    def attitude(self, t: object) -> np.ndarray:
        """The deck's roll, pitch and yaw and their rates at times ``t`` (the rotations of
        the same components as the pad's motion, small angles).

        Parameters
        ----------
        t : float or array_like of shape (n,)
            Times [s].

        Returns
        -------
        numpy.ndarray, shape (n, 2, 3)
            ``out[i, 0]`` roll, pitch, yaw [rad], ``out[i, 1]`` their rates [rad/s] at
            ``t[i]`` (about the ship's x, y, z).
        """
        t = np.atleast_1d(np.asarray(t, dtype=np.float64))
        out = np.zeros((t.size, 2, 3))
        w = self._rotations
        for axis in range(3):
            rows = w[w[:, 0] == axis]
            arg = np.outer(t, rows[:, 2]) + rows[:, 3]
            out[:, 0, axis] = np.sin(arg) @ rows[:, 1]
            out[:, 1, axis] = np.cos(arg) @ (rows[:, 1] * rows[:, 2])
        return out

    def to_dict(self) -> dict:
        """The motion as the keys of a ``[base]`` table.

        Returns
        -------
        dict
            ``{"motion": "ship"}`` and the keys of ``MOTION_KEYS["ship"]``.
        """
        out: dict = {"motion": "ship"}
        for name in MOTION_KEYS["ship"]:
            value = getattr(self, name)
            out[name] = list(value) if isinstance(value, tuple) else value
        return out


def deck_motion_rms(roll: np.ndarray, pitch: np.ndarray, heave_velocity: np.ndarray) -> dict:
    """The NATO STANAG 4154 deck-motion figures of recorded series: the root mean square
    sqrt(mean(x^2)) of the deck's roll and pitch [deg] and of the pad's vertical velocity
    [m/s] (the standard's limits for V/STOL operations: 2.5 deg, 1.5 deg, 1.0 m/s).

    Parameters
    ----------
    roll, pitch : numpy.ndarray, shape (n,)
        The deck's roll and pitch [rad].
    heave_velocity : numpy.ndarray, shape (n,)
        The pad's velocity along n3 [m/s].

    Returns
    -------
    dict of str to float
        ``deck_roll_rms`` [deg], ``deck_pitch_rms`` [deg], ``deck_heave_velocity_rms`` [m/s];
        NaN without samples.
    """

    def rms(x: np.ndarray) -> float:
        x = np.asarray(x, dtype=float)
        return float(np.sqrt(np.mean(x**2))) if x.size else math.nan

    return {
        "deck_roll_rms": math.degrees(rms(roll)),
        "deck_pitch_rms": math.degrees(rms(pitch)),
        "deck_heave_velocity_rms": rms(heave_velocity),
    }


# --- the RAO file ---------------------------------------------------------------------------


def write_rao_csv(rows: np.ndarray) -> str:
    """An RAO file's text: the header ``RAO_HEADER``, then one line per row, each number with
    9 significant digits (``read_rao_csv`` reads it back).

    Parameters
    ----------
    rows : numpy.ndarray, shape (k, 14)
        Rows of ``RAO_HEADER``'s columns, frequency-major, headings increasing within each
        frequency.

    Returns
    -------
    str
        The file's text (ASCII, ``\\n`` line ends).
    """
    lines = [",".join(RAO_HEADER)]
    lines += [",".join(f"{v:.9g}" for v in row) for row in np.asarray(rows, dtype=float)]
    return "\n".join(lines) + "\n"


def read_rao_csv(path: str | Path, *, sha256: str = "") -> RaoTable:
    """An ``RaoTable`` from a CSV file: the header ``RAO_HEADER`` (frequency [rad/s], heading
    [deg], then amplitude [m/m or rad/m] and phase [rad] of surge, sway, heave, roll, pitch,
    yaw), then one row per (frequency, heading): frequencies increasing, the same headings,
    increasing, under each frequency; at least two frequencies.

    The file is opened by ``_io.open_user_file`` (a regular file of at most
    ``RAO_MAX_BYTES``, its size checked before it is read) and at most ``RAO_MAX_ROWS`` rows
    are held; each cell a plain decimal number within its column's range (``RAO_COLUMNS``).
    The bytes are hashed (SHA-256), recorded with the run.

    Parameters
    ----------
    path : str or pathlib.Path
        The file.
    sha256 : str, optional
        The SHA-256 the file must have; empty: any.

    Returns
    -------
    RaoTable
        Its ``source`` the resolved path, its ``sha256`` the hash of the bytes.

    Raises
    ------
    ParameterError
        A missing, unreadable or oversized file, a wrong header, a bad cell or grid, or
        other bytes than ``sha256``: one line naming the file, the row and the column, never
        its contents.
    """
    from .._io import open_user_file

    if sha256 and not (isinstance(sha256, str) and _SHA256.fullmatch(sha256)):
        raise ParameterError("base.rao_file_sha256", sha256, "64 hexadecimal digits (lower "
                             "case) or empty")  # fmt: skip
    src = str(path)
    with open_user_file(path, field="base.rao_file", what="a CSV of RAOs",
                        max_bytes=RAO_MAX_BYTES) as (fh, resolved, _):  # fmt: skip
        try:
            data = fh.read(RAO_MAX_BYTES + 1)
        except OSError as exc:
            raise ParameterError("base.rao_file", src, "a readable CSV of RAOs "
                                 f"({exc.strerror or 'a read error'})") from None  # fmt: skip
    digest = hashlib.sha256(data).hexdigest()
    if sha256 and digest != sha256:
        raise ParameterError(
            "base.rao_file_sha256", sha256, f"the SHA-256 of {src}'s bytes (the file changed "
            "since it was recorded)",
        )  # fmt: skip
    table = _parse_raos(data, src)
    return table._replace(source=str(resolved), sha256=digest)


def _parse_raos(data: bytes, src: str) -> RaoTable:
    """The table of an RAO file's bytes, each refusal one line naming the row and column."""

    def refuse(row: int, value: str, allowed: str, column: str = "") -> None:
        where = f"base.rao_file row {row}" + (f" column {column}" if column else "")
        raise ParameterError(where, value, allowed, source=src)

    lines = data.split(b"\n")
    if lines and lines[-1] == b"":
        lines.pop()
    if not lines:
        refuse(1, "an empty file", _RAO_TEXT)
    if lines[0].removeprefix(b"\xef\xbb\xbf").strip().replace(b" ", b"") != _HEADER:
        refuse(1, "not the header", _RAO_TEXT)
    if len(lines) - 1 > RAO_MAX_ROWS:
        raise ParameterError("base.rao_file", f"more than {RAO_MAX_ROWS} rows",
                             f"at most {RAO_MAX_ROWS} rows after the header",
                             source=src)  # fmt: skip
    names = tuple(RAO_COLUMNS)
    values = np.empty((len(lines) - 1, len(names)))
    for i, line in enumerate(lines[1:]):
        row = i + 2
        cells = line.rstrip(b"\r").split(b",")
        if len(cells) != len(names):
            refuse(row, f"{len(cells)} cells", f"{len(names)} plain decimal numbers "
                   "(RAO_HEADER's columns)")  # fmt: skip
        for j, (name, cell) in enumerate(zip(names, cells, strict=True)):
            if not _RAO_ROW.fullmatch(cell):
                refuse(row, "not a plain decimal number", "a plain decimal number such as "
                       "-0.5, 12 or 1.25e-3 (no '_', inf or nan)", column=name)  # fmt: skip
            x = float(cell)
            key = RAO_COLUMNS[name]
            assert key.low is not None and key.high is not None
            if not (key.low < x if key.low_open else key.low <= x) or x > key.high:
                refuse(row, "out of its range", key.allowed(), column=name)
            values[i, j] = x
    freq, head = values[:, 0], values[:, 1]
    headings = head[freq == freq[0]] if freq.size else head
    n_h = headings.size
    if freq.size < 2 * max(n_h, 1) or freq.size % n_h:
        raise ParameterError("base.rao_file", f"{freq.size} rows", "rows for at least two "
                             "frequencies, each with the same headings", source=src)  # fmt: skip
    grid_f = freq.reshape(-1, n_h)
    grid_h = head.reshape(-1, n_h)
    for k in range(grid_f.shape[0]):
        for j in range(n_h):
            row = k * n_h + j + 2
            if grid_f[k, j] != grid_f[k, 0] or (k and grid_f[k, 0] <= grid_f[k - 1, 0]):
                refuse(row, "not on the grid", f"{n_h} rows per frequency, frequencies "
                       "increasing", column="frequency")  # fmt: skip
            if grid_h[k, j] != headings[j] or (j and headings[j] <= headings[j - 1]):
                refuse(row, "not on the grid", "the first frequency's headings, increasing, "
                       "under every frequency", column="heading")  # fmt: skip
    amp = values[:, 2::2].reshape(-1, n_h, 6)
    phase = values[:, 3::2].reshape(-1, n_h, 6)
    return RaoTable(grid_f[:, 0].copy(), headings.copy(), amp * np.exp(1j * phase))


@functools.cache
def default_raos() -> RaoTable:
    """The default ship's RAOs (``DEFAULT_RAO_FILE`` in the package; the hull and how they
    were computed: ``benchmarks/ship_raos.py``), read once.

    Returns
    -------
    RaoTable
        Its ``source`` is "" (the package's own file).
    """
    data = resources.files("tetherheli").joinpath(DEFAULT_RAO_FILE).read_bytes()
    table = _parse_raos(data, DEFAULT_RAO_FILE)
    return table._replace(sha256=hashlib.sha256(data).hexdigest())
