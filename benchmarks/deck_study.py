"""The moving-deck study (issue 26 item 5): the tables of ``docs/studies/deck.md``.

Run: python benchmarks/deck_study.py [--seeds N] [--print]
Flies ``tetherheli.studies.deck``: station-keeping relative to a heaving deck
(``deck_sea_state_tethered``/``_free``: the paper's simulation 1 winds) over significant wave
heights 0.5-3 m, free against tethered, perfect sensors, GNSS or the tether as the position
sensor, the deck's heave fed forward or not; then the tethered landing
(``landing_sea_state``) over the same sea states and N seeds each (1 to ``MAX_SEEDS``; the
station-keeping table at most 5). Writes the page whole once the study is done (the
project's own file: ``cli._script.write_docs_file``, checked before anything runs;
``--print``: prints it instead). A wrong argument is one line and exit 2, before anything
runs. About five minutes on two shared cores at the default seeds.
"""

from __future__ import annotations

import platform
import sys
import time
from pathlib import Path

from tetherheli import __version__
from tetherheli.cli._common import count_arg
from tetherheli.cli._script import docs_file, run_script, script_parser, write_docs_file
from tetherheli.studies.deck import landing_rows, station_rows

ROOT = Path(__file__).resolve().parents[1]
#: The page written (relative to ``ROOT``).
PAGE = "docs/studies/deck.md"
HEIGHTS = (0.5, 1.0, 2.0, 3.0)
#: The most seeds per case (``--seeds``): the landing table flies 8 runs per seed.
MAX_SEEDS = 100
#: The station-keeping table's seeds: the first ``--seeds``, at most this many.
STATION_SEEDS = 5


def _f(x: float, digits: int = 3) -> str:
    return "-" if x != x else f"{x:.{digits}g}"


def station_table(rows) -> list[str]:
    out = [
        "| Hs [m] | configuration | sensing | heave fed forward | RMS horizontal [m] | "
        "RMS vertical [m] | peak vertical [m] | tension [N] | failed |",
        "|---:|---|---|---|---:|---:|---:|---|---:|",
    ]
    for r in rows:
        tension = "-" if r.configuration == "free" else (
            f"{_f(r.tension_min)}-{_f(r.tension_max)}")  # fmt: skip
        ff = "yes" if r.feedforward else "no"
        out.append(
            f"| {r.height:g} | {r.configuration} | {r.sensing} | {ff} "
            f"| {_f(r.rms_horizontal)} | {_f(r.rms_vertical)} | {_f(r.peak_vertical)} | "
            f"{tension} | {r.failed}/{r.runs} |"
        )
    return out


def landing_table(rows) -> list[str]:
    out = [
        "| Hs [m] | heave fed forward | landed | touchdown speed, mean / max [m/s] | "
        "offset max [m] | tilt max [rad] | failures |",
        "|---:|---|---:|---|---:|---:|---|",
    ]
    for r in rows:
        failures = ", ".join(f"{k} {v}" for k, v in sorted(r.failures.items())) or "-"
        out.append(
            f"| {r.height:g} | {'yes' if r.feedforward else 'no'} | {r.landed}/{r.runs} | "
            f"{_f(r.speed_mean)} / {_f(r.speed_max)} | {_f(r.offset_max)} | "
            f"{_f(r.attitude_max)} | {failures} |"
        )
    return out


#: what the station-keeping table shows (its rows say it with numbers)
STATION_READING = [
    "Reading: the horizontal error is the paper's winds' (the deck heaves only), and the "
    "tether cuts it by a third in every sea state; the vertical error relative to the deck "
    "grows in proportion to Hs, the tether trims it by about a tenth, and feeding the deck's "
    "heave forward removes most of it (free or tethered), after which the tension barely "
    "moves. The tether stays taut up to Hs = 3 m. With the consumer GNSS as the position "
    "source its own errors dominate every sea state, as they do over a still deck (the "
    "shipped `sensing_gps` at the same seeds: metres of RMS, and the seed-0 noise draw "
    "diverges with the paper's controller); the tether as the sensor gives the perfect "
    "sensors' figures.",
]


#: The ship's section (``[base] motion = "ship"``): its model, conventions, sources and
#: checks; no runs of the study (``ship_hover_tethered`` is flown by ``tetherheli simulate``)
#: what a landing's run folder, summary and animation show (issue 46 item 8)
LANDING_OUTPUTS = (
    "A landing's run folder (`tetherheli simulate scenarios/landing_sea_state.toml`, or "
    'any scenario with `[maneuver] type = "tethered_landing"`) holds the landing figure '
    "`landing.png` (`tetherheli.viz.plots.figure_landing`) in place of the hover's "
    "`outputs.png` and `inputs.png`: HO's height above the pad with the gear's "
    "(`gear_height` below HO) and the deck at zero; the deck's heave (`base_n3`) and, "
    "over a ship, its roll and pitch; the tension at P and, for a lumped tether, at the "
    "winch; the paid-out length LN; the gear's penetration and force when the run "
    "records them; the touchdown as a vertical line on every panel (and the settling, "
    "when recorded). Its `summary.json`, `report.md` and the result's summary (`repr`) "
    "give the landing's figures (`SimulationResult.landing_metrics`: touchdown time, "
    "vertical and horizontal speed relative to the deck, offset from the pad, tilt, "
    "tension at P, the gear's lowest height and, when recorded, its largest penetration "
    "and force) instead of the hover's peak deviations, which stay in `summary.json`'s "
    "`metrics` only. The animation (`tetherheli animate`) and the replay (`tetherheli "
    "view`) draw the deck as a plane moving with the recorded heave (`base_n1..3`) and, "
    "over a ship, tilting with its roll, pitch and yaw, with the pad marked (a ring "
    "around the winch); no still ground is drawn under a moving deck, and a landing's "
    "close-up shows the deck."
)

SHIP_SECTION = [
    "## A ship in six degrees of freedom",
    "",
    '`[base] motion = "ship"` (`tetherheli.base.ShipBase`, the shipped '
    "`ship_hover_tethered`) puts the winch on the pad of a ship under way in a long-crested "
    "JONSWAP sea: surge, sway, heave, roll, pitch and yaw of the ship's centre of motion "
    "from response amplitude operators (RAOs) times the sea, at the encounter frequencies.",
    "",
    "Model (linear seakeeping, small angles). The sea is `SeaStateBase`'s, one source: "
    "the JONSWAP spectrum of DNV-RP-C205 eq 3.5.5 as `components` sinusoids evenly over "
    "[0.5, 4] w_p with 4 sqrt(m0) = Hs, and the first set of random phases of `seed` "
    "(`base.motion.sea_components`, `sea_phases`). A wave component of amplitude a, "
    "frequency w and phase e moves each degree of freedom by |H(w)| a sin(w_e t + e + "
    "phase(w)), H the RAO at the wave heading (interpolated linearly in its complex value "
    "between the file's headings and frequencies; below the lowest frequency the lowest's, "
    "above the highest zero). The pad at r (`pad`, in the ship's axes) moves by translation "
    "+ rotation x r, so its position, velocity and acceleration are sums of sinusoids in "
    "the engine's packed form (`base.compiled`: no engine change). The ship's `speed` U is "
    "the base's constant velocity (U, 0, 0), as `[base] velocity` is for `motion = "
    '"velocity"`: HO starts at rest relative to the pad, so at the pad\'s velocity at t = 0 '
    "(`runs.setup.base_velocity`), and the controller holds a point of the pad. The pad's "
    "mean position is the origin of N at t = 0.",
    "",
    "Conventions. The ship's axes: x forward, y to port, z up, from its centre of motion; "
    "the ship heads along n1, so x = n1, y = n2, z = n3 on average. Roll, pitch and yaw are "
    "right-handed small rotations about x, y, z (positive pitch puts the bow down). "
    "`wave_heading` chi is where the waves come from, from the bow toward port: 0 head "
    "seas, 90 beam seas from port, 180 following. A phase is that of the motion against the "
    "wave elevation a cos(w t + e) at the centre of motion: |H| a cos(w t + e + phase). "
    "The encounter frequency (deep water; Lewis 1989, Principles of Naval Architecture vol "
    "III, eq 8.62, with mu = 180 deg - chi the angle between course and wave travel): w_e = "
    "w + w^2 U cos(chi) / g. In following seas w_e reaches zero at w = g / (U |cos chi|) and "
    "is negative beyond, where the waves overtake the ship; such a component is folded as "
    "the literature does, sin(-|w_e| t + p) = sin(|w_e| t + pi - p): the same motion, each "
    "component's variance kept. The RAOs are taken at the wave frequency for the stated "
    "speed; the default ship's are for zero speed, an approximation under way (Froude "
    "number 0.23 at 5 m/s).",
    "",
    "The default ship (`benchmarks/ship_raos.py`, which writes "
    "`src/tetherheli/base/data/default_ship_raos.csv`): a box hull 50 m long, 8 m wide, "
    "2.5 m draught (a patrol-vessel-like size), 1.025e6 kg, its centre of gravity on the "
    "waterline amidships (the centre of motion; GM 0.86 m from Capytaine's hydrostatics, "
    "0.88 m in closed form), radii of gyration 0.40 B in roll and 0.25 L in pitch and yaw. "
    "Capytaine 2.3 (linear potential flow, boundary elements, zero speed, deep water, a lid "
    "against irregular frequencies) gives added mass, radiation damping and excitation at "
    "40 frequencies from 0.2 to 2.6 rad/s and 7 headings 0-180 deg; a potential flow has "
    "no viscous roll damping, so 10% of critical is added at the roll natural frequency "
    "(0.797 rad/s, a period of 7.9 s, added inertia 0.30 I44). Another ship: `rao_file` "
    '(the scenario reference\'s "RAO files"), read and recorded as a track file is.',
    "",
    "What a run records: `base_n1..3`, `base_v1..3` (the pad) and `deck_roll`, "
    "`deck_pitch`, `deck_yaw` [rad] and their rates `..._rate` [rad/s], from the same "
    "components (`ShipBase.attitude`) at the samples. The summary (`SimulationResult."
    "deck_motion`, printed with the result) gives the NATO STANAG 4154 deck-motion "
    "figures for V/STOL operations: RMS roll, RMS pitch and the pad's RMS vertical velocity "
    "over the recorded samples, against the limits 2.5 deg, 1.5 deg and 1.0 m/s. "
    "`ship_hover_tethered` (Hs 2 m, Tp 7 s, seed 1, waves 30 deg off the bow, 5 m/s, the pad "
    "18 m aft and 3 m up) records 0.93 deg, 1.38 deg and 0.66 m/s: within the limits "
    "(`tetherheli simulate scenarios/ship_hover_tethered.toml --out ship`).",
    "",
    "How it is checked (`tests/test_ship_motion.py`): over a long record each degree of "
    "freedom's standard deviation equals sqrt(int |H(w)|^2 S(w) dw) computed by an outside "
    "code, waveresponse 1.4 (its own JONSWAP, its interpolation of the RAO), within 3% "
    "(0.75% measured, the roll's resonance the largest); the pad's motion less the centre's "
    "equals the recorded rotation x r at random times; the encounter frequency is w at zero "
    "speed and the formula under way, and folded following seas give the unfolded signal; "
    "the RAO file's reader refuses bad files in one line naming the row and column; a "
    "scenario over a ship flies in `simulate` and records the deck's attitude, and its "
    "STANAG figures equal a direct computation from the series; Capytaine recomputes rows "
    "of the shipped RAOs (skipped without it).",
    "",
]


def page(station, landing, seeds: int, seconds: float) -> str:
    """The page's Markdown: the station-keeping and landing tables and how they were made.

    Raises
    ------
    ValueError
        A table without rows (a study with nothing to report writes nothing).
    """
    if not station or not landing or seeds < 1:
        raise ValueError(f"nothing to report: {len(station)} station, {len(landing)} landing rows")
    lines = [
        "# A winch on a moving deck",
        "",
        "Regenerated by (from the repository root; a test checks that each command and file "
        "exists):",
        "",
        f"- `python benchmarks/deck_study.py --seeds {seeds}`",
        "",
        "The winch sits on a deck that heaves in a JONSWAP sea state (`[base] motion = "
        '"sea_state"`, `tetherheli.base.SeaStateBase`: Hs as given, Tp = 7 s, gamma 3.3, 128 '
        "components, the seeds 0.."
        f"{seeds - 1}; the deck follows the waves with a unit response, no roll or pitch). "
        "The engine flies helicopter and tether in the deck's translating frame (the deck's "
        "acceleration acts as the inertial force -m b'', `derive(moving_base=True)`), and "
        'the controller holds a point of the deck (`[control] reference = "base"`): it '
        "flies on the position relative to the deck. The runs are the shipped scenarios "
        "`deck_sea_state_tethered`, `deck_sea_state_free` (the paper's simulation 1: a 20 N "
        "pulse at 10 s, then 20 sin(2 pi 0.1 t) N along n1 from 30 s, 60 s) and "
        "`landing_sea_state`, with Hs and the seed varied (`tetherheli.studies.deck`).",
        "",
        "Assumptions: over the deck the sensors measure the state relative to it. GNSS is "
        "the helicopter's receiver minus the deck's, with one receiver's noise model "
        "(`sensing_gps`'s consumer GNSS: the common-mode errors cancel, the deck "
        "receiver's own noise is not added); the laser altimeter reads the height above "
        "the deck; the tether (`sensing_tether`) its geometry from the deck's winch. The "
        'seed is also the sensor noise\'s. "Heave fed forward" is `[control] '
        "base_feedforward = true`: the deck's vertical acceleration, known from a deck motion "
        "sensor, added to the thrust as m b''_3 / (cos q4 cos q5) (`control.deck`).",
        "",
        "## Station-keeping relative to the deck",
        "",
        "Means over the seeds of each run's RMS and peak deviation of HO from its point of "
        "the deck (the horizontal RMS combines q1 and q2), and of the tension's range; a "
        'failed run (its status not "completed") is left out of the means and counted.',
        "",
        *station_table(station),
        "",
        *STATION_READING,
        "",
        "## Tethered landing on the heaving deck",
        "",
        "`landing_sea_state`: from the hover 10 m up the helicopter descends relative to the "
        "deck at 0.3 m/s from t = 5 s, the winch reeling in with the tension reference going "
        "from 25 N to 15 N (the tether a rope, EA = 375 N: the paper's 40 N/m at the hover, "
        "stiffer as it shortens; eq 56's gains scaled to its stiffness at touchdown), the "
        "LQI's tether-angle gains scaled with the length; touchdown "
        "when the gear (0.35 m below HO) reaches the deck, within 0.5 m/s, 0.5 m of the pad "
        "and 0.26 rad of tilt. The touchdown speed is relative to the deck.",
        "",
        *landing_table(landing),
        "",
        LANDING_OUTPUTS,
        "",
        *SHIP_SECTION,
        f"Measured with tetherheli {__version__}, Python {platform.python_version()}, in "
        f"{seconds:.0f} s on {platform.machine()}.",
        "",
    ]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    """Run the study and write (or print) the page.

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
    return run_script(__file__, _study, argv)


def _study(argv: list[str]) -> int:
    parser = script_parser(__file__, __doc__)
    parser.add_argument(
        "--seeds", type=count_arg("--seeds", 1, MAX_SEEDS), default=10,
        help=f"sea-state seeds per case, 1 to {MAX_SEEDS} (default 10)",
    )  # fmt: skip
    parser.add_argument("--print", action="store_true", help="print the page instead")
    args = parser.parse_args(argv)
    if not args.print:
        docs_file(ROOT, PAGE)  # before the minutes of flying
    t0 = time.perf_counter()
    station = station_rows(HEIGHTS, range(min(args.seeds, STATION_SEEDS)))
    landing = landing_rows(HEIGHTS, range(args.seeds))
    text = page(station, landing, args.seeds, time.perf_counter() - t0)
    if args.print:
        sys.stdout.write(text)
    else:
        write_docs_file(ROOT, PAGE, text)
        print(f"wrote {PAGE}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
