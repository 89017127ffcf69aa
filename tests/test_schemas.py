"""The CSV files' columns, written out here in full (issue 10, item 6): a change to a file
format must be a conscious one that edits this file too.

Each header is pinned exactly (names and order); the run CSV's columns are also checked for
their meaning against independent routes (eq 28 for TC, eqs 43-45 for q1..q3).
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from tetherheli import simulate
from tetherheli.scenario.core import Scenario
from tetherheli.sensing.config import SensorConfig
from tetherheli.wind import Pulse

#: ``SimulationResult.to_csv`` / ``save``: time, the tethered state (names.TETHERED_STATE),
#: HO's position, the applied inputs, the feed-forward torques of eq 55, tension, reel rate,
#: wind force.
RUN_COLUMNS = [
    "t",
    "q4", "q5", "q6", "q7", "q8", "q9", "u1", "u2", "u3", "u4", "u5", "u6", "LN",
    "q1", "q2", "q3",
    "fMR3", "tMR1", "tMR2", "fTR2",
    "C1_ffwd", "C2_ffwd",
    "TC", "RC",
    "Fw1", "Fw2", "Fw3",
]  # fmt: skip

#: With sensors, the controller's position estimate follows.
SENSED_COLUMNS = [*RUN_COLUMNS, "q1_est", "q2_est", "q3_est"]

#: ``tetherheli sweep``'s sweep.csv.
SWEEP_COLUMNS = [
    "value", "metric", "status",
    "peak_tether_moment_Nm", "peak_tether_angle_deg", "eq40_worst_case_moment_Nm",
]  # fmt: skip

#: Monte Carlo results.csv with ``params = {"helicopter.m_F" = ..., "tether.K_C" = ...}``.
MONTECARLO_COLUMNS = [
    "run", "seed_entropy", "spawn_key",
    "amplitude_scale", "direction_deg", "phase_rad", "start_shift_s",
    "factor:helicopter.m_F", "factor:tether.K_C", "value:helicopter.m_F", "value:tether.K_C",
    "configuration", "status", "message", "reason",
    "peak_q1", "peak_q2", "peak_q3", "peak_q4_deg", "peak_q5_deg",
    "rms_q1", "rms_q2", "rms_q3", "tension_min", "tension_max", "n_samples",
    "release_time", "release_tension",
]  # fmt: skip

PULSE = Pulse(start=0.1, duration=0.2, magnitude=20.0, direction=(0.6, 0.8, 0.0))


def _read(path: Path) -> tuple[list[str], np.ndarray]:
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    return rows[0], np.array(rows[1:], dtype=float)


def test_run_csv_columns_and_their_meaning(tmp_path, paper):
    """The run CSV's header is RUN_COLUMNS, in order; t is k dt, TC is eq 28's
    KC max(q9 - LN, 0), q1..q3 are eqs 43-45 of the state columns, Fw is the pulse."""
    r = simulate(Scenario(name="run", duration=0.5, wind=PULSE))
    paths = r.save(tmp_path)
    header, data = _read(paths["csv"])
    assert header == RUN_COLUMNS
    assert list(r.columns()) == RUN_COLUMNS
    col = {name: data[:, i] for i, name in enumerate(header)}
    np.testing.assert_allclose(col["t"], 0.01 * np.arange(51), rtol=0, atol=1e-12)
    np.testing.assert_allclose(
        col["TC"], paper.tether.K_C * np.maximum(col["q9"] - col["LN"], 0.0), rtol=1e-12
    )
    h = paper.helicopter
    arm = h.d_O_P3 - (h.m_F * h.d_O_FO3 + h.m_MR * h.d_O_MRO3) / (h.m_F + h.m_MR)  # eq 3
    s4, c4, s5, c5 = (f(col[q]) for q in ("q4", "q5") for f in (np.sin, np.cos))
    s7, c7, s8, c8 = (f(col[q]) for q in ("q7", "q8") for f in (np.sin, np.cos))
    q9 = col["q9"]
    np.testing.assert_allclose(col["q1"], q9 * s8 - arm * s5, rtol=0, atol=1e-12)
    np.testing.assert_allclose(col["q2"], -q9 * s7 * c8 + arm * s4 * c5, rtol=0, atol=1e-12)
    np.testing.assert_allclose(col["q3"], q9 * c7 * c8 - arm * c4 * c5, rtol=0, atol=1e-12)
    t = col["t"]
    on, off = (t > 0.1 + 1e-6) & (t < 0.3 - 1e-6), (t < 0.1 - 1e-6) | (t > 0.3 + 1e-6)
    np.testing.assert_allclose(col["Fw1"][on], 12.0)  # 20 N along (0.6, 0.8, 0)
    np.testing.assert_allclose(col["Fw2"][on], 16.0)
    assert np.all(col["Fw1"][off] == 0.0) and np.all(col["Fw3"] == 0.0)


def test_run_csv_with_sensors_appends_the_estimate(tmp_path):
    sensors = SensorConfig(position_source="gps", gps_std=(0.02, 0.02, 0.03))
    r = simulate(Scenario(name="sensed", duration=0.1, sensors=sensors, seed=1))
    header, data = _read(r.to_csv(tmp_path / "sensed.csv"))
    assert header == SENSED_COLUMNS
    err = data[:, -3:] - data[:, 14:17]  # estimate minus true q1..q3
    assert 0.0 < np.abs(err).max() < 0.2


def test_sweep_csv_columns(tmp_path):
    from tetherheli.report.sweep import write_sweep
    from tetherheli.studies.sweep import sweep

    s = Scenario(duration=0.2)
    r = sweep(s, "tether.K_C", np.array([30.0, 40.0]), "peak_q1")
    write_sweep(r, tmp_path / "sw", command="test")
    with open(tmp_path / "sw" / "sweep.csv", newline="") as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == SWEEP_COLUMNS
    assert [float(row[0]) for row in rows[1:]] == [30.0, 40.0]
    assert [row[2] for row in rows[1:]] == ["completed", "completed"]
    assert all(math.isfinite(float(row[1])) for row in rows[1:])


def test_montecarlo_results_csv_columns(tmp_path):
    from tetherheli.report import run_montecarlo
    from tetherheli.studies.montecarlo import MonteCarloConfig

    config = MonteCarloConfig(
        runs=1,
        seed=3,
        amplitude_std_percent=10.0,
        params=(("helicopter.m_F", 5.0), ("tether.K_C", 10.0)),
    )
    base = Scenario(name="mc", duration=0.2, wind=PULSE)
    run_montecarlo(base, config, tmp_path / "mc", progress=False)
    with open(tmp_path / "mc" / "results.csv", newline="") as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == MONTECARLO_COLUMNS
    assert [len(row) for row in rows[1:]] == [len(MONTECARLO_COLUMNS)] * 2
    assert [row[MONTECARLO_COLUMNS.index("configuration")] for row in rows[1:]] == [
        "free",
        "tethered",
    ]
