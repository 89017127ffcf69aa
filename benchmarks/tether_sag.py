"""Trim with a massive tether and the tether as a position sensor with sag (issue 13, items 3
and 5).

Run: python benchmarks/tether_sag.py
Prints two tables, computed in this run (a few tens of seconds):

1. The hover trim with the tether hanging straight down from P to the winch
   (``tether.lumped_trim.hover_trim_lumped``) at the paper's ground tension of 25 N, for tether
   heights 10-100 m and two cables: the unstretched length, the tension at P, the main rotor's
   thrust fMR3 and the extra thrust over the paper's tethered trim with a massless tether.
2. The position error of Sec. IV-F's straight-tether estimate from the winch tangent
   (``straight_tether_estimates``: with the altimeter, and with the paid-out length) and of the
   catenary estimator (``catenary_position_estimate``: tension, tangent and paid-out length;
   with the wind ignored, and with the wind known to 1 m/s too little), for P at 90 deg
   (straight above the winch, the paper's hover) and 60 deg elevation, steady wind 0-10 m/s
   along n1 (towards P's side) with drag on the cable (``static_cable``), ground tension 25 N.
   Errors are the horizontal distance |estimate - P| in n1, n2 [m].
"""

from __future__ import annotations

import math

import numpy as np

from tetherheli import Params
from tetherheli.errors import InfeasibleError
from tetherheli.model.trim import hover_trim
from tetherheli.tether.catenary import (
    catenary_position_estimate,
    static_cable,
    straight_tether_estimates,
)
from tetherheli.tether.chain import LumpedTether
from tetherheli.tether.lumped_trim import hover_trim_lumped

TENSION_N = 25.0  # the paper's ground tension (Table V)
LENGTHS_M = (10.0, 25.0, 50.0, 100.0)
WINDS_M_S = (0.0, 5.0, 10.0)
CABLES = {
    # the paper's tether (EA = K_C L0N = 375 N) as a 20 g/m, 5 mm cable
    "paper-like 0.02 kg/m, 5 mm, EA 375 N": LumpedTether(segments=20),
    # a 6 mm power-and-data cable, EA of tens of kN
    "power 0.03 kg/m, 6 mm, EA 20 kN": LumpedTether(
        segments=20, mass_per_length_kg_m=0.03, diameter_m=0.006, EA_N=20e3
    ),
}


def _horizontal(err: np.ndarray) -> float:
    return math.hypot(err[0], err[1])


def trim_table(params: Params) -> None:
    base = hover_trim(params, TENSION_N).u_total[0]
    print(f"Hover trim, ground tension {TENSION_N:g} N (massless tether: fMR3 = {base:.3f} N)")
    print("| cable | height q9 [m] | L0 [m] | tension at P [N] | fMR3 [N] | extra fMR3 [N] |")
    print("|---|---:|---:|---:|---:|---:|")
    for name, tether in CABLES.items():
        for q9 in LENGTHS_M:
            lt = hover_trim_lumped(params, tether, TENSION_N, q9)
            f = lt.trim.u_total[0]
            print(
                f"| {name} | {q9:g} | {lt.unstretched_length_m:.2f} | {lt.top_tension_N:.2f} "
                f"| {f:.2f} | {f - base:.2f} |"
            )


def sensor_table(g: float) -> None:
    print()
    print(f"Position error of P [m, horizontal], ground tension {TENSION_N:g} N")
    print(
        "| cable | elevation | length [m] | wind [m/s] | IV-F altimeter | IV-F length "
        "| catenary, wind ignored | catenary, wind -1 m/s |"
    )
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for name, tether in CABLES.items():
        for elev in (90.0, 60.0):
            e = np.array([math.cos(math.radians(elev)), 0.0, math.sin(math.radians(elev))])
            for length in LENGTHS_M:
                for wind in WINDS_M_S:
                    r_P = length * e
                    try:
                        cab = static_cable(r_P, TENSION_N, tether, g, (wind, 0.0, 0.0))
                    except InfeasibleError:
                        print(f"| {name} | {elev:g} | {length:g} | {wind:g} | no static cable |")
                        continue
                    alt, by_len = straight_tether_estimates(cab, tether.EA_N)
                    args = (*cab.encoder_angles, TENSION_N, cab.unstretched_length_m, tether, g)
                    ignored = catenary_position_estimate(*args)
                    low = max(wind - 1.0, 0.0)
                    known = catenary_position_estimate(*args, wind=(low, 0.0, 0.0))
                    cols = [alt, by_len, ignored, known]
                    errs = " | ".join(f"{_horizontal(c - r_P):.3f}" for c in cols)
                    print(f"| {name} | {elev:g} | {length:g} | {wind:g} | {errs} |")


def main() -> None:
    params = Params.paper()
    trim_table(params)
    sensor_table(params.helicopter.g)


if __name__ == "__main__":
    main()
