import control
import numpy as np

from tetherheli import linearize, simulate
from tetherheli.control.lqi import augment_lqi
from tetherheli.control.paper import PaperController
from tetherheli.runs.setup import LQI_STATES, engine_setup
from tetherheli.scenario.core import paper_scenario

scenario = paper_scenario(1, "tethered")  # 20 N wind pulse along n1 at t = 10 s
setup = engine_setup(scenario)
c = scenario.control

# design: the paper's LQI structure, but 10x the weight on the four integrators
design = linearize(setup.model, setup.model.trim(0.0, scenario.q9)).select(LQI_STATES)
sysd = design.to_statespace(c.dt)
_, _, C_lqi = augment_lqi(sysd.A, sysd.B, sysd.C, c.dt)
Qy = np.diag([1.0, 1.0, 1.0, 1.0, 100.0, 100.0, 100.0, 100.0])
K, _, E = control.dlqr(sysd, C_lqi.T @ Qy @ C_lqi, np.eye(4), integral_action=-c.dt * sysd.C)
print("closed-loop spectral radius:", round(float(np.max(np.abs(E))), 6))

# fly it: the paper's scheme (feed-forward, tension PI on the winch) with our gain K
_, x_ref, y_ref, u0, u0_free, z0 = setup.law
custom = PaperController(
    K, x_ref, y_ref, u0, setup.ctrl, setup.model.constants, free_trim_input=u0_free, z_init=z0
)
for label, controller in (("paper LQI", None), ("python-control", custom)):
    result = simulate(scenario, controller=controller)
    dq1 = result.deviations()["q1"]
    print(f"{label}: status {result.status}, max |q1 - q1_0| = {np.max(np.abs(dq1)):.4f} m")
