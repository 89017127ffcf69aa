import control
import numpy as np

from tetherheli import Params, TetheredHelicopter, linearize
from tetherheli.control.lqi import augment_lqi
from tetherheli.runs.setup import LQI_STATES, paper_gain
from tetherheli.scenario.core import ControlSettings

params = Params.paper()
model = TetheredHelicopter(params)

# 1. the taut-tether hover (T_ref = 25 N), all 13 states; by default the inputs are the
#    controls (rotor inputs + reel rate RC), so LQR with identity weights just works
lin = linearize(model, model.trim(params.tension_control.T_ref, 10.0))
sys = lin.to_statespace()
print(sys.state_labels)
print(sys.input_labels, sys.output_labels)
print("poles:", np.round(np.sort_complex(sys.poles()), 4))
K_lqr, _, E_lqr = control.lqr(sys, np.eye(sys.nstates), np.eye(sys.ninputs))
print("lqr: max Re(closed-loop pole) =", round(float(np.max(E_lqr.real)), 4))
print(lin.to_statespace(inputs=("fMR3", "tMR1", "tMR2", "fTR2", "RC", "Fw1")).input_labels)

# 2. why the rotor inputs alone are not enough
rotor = ("fMR3", "tMR1", "tMR2", "fTR2")
print(lin.uncontrollable_modes(rotor))
try:
    lin.to_statespace(inputs=rotor, require_stabilisable=True)
except ValueError as exc:
    print(exc)

# 3. the paper's LQI gain from control.dlqr (eqs 47-53)
c = ControlSettings()
design = linearize(model, model.trim(0.0, 10.0)).select(LQI_STATES)
sysd = design.to_statespace(c.dt)
_, _, C_lqi = augment_lqi(sysd.A, sysd.B, sysd.C, c.dt)
K, _, _ = control.dlqr(
    sysd, C_lqi.T @ np.diag(c.Qy) @ C_lqi, np.diag(c.Ru), integral_action=-c.dt * sysd.C
)
ours = paper_gain(params, c.dt, c.Qy, c.Ru)
print("max |K_dlqr - K_ours| =", np.max(np.abs(K - ours.K)))

# 4. step response of the closed LQI loop from the height reference r_q3 to the outputs
n, p = sysd.nstates, sysd.noutputs
Acl = ours.closed_loop
Bref = np.zeros((n + p, p))
Bref[n:] = c.dt * np.eye(p)  # z+ = z + dt (r - y), eq 50
Ccl = np.hstack([sysd.C, np.zeros((p, p))])
loop = control.ss(
    Acl,
    Bref,
    Ccl,
    0,
    c.dt,
    inputs=["r_q1", "r_q2", "r_q3", "r_q6"],
    outputs=list(sysd.output_labels),
    name="LQI loop",
)
step = control.step_response(loop, T=np.arange(0, 40, c.dt), input=2, output=2)
info = control.step_info(step.outputs, step.time)
print({k: round(v, 3) for k, v in info.items() if k in ("RiseTime", "SettlingTime", "Overshoot")})

# 5. frequency response of the same loop, r_q3 -> q3 (magnitude and phase at 0.1 and 1 rad/s)
mag, phase, w = control.frequency_response(loop[2, 2], omega=np.array([0.1, 1.0]))
print("|T| =", np.round(mag, 4), "phase [deg] =", np.round(np.degrees(phase), 2))
