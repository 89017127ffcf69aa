"""The tether study (issue 13, item 6): does the paper's stabilising effect survive at 10-100 m
of real cable, and what ground tension and cable does it need?

Static half (``static_rows``, ``hover_limits``), for each cable hanging straight down from P
to the winch (the paper's geometry; the vertical elastic catenary of
``tether_lumped.hover_trim_lumped``):

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
"""

from __future__ import annotations

import dataclasses
import itertools
import json
import math
import tomllib
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy import optimize

from .. import names
from .._validation import check_number
from ..analysis import reduction_percent
from ..errors import ParameterError
from ..model import tether_lumped as tl
from ..params import TETHER_LENGTH_RANGE, Params

__all__ = [
    "DEFAULT_ELEVATIONS_DEG",
    "DEFAULT_LENGTHS_M",
    "DEFAULT_THRUST_TO_WEIGHT",
    "DEFAULT_WINDS_M_S",
    "DYNAMIC_CASES",
    "PAPER_LOOP_GAIN",
    "STUDY_CABLES",
    "TETHER_MODELS",
    "TURBULENCE_SETTLE_S",
    "WINCH_GAINS",
    "StudyCable",
    "cable_stiffness",
    "check_grid",
    "dynamic_rows",
    "hover_limits",
    "json_ready",
    "lateral_stiffness",
    "run_tether_study",
    "select_cables",
    "sensing_table",
    "static_rows",
    "study_scenarios",
    "study_table",
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
    tether: tl.LumpedTether
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
        tl.LumpedTether(segments=20),
        "EA = K_C L0N = 40 N/m x 9.375 m (Table III, eq 28); 20 g/m and 5 mm assumed (the "
        "paper's tether is massless)",
    ),
    StudyCable(
        "power",
        "power-and-data: 30 g/m, EA 20 kN, 5 mm",
        tl.LumpedTether(segments=20, mass_per_length_kg_m=0.03, EA_N=20e3),
        "assumed: a 5 mm copper-pair cable with an aramid strength member, in the 10-40 g/m "
        "range issue 13 gives for tethered UAVs; EA of tens of kN (issue 13)",
    ),
    StudyCable(
        "data",
        "light data: 10 g/m, EA 5 kN, 3 mm",
        tl.LumpedTether(segments=20, mass_per_length_kg_m=0.01, EA_N=5e3, diameter_m=0.003),
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


def cable_stiffness(tether: tl.LumpedTether, q9: float, T_ref: float) -> float:
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


# ----------------------------------------------------------------------------------------------
# static half
# ----------------------------------------------------------------------------------------------


def _top_tension_length(q9: float, top_tension_N: float, w: float, EA: float) -> float:
    """Unstretched length L0 [m] of a vertical cable of height q9 with tension T_P at the top:
    the smaller root of (w / 2EA) L0^2 - (1 + T_P / EA) L0 + q9 = 0 (T(s) = T_P - w (L0 - s))."""
    b = 1.0 + top_tension_N / EA
    disc = b * b - 2.0 * w * q9 / EA
    if disc < 0.0:
        return math.nan
    return 2.0 * q9 / (b + math.sqrt(disc))


def lateral_stiffness(
    ground_tension_N: float, tether: tl.LumpedTether, g: float, unstretched_length_m: float
) -> float:
    """Quasi-static lateral stiffness [N/m] of a vertical hanging cable at its top, pinned at
    the winch: k = 1 / (ln(T_P / T_g) / (mu g) + L0 / EA); a massless cable's limit is
    T / (L0 (1 + T / EA)) = T / q9, the paper's pendulum.

    Parameters
    ----------
    ground_tension_N : float
        Tension at the winch [N], > 0 (at P: T_P = T_g + mu g L0).
    tether : LumpedTether
        The cable (mu, EA).
    g : float
        Gravity [m/s^2].
    unstretched_length_m : float
        L0 [m].

    Returns
    -------
    float
        dH/dx at P [N/m].
    """
    w = tether.mass_per_length_kg_m * g
    Tg, L0 = ground_tension_N, unstretched_length_m
    # ln(Tp/Tg)/w, written so that w -> 0 (Tp -> Tg) stays accurate: L0 log1p(x)/x, x = wL0/Tg
    x = w * L0 / Tg
    compliance = (L0 / Tg) * (math.log1p(x) / x if x > 1e-12 else 1.0 - 0.5 * x)
    return 1.0 / (compliance + L0 / tether.EA_N)


def _free_thrust(params: Params) -> float:
    from ..model.trim import hover_trim

    return float(hover_trim(params, 0.0).u_total[0])


def static_rows(
    params: Params,
    cables: Sequence[StudyCable],
    lengths_m: Sequence[float],
    *,
    top_tension_N: float = 25.0,
    ground_tension_N: float = 25.0,
    max_thrust_N: float | None = None,
) -> list[dict[str, Any]]:
    """The static half per (cable, length): see the module docstring.

    Parameters
    ----------
    params : Params
        The helicopter (Table II).
    cables : sequence of StudyCable
        The cables.
    lengths_m : sequence of float
        Heights q9 of P above the winch [m].
    top_tension_N : float, optional
        The tension to keep at P [N] (the paper's 25 N).
    ground_tension_N : float, optional
        The load cell's tension of the second policy [N] (the paper's 25 N).
    max_thrust_N : float, optional
        Maximum fMR3 [N]; default ``DEFAULT_THRUST_TO_WEIGHT`` x the free hover thrust.

    Returns
    -------
    list of dict
        Per (cable, length): ``L0_m`` and ``ground_tension_for_top_N`` (NaN when T_g <= 0:
        impossible) for 25 N at P; with 25 N at the winch ``top_tension_N``, ``fMR3_N``,
        ``extra_lift_N`` (over the massless tether's trim), ``lift_margin_N``;
        ``k_lateral_N_m`` (cable, 25 N at the winch) and ``k_lateral_massless_N_m``
        (T_ref / q9).
    """
    from ..model.trim import hover_trim

    g = params.helicopter.g
    Tp = check_number("top_tension_N", top_tension_N, low=0.0, low_open=True, unit="[N]")
    Tg = check_number("ground_tension_N", ground_tension_N, low=0.0, low_open=True, unit="[N]")
    if max_thrust_N is None:
        max_thrust_N = DEFAULT_THRUST_TO_WEIGHT * _free_thrust(params)
    fmax = check_number("max_thrust_N", max_thrust_N, low=0.0, low_open=True, unit="[N]")
    rows = []
    for cable in cables:
        t = cable.tether
        w = t.mass_per_length_kg_m * g
        for q9 in lengths_m:
            massless = float(hover_trim(params, Tg, q9).u_total[0])
            L0_top = _top_tension_length(q9, Tp, w, t.EA_N)
            Tg_top = Tp - w * L0_top if L0_top == L0_top else math.nan
            lt = tl.hover_trim_lumped(params, t, Tg, q9)
            f = float(lt.trim.u_total[0])
            rows.append(
                {
                    "cable": cable.key,
                    "length_m": float(q9),
                    "L0_m": L0_top,
                    "ground_tension_for_top_N": Tg_top if Tg_top > 0.0 else math.nan,
                    "top_tension_N": lt.top_tension_N,
                    "fMR3_N": f,
                    "extra_lift_N": f - massless,
                    "lift_margin_N": fmax - f,
                    "k_lateral_N_m": lateral_stiffness(Tg, t, g, lt.unstretched_length_m),
                    "k_lateral_massless_N_m": Tg / q9,
                }
            )
    return rows


def hover_limits(
    params: Params,
    cables: Sequence[StudyCable],
    *,
    top_tension_N: float = 25.0,
    ground_tension_N: float = 25.0,
    max_thrust_N: float | None = None,
) -> list[dict[str, Any]]:
    """The lengths at which hover becomes impossible, per cable.

    Parameters
    ----------
    params : Params
        The helicopter.
    cables : sequence of StudyCable
        The cables.
    top_tension_N, ground_tension_N, max_thrust_N : float, optional
        As ``static_rows``.

    Returns
    -------
    list of dict
        ``cable``; ``max_length_top_tension_m``: the height at which the ground tension for
        ``top_tension_N`` at P reaches 0 (L0 = T_P / (mu g), q9 = L0 (1 + T_P / (2 EA)));
        ``max_length_thrust_m``: the height at which fMR3 with ``ground_tension_N`` at the
        winch reaches ``max_thrust_N`` (NaN: not within ``TETHER_LENGTH_RANGE``);
        ``max_thrust_N``.
    """
    g = params.helicopter.g
    if max_thrust_N is None:
        max_thrust_N = DEFAULT_THRUST_TO_WEIGHT * _free_thrust(params)
    fmax = check_number("max_thrust_N", max_thrust_N, low=0.0, low_open=True, unit="[N]")
    Tp = check_number("top_tension_N", top_tension_N, low=0.0, low_open=True, unit="[N]")
    out = []
    for cable in cables:
        t = cable.tether
        w = t.mass_per_length_kg_m * g
        L0 = Tp / w
        q9_top = L0 * (1.0 + Tp / (2.0 * t.EA_N))

        def excess(q9: float, t: tl.LumpedTether = t) -> float:
            lt = tl.hover_trim_lumped(params, t, ground_tension_N, q9)
            return float(lt.trim.u_total[0]) - fmax

        lo, hi = TETHER_LENGTH_RANGE
        if excess(lo) >= 0.0:
            q9_thrust = 0.0
        elif excess(hi) < 0.0:
            q9_thrust = math.nan
        else:
            q9_thrust = float(optimize.brentq(excess, lo, hi, xtol=1e-6))
        out.append(
            {
                "cable": cable.key,
                "max_length_top_tension_m": q9_top,
                "max_length_thrust_m": q9_thrust,
                "max_thrust_N": fmax,
            }
        )
    return out


# ----------------------------------------------------------------------------------------------
# dynamic half
# ----------------------------------------------------------------------------------------------


def _turbulence(configuration: str, q9: float):
    """The shipped turbulence scenario at hover height q9 (its IEC calibration at q9)."""
    from ..shipped import shipped_scenario_text
    from ..sim.scenario import scenario_from_dict

    name = f"turbulence_hover_{configuration}"
    data = tomllib.loads(shipped_scenario_text(name))
    data["q9"] = q9
    data["wind"]["model"]["height_m"] = q9
    return scenario_from_dict(data, source=f"shipped scenario {name} at q9 = {q9:g} m")


def _checked_duration(duration_s: float, scenario: Any) -> float:
    """``duration_s`` checked as the study's ``duration`` of ``scenario``'s runs: at least one
    and a whole number of its control samples, at most its own duration [s]."""
    dt, longest = scenario.control.dt, scenario.duration
    allowed = (
        f"a duration in [{dt:g}, {longest:g}] s, a whole number of the runs' control.dt = {dt:g} s"
    )
    d = check_number("duration", duration_s, low=dt, high=longest, allowed=allowed)
    if abs(d / dt - round(d / dt)) > 1e-9 * d / dt:
        raise ParameterError("duration", duration_s, allowed)
    return d


def study_scenarios(
    cable: StudyCable,
    length_m: float,
    *,
    model: str = "lumped",
    winch_gain: str = "paper",
    duration_s: float | None = None,
    params: Params | None = None,
) -> dict[str, Any]:
    """The dynamic half's runs at one (cable, length): ``"{case}_free"`` and
    ``"{case}_tethered"`` for each case of ``DYNAMIC_CASES``.

    Parameters
    ----------
    cable : StudyCable
        The cable (the free runs do not depend on it).
    length_m : float
        The hover height q9 [m].
    model : str, optional
        One of ``TETHER_MODELS``.
    winch_gain : str, optional
        One of ``WINCH_GAINS``.
    duration_s : float, optional
        Shorten every run to this many seconds (default: each scenario's own, 60 s and
        120 s).
    params : Params, optional
        The helicopter and tension control (default the paper's); the tether's K_C is
        replaced by the cable's (module docstring).

    Returns
    -------
    dict of str to Scenario
    """
    from ..sim.scenario import paper_scenario

    if model not in TETHER_MODELS:
        raise ParameterError("tether model", model, f"one of {list(TETHER_MODELS)}")
    lo, hi = TETHER_LENGTH_RANGE
    q9 = check_number("length_m", length_m, low=lo, high=hi, unit="[m]")
    from ..sim.scenario import TetherSettings

    if winch_gain not in WINCH_GAINS:
        raise ParameterError("winch gain", winch_gain, f"one of {list(WINCH_GAINS)}")
    params = Params.paper() if params is None else params
    tc = params.tension_control
    T_ref = tc.T_ref
    t = cable.tether
    K = cable_stiffness(t, q9, T_ref)
    winch_params = params
    if winch_gain == "scaled":
        dt = paper_scenario(1, "tethered").control.dt
        factor = min(1.0, PAPER_LOOP_GAIN / tension_loop_gain(K, tc.K_P, dt))
        winch_params = params.replace(
            tension_control={"K_P": tc.K_P * factor, "K_I": tc.K_I * factor}
        )
    if model == "lumped":
        tethered_params = winch_params
        tether = TetherSettings(
            model="lumped",
            segments=t.segments,
            mass_per_length=t.mass_per_length_kg_m,
            EA=t.EA_N,
            damping_ratio=t.damping_ratio or 0.0,
            internal_damping=t.internal_damping_Ns or 0.0,
            diameter=t.diameter_m,
            drag_coefficient=t.drag_coefficient,
            tangential_drag_coefficient=t.tangential_drag_coefficient,
        )
    else:
        tethered_params = winch_params.replace(tether={"K_C": K})
        tether = TetherSettings()
    out = {}
    for case, _ in DYNAMIC_CASES:
        for conf in ("free", "tethered"):
            if case == "turbulence":
                s = _turbulence(conf, q9)
            else:
                s = paper_scenario(int(case[-1]), conf).replace(q9=q9)
            if conf == "tethered":
                s = s.replace(params=tethered_params, tether=tether)
            else:
                s = s.replace(params=params)
            if duration_s is not None:
                s = s.replace(duration=_checked_duration(duration_s, s))
            if case == "turbulence" and s.duration > 2.0 * TURBULENCE_SETTLE_S:
                s = s.replace(metrics_start=TURBULENCE_SETTLE_S)
            out[f"{case}_{conf}"] = s
    return out


def dynamic_rows(
    cables: Sequence[StudyCable],
    lengths_m: Sequence[float],
    *,
    model: str = "lumped",
    winch_gain: str = "paper",
    duration_s: float | None = None,
    workers: int | None = None,
    on_done: Callable[[int], None] | None = None,
) -> tuple[list[dict[str, Any]], dict[str, Any]]:
    """Fly the dynamic half with ``run_batch``: one row per (cable, length).

    Parameters
    ----------
    cables : sequence of StudyCable
        The cables.
    lengths_m : sequence of float
        Hover heights q9 [m].
    model : str, optional
        One of ``TETHER_MODELS``.
    winch_gain : str, optional
        One of ``WINCH_GAINS``.
    duration_s : float, optional
        Shorter runs (``study_scenarios``).
    workers : int, optional
        ``run_batch``'s threads.
    on_done : callable, optional
        Progress callback (``run_batch``).

    Returns
    -------
    rows : list of dict
        ``cable``, ``length_m``, ``tether_model``, ``winch_gain``, ``K_P`` [m/(s N)],
        ``tension_loop_gain`` (``tension_loop_gain``), ``completed`` and per case and metric
        ``{case}_{metric}_free``, ``{case}_{metric}_tethered`` [m] and
        ``{case}_{metric}_reduction_pct`` (NaN when a run failed or the free run did not
        deviate, e.g. a run shorter than the first wind), the tension range
        ``{case}_tension_min_N``/``_max_N`` and ``{case}_status``.
    scenarios : dict of str to dict
        Every run's configuration (``Scenario.to_dict``) by run id "cable/length/run".
    """
    from ..sim.batch import run_batch

    runs: list[tuple[str, float, str, Any]] = []
    for cable in cables:
        for q9 in lengths_m:
            for run, s in study_scenarios(
                cable, q9, model=model, winch_gain=winch_gain, duration_s=duration_s
            ).items():
                runs.append((cable.key, q9, run, s))
    result = run_batch(
        [r[3] for r in runs], workers=workers, record_setup_failures=True, on_done=on_done
    )
    by_id = {(c, q9, run): i for i, (c, q9, run, _) in enumerate(runs)}
    rows = []
    for cable in cables:
        for q9 in lengths_m:
            teth = runs[by_id[(cable.key, q9, "sim1_tethered")]][3]
            K_P = teth.params.tension_control.K_P
            K = cable_stiffness(cable.tether, q9, teth.params.tension_control.T_ref)
            row: dict[str, Any] = {
                "cable": cable.key,
                "length_m": q9,
                "tether_model": model,
                "winch_gain": winch_gain,
                "K_P": K_P,
                "tension_loop_gain": tension_loop_gain(K, K_P, teth.control.dt),
            }
            completed = True
            for case, metrics in DYNAMIC_CASES:
                i_free = by_id[(cable.key, q9, f"{case}_free")]
                i_teth = by_id[(cable.key, q9, f"{case}_tethered")]
                ok = bool(result.ok[i_free] and result.ok[i_teth])
                completed &= ok
                row[f"{case}_status"] = (
                    "completed"
                    if ok
                    else "; ".join(
                        f"{conf}: {result.message(i)} {result.reasons[i]}".strip()
                        for conf, i in (("free", i_free), ("tethered", i_teth))
                        if not result.ok[i]
                    )
                )
                m_free, m_teth = result.metrics(i_free), result.metrics(i_teth)
                for m in metrics:
                    row[f"{case}_{m}_free"] = m_free[m]
                    row[f"{case}_{m}_tethered"] = m_teth[m]
                    # NaN: a failed run, or no deviation of the free run (no wind yet)
                    row[f"{case}_{m}_reduction_pct"] = (
                        reduction_percent(m_free[m], m_teth[m])
                        if ok and m_free[m] > 0.0
                        else math.nan
                    )
                row[f"{case}_tension_min_N"] = m_teth["tension_min"]
                row[f"{case}_tension_max_N"] = m_teth["tension_max"]
            row["completed"] = completed
            rows.append(row)
    configs = {f"{c}/{q9:g}/{run}": s.to_dict() for c, q9, run, s in runs}
    return rows, configs


def mark_thrust_infeasible(
    static: Sequence[dict[str, Any]], dynamic: Sequence[dict[str, Any]], max_thrust_N: float
) -> None:
    """Mark as failed (in place) every dynamic row whose static hover needs more thrust than
    ``max_thrust_N`` (a negative ``lift_margin_N``): such a hover cannot be flown, whatever
    the dynamic run did, so it is never "completed" and yields no reduction.

    Parameters
    ----------
    static : sequence of dict
        ``static_rows``' rows (``cable``, ``length_m``, ``fMR3_N``, ``lift_margin_N``).
    dynamic : sequence of dict
        ``dynamic_rows``' rows, changed in place: ``completed`` False, each case's status
        saying why, its reductions NaN.
    max_thrust_N : float
        The thrust limit the margin was computed against [N].
    """
    short = {(r["cable"], r["length_m"]): r for r in static if not r["lift_margin_N"] >= 0.0}
    for row in dynamic:
        st = short.get((row["cable"], row["length_m"]))
        if st is None:
            continue
        why = (
            f"infeasible hover: fMR3 = {st['fMR3_N']:.6g} N exceeds the maximum thrust "
            f"{max_thrust_N:.6g} N (thrust margin {st['lift_margin_N']:.4g} N)"
        )
        row["completed"] = False
        for case, metrics in DYNAMIC_CASES:
            row[f"{case}_status"] = why
            for m in metrics:
                row[f"{case}_{m}_reduction_pct"] = math.nan


def _finite_or_none(x: Any) -> Any:
    if isinstance(x, float) and not math.isfinite(x):
        return None
    if isinstance(x, np.floating):
        return _finite_or_none(float(x))
    return x


def json_ready(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """``rows`` with NaN as None (strict JSON)."""
    return [{k: _finite_or_none(v) for k, v in r.items()} for r in rows]


# ----------------------------------------------------------------------------------------------
# the whole study (the command: tetherheli tether-study, cli/tether_study.py)
# ----------------------------------------------------------------------------------------------

#: The study's default grids: lengths [m] (issue 13: 10-100 m), steady winds [m/s] and
#: elevations of P [deg] of the sensing half.
DEFAULT_LENGTHS_M: tuple[float, ...] = names.TETHER_STUDY_LENGTHS_M
DEFAULT_WINDS_M_S: tuple[float, ...] = names.TETHER_STUDY_WINDS_M_S
DEFAULT_ELEVATIONS_DEG: tuple[float, ...] = names.TETHER_STUDY_ELEVATIONS_DEG
#: The paper's tension (Sec. VI): at P for the first policy, at the winch for the second and
#: for the sensing half.
PAPER_TENSION_N = 25.0


def _csv(rows: Sequence[dict[str, Any]]) -> str:
    import csv
    import io

    buf = io.StringIO()
    columns = list(rows[0]) if rows else []
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(columns)
    for r in rows:
        writer.writerow([r.get(c, "") for c in columns])
    return buf.getvalue()


def _f(x: Any, spec: str) -> str:
    return "-" if x is None or (isinstance(x, float) and not math.isfinite(x)) else format(x, spec)


def study_table(static: Sequence[dict[str, Any]], dynamic: Sequence[dict[str, Any]]) -> str:
    """The study's main table (Markdown): per cable and length the ground tension for 25 N at
    P, the extra thrust and margin with 25 N at the winch, the lateral stiffness, and the
    reductions [%] of peak q1 (sim 1), peak q2 (sim 2) and RMS q1 (turbulence).

    Parameters
    ----------
    static, dynamic : sequence of dict
        ``static_rows`` and ``dynamic_rows`` on the same cables and lengths.

    Returns
    -------
    str
    """
    dyn = {(r["cable"], r["length_m"]): r for r in dynamic}
    head = (
        "| cable | q9 [m] | T_ground for 25 N at P [N] | T_P with 25 N at winch [N] "
        "| extra fMR3 [N] | thrust margin [N] | k_lat [N/m] (massless) "
        "| sim 1 peak q1 [%] | sim 2 peak q2 [%] | turbulence RMS q1 [%] |\n"
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n"
    )
    lines = []
    for r in static:
        d = dyn.get((r["cable"], r["length_m"]), {})
        lines.append(
            f"| {r['cable']} | {r['length_m']:g} | {_f(r['ground_tension_for_top_N'], '.2f')} "
            f"| {r['top_tension_N']:.2f} | {r['extra_lift_N']:.2f} | {r['lift_margin_N']:.2f} "
            f"| {r['k_lateral_N_m']:.3f} ({r['k_lateral_massless_N_m']:.3f}) "
            f"| {_f(d.get('sim1_peak_q1_reduction_pct'), '.1f')} "
            f"| {_f(d.get('sim2_peak_q2_reduction_pct'), '.1f')} "
            f"| {_f(d.get('turbulence_rms_q1_reduction_pct'), '.1f')} |"
        )
    return head + "\n".join(lines) + "\n"


def sensing_table(rows: Sequence[dict[str, Any]]) -> str:
    """The sensing half as a Markdown table: horizontal errors [m] of each estimate.

    Parameters
    ----------
    rows : sequence of dict
        ``tether_sensing.sensing_study``'s rows.

    Returns
    -------
    str
    """
    from .tether_sensing import ESTIMATES

    head = (
        "| cable | elevation [deg] | length [m] | wind [m/s] | winch-tangent angle [deg] | "
        + " | ".join(ESTIMATES)
        + " |\n|"
        + "---|" * (5 + len(ESTIMATES))
        + "\n"
    )
    lines = []
    for r in rows:
        if r["status"] != "ok":
            lines.append(
                f"| {r['cable']} | {r['elevation_deg']:g} | {r['length_m']:g} "
                f"| {r['wind_m_s']:g} | {r['status']} |" + " |" * len(ESTIMATES)
            )
            continue
        cells = " | ".join(f"{r[e]:.3f}" for e in ESTIMATES)
        lines.append(
            f"| {r['cable']} | {r['elevation_deg']:g} | {r['length_m']:g} | {r['wind_m_s']:g} "
            f"| {r['ground_angle_deg']:.2f} | {cells} |"
        )
    return head + "\n".join(lines) + "\n"


def run_tether_study(
    out: str,
    *,
    cables: Sequence[StudyCable] = STUDY_CABLES,
    lengths_m: Sequence[float] = DEFAULT_LENGTHS_M,
    winds_m_s: Sequence[float] = DEFAULT_WINDS_M_S,
    elevations_deg: Sequence[float] = DEFAULT_ELEVATIONS_DEG,
    model: str = "lumped",
    winch_gain: str = "paper",
    duration_s: float | None = None,
    max_thrust_N: float | None = None,
    workers: int | None = None,
    command: str = "",
    force: bool = False,
    progress: bool = True,
    figure_format: str = "png",
) -> dict[str, Any]:
    """Run the whole study and write it to ``out`` (whole or not at all,
    ``_io.output_directory``): study.md (the main table and the hover limits), static.csv,
    dynamic.csv, sensing.csv / sensing.md, reduction.png, static.png, sensing.png and
    summary.json (every row, the cables, the grids and every run's configuration).

    Parameters
    ----------
    out : str
        The output folder.
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
        Shorten the dynamic runs (default: the scenarios' own 60 s and 120 s).
    max_thrust_N : float, optional
        Maximum fMR3 [N] (default ``DEFAULT_THRUST_TO_WEIGHT`` x the free hover thrust).
    workers : int, optional
        ``run_batch``'s threads.
    command : str, optional
        The command line, recorded.
    force : bool, optional
        Replace this command's earlier output in ``out``.
    progress : bool, optional
        Progress on stderr.
    figure_format : {"png", "pdf", "svg"}, optional
        File format of the three figures (default "png").

    Returns
    -------
    dict
        The summary written to summary.json.
    """
    from .. import __version__
    from .._io import atomic_write_text, claim_output_directory, output_directory
    from ..progress import Progress
    from ..viz.plots import save_figure
    from ..viz.tether_study import (
        figure_study_reduction,
        figure_study_sensing,
        figure_study_static,
    )
    from .tether_sensing import sensing_study

    lo, hi = TETHER_LENGTH_RANGE
    lengths = check_grid("lengths", lengths_m, low=lo, high=hi, unit="[m]")
    winds = check_grid("winds", winds_m_s, low=0.0, high=30.0, unit="[m/s]")
    elevations = check_grid("elevations", elevations_deg, low=1.0, high=90.0, unit="[deg]")
    if model not in TETHER_MODELS:
        raise ParameterError("model", model, f"one of {list(TETHER_MODELS)}")
    if winch_gain not in WINCH_GAINS:
        raise ParameterError("winch_gain", winch_gain, f"one of {list(WINCH_GAINS)}")
    if duration_s is not None:  # fail before any work: the paper's runs (60 s) are the shortest
        from ..sim.scenario import paper_scenario

        duration_s = _checked_duration(duration_s, paper_scenario(1, "free"))
    claim_output_directory(out, force=force)
    params = Params.paper()
    if max_thrust_N is None:
        max_thrust_N = DEFAULT_THRUST_TO_WEIGHT * _free_thrust(params)
    static = static_rows(params, cables, lengths, max_thrust_N=max_thrust_N)
    limits = hover_limits(params, cables, max_thrust_N=max_thrust_N)
    n_runs = len(cables) * len(lengths) * 2 * len(DYNAMIC_CASES)
    with Progress("tether-study", n_runs, "runs", enabled=progress) as bar:
        dynamic, configs = dynamic_rows(
            cables,
            lengths,
            model=model,
            winch_gain=winch_gain,
            duration_s=duration_s,
            workers=workers,
            on_done=bar.update,
        )
    mark_thrust_infeasible(static, dynamic, max_thrust_N)
    g = params.helicopter.g
    sensing = sensing_study(cables, lengths, winds, elevations, PAPER_TENSION_N, g)
    labels = {c.key: c.label for c in cables}
    md = (
        f"# Tether study ({model} tether, {winch_gain} winch gains in the dynamic runs)\n\n"
        + study_table(static, dynamic)
        + "\nHover limits (25 N at P: the ground tension reaches 0; 25 N at the winch: fMR3 "
        f"reaches {max_thrust_N:.2f} N):\n\n| cable | max q9, 25 N at P [m] "
        "| max q9, 25 N at winch [m] |\n|---|---:|---:|\n"
        + "".join(
            f"| {r['cable']} | {r['max_length_top_tension_m']:.1f} "
            f"| {_f(r['max_length_thrust_m'], '.1f')} |\n"
            for r in limits
        )
    )
    summary = {
        "command": command,
        "tetherheli_version": __version__,
        "tether_model": model,
        "winch_gain": winch_gain,
        "note": (
            "dynamic runs: the paper's massless straight tether with K_C = (EA + T_ref) / q9 "
            "(the cable's stiffness, neither its weight nor its drag nor its inertia)"
            if model == "massless"
            else "dynamic runs: the lumped-mass chain, T_ref at the winch"
        )
        + "; static and sensing halves: the elastic catenary with mass and drag",
        "cables": [c.to_dict() for c in cables],
        "lengths_m": list(lengths),
        "winds_m_s": list(winds),
        "elevations_deg": list(elevations),
        "tension_N": PAPER_TENSION_N,
        "max_thrust_N": max_thrust_N,
        "thrust_to_weight_default": DEFAULT_THRUST_TO_WEIGHT,
        "duration_s": duration_s,
        "static": json_ready(static),
        "hover_limits": json_ready(limits),
        "dynamic": json_ready(dynamic),
        "sensing": json_ready(sensing),
        "scenarios": configs,
    }
    figures = {
        f"reduction.{figure_format}": figure_study_reduction(dynamic, labels),
        f"static.{figure_format}": figure_study_static(static, labels, max_thrust_N),
        f"sensing.{figure_format}": figure_study_sensing(sensing, labels),
    }
    with output_directory(out, writer="tether-study", force=force) as tmp:
        for name, fig in figures.items():
            save_figure(fig, tmp / name)
        atomic_write_text(tmp / "study.md", md)
        atomic_write_text(tmp / "static.csv", _csv(static))
        atomic_write_text(tmp / "dynamic.csv", _csv(dynamic))
        atomic_write_text(tmp / "sensing.csv", _csv(sensing))
        atomic_write_text(tmp / "sensing.md", sensing_table(sensing))
        atomic_write_text(tmp / "summary.json", json.dumps(summary, indent=1) + "\n")
    return summary
