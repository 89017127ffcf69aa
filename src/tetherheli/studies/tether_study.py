"""The tether study (issue 13, item 6): does the paper's stabilising effect survive at 10-100 m
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

This module runs the whole study and writes its tables (``run_tether_study``); the study's
cables and choices are ``studies.tether_cables``, its halves ``studies.tether_static`` and
``studies.tether_dynamic``, whose public names are re-exported here.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from .. import names
from ..errors import ParameterError
from ..params import TETHER_LENGTH_RANGE, Params
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
        max_thrust_N = _max_thrust(params, None)
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
