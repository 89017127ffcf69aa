"""Hover trim (Tables IV and V) and the open-loop poles of the linearized helicopter
(eqs 41-45) at zero tension and at the paper's 25 N: without tension every pole but the
rotor's is at the origin; the taut tether adds oscillatory modes and an unstable pair, which
the LQI must hold.

Run: python examples/trim_and_linearization_poles.py [OUT_DIR]  (writes trim_poles.png)
"""

import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import tetherheli as th

out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
heli = th.TetheredHelicopter()  # the paper's parameters (Tables II and III)

fig, ax = plt.subplots(figsize=(6, 4.5))
cases = (
    (0.0, "o", "tab:red", "TC = 0 N (Table IV)"),
    (25.0, "x", "tab:blue", "TC = 25 N (Table V)"),
)
for tension, marker, colour, label in cases:
    trim = heli.trim(tension)  # 0 N: Table IV's hover; 25 N: Table V's
    print(f"TC = {tension:4.1f} N: u0 = {np.round(trim.u, 4)} [N, N m, N m, N]")
    poles = np.linalg.eigvals(th.linearize(heli, trim).A[:12, :12])  # LN's integrator left out
    print("  poles:", np.round(np.sort_complex(poles), 3))
    ax.plot(poles.real, poles.imag, marker, mfc="none", color=colour, label=label)
ax.axvline(0.0, color="0.6", lw=0.8)
ax.set_xlim(-1.0, 1.0)
ax.set_ylim(-3.0, 3.0)
ax.set_xlabel("real part [1/s]")
ax.set_ylabel("imaginary part [rad/s]")
ax.set_title("Hover poles (the rotor's +-35 rad/s mode is off the plot)")
ax.legend(loc="upper left")
fig.tight_layout()
fig.savefig(out / "trim_poles.png", dpi=120)
print(f"wrote {out / 'trim_poles.png'}")
