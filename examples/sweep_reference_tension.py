"""A small design sweep: RMS q1 deviation in the paper's simulation 1 against the reference
tension Tref, with eq 40's bound from the paper's 20 % rule (one compiled batch).

Run: python examples/sweep_reference_tension.py [OUT_DIR] [--force]  (writes sweep_tref.png
into OUT_DIR, default examples_out, by the commands' output rules)
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from tetherheli.cli._script import figure_example
from tetherheli.scenario.core import paper_scenario
from tetherheli.studies.sweep import sweep

#: The figure written into OUT_DIR.
FIGURE = "sweep_tref.png"


def figures() -> dict[str, Figure]:
    """Sweep Tref over 0-40 N; print the RMS q1 deviation of each and eq 40's bound.

    Returns
    -------
    dict
        ``FIGURE`` -> the RMS q1 deviation against Tref with the bound.
    """
    result = sweep(
        paper_scenario(1, "tethered"),
        "tension_control.T_ref",
        np.array([0.0, 10.0, 20.0, 25.0, 30.0, 40.0]),
        "rms_q1",
        moments=False,
    )
    for value, metric in zip(result.values, result.metric, strict=True):
        print(f"Tref = {value:4.0f} N: RMS q1 = {metric:.4f} m")
    print(f"eq 40 bound (paper's 20 % rule): Tref < {result.bound:.2f} N")

    fig = Figure(figsize=(6, 4), layout="tight")
    ax = fig.subplots()
    ax.plot(result.values, result.metric, "o-", color="tab:blue")
    ax.axvline(result.bound, color="tab:red", ls="--", label="eq 40 bound")
    ax.set_xlabel("reference tension Tref [N]")
    ax.set_ylabel("RMS q1 deviation [m]")
    ax.legend(loc="upper right")
    return {FIGURE: fig}


def main(argv: list[str] | None = None) -> int:
    """Run the example (``cli._script.figure_example``); the exit code."""
    return figure_example(__file__, __doc__, figures, [FIGURE], argv)


if __name__ == "__main__":
    raise SystemExit(main())
