"""python-control's dlqr on our labelled export gives the paper's LQI gain (eqs 47-53), and
the closed loop's poles are the same.

Run: python examples/python_control_dlqr_equals_lqi.py [OUT_DIR] [--force]  (writes
dlqr_lqi_poles.png into OUT_DIR, default examples_out, by the commands' output rules)
"""

from __future__ import annotations

import control
import numpy as np
from matplotlib.figure import Figure

from tetherheli import Params, TetheredHelicopter, linearize
from tetherheli.cli._script import figure_example
from tetherheli.control.lqi import augment_lqi
from tetherheli.runs.setup import LQI_STATES, paper_gain
from tetherheli.scenario.core import ControlSettings

#: The figure written into OUT_DIR.
FIGURE = "dlqr_lqi_poles.png"


def figures() -> dict[str, Figure]:
    """Design the LQI with ``control.dlqr`` and with ours; print the largest gain difference.

    Returns
    -------
    dict
        ``FIGURE`` -> both closed loops' poles near z = 1.
    """
    params, c = Params.paper(), ControlSettings()
    model = TetheredHelicopter(params)

    # the paper designs on the tethered equations at TC = 0 about Table IV (Sec. V-A)
    design = linearize(model, model.trim(0.0, 10.0)).select(LQI_STATES)
    sysd = design.to_statespace(c.dt)
    G_lqi, H_lqi, C_lqi = augment_lqi(sysd.A, sysd.B, sysd.C, c.dt)
    # python-control integrates z+ = z + C x; the paper z+ = z + dt (r - y): scale by -dt
    K, _, _ = control.dlqr(
        sysd, C_lqi.T @ np.diag(c.Qy) @ C_lqi, np.diag(c.Ru), integral_action=-c.dt * sysd.C
    )
    ours = paper_gain(params, c.dt, c.Qy, c.Ru)
    print("max |K_dlqr - K_ours| =", np.max(np.abs(K - ours.K)))

    poles_dlqr = np.linalg.eigvals(G_lqi - H_lqi @ K)
    poles_ours = np.linalg.eigvals(ours.closed_loop)
    fig = Figure(figsize=(5, 5), layout="tight")
    ax = fig.subplots()
    theta = np.linspace(0.0, 2.0 * np.pi, 400)
    ax.plot(np.cos(theta), np.sin(theta), color="0.7", lw=0.8)
    ax.plot(poles_ours.real, poles_ours.imag, "o", mfc="none", color="tab:blue", label="ours")
    ax.plot(poles_dlqr.real, poles_dlqr.imag, "x", color="tab:orange", label="control.dlqr")
    ax.set_xlim(0.98, 1.003)
    ax.set_ylim(-0.0165, 0.0165)
    ax.set_xlabel("real part")
    ax.set_ylabel("imaginary part")
    ax.set_title("Closed-loop LQI poles (dt = 10 ms), near z = 1")
    ax.legend(loc="upper left")
    return {FIGURE: fig}


def main(argv: list[str] | None = None) -> int:
    """Run the example (``cli._script.figure_example``); the exit code."""
    return figure_example(__file__, __doc__, figures, [FIGURE], argv)


if __name__ == "__main__":
    raise SystemExit(main())
