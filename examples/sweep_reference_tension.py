"""A small design sweep: RMS q1 deviation in the paper's simulation 1 against the reference
tension Tref, with eq 40's bound from the paper's 20 % rule (one compiled batch).

Run: python examples/sweep_reference_tension.py [OUT_DIR]  (writes sweep_tref.png)
"""

import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from tetherheli.sim.scenario import paper_scenario
from tetherheli.studies.sweep import sweep

out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
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

fig, ax = plt.subplots(figsize=(6, 4))
ax.plot(result.values, result.metric, "o-", color="tab:blue")
ax.axvline(result.bound, color="tab:red", ls="--", label="eq 40 bound")
ax.set_xlabel("reference tension Tref [N]")
ax.set_ylabel("RMS q1 deviation [m]")
ax.legend(loc="upper right")
fig.tight_layout()
fig.savefig(out / "sweep_tref.png", dpi=120)
print(f"wrote {out / 'sweep_tref.png'}")
