"""run_batch: a batch of N runs equals N single ``simulate`` runs (summaries, status)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tetherheli.analysis import run_metrics
from tetherheli.engine import loop as engine
from tetherheli.errors import ParameterError
from tetherheli.runs import simulate
from tetherheli.runs.batch import METRIC_NAMES, run_batch, summary_metrics
from tetherheli.scenario.core import Limits, paper_scenario
from tetherheli.wind import Pulse, Sine


def _short(configuration: str, magnitude: float, angle: float, m_F: float):
    base = paper_scenario(1, configuration)
    d = (math.cos(angle), math.sin(angle), 0.0)
    wind = Pulse(1.0, 0.5, magnitude, d) + Sine(0.5 * magnitude, 0.5, 2.0, d)
    return base.replace(
        duration=5.0, wind=wind, params=base.params.replace({"helicopter.m_F": m_F})
    )


@pytest.fixture(scope="module")
def scenarios():
    out = []
    for i in range(4):
        for cfg in ("free", "tethered"):
            out.append(_short(cfg, 10.0 + 5 * i, 0.3 * i, 12.0 + 0.2 * (i % 2)))
    return out


def _expected(result) -> dict[str, float]:
    m = run_metrics(result)
    return {
        "peak_q1": m.peak_abs_dev["q1"],
        "peak_q2": m.peak_abs_dev["q2"],
        "peak_q3": m.peak_abs_dev["q3"],
        "peak_q4_deg": m.peak_abs_dev["q4_deg"],
        "peak_q5_deg": m.peak_abs_dev["q5_deg"],
        "rms_q1": m.rms_dev["q1"],
        "rms_q2": m.rms_dev["q2"],
        "rms_q3": m.rms_dev["q3"],
        "tension_min": m.tension_min,
        "tension_max": m.tension_max,
        "n_samples": float(result.time.size),
    }


@pytest.mark.parametrize("workers", [1, 2])
def test_batch_equals_single_runs(scenarios, workers):
    batch = run_batch(scenarios, workers=workers)
    assert len(batch) == len(scenarios)
    for i, s in enumerate(scenarios):
        single = simulate(s)
        assert single.ok and bool(batch.ok[i])
        assert batch.samples_done[i] == single.time.size
        got, want = batch.metrics(i), _expected(single)
        assert list(got) == list(METRIC_NAMES)
        for k in METRIC_NAMES:
            assert got[k] == pytest.approx(want[k], rel=1e-12, abs=1e-12), k


def test_failed_run_status_matches_single():
    s = _short("tethered", 20.0, 0.0, 12.0).replace(limits=Limits(max_deviation=0.05))
    single = simulate(s)
    batch = run_batch([s, s], workers=2)
    assert not single.ok
    assert list(batch.status) == [single.status] * 2
    assert list(batch.samples_done) == [single.time.size] * 2
    assert batch.messages()[0] == engine.STATUS_MESSAGES[single.status]


def test_design_params_changes_only_the_gain(scenarios):
    s = scenarios[3]  # tethered, m_F = 12.2 kg (nominal 12)
    nominal = paper_scenario(1, "tethered").params
    own = run_batch([s], workers=1)
    designed = run_batch([s], workers=1, design_params=nominal)
    assert not np.array_equal(own.summaries, designed.summaries)  # m_F differs from nominal
    same = run_batch([s.replace(params=nominal)], workers=1, design_params=nominal)
    ref = run_batch([s.replace(params=nominal)], workers=1)
    np.testing.assert_array_equal(same.summaries, ref.summaries)


def test_empty_batch_and_bad_workers(scenarios):
    assert len(run_batch([])) == 0
    with pytest.raises(ParameterError, match="workers"):
        run_batch(scenarios[:1], workers=0)


def test_summary_metrics_of_no_sample():
    m = summary_metrics(np.zeros(len(engine.SUMMARY_FIELDS)))
    assert m["n_samples"] == 0.0 and math.isnan(m["peak_q1"])


@pytest.mark.parametrize("configuration", ["free", "tethered"])
def test_design_params_setup_changes_only_the_gain(configuration):
    """``run_setup(s, nominal)``: plant, trim and packing of s; the gain of the nominal design."""
    from tetherheli.runs.setup import run_setup

    s = _short(configuration, 20.0, 0.0, 12.3)
    nominal = paper_scenario(1, configuration).params
    model, trim, gain, ctrl, cfg = run_setup(s, nominal)
    m2, t2, g2, c2, f2 = run_setup(s)
    np.testing.assert_array_equal(ctrl, c2)
    np.testing.assert_array_equal(cfg, f2)
    np.testing.assert_array_equal(trim.x, t2.x)
    np.testing.assert_array_equal(model.constants, m2.constants)
    _, _, g_nominal, _, _ = run_setup(s.replace(params=nominal))
    np.testing.assert_array_equal(gain.K, g_nominal.K)
    assert not np.array_equal(gain.K, g2.K)


def test_batch_with_actuators_and_sensor_noise_equals_single():
    from tetherheli.scenario.core import ActuatorSettings
    from tetherheli.sensing.config import SensorConfig

    s = _short("tethered", 20.0, 0.2, 12.0).replace(
        actuators=ActuatorSettings(time_constant=0.02, reel_rate_limit=0.5),
        sensors=SensorConfig(position_source="gps", gps_std=(0.02, 0.02, 0.03), gyro_std=1e-3),
        seed=3,
    )
    single = simulate(s)
    got, want = run_batch([s, s], workers=2), _expected(single)
    for i in range(2):
        for k in METRIC_NAMES:
            assert got.metrics(i)[k] == pytest.approx(want[k], rel=1e-12, abs=1e-12), k


def test_dask_cluster_equals_in_process(scenarios, tmp_path, local_cluster):
    """Issue 5: the same batch on a local dask.distributed cluster (2 worker processes, so
    the scenarios really are pickled) equals the in-process result exactly."""
    from tetherheli.runs.batch import connect

    with local_cluster(
        n_workers=2, threads_per_worker=1, processes=True, local_directory=str(tmp_path)
    ) as cluster:
        client = connect(cluster.scheduler_address)
        try:
            remote = run_batch(scenarios, client=client)
        finally:
            client.close()
    local = run_batch(scenarios, workers=2)
    np.testing.assert_array_equal(remote.summaries, local.summaries)
    np.testing.assert_array_equal(remote.status, local.status)
    np.testing.assert_array_equal(remote.samples_done, local.samples_done)


@pytest.mark.parametrize(
    ("address", "match"),
    [("localhost:8786", "tcp://host:8786"), ("tcp://127.0.0.1:9", "reachable")],
)
def test_bad_scheduler_is_one_line(address, match):
    pytest.importorskip("distributed")
    from tetherheli.runs.batch import connect

    with pytest.raises(ParameterError, match=match) as info:
        connect(address, timeout_s=1.0)
    assert "\n" not in str(info.value) and "scheduler" in str(info.value)
