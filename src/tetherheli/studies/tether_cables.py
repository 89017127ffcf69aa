"""The tether study's choices (``studies.tether_study``): its cables (``StudyCable``,
``STUDY_CABLES``), the winch's gains and their loop-gain rule (``WINCH_GAINS``,
``tension_loop_gain``, ``cable_stiffness``), the tether models and cases of the dynamic half,
and the checks of the cables and grids a user asks for.
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from .. import names
from .._validation import check_number
from ..errors import ParameterError
from ..tether.chain import LumpedTether

__all__ = [
    "DEFAULT_THRUST_TO_WEIGHT",
    "DYNAMIC_CASES",
    "PAPER_LOOP_GAIN",
    "STUDY_CABLES",
    "TETHER_MODELS",
    "TURBULENCE_SETTLE_S",
    "WINCH_GAINS",
    "StudyCable",
    "cable_stiffness",
    "check_grid",
    "select_cables",
    "tension_loop_gain",
]


@dataclass(frozen=True)
class StudyCable:
    """A cable of the study.

    Parameters
    ----------
    key : str
        Short name (``--cables``).
    label : str
        Legend text.
    tether : LumpedTether
        Its mass per length, EA, diameter and drag.
    source : str
        Where its numbers come from (an assumption is said to be one).
    """

    key: str
    label: str
    tether: LumpedTether
    source: str

    def to_dict(self) -> dict[str, Any]:
        """The cable as plain data (summary.json).

        Returns
        -------
        dict of str to object
            key, label, source and the tether's fields.
        """
        return {
            "key": self.key,
            "label": self.label,
            "source": self.source,
            "tether": dataclasses.asdict(self.tether),
        }


#: The study's cables. Drag: a round cable in cross-flow, Cd 1.1 (Hoerner, Fluid-Dynamic
#: Drag, 1965, ch. 3: 1.0-1.2 below the drag crisis), no tangential drag.
STUDY_CABLES: tuple[StudyCable, ...] = (
    StudyCable(
        "paper",
        "paper-like: 20 g/m, EA 375 N, 5 mm",
        LumpedTether(segments=20),
        "EA = K_C L0N = 40 N/m x 9.375 m (Table III, eq 28); 20 g/m and 5 mm assumed (the "
        "paper's tether is massless)",
    ),
    StudyCable(
        "power",
        "power-and-data: 30 g/m, EA 20 kN, 5 mm",
        LumpedTether(segments=20, mass_per_length_kg_m=0.03, EA_N=20e3),
        "assumed: a 5 mm copper-pair cable with an aramid strength member, in the 10-40 g/m "
        "range issue 13 gives for tethered UAVs; EA of tens of kN (issue 13)",
    ),
    StudyCable(
        "data",
        "light data: 10 g/m, EA 5 kN, 3 mm",
        LumpedTether(segments=20, mass_per_length_kg_m=0.01, EA_N=5e3, diameter_m=0.003),
        "assumed: a 3 mm aramid-jacketed data cable (optical fibre or twisted pair), the light "
        "end of issue 13's 10-40 g/m",
    ),
)

#: The maximum main-rotor thrust as a multiple of the free hover thrust (Table IV's fMR3) when
#: none is given: an assumption (the paper states no maximum thrust); 1.5 is a thrust-to-
#: weight ratio at the low end of what small rotorcraft are built with.
DEFAULT_THRUST_TO_WEIGHT = names.TETHER_STUDY_THRUST_TO_WEIGHT

#: The winch gains the dynamic half can fly (module docstring).
WINCH_GAINS: tuple[str, ...] = names.TETHER_STUDY_WINCH_GAINS
#: The tension loop gain K K_P dt of the paper's hover (Table III's K_C, eq 56's K_P, 10 ms):
#: what ``"scaled"`` keeps.
PAPER_LOOP_GAIN = 40.0 * 1.0 * 0.01


def tension_loop_gain(stiffness_N_m: float, K_P: float, dt: float) -> float:
    """K K_P dt: the tension loop's gain per sample (module docstring); the loop is stable
    below 2.

    Parameters
    ----------
    stiffness_N_m : float
        The tether's axial stiffness K over its length [N/m].
    K_P : float
        Eq 56's proportional gain [m/(s N)].
    dt : float
        Sample time [s].

    Returns
    -------
    float
    """
    return stiffness_N_m * K_P * dt


def cable_stiffness(tether: LumpedTether, q9: float, T_ref: float) -> float:
    """K = (EA + T_ref) / q9 [N/m]: the cable's axial stiffness over its length at tension
    T_ref (eq 28 taut: K (q9 - LN) = T_ref with LN = q9 / (1 + T_ref / EA)); the paper's cable
    at 10 m gives Table III's K_C = 40 N/m.

    Parameters
    ----------
    tether : LumpedTether
        The cable (EA).
    q9 : float
        Its length [m].
    T_ref : float
        The tension [N].

    Returns
    -------
    float
    """
    return (tether.EA_N + T_ref) / q9


#: [s] The turbulence runs' metrics start after this settling time (both configurations):
#: a lumped chain starts hanging windless and is blown into shape in the first seconds. Runs
#: no longer than twice this count from t = 0.
TURBULENCE_SETTLE_S = 30.0

#: The tether models the dynamic half can fly (module docstring).
TETHER_MODELS: tuple[str, ...] = names.TETHER_STUDY_MODELS

#: The dynamic half's cases: (key, shipped scenario or paper simulation, the metrics whose
#: reduction is reported). Paper sims: the deviation along the wind; turbulence (mean wind
#: along n1, gusts on every axis): both horizontal ones.
DYNAMIC_CASES: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("sim1", ("peak_q1", "rms_q1")),
    ("sim2", ("peak_q2", "rms_q2")),
    ("turbulence", ("peak_q1", "rms_q1", "rms_q2")),
)


def select_cables(keys: Sequence[str]) -> tuple[StudyCable, ...]:
    """The ``STUDY_CABLES`` named by ``keys``, in that order.

    Parameters
    ----------
    keys : sequence of str
        Cable keys, each once.

    Returns
    -------
    tuple of StudyCable

    Raises
    ------
    ParameterError
        An unknown or repeated key, or none.
    """
    known = {c.key: c for c in STUDY_CABLES}
    allowed = f"distinct names from {list(known)}"
    if not keys or len(set(keys)) != len(keys) or any(k not in known for k in keys):
        raise ParameterError("cables", list(keys), allowed)
    return tuple(known[k] for k in keys)


def check_grid(
    field: str, values: Sequence[float], *, low: float, high: float, unit: str
) -> tuple[float, ...]:
    """A study grid: at least one value, each finite within [low, high], strictly ascending.

    Parameters
    ----------
    field : str
        Name in the error message (e.g. "lengths").
    values : sequence of float
        The grid.
    low, high : float
        The allowed range.
    unit : str
        Unit for the message, e.g. "[m]".

    Returns
    -------
    tuple of float

    Raises
    ------
    ParameterError
        Empty, out of range, not a number, or not strictly ascending.
    """
    vals = list(values)
    allowed = f"one or more numbers in [{low:g}, {high:g}] {unit}, strictly ascending"
    if not vals:
        raise ParameterError(field, vals, allowed)
    out = tuple(check_number(field, v, low=low, high=high, allowed=allowed) for v in vals)
    if any(b <= a for a, b in itertools.pairwise(out)):
        raise ParameterError(field, list(values), allowed)
    return out
