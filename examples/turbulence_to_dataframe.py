"""Hover in calibrated turbulence (IEC 61400-1 class A gusts in a 5 m/s mean wind), the run as
a pandas DataFrame with units (needs pandas: pip install "tetherheli[data]").

Run: python examples/turbulence_to_dataframe.py [OUT_DIR] [--force]  (writes
turbulence_dataframe.png into OUT_DIR, default examples_out, by the commands' output rules)
"""

from __future__ import annotations

from matplotlib.figure import Figure

import tetherheli as th
from tetherheli.cli._script import figure_example

#: The figure written into OUT_DIR.
FIGURE = "turbulence_dataframe.png"


def figures() -> dict[str, Figure]:
    """Fly 30 s of the shipped turbulence hover free and tethered as DataFrames; print the
    tethered run's means and standard deviations with their units.

    Returns
    -------
    dict
        ``FIGURE`` -> the wind force and q1 of both runs.
    """
    frames = {}
    for c in ("free", "tethered"):
        s = th.load_scenario(f"turbulence_hover_{c}").replace(duration=30.0)
        frames[c] = th.simulate(s).to_dataframe()  # index t [s], units in df.attrs["units"]

    df = frames["tethered"]
    units = df.attrs["units"]
    print(df[["q1", "q2", "TC", "Fw1"]].describe().loc[["mean", "std"]])
    print("units:", {k: units[k] for k in ("q1", "TC", "Fw1")})

    fig = Figure(figsize=(7, 5), layout="tight")
    ax_w, ax_q = fig.subplots(2, 1, sharex=True)
    ax_w.plot(df.index, df["Fw1"], color="k")
    ax_w.set_ylabel(f"Fw1 [{units['Fw1']}]")
    for c, colour in (("free", "tab:red"), ("tethered", "tab:blue")):
        q1 = frames[c]["q1"]
        ax_q.plot(q1.index, q1 - q1.iloc[0], color=colour, label=c)
    ax_q.set_ylabel(f"q1 - q1(0) [{units['q1']}]")
    ax_q.set_xlabel(f"t [{units['t']}]")
    ax_q.legend(loc="upper left")
    return {FIGURE: fig}


def main(argv: list[str] | None = None) -> int:
    """Run the example (``cli._script.figure_example``); the exit code."""
    return figure_example(__file__, __doc__, figures, [FIGURE], argv)


if __name__ == "__main__":
    raise SystemExit(main())
