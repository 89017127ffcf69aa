"""The lumped cable against MoorDyn v2 (issue 23 item 6; the moving anchor: issue 26): the
tables of ``docs/studies/moordyn.md``.

Run: python benchmarks/moordyn_validation.py [--print]
Flies every case of ``moordyn_cases.MOORDYN_CASES`` (beside this script) and
``MOVING_ANCHOR_CASES`` in MoorDyn (dtM 1e-4 s, RK4, 20 couplings per 10 ms sample: the
reference) and in ours (the engine's default 10 ms, and 10 ms / 64 as our converged run), then
the differences by design, and writes the page whole at the end (the project's own file:
``cli._script.write_docs_file``, checked before anything runs; ``--print``: prints it
instead). Needs ``pip install "tetherheli[validation]"``; a few minutes on two shared cores.
"""

from __future__ import annotations

import math
import sys
import textwrap
from dataclasses import replace
from pathlib import Path

import numpy as np
from moordyn_cases import (  # beside this script: the cases the tests fly too
    MOORDYN_CASES,
    MOVING_ANCHOR_CASES,
    compare_case,
    half_segment_inertia,
    relative_rms,
    slack_push,
    steady_state,
)

from tetherheli.cli._script import docs_file, run_script, script_parser, write_docs_file
from tetherheli.tether import buoyant_gravity, drive_cable, drive_moordyn

ROOT = Path(__file__).resolve().parents[1]
#: The page written (relative to ``ROOT``).
PAGE = "docs/studies/moordyn.md"
COUPLING = 20


def _pct(x: float) -> str:
    return "-" if math.isnan(x) else f"{100.0 * x:.2f} %"


def _sci(x: float) -> str:
    return f"{x:.1e}"


_HEADER = [
    "| case | static force, rel. error | RMS diff., ours 10 ms | ours converged | "
    "our step alone | force spread [N] | least k (l - l0) [N] |",
    "|---|---|---|---|---|---|---|",
]


def case_table(cases=MOORDYN_CASES) -> tuple[list[str], dict]:
    rows = list(_HEADER)
    figures = {}
    for name, case in cases.items():
        print(f"  {name}", file=sys.stderr, flush=True)
        f = compare_case(case, coupling=COUPLING)
        figures[name] = f
        static = "(in the wind: below)" if any(case.wind) else _sci(f.static_error)
        moving = case.amplitude > 0.0 or case.anchor_amplitude > 0.0
        spread = f"{f.force_std:.2f}" if moving else "-"
        rows.append(
            f"| {name} | {static} | {_pct(f.rms_default)} | {_pct(f.rms_converged)} | "
            f"{_pct(f.rms_step)} | {spread} | {f.min_tension:.1f} |"
        )
    return rows, figures


def drag_off_table() -> list[str]:
    rows = [
        "| case, drag off | RMS diff., ours 10 ms | ours converged | our step alone |",
        "|---|---|---|---|",
    ]
    for name in ("sideways 1 Hz", "sideways 3 Hz", "heavy 50 m, 0.2 Hz"):
        case = MOORDYN_CASES[name]
        f = compare_case(case, cable=replace(case.cable, drag_coefficient=1e-9),
                         coupling=COUPLING)  # fmt: skip
        rows.append(
            f"| {name} | {_pct(f.rms_default)} | {_pct(f.rms_converged)} | {_pct(f.rms_step)} |"
        )
    return rows


def moving_anchor_lines() -> list[str]:
    rows, figures = case_table(MOVING_ANCHOR_CASES)
    heave = [f for f in figures.values() if f.case.anchor_axis == 2]
    sway = next(f for f in figures.values() if f.case.anchor_axis == 0)
    drag_off = compare_case(sway.case, cable=replace(sway.case.cable, drag_coefficient=1e-9),
                            coupling=COUPLING)  # fmt: skip
    worst_heave = max(f.rms_converged for f in heave)
    return [
        "The anchor on a moving base (a heaving or swaying deck, `tetherheli.base`), the top "
        "held still 10 m up, the anchor's motion starting at rest. The two codes take two "
        "routes to the same motion: ours (`drive_cable(anchor=<a BaseMotion>)`) flies the "
        "chain in the base's translating frame, with the nodes' positions relative to the "
        "base, the air relative to the base and the inertial force -m b'' on the free nodes; "
        "MoorDyn moves a coupled anchor point in N, as it moves the top. The top's force is "
        "compared in N:",
        "",
        *rows,
        "",
        f"Heaving, the two agree to {_sci(worst_heave)} of the force's variation or better "
        "once our step converges: at 10 ms the difference is our step's. The sway differs "
        f"more ({_pct(sway.rms_converged)} converged) for the reason the sideways cases do: "
        "the deck sways the cable across the still air, and the two codes place the drag "
        "differently (below). With drag off the sway case agrees to "
        f"{_sci(drag_off.rms_converged)} once our step converges (ours 10 ms: "
        f"{_pct(drag_off.rms_default)}, our step's).",
    ]


def wind_table(wind_figures) -> list[str]:
    case = wind_figures.case
    F_md, x_md, _ = steady_state(wind_figures.reference, case.settle)
    F_ours, x_ours, stretch = steady_state(wind_figures.ours, case.settle)
    scaled = compare_case(case, refine=None, coupling=COUPLING, drag_scale=stretch)
    F_sc, x_sc, _ = steady_state(scaled.reference, case.settle)
    return [
        "| run | horizontal force at the top [N] | middle node's blow-out [m] |",
        "|---|---|---|",
        f"| MoorDyn | {F_md[0]:.4f} | {x_md[0]:.4f} |",
        f"| ours (10 ms) | {F_ours[0]:.4f} ({_pct(F_ours[0] / F_md[0] - 1)}) | "
        f"{x_ours[0]:.4f} ({_pct(x_ours[0] / x_md[0] - 1)}) |",
        f"| MoorDyn, Cd x mean stretch {stretch:.4f} | {F_sc[0]:.4f} "
        f"(ours {_pct(F_ours[0] / F_sc[0] - 1)}) | {x_sc[0]:.4f} "
        f"(ours {_pct(x_ours[0] / x_sc[0] - 1)}) |",
    ]


def slack_lines(slack_figures) -> list[str]:
    ref, ours = slack_figures.reference, slack_figures.ours
    slack, push = slack_push(ref)
    first = min(int(np.argmax(slack.any(axis=1))), int(np.argmax(slack_push(ours)[0].any(axis=1))))
    before = slice(0, first)
    undamped = compare_case(slack_figures.case, refine=16, coupling=COUPLING,
                            cable=replace(slack_figures.case.cable, damping_ratio=0.0))  # fmt: skip
    return [
        f"- some segment slack in {_pct(float(slack.any(axis=1).mean()))} of MoorDyn's samples; "
        f"its slack dashpots push up to {np.max(push):.2f} N (ours: 0 by design);",
        f"- until the first slack sample (t = {ref.t[first]:.2f} s) the forces agree to "
        f"{_sci(relative_rms(ours.top_force[before], ref.top_force[before]))} of their "
        f"variation; over the run they differ by {_pct(slack_figures.rms_default)} "
        f"(ours converged: {_pct(slack_figures.rms_converged)});",
        f"- both undamped (no dashpot either side, the same slack rule): "
        f"{_pct(undamped.rms_default)}, but our own step's error is then "
        f"{_pct(undamped.rms_step)} (against ours at 10 ms / 16): snap loading without "
        "damping is chaotic, neither run is a reference.",
    ]


def other_lines(figures) -> list[str]:
    side = figures["sideways 3 Hz"]
    ratio = half_segment_inertia(side.case, side.force_std)
    case = MOORDYN_CASES["static inclined"]
    kw = {"anchor": (0, 0, 0), "top": case.top(), "duration": 0.01, "dt": 0.01}
    ref = drive_moordyn(case.cable, coupling=COUPLING, **kw).top_force[0]
    plain = drive_cable(case.cable, **kw).top_force[0]
    fixed = drive_cable(case.cable, g=buoyant_gravity(case.cable), **kw).top_force[0]
    rel = lambda F: float(np.linalg.norm(F - ref) / np.linalg.norm(ref))  # noqa: E731
    return [
        f"- top half-segment: its inertial force (mu l0 / 2) a_top is {_pct(ratio)} of the "
        "force's spread for the paper's cable at 3 Hz sideways; neither code's force at the "
        "top includes it (MoorDyn hands the mass to the coupled point, `GetPointM`; our "
        "engine leaves it out);",
        f"- buoyancy (the displaced air, which MoorDyn weighs): the static force with g alone "
        f"differs by {_sci(rel(plain))}, with `buoyant_gravity` by {_sci(rel(fixed))} "
        "(static inclined).",
    ]


def page() -> str:
    rows, figures = case_table()
    parts = [
        "# The lumped cable against MoorDyn v2",
        "",
        "Regenerated by (from the repository root; a test checks that each command and file "
        "exists):",
        "",
        "- `python benchmarks/moordyn_validation.py`",
        "",
        "`tetherheli.tether.drive_moordyn` flies a `Cable` in MoorDyn v2 (MoorDyn-C 2.7.2 "
        'through its Python API, `pip install "tetherheli[validation]"`) between the same '
        "anchor (fixed, or on a moving base: below) and prescribed top motion as `drive_cable`. "
        "MoorDyn is set up in air: "
        "fluid density 1.225 kg/m^3, added mass Ca = CaAx = 0, EI = 0, BA = the segment "
        "dashpot times l0, the chain 1000 m under its still surface (no node reaches the "
        "surface or the seabed), a uniform steady current for the wind, its stationary solver "
        "(threshIC 1e-7) for the start; ours flies with `buoyant_gravity` (MoorDyn weighs the "
        "displaced air). Reference: MoorDyn, dtM = 1e-4 s (RK4), 20 `Step` calls per 10 ms "
        "sample. Figures: the RMS of the difference of the force at the top over the "
        "reference's spread sqrt(mean |F - mean F|^2), after the motion's 1 s ramp "
        "(`relative_rms`); the static force's relative error at t = 0. Paper's cable: "
        "9.375 m, EA 375 N, 20 g/m, 5 mm, Cd 1.1, damping ratio 0.1, N = 10, top 10 m above "
        "the anchor (inclined: at 60 deg); heavy cable: 50 m, EA 20 kN, 0.1 kg/m, 10 mm, "
        "top at (30, 0, 38) m. `pytest tests/test_moordyn.py` holds each figure to a "
        "tolerance.",
        "",
        "## The cases",
        "",
        "The least k (l - l0) is our run's least elastic tension over all segments and "
        "samples (0: some segment went slack).",
        "",
        *rows,
        "",
        "Sideways, the difference that remains when our step converges is the drag's "
        "placement (below): with drag off the two codes agree to 2e-4 or better:",
        "",
        *drag_off_table(),
        "",
        "## The anchor on a moving base",
        "",
        *moving_anchor_lines(),
        "",
        "## Differences by design",
        "",
        "**Drag per stretched length at the segment midpoints** (ours) against per "
        "unstretched length at the nodes (MoorDyn): the paper's cable in a steady 10 m/s "
        "wind, means over 6-8 s:",
        "",
        *wind_table(figures["steady wind 10 m/s"]),
        "",
        "**Slack segments carry no tension and no damping** in ours; MoorDyn's dashpot "
        "BA (dl/dt) / l0 acts slack or taut, so it can push. The top moving 1 m vertically "
        "at 1 Hz (below L0 at the bottom of the swing):",
        "",
        *slack_lines(figures["slack: vertical 1 m, 1 Hz"]),
        "",
        "**Other differences:**",
        "",
        *other_lines(figures),
        "",
    ]
    out = []
    for line in parts:
        if line.startswith(("|", "#", "- `")) or not line:
            out.append(line)
            continue
        indent = "  " if line.startswith("- ") else ""
        # keep a figure and its unit on one line: "0.69 %" is not broken
        text = textwrap.fill(line.replace(" %", "\0%"), 95, subsequent_indent=indent)
        out.append(text.replace("\0%", " %"))
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    """Compare the cases and write (or print) the page.

    Parameters
    ----------
    argv : list of str, optional
        The arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        0 done, 2 a wrong argument or a page that may not be written (one line, nothing
        run or written).
    """
    return run_script(__file__, _compare, argv)


def _compare(argv: list[str]) -> int:
    parser = script_parser(__file__, __doc__)
    parser.add_argument("--print", action="store_true", help="print the page, do not write it")
    args = parser.parse_args(argv)
    if not args.print:
        docs_file(ROOT, PAGE)  # before the minutes of flying
    text = page()
    if args.print:
        print(text)
    else:
        write_docs_file(ROOT, PAGE, text)
        print(f"wrote {PAGE}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
