"""Issue 24, items 2 and 3: one sample step for every controller, its metrics computed once,
named packs, and the compiled law chosen by name.

The Python path (the MPC, a user's ``Controller``, the adaptive reference) calls the engine's
compiled phases (``stepping.step_sense``, ``step_command``) instead of
re-composing them, so a Python copy of the paper's law flies the compiled loop's run bit for
bit, and its on-line metrics are the compiled loop's; ``analysis.run_metrics`` reads a
recorded run through the same accumulation (``engine.summary.summarize``) as ``run_batch``.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from tetherheli.analysis import run_metrics
from tetherheli.control.base import Command, Controller
from tetherheli.control.paper import PaperController, check_law
from tetherheli.errors import ParameterError
from tetherheli.layout import (
    CONTROL_LAW_GAIN_SHAPES,
    CONTROL_LAWS,
    CTRL_LAW,
    LOOP_EVENT,
    LOOP_FFWD,
    LOOP_HELD,
    LOOP_INPUTS,
    LOOP_SC_MEAS,
    LOOP_SC_TRUE,
    LOOP_SIZE,
    LOOP_WINCH,
    LOOP_X_MEAS,
    LOOP_Y,
    LOOP_Y_EST,
    LOOP_Z,
    LoopState,
    Signals,
)
from tetherheli.runs import simulate
from tetherheli.runs.batch import run_batch, summary_metrics
from tetherheli.runs.setup import engine_setup
from tetherheli.shipped import shipped_scenario
from tetherheli.status import Status

SHORT = 6.0  # [s]: past the paper's 1-2 s pulse


def _paper_as_python(scenario):
    setup = engine_setup(scenario)
    K, _x_ref, y_ref, u0, u0_free, z0 = setup.law
    return PaperController(
        K, setup.trim.x, y_ref, u0, setup.ctrl, setup.model.constants,
        free_trim_input=u0_free, z_init=z0,
    )  # fmt: skip


@pytest.mark.parametrize("name", ["paper_sim1_tethered", "sensing_gps", "paper_sim1_lumped"])
def test_python_controller_flies_the_compiled_step_bit_for_bit(name):
    """The paper's law as a Python ``Controller`` goes through ``step_command``: every
    recorded array equals the compiled loop's exactly (massless, sensed and lumped runs),
    with ``metrics_start`` honoured by both (one accumulation, ``engine.summary.accumulate``)."""
    s = shipped_scenario(name).replace(duration=SHORT, metrics_start=2.0)
    compiled = simulate(s)
    python = simulate(s, controller=_paper_as_python(s))
    assert compiled.ok and python.ok
    for field in ("states", "outputs", "inputs", "feedforward", "tension", "reel_rate", "wind"):
        np.testing.assert_array_equal(getattr(python, field), getattr(compiled, field), field)
    for column, values in compiled.extra.items():
        np.testing.assert_array_equal(python.extra[column], values, column)
    assert run_metrics(python) == run_metrics(compiled)


def test_run_metrics_equal_the_engines_online_summary():
    """``run_metrics`` of a recorded run (any window) is ``summary_metrics`` of the summary
    ``run_batch`` accumulates while the run flies, exactly: one definition of each metric."""
    s = shipped_scenario("paper_sim1_tethered").replace(duration=SHORT, metrics_start=1.5)
    recorded = run_metrics(simulate(s))
    batch = run_batch([s], lanes=False)
    online = summary_metrics(batch.summaries[0])
    assert online["n_samples"] == s.n_samples + 1 - round(1.5 / s.control.dt)
    assert recorded.peak_abs_dev == {
        "q1": online["peak_q1"], "q2": online["peak_q2"], "q3": online["peak_q3"],
        "q4_deg": online["peak_q4_deg"], "q5_deg": online["peak_q5_deg"],
    }  # fmt: skip
    assert recorded.rms_dev == {k: online[f"rms_{k}"] for k in ("q1", "q2", "q3")}
    assert (recorded.tension_min, recorded.tension_max) == (
        online["tension_min"],
        online["tension_max"],
    )
    # and an independent route: NumPy over the recorded window
    r = simulate(s)
    k0 = round(1.5 / s.control.dt)
    dev = r.outputs[k0:, 0] - r.trim_output[0]
    assert recorded.rms_dev["q1"] == pytest.approx(np.sqrt(np.mean(dev**2)), rel=1e-12)
    assert recorded.peak_abs_dev["q1"] == np.max(np.abs(dev))


class _Bad(Controller):
    """Hover at the trim, then a non-finite command at ``t_bad``."""

    def __init__(self, u, t_bad):
        self.u, self.t_bad = np.asarray(u, dtype=float), t_bad

    def reset(self):
        pass

    def step(self, t, measurement):
        u = self.u if t < self.t_bad else np.full(4, np.nan)
        return Command(inputs=u, reel_rate=0.0)


def test_a_non_finite_command_fails_the_sample_it_is_given():
    s = shipped_scenario("paper_sim1_tethered").replace(duration=2.0)
    setup = engine_setup(s)
    r = simulate(s, controller=_Bad(setup.trim.u_total, 0.5))
    assert r.status == Status.NONFINITE
    assert r.time[-1] == pytest.approx(0.49)  # the sample at 0.5 s is not recorded
    assert np.all(np.isfinite(r.states))


def test_a_command_of_the_wrong_shape_is_refused():
    s = shipped_scenario("paper_sim1_tethered").replace(duration=1.0)

    class Short(_Bad):
        def step(self, t, measurement):
            return Command(inputs=np.zeros(3))

    with pytest.raises(ValueError, match=r"inputs has shape \(3,\); allowed: \(4,\)"):
        simulate(s, controller=Short(np.zeros(4), 9.0))


def test_the_adaptive_reference_swaps_only_the_integrator():
    """The adaptive path runs the same compiled sample phases; against RK4 it differs only by
    the integrator's truncation (the paper's pulse, 6 s)."""
    s = shipped_scenario("paper_sim1_tethered").replace(duration=SHORT)
    rk4, adaptive = simulate(s), simulate(s, method="adaptive")
    assert adaptive.ok and adaptive.method == "adaptive"
    np.testing.assert_allclose(adaptive.outputs, rk4.outputs, rtol=0, atol=1e-6)
    np.testing.assert_array_equal(adaptive.outputs[0], rk4.outputs[0])


def test_named_packs_keep_the_layout_indices():
    """``LoopState`` and ``Signals`` are named records whose positions are the layout's."""
    assert len(LoopState._fields) == LOOP_SIZE
    for index, field in (
        (LOOP_Z, "z"), (LOOP_WINCH, "winch"), (LOOP_HELD, "held"), (LOOP_EVENT, "event"),
        (LOOP_X_MEAS, "x_meas"), (LOOP_SC_MEAS, "sc_meas"), (LOOP_SC_TRUE, "sc_true"),
        (LOOP_Y, "y"), (LOOP_Y_EST, "y_est"), (LOOP_INPUTS, "inputs"), (LOOP_FFWD, "ffwd"),
    ):  # fmt: skip
        assert LoopState._fields[index] == field
    sig = Signals.zeros(5, drum=True, nodes=3)
    assert sig.x.shape == (5, 13) and sig.nodes.shape == (5, 3, 3) and sig.winch.shape == (5, 2)
    assert Signals.zeros(5).nodes.shape == (0, 0, 3) and Signals.zeros(5).winch.shape == (1, 2)


def test_the_compiled_law_is_chosen_by_name():
    """``ctrl[CTRL_LAW]`` names the law; the set-up pairs it with its gain, and a gain of the
    other law's shape, or an unknown code, is refused where it enters (one line)."""
    base = shipped_scenario("paper_sim1_tethered")
    tether = base.replace(control=dataclasses.replace(base.control, controller="tether_lqi"))
    for scenario, name in ((base, "paper"), (tether, "tether_lqi")):
        setup = engine_setup(scenario)
        code = int(setup.ctrl[CTRL_LAW])
        assert CONTROL_LAWS[code] == name
        assert setup.law[0].shape == CONTROL_LAW_GAIN_SHAPES[code]
        assert check_law(setup.ctrl, setup.law[0]) == name
    setup = engine_setup(base)
    wrong = setup.ctrl.copy()
    wrong[CTRL_LAW] = CONTROL_LAWS.index("tether_lqi")
    with pytest.raises(ParameterError, match=r"shape \(9, 17\) for the tether_lqi law"):
        PaperController(setup.law[0], setup.trim.x, setup.trim.y, setup.trim.u, wrong,
                        setup.model.constants)  # fmt: skip
    wrong[CTRL_LAW] = 7
    with pytest.raises(ParameterError, match=r"ctrl\[CTRL_LAW\]"):
        check_law(wrong, setup.law[0])
