"""Hover trim (Tables IV and V) and the open-loop poles of the linearized helicopter
(eqs 41-45) at zero tension and at the paper's 25 N: without tension every pole but the
rotor's is at the origin; the taut tether adds oscillatory modes and an unstable pair, which
the LQI must hold.

Run: python examples/trim_and_linearization_poles.py [OUT_DIR] [--force]  (writes
trim_poles.png into OUT_DIR, default examples_out, by the commands' output rules)
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

import tetherheli as th
from tetherheli.cli._script import figure_example

#: The figure written into OUT_DIR.
FIGURE = "trim_poles.png"


def figures() -> dict[str, Figure]:
    """Trim at 0 N and 25 N; print each trim input and its poles.

    Returns
    -------
    dict
        ``FIGURE`` -> the poles of both linearizations.
    """
    heli = th.TetheredHelicopter()  # the paper's parameters (Tables II and III)

    fig = Figure(figsize=(6, 4.5), layout="tight")
    ax = fig.subplots()
    cases = (
        (0.0, "o", "tab:red", "TC = 0 N (Table IV)"),
        (25.0, "x", "tab:blue", "TC = 25 N (Table V)"),
    )
    for tension, marker, colour, label in cases:
        trim = heli.trim(tension)  # 0 N: Table IV's hover; 25 N: Table V's
        print(f"TC = {tension:4.1f} N: u0 = {np.round(trim.u, 4)} [N, N m, N m, N]")
        poles = np.linalg.eigvals(th.linearize(heli, trim).A[:12, :12])  # LN's integrator out
        print("  poles:", np.round(np.sort_complex(poles), 3))
        ax.plot(poles.real, poles.imag, marker, mfc="none", color=colour, label=label)
    ax.axvline(0.0, color="0.6", lw=0.8)
    ax.set_xlim(-1.0, 1.0)
    ax.set_ylim(-3.0, 3.0)
    ax.set_xlabel("real part [1/s]")
    ax.set_ylabel("imaginary part [rad/s]")
    ax.set_title("Hover poles (the rotor's +-35 rad/s mode is off the plot)")
    ax.legend(loc="upper left")
    return {FIGURE: fig}


def main(argv: list[str] | None = None) -> int:
    """Run the example (``cli._script.figure_example``); the exit code."""
    return figure_example(__file__, __doc__, figures, [FIGURE], argv)


if __name__ == "__main__":
    raise SystemExit(main())
