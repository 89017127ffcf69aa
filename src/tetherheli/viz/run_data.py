"""The runs an animation draws: ``RunData`` (a saved run's positions, attitudes, tether and
wind, with the helicopter's drawn points), read through ``results.result.load_result``
(``load_run``, ``list_runs``). ``viz.animation`` re-exports these names.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np

from ..errors import ParameterError
from ..model.kinematics import HelicopterPoints, helicopter_points
from ..params import HelicopterParams, Params
from ..results.files import BASE_POSITION_COLUMNS, DECK_ATTITUDE_COLUMNS, _series_path
from ..results.landing import is_landing
from ..results.result import list_results, load_result

__all__ = ["RunData", "list_runs", "load_run"]


@dataclass(frozen=True, eq=False)
class RunData:
    """One saved run, as much of it as the animation draws.

    Parameters
    ----------
    stem : str
        File stem in the result directory (``<stem>.csv``, ``<stem>.json``).
    name : str
        The scenario's name (configuration["name"]).
    configuration : {"free", "tethered"}
        The run's configuration.
    time : ndarray, shape (n,)
        Sample times [s], strictly increasing.
    q : ndarray, shape (n, 9)
        Generalized coordinates q1..q9: HO position q1..q3 [m], Euler angles q4..q6 [rad],
        tether angles q7, q8 [rad] and length q9 [m] (for a free run q7..q9 locate P as if a
        tether were there).
    wind : ndarray, shape (n, 3)
        Wind force on HO in N [N] (Fw1, Fw2, Fw3).
    tension : ndarray, shape (n,)
        Tether tension TC [N] (zero for a free run).
    trim_position : ndarray, shape (3,)
        HO at the run's trim point [m].
    helicopter : HelicopterParams
        The helicopter parameters of the run (for the point offsets).
    status : int
        0 if the run completed, else the simulator's failure code.
    message : str
        The simulator's status message.
    version : str
        The tetherheli version that wrote the run.
    base : ndarray, shape (n, 3), optional
        The winch's base in N at each sample [m] (``base_n1..3``; None: a fixed base at NO,
        stored as zeros). Over a moving base q1..q3 are relative to it.
    nodes : ndarray, shape (n, N + 1, 3), optional
        A lumped tether's recorded node positions relative to the base [m], row 0 the winch
        and row N the point P (``node<i>_n<a>``; None when not recorded).
    deck_attitude : ndarray, shape (n, 3), optional
        The deck's roll, pitch and yaw [rad] over a ship (``deck_roll``, ``deck_pitch``,
        ``deck_yaw``: rotations about n1, n2, n3, ``base.ship``); None: a level deck.
    gear_height : float, optional
        A landing's gear height below HO [m] (``[maneuver] gear_height``); None: not a
        landing.
    """

    stem: str
    name: str
    configuration: Literal["free", "tethered"]
    time: np.ndarray
    q: np.ndarray
    wind: np.ndarray
    tension: np.ndarray
    trim_position: np.ndarray
    helicopter: HelicopterParams
    status: int
    message: str
    version: str
    base: np.ndarray = None  # type: ignore[assignment]  # None: zeros (__post_init__)
    nodes: np.ndarray | None = None
    deck_attitude: np.ndarray | None = None
    gear_height: float | None = None

    def __post_init__(self) -> None:
        if self.base is None:
            object.__setattr__(self, "base", np.zeros((len(self.time), 3)))
        for name in ("time", "q", "wind", "tension", "trim_position", "base", "nodes",
                     "deck_attitude"):  # fmt: skip
            value = getattr(self, name)
            if value is not None:
                value.setflags(write=False)

    @property
    def position(self) -> np.ndarray:
        """HO in N, (n, 3) [m]."""
        return self.q[:, 0:3]

    @property
    def world_position(self) -> np.ndarray:
        """HO in N with the base's motion added, (n, 3) [m] (``position`` + ``base``)."""
        return self.position + self.base

    @property
    def base_moves(self) -> bool:
        """True when the recorded base moved (any ``base_n1..3`` other than its first)."""
        return bool(np.any(self.base != self.base[:1]))

    @property
    def deck_rotation(self) -> np.ndarray:
        """The deck's rotation from N at every sample, (n, 3, 3): roll, pitch, yaw about n1,
        n2, n3 (extrinsic x-y-z, ``deck_attitude``); the identity for a level deck."""
        n = len(self.time)
        if self.deck_attitude is None:
            return np.broadcast_to(np.eye(3), (n, 3, 3))
        from scipy.spatial.transform import Rotation

        angles = np.nan_to_num(np.asarray(self.deck_attitude, dtype=float))
        return Rotation.from_euler("xyz", angles).as_matrix()

    @property
    def angles(self) -> np.ndarray:
        """Euler angles q4, q5, q6, (n, 3) [rad]."""
        return self.q[:, 3:6]

    @property
    def tethered(self) -> bool:
        return self.configuration == "tethered"

    def points(self) -> HelicopterPoints:
        """The named points at every sample, each (n, 3) [m].

        Returns
        -------
        HelicopterPoints
            The helicopter's named points (``model.kinematics.helicopter_points``).
        """
        return helicopter_points(self.position, self.angles, self.helicopter)


#: The stems of the runs saved in a directory (``tetherheli.results.list_results``).
list_runs = list_results


def load_run(directory: str | Path, stem: str | None = None) -> RunData:
    """Read one run saved by ``SimulationResult.save(directory, stem)``, through
    ``tetherheli.results.load_result``, as much of it as the animation draws.

    Parameters
    ----------
    directory : path of the result directory
    stem : which run; None when the directory holds exactly one

    Returns
    -------
    RunData

    Raises
    ------
    ParameterError
        If the directory is missing or holds no (or, with ``stem=None``, several) runs, or a
        file is malformed or holds no samples (the message names the file and what is
        expected).
    """
    result = load_result(directory, stem)
    path = Path(directory)
    stem = stem if stem is not None else list_results(path)[0]
    if result.time.size == 0:
        series = _series_path(path, stem)  # the run's .csv or .parquet, as load_result read it
        raise ParameterError(
            series.suffix[1:], "no data rows", "at least one row of samples", source=str(series)
        )
    helicopter = Params.paper().helicopter
    params = result.configuration.get("params")
    if isinstance(params, dict) and isinstance(params.get("helicopter"), dict):
        helicopter = Params.from_mapping(
            {"helicopter": params["helicopter"]}, source=str(path / f"{stem}.json")
        ).helicopter
    return RunData(
        stem=stem,
        name=str(result.configuration.get("name", stem)),
        configuration=result.configuration["configuration"],
        time=result.time,
        q=np.column_stack([result.outputs[:, :3], result.states[:, :6]]),
        wind=result.wind,
        tension=result.tension,
        trim_position=result.trim_output[:3],
        helicopter=helicopter,
        status=result.status,
        message=result.message,
        version=result.version,
        base=_base(result.extra, len(result.time)),
        nodes=_nodes(result.extra),
        deck_attitude=(
            np.column_stack([result.extra[c] for c in DECK_ATTITUDE_COLUMNS])
            if all(c in result.extra for c in DECK_ATTITUDE_COLUMNS)
            else None
        ),
        gear_height=(
            float(result.configuration["maneuver"]["gear_height"])
            if is_landing(result.configuration)
            else None
        ),
    )


def _base(extra: dict[str, np.ndarray], n: int) -> np.ndarray:
    """The recorded base position (``base_n1..3``), or zeros (n, 3) for a fixed base."""
    if all(name in extra for name in BASE_POSITION_COLUMNS):
        return np.column_stack([extra[name] for name in BASE_POSITION_COLUMNS])
    return np.zeros((n, 3))


def _nodes(extra: dict[str, np.ndarray]) -> np.ndarray | None:
    """A lumped tether's recorded nodes (``node<i>_n<a>``), (n, N + 1, 3), or None."""
    count = 0
    while all(f"node{count}_n{a}" in extra for a in (1, 2, 3)):
        count += 1
    if count < 2:
        return None
    return np.stack(
        [np.column_stack([extra[f"node{i}_n{a}"] for a in (1, 2, 3)]) for i in range(count)],
        axis=1,
    )


def _load_runs(directory: str | Path, stems: Sequence[str] | None) -> list[RunData]:
    available = list_results(directory)
    if stems is None:
        if not available:
            load_result(directory)  # raises: no runs, naming what a result directory holds
        stems = available
    elif isinstance(stems, str) or len(stems) == 0:
        raise ParameterError("stems", stems, f"a non-empty list of run stems from {available}")
    return [load_run(directory, s) for s in stems]
