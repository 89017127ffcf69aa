"""The tether study: does the paper's stabilising effect survive at 10-100 m
of real cable, and what ground tension and cable does it need?

Static half (``static_rows``, ``hover_limits``), for each cable hanging straight down from P
to the winch (the paper's geometry; the vertical elastic catenary of
``tether.lumped_trim.hover_trim_lumped``):

- the ground tension that keeps the paper's 25 N at P: T_g = T_P - mu g L0, with L0 the
  unstretched length from q9 = L0 + (T_P L0 - mu g L0^2 / 2) / EA;
- with the winch holding the paper's 25 N at the load cell instead: the tension at P, the main
  rotor's thrust fMR3 and its extra over the paper's massless tether, and the margin to the
  maximum thrust (the paper gives none: ``max_thrust_N``, by default
  ``DEFAULT_THRUST_TO_WEIGHT`` times the free hover thrust of Table IV, an assumption);
- the quasi-static lateral stiffness of the tether at P, k = 1 / (ln(T_P / T_g) / (mu g) +
  L0 / EA) (a small horizontal force H at the top of a vertical heavy cable tilts it by
  H / T(s) at every point; ``lateral_stiffness``), against a massless tether's T / q9, the
  paper's pendulum restoring force;
- the lengths at which hover becomes impossible: T_g reaches 0 with 25 N at P (the cable
  weighs the whole tension), and fMR3 reaches the maximum thrust with 25 N at the winch.

Dynamic half (``dynamic_rows``): Sec. VI's simulations 1 and 2 and the turbulence scenario
(``turbulence_hover_*``, its IEC calibration at the hover height q9, metrics after
``TURBULENCE_SETTLE_S``), free and tethered, per
cable and length, through ``run_batch``; the paper's metric is the reduction
100 (free - tethered) / free of the peak and RMS deviation (``analysis.reduction_percent``).

The winch (eq 56's PI, ``WINCH_GAINS``): with the reel rate held over a sample dt, the
tension loop of a tether of axial stiffness K is T_(k+1) - T_ref = (1 - K K_P dt)
(T_k - T_ref) (+ the small integral term): stable only while K K_P dt < 2
(``tension_loop_gain``; the paper's 40 N/m x 1 m/(s N) x 0.01 s = 0.4). A real cable is far
stiffer over a short length (EA / q9: 2000 N/m for 20 kN at 10 m), so ``"paper"`` flies the
paper's K_P = 1, K_I = 0.1 and ``"scaled"`` scales both down, where needed, to keep the
paper's loop gain 0.4 with K = (EA + T_ref) / q9.

Tether models of the dynamic half (``TETHER_MODELS``): ``"lumped"``, the lumped-mass chain
in the engine (``[tether] model = "lumped"``: weight, sag, inertia, and drag in the
turbulence scenario's air; T_ref is held at the winch's load cell); ``"massless"``, the
paper's straight elastic tether (eq 28) with the cable's axial stiffness over the length,
K_C = (EA + T_ref) / q9 (``cable_stiffness``): the cable's stiffness without its weight,
drag or inertia, a stand-in that separates what the length does from what the mass does.

This module runs the whole study (``tether_study``, on a checked ``TetherStudyConfig``) and
returns its rows (``TetherStudy``); ``report.tether_study`` writes its tables, pages and
figures. The study's cables and choices are ``studies.tether_cables``, its halves
``studies.tether_static`` and ``studies.tether_dynamic``, whose public names are re-exported
here.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import names
from ..errors import ParameterError
from ..params import TETHER_LENGTH_RANGE, Params
from ..results.result import SummaryRepr
from .tether_cables import (
    DEFAULT_THRUST_TO_WEIGHT,
    DYNAMIC_CASES,
    PAPER_LOOP_GAIN,
    STUDY_CABLES,
    TETHER_MODELS,
    TURBULENCE_SETTLE_S,
    WINCH_GAINS,
    StudyCable,
    cable_stiffness,
    check_grid,
    select_cables,
    tension_loop_gain,
)
from .tether_dynamic import _checked_duration, dynamic_rows, mark_thrust_infeasible, study_scenarios
from .tether_static import _max_thrust, hover_limits, lateral_stiffness, static_rows

__all__ = [
    "DEFAULT_ELEVATIONS_DEG",
    "DEFAULT_LENGTHS_M",
    "DEFAULT_THRUST_TO_WEIGHT",
    "DEFAULT_WINDS_M_S",
    "DYNAMIC_CASES",
    "PAPER_LOOP_GAIN",
    "PAPER_TENSION_N",
    "STUDY_CABLES",
    "TETHER_MODELS",
    "TURBULENCE_SETTLE_S",
    "WINCH_GAINS",
    "StudyCable",
    "TetherStudy",
    "TetherStudyConfig",
    "cable_stiffness",
    "check_grid",
    "dynamic_rows",
    "hover_limits",
    "json_ready",
    "lateral_stiffness",
    "select_cables",
    "static_rows",
    "study_scenarios",
    "tension_loop_gain",
    "tether_study",
]


def _finite_or_none(x: Any) -> Any:
    if isinstance(x, float) and not math.isfinite(x):
        return None
    if isinstance(x, np.floating):
        return _finite_or_none(float(x))
    return x


def json_ready(rows: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """``rows`` with NaN as None (strict JSON).

    Parameters
    ----------
    rows : sequence of dict
        Rows of the study.

    Returns
    -------
    list of dict
    """
    return [{k: _finite_or_none(v) for k, v in r.items()} for r in rows]


# ----------------------------------------------------------------------------------------------
# the whole study (the command: tetherheli tether-study, report/tether_study.py)
# ----------------------------------------------------------------------------------------------

#: The study's default grids: lengths [m] (10-100 m), steady winds [m/s] and
#: elevations of P [deg] of the sensing half.
DEFAULT_LENGTHS_M: tuple[float, ...] = names.TETHER_STUDY_LENGTHS_M
DEFAULT_WINDS_M_S: tuple[float, ...] = names.TETHER_STUDY_WINDS_M_S
DEFAULT_ELEVATIONS_DEG: tuple[float, ...] = names.TETHER_STUDY_ELEVATIONS_DEG
#: The paper's tension (Sec. VI): at P for the first policy, at the winch for the second and
#: for the sensing half.
PAPER_TENSION_N = 25.0


@dataclass(frozen=True)
class TetherStudyConfig:
    """What the whole study computes, checked when it is built (before any work): the cables,
    the grids, the dynamic half's tether model, winch gains and run length, the maximum thrust.

    Parameters
    ----------
    cables : sequence of StudyCable, optional
        Default ``STUDY_CABLES``.
    lengths_m : sequence of float, optional
        Hover heights q9 [m] (``check_grid``), default ``DEFAULT_LENGTHS_M``.
    winds_m_s, elevations_deg : sequence of float, optional
        The sensing half's steady winds [m/s] and elevations of P [deg].
    model : str, optional
        The dynamic half's tether model (``TETHER_MODELS``).
    winch_gain : str, optional
        The winch's PI gains (``WINCH_GAINS``).
    duration_s : float, optional
        Shorten the dynamic runs (default: the scenarios' own 60 s and 120 s); at least one
        and a whole number of control samples.
    max_thrust_N : float, optional
        Maximum fMR3 [N] (default ``DEFAULT_THRUST_TO_WEIGHT`` x the free hover thrust).

    Raises
    ------
    ParameterError
        A grid, model, winch gain or duration out of range.
    """

    cables: tuple[StudyCable, ...] = STUDY_CABLES
    lengths_m: tuple[float, ...] = DEFAULT_LENGTHS_M
    winds_m_s: tuple[float, ...] = DEFAULT_WINDS_M_S
    elevations_deg: tuple[float, ...] = DEFAULT_ELEVATIONS_DEG
    model: str = "lumped"
    winch_gain: str = "paper"
    duration_s: float | None = None
    max_thrust_N: float | None = None

    def __post_init__(self) -> None:
        lo, hi = TETHER_LENGTH_RANGE
        checked: dict[str, Any] = {
            "cables": tuple(self.cables),
            "lengths_m": check_grid("lengths", self.lengths_m, low=lo, high=hi, unit="[m]"),
            "winds_m_s": check_grid("winds", self.winds_m_s, low=0.0, high=30.0, unit="[m/s]"),
            "elevations_deg": check_grid(
                "elevations", self.elevations_deg, low=1.0, high=90.0, unit="[deg]"
            ),
        }
        if self.model not in TETHER_MODELS:
            raise ParameterError("model", self.model, f"one of {list(TETHER_MODELS)}")
        if self.winch_gain not in WINCH_GAINS:
            raise ParameterError("winch_gain", self.winch_gain, f"one of {list(WINCH_GAINS)}")
        if self.duration_s is not None:  # the paper's runs (60 s) are the shortest
            from ..scenario.core import paper_scenario

            checked["duration_s"] = _checked_duration(self.duration_s, paper_scenario(1, "free"))
        for name, value in checked.items():
            object.__setattr__(self, name, value)


@dataclass(frozen=True, repr=False)
class TetherStudy(SummaryRepr):
    """The whole study's rows (``tether_study``): its static half per cable and length, the
    hover limits per cable, the dynamic half per cable and length (a row per case's free and
    tethered runs, marked failed where the hover exceeds the maximum thrust), the sensing half
    per cable, elevation, length and wind, and every run's configuration.

    Parameters
    ----------
    config : TetherStudyConfig
        What was computed.
    max_thrust_N : float
        The maximum fMR3 [N] used (``config.max_thrust_N`` or its default).
    static : tuple of dict
        ``static_rows``'s rows.
    hover_limits : tuple of dict
        ``hover_limits``'s rows.
    dynamic : tuple of dict
        ``dynamic_rows``'s rows.
    sensing : tuple of dict
        ``tether_sensing.sensing_study``'s rows.
    scenarios : dict of str to dict
        Every dynamic run's configuration (``Scenario.to_dict``) by run id
        "cable/length/run".
    """

    config: TetherStudyConfig
    max_thrust_N: float
    static: tuple[dict[str, Any], ...]
    hover_limits: tuple[dict[str, Any], ...]
    dynamic: tuple[dict[str, Any], ...]
    sensing: tuple[dict[str, Any], ...]
    scenarios: dict[str, Any]

    def _summary_rows(self) -> list[tuple[str, str]]:
        c = self.config
        return [
            ("cables", ", ".join(cable.key for cable in c.cables)),
            ("lengths", ", ".join(f"{x:g}" for x in c.lengths_m) + " m"),
            ("tether model", c.model),
            ("rows", f"{len(self.static)} static, {len(self.dynamic)} dynamic "
                     f"({len(self.failed)} failed), {len(self.sensing)} sensing"),
        ]  # fmt: skip

    @property
    def labels(self) -> dict[str, str]:
        """Cable key -> its legend text, in the study's order."""
        return {c.key: c.label for c in self.config.cables}

    @property
    def failed(self) -> tuple[dict[str, Any], ...]:
        """The dynamic rows with a run that did not complete."""
        return tuple(r for r in self.dynamic if not r["completed"])

    def as_dict(self) -> dict[str, Any]:
        """The study as plain data (summary.json, NaN as None): the choices, the cables, the
        grids, every row and every run's configuration.

        Returns
        -------
        dict
        """
        c = self.config
        return {
            "tether_model": c.model,
            "winch_gain": c.winch_gain,
            "note": (
                "dynamic runs: the paper's massless straight tether with K_C = (EA + T_ref) / q9 "
                "(the cable's stiffness, neither its weight nor its drag nor its inertia)"
                if c.model == "massless"
                else "dynamic runs: the lumped-mass chain, T_ref at the winch"
            )
            + "; static and sensing halves: the elastic catenary with mass and drag",
            "cables": [cable.to_dict() for cable in c.cables],
            "lengths_m": list(c.lengths_m),
            "winds_m_s": list(c.winds_m_s),
            "elevations_deg": list(c.elevations_deg),
            "tension_N": PAPER_TENSION_N,
            "max_thrust_N": self.max_thrust_N,
            "thrust_to_weight_default": DEFAULT_THRUST_TO_WEIGHT,
            "duration_s": c.duration_s,
            "static": json_ready(self.static),
            "hover_limits": json_ready(self.hover_limits),
            "dynamic": json_ready(self.dynamic),
            "sensing": json_ready(self.sensing),
            "scenarios": self.scenarios,
        }


def tether_study(
    config: TetherStudyConfig, *, workers: int | None = None, progress: bool = True
) -> TetherStudy:
    """Run the whole study: the static half and the hover limits, the dynamic half through
    ``run_batch`` and the sensing half (``report.tether_study`` writes it).

    Parameters
    ----------
    config : TetherStudyConfig
        The cables, grids and choices.
    workers : int, optional
        ``run_batch``'s threads.
    progress : bool, optional
        Progress of the dynamic runs on stderr.

    Returns
    -------
    TetherStudy
    """
    from ..progress import Progress
    from .tether_sensing import sensing_study

    if not isinstance(config, TetherStudyConfig):
        raise TypeError("config must be a TetherStudyConfig")
    cables, lengths = config.cables, config.lengths_m
    params = Params.paper()
    max_thrust_N = config.max_thrust_N
    if max_thrust_N is None:
        max_thrust_N = _max_thrust(params, None)
    static = static_rows(params, cables, lengths, max_thrust_N=max_thrust_N)
    limits = hover_limits(params, cables, max_thrust_N=max_thrust_N)
    n_runs = len(cables) * len(lengths) * 2 * len(DYNAMIC_CASES)
    with Progress("tether-study", n_runs, "runs", enabled=progress) as bar:
        dynamic, scenarios = dynamic_rows(
            cables,
            lengths,
            model=config.model,
            winch_gain=config.winch_gain,
            duration_s=config.duration_s,
            workers=workers,
            on_done=bar.update,
        )
    mark_thrust_infeasible(static, dynamic, max_thrust_N)
    g = params.helicopter.g
    sensing = sensing_study(
        cables, lengths, config.winds_m_s, config.elevations_deg, PAPER_TENSION_N, g
    )
    return TetherStudy(
        config=config,
        max_thrust_N=max_thrust_N,
        static=tuple(static),
        hover_limits=tuple(limits),
        dynamic=tuple(dynamic),
        sensing=tuple(sensing),
        scenarios=scenarios,
    )
