"""The tether study's dynamic half (``studies.tether_study``): Sec. VI's simulations and the
turbulence scenario, free and tethered, per cable, length, tether model and winch gain
(``study_scenarios``), flown through ``run_batch`` (``dynamic_rows``), and the runs beyond the
maximum thrust marked (``mark_thrust_infeasible``).
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Callable, Sequence
from typing import Any

from .._validation import check_number
from ..analysis import reduction_percent
from ..errors import ParameterError
from ..params import TETHER_LENGTH_RANGE, Params
from .tether_cables import (
    DYNAMIC_CASES,
    PAPER_LOOP_GAIN,
    TETHER_MODELS,
    TURBULENCE_SETTLE_S,
    WINCH_GAINS,
    StudyCable,
    cable_stiffness,
    tension_loop_gain,
)

__all__ = ["dynamic_rows", "mark_thrust_infeasible", "study_scenarios"]


def _turbulence(configuration: str, q9: float):
    """The shipped turbulence scenario at hover height q9 (its IEC calibration at q9)."""
    from ..scenario.core import scenario_from_dict
    from ..shipped import shipped_scenario_text

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
    from ..scenario.core import paper_scenario

    if model not in TETHER_MODELS:
        raise ParameterError("tether model", model, f"one of {list(TETHER_MODELS)}")
    lo, hi = TETHER_LENGTH_RANGE
    q9 = check_number("length_m", length_m, low=lo, high=hi, unit="[m]")
    from ..scenario.core import TetherSettings

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
    from ..runs.batch import run_batch

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
