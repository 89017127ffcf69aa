"""Hover in calibrated turbulence (IEC 61400-1 class A gusts in a 5 m/s mean wind), the run as
a pandas DataFrame with units (needs pandas: pip install "tetherheli[data]").

Run: python examples/turbulence_to_dataframe.py [OUT_DIR]  (writes turbulence_dataframe.png)
"""

import sys
from pathlib import Path

import matplotlib.pyplot as plt

import tetherheli as th

out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
scenarios = Path(__file__).resolve().parents[1] / "scenarios"
frames = {}
for c in ("free", "tethered"):
    s = th.load_scenario(scenarios / f"turbulence_hover_{c}.toml").replace(duration=30.0)
    frames[c] = th.simulate(s).to_dataframe()  # index t [s], units in df.attrs["units"]

df = frames["tethered"]
units = df.attrs["units"]
print(df[["q1", "q2", "TC", "Fw1"]].describe().loc[["mean", "std"]])
print("units:", {k: units[k] for k in ("q1", "TC", "Fw1")})

fig, (ax_w, ax_q) = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
ax_w.plot(df.index, df["Fw1"], color="k")
ax_w.set_ylabel(f"Fw1 [{units['Fw1']}]")
for c, colour in (("free", "tab:red"), ("tethered", "tab:blue")):
    q1 = frames[c]["q1"]
    ax_q.plot(q1.index, q1 - q1.iloc[0], color=colour, label=c)
ax_q.set_ylabel(f"q1 - q1(0) [{units['q1']}]")
ax_q.set_xlabel(f"t [{units['t']}]")
ax_q.legend(loc="upper left")
fig.tight_layout()
fig.savefig(out / "turbulence_dataframe.png", dpi=120)
print(f"wrote {out / 'turbulence_dataframe.png'}")
