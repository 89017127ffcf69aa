"""python-control's dlqr on our labelled export gives the paper's LQI gain (eqs 47-53), and
the closed loop's poles are the same.

Run: python examples/python_control_dlqr_equals_lqi.py [OUT_DIR]  (writes dlqr_lqi_poles.png)
"""

import sys
from pathlib import Path

import control
import matplotlib.pyplot as plt
import numpy as np

from tetherheli import Params, TetheredHelicopter, linearize
from tetherheli.control.lqi import augment_lqi
from tetherheli.sim.scenario import ControlSettings
from tetherheli.sim.setup import LQI_STATES, paper_gain

out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
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
fig, ax = plt.subplots(figsize=(5, 5))
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
fig.tight_layout()
fig.savefig(out / "dlqr_lqi_poles.png", dpi=120)
print(f"wrote {out / 'dlqr_lqi_poles.png'}")
