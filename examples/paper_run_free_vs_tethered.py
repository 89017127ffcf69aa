"""The paper's simulation 1 (Sec. VI, Fig. 6): wind along n1, free against tethered, and the
measured reduction of the q1 deviation.

Run: python examples/paper_run_free_vs_tethered.py [OUT_DIR]  (writes paper_sim1_q1.png)
"""

import sys
from pathlib import Path

import matplotlib.pyplot as plt

from tetherheli import simulate
from tetherheli.analysis import reduction_percent, run_metrics
from tetherheli.sim.scenario import paper_scenario

out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
runs = {c: simulate(paper_scenario(1, c)) for c in ("free", "tethered")}
rms = {c: run_metrics(r).rms_dev["q1"] for c, r in runs.items()}
print(f"RMS q1 deviation: free {rms['free']:.4f} m, tethered {rms['tethered']:.4f} m")
print(f"reduction: {reduction_percent(rms['free'], rms['tethered']):.1f} %")

fig, (ax_w, ax_q) = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
ax_w.plot(runs["free"].time, runs["free"].wind[:, 0], color="k")
ax_w.set_ylabel("wind force on HO, n1 [N]")
for c, colour in (("free", "tab:red"), ("tethered", "tab:blue")):
    r = runs[c]
    ax_q.plot(r.time, r.outputs[:, 0] - r.trim_output[0], color=colour, label=c)
ax_q.set_ylabel("q1 - trim [m]")
ax_q.set_xlabel("t [s]")
ax_q.legend(loc="upper left")
fig.tight_layout()
fig.savefig(out / "paper_sim1_q1.png", dpi=120)
print(f"wrote {out / 'paper_sim1_q1.png'}")
