"""The paper's simulation 1 (Sec. VI, Fig. 6): wind along n1, free against tethered, and the
measured reduction of the q1 deviation.

Run: python examples/paper_run_free_vs_tethered.py [OUT_DIR] [--force]  (writes
paper_sim1_q1.png into OUT_DIR, default examples_out, by the commands' output rules)
"""

from __future__ import annotations

from matplotlib.figure import Figure

from tetherheli import simulate
from tetherheli.analysis import reduction_percent, run_metrics
from tetherheli.cli._script import figure_example
from tetherheli.scenario.core import paper_scenario

#: The figure written into OUT_DIR.
FIGURE = "paper_sim1_q1.png"


def figures() -> dict[str, Figure]:
    """Fly the paper's simulation 1 free and tethered; print the RMS q1 deviations.

    Returns
    -------
    dict
        ``FIGURE`` -> the wind and q1 of both runs.
    """
    runs = {c: simulate(paper_scenario(1, c)) for c in ("free", "tethered")}
    rms = {c: run_metrics(r).rms_dev["q1"] for c, r in runs.items()}
    print(f"RMS q1 deviation: free {rms['free']:.4f} m, tethered {rms['tethered']:.4f} m")
    print(f"reduction: {reduction_percent(rms['free'], rms['tethered']):.1f} %")

    fig = Figure(figsize=(7, 5), layout="tight")
    ax_w, ax_q = fig.subplots(2, 1, sharex=True)
    ax_w.plot(runs["free"].time, runs["free"].wind[:, 0], color="k")
    ax_w.set_ylabel("wind force on HO, n1 [N]")
    for c, colour in (("free", "tab:red"), ("tethered", "tab:blue")):
        r = runs[c]
        ax_q.plot(r.time, r.outputs[:, 0] - r.trim_output[0], color=colour, label=c)
    ax_q.set_ylabel("q1 - trim [m]")
    ax_q.set_xlabel("t [s]")
    ax_q.legend(loc="upper left")
    return {FIGURE: fig}


def main(argv: list[str] | None = None) -> int:
    """Run the example (``cli._script.figure_example``); the exit code."""
    return figure_example(__file__, __doc__, figures, [FIGURE], argv)


if __name__ == "__main__":
    raise SystemExit(main())
