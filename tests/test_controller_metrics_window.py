"""``compare``'s measures share ``simulate``'s metrics and window (issue 24, item 2): with
``metrics_start = 30`` the comparison's RMS q1 is ``analysis.run_metrics``'s over t >= 30 s,
not the whole run's (it was 0.6772, the whole run, against 0.9379)."""

from __future__ import annotations

import numpy as np

from tetherheli import simulate
from tetherheli.analysis import run_metrics
from tetherheli.runs.setup import engine_setup
from tetherheli.scenario.core import paper_scenario
from tetherheli.studies.controllers import controller_metrics


def test_controller_metrics_follow_metrics_start():
    scenario = paper_scenario(1, "tethered").replace(duration=20.0, metrics_start=12.0)
    result = simulate(scenario)
    u_trim = engine_setup(scenario).trim.u_total
    ours = controller_metrics(result, u_trim, None)
    m = run_metrics(result)
    assert ours["rms_q1"] == m.rms_dev["q1"]
    assert ours["peak_q1"] == m.peak_abs_dev["q1"]
    assert ours["tension_max"] == m.tension_max
    k0 = 1200
    whole = float(np.sqrt(np.mean((result.outputs[:, 0] - result.trim_output[0]) ** 2)))
    window = float(np.sqrt(np.mean((result.outputs[k0:, 0] - result.trim_output[0]) ** 2)))
    np.testing.assert_allclose(ours["rms_q1"], window, rtol=1e-12)
    assert abs(ours["rms_q1"] - whole) > 1e-3 * whole
    du = result.inputs[k0:, 0] - u_trim[0]
    np.testing.assert_allclose(ours["rms_dfMR3"], np.sqrt(np.mean(du**2)), rtol=1e-12)
