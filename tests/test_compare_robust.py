"""Issue 14, items 2-3: the controllers' comparison over a Monte Carlo with plant dispersion
(``studies.robust.montecarlo_compare``, ``tetherheli compare --montecarlo``), the tethered LQI
flown with the scenario's sensors (its tether length from the load cell, eq 28), and the
smallest cyclic limit per controller (``minimum_cyclic_limit(controller=...)``)."""

from __future__ import annotations

import dataclasses
import json
import math
from importlib.resources import files

import numpy as np
import pytest

from tetherheli.cli import main
from tetherheli.control.paper import tension_q9
from tetherheli.errors import TetherheliError
from tetherheli.layout import CTRL_SIZE, CTRL_TENSION_K_C
from tetherheli.model.kernels import tension_from_state
from tetherheli.runs import simulate
from tetherheli.runs.batch import run_batch
from tetherheli.scenario import load_scenario
from tetherheli.sensing.sensors import hover_error_std
from tetherheli.studies.controllers import eq40_saturated, with_controller
from tetherheli.studies.cyclic_limit import minimum_cyclic_limit
from tetherheli.studies.montecarlo import draw, draw_seed, load_montecarlo
from tetherheli.studies.montecarlo.config import montecarlo_config_from_dict
from tetherheli.studies.robust import FREE, montecarlo_compare
from tetherheli.studies.sweep import _with

CONTROLLERS = ("paper", "tether_lqi")


def _shipped(name: str) -> str:
    return str(files("tetherheli") / "scenarios" / name)


@pytest.fixture(scope="module")
def short_mc():
    """The shipped simulation-1 Monte Carlo cut to 14 s (the pulse at 10 s), 3 draws."""
    base, config = load_montecarlo(_shipped("montecarlo_paper_sim1.toml"))
    return base.replace(duration=14.0), dataclasses.replace(config, runs=3)


def _one_by_one(base, config, label, i):
    """Draw i flown alone by the lane engine (``run_batch``, the ``montecarlo`` command's
    route), the controller designed on the nominal parameters."""
    s = draw(base, config, draw_seed(config.seed, i), i).scenario
    s = with_controller(
        s.replace(configuration="free" if label == FREE else "tethered"),
        "paper" if label == FREE else label,
    )
    batch = run_batch([s], design_params=base.params, workers=1)
    return bool(batch.ok[0]), batch.metrics(0)


def test_montecarlo_comparison_equals_the_draws_flown_one_by_one(short_mc):
    """Every draw's measures equal those of the draw flown alone by the lane engine, the
    p50 row is numpy's median of them and the paired reduction that of the free and
    tethered numbers (statistics' definition 100 (free - tethered) / free)."""
    base, config = eq40_saturated(short_mc[0]), short_mc[1]
    mc = montecarlo_compare(short_mc[0], config, CONTROLLERS, eq40=True)
    assert mc.labels == (FREE, *CONTROLLERS) and mc.runs == 3
    alone = {lab: [_one_by_one(base, config, lab, i) for i in range(3)] for lab in mc.labels}
    names = ("peak_q1", "peak_q2", "peak_q3", "rms_q1", "rms_q2", "rms_q3")
    for lab in mc.labels:
        assert mc.ok[lab].all() and mc.failures(lab) == 0
        for i, (ok, m) in enumerate(alone[lab]):
            assert ok
            for name in names:
                assert mc.values[lab][name][i] == pytest.approx(m[name], rel=1e-9, abs=1e-12)
            att = max(m["peak_q4_deg"], m["peak_q5_deg"])
            assert mc.values[lab]["peak_attitude_deg"][i] == pytest.approx(att, rel=1e-9)
            if lab != FREE:
                assert mc.values[lab]["tension_min"][i] == pytest.approx(m["tension_min"])
                assert mc.values[lab]["tension_max"][i] == pytest.approx(m["tension_max"])
    rows = {(r["configuration"], r["controller"], r["scenario"][-3:]): r for r in mc.rows()}
    for lab in CONTROLLERS:
        r = rows[("tethered", lab, "p50")]
        teth = np.array([m["peak_q1"] for _, m in alone[lab]])
        free = np.array([m["peak_q1"] for _, m in alone[FREE]])
        assert r["peak_q1"] == pytest.approx(np.median(teth), rel=1e-9)
        assert r["reduction_peak_q1_p50"] == pytest.approx(
            np.median(100 * (free - teth) / free), rel=1e-9
        )
        assert r["failures"] == 0 and r["runs"] == 3


def test_montecarlo_comparison_counts_the_failures(short_mc):
    """A fMR3 limit of 135 N with the fuselage mass dispersed by +-20%: the nominal tethered
    helicopter cannot hover (about 147 N needed with the 25 N tension, Table V), only its
    light draws can, and the free draws whose mass needs more than 135 N cannot either. The
    counts equal those of the draws tried one by one; the failures sit in the tail (the
    percentiles infinite) and their reductions at -inf."""
    base, _ = short_mc
    a = base.actuators
    base = base.replace(
        actuators=dataclasses.replace(a, u_max=(135.0, *a.u_max[1:])), duration=11.0
    )
    config = montecarlo_config_from_dict({"runs": 6, "seed": 7, "params": {"helicopter.m_F": 20.0}})
    mc = montecarlo_compare(base, config, CONTROLLERS)
    expected = {}
    for lab in mc.labels:
        failed = 0
        for i in range(6):
            try:
                ok, _ = _one_by_one(base, config, lab, i)
            except TetherheliError:
                ok = False
            failed += not ok
        expected[lab] = failed
    assert expected[FREE] not in (0, 6), "the draw should mix hovering and failing draws"
    for lab in mc.labels:
        assert mc.failures(lab) == expected[lab]
    for lab in CONTROLLERS:
        failed = ~mc.ok[lab]
        assert failed.sum() > 3, "more than half the tethered draws cannot hover"
        assert all(mc.statuses[lab][i].startswith("set-up:") for i in np.flatnonzero(failed))
        red = mc.reduction(lab, "peak_q1")
        free_ok = mc.ok[FREE]
        assert np.all(red[failed & free_ok] == -np.inf)
        # a failed free run is no reference: no reduction, never 100 % (issue 22, class 4)
        assert np.isnan(red[~free_ok]).all() and np.isfinite(red[free_ok & ~failed]).all()
        assert np.isinf(mc.percentiles(lab)["peak_q1"]).all()  # p50 and p95 among failures
        assert mc.percentiles(lab)["tension_min"][0] == -np.inf
        row = next(
            r for r in mc.rows() if r["controller"] == lab and r["configuration"] == "tethered"
        )
        assert row["failures"] == failed.sum() and not row["completed"]
        assert f"{mc.failures(FREE)}/6 without a free reference" in row["status"]
        assert row["reduction_peak_q1_p50"] != 100.0


def test_compare_cli_writes_the_montecarlo_rows(tmp_path, short_mc):
    """``compare --montecarlo FILE --runs N``: p50 and p95 rows per run kind in compare.csv,
    the reductions' table and the per-draw values in summary.json; exit 0."""
    base, _ = short_mc
    path = tmp_path / "mc.toml"
    text = base.to_toml() + "\n[montecarlo]\nruns = 50\nseed = 20261122\n"
    text += 'params = { "helicopter.m_F" = 5.0 }\n'
    path.write_text(text)
    out = tmp_path / "out"
    assert main(["compare", "--montecarlo", str(path), "--runs", "2", "--out", str(out)]) == 0
    rows = (out / "compare.csv").read_text().splitlines()
    assert len(rows) == 1 + 2 * 3
    assert "reduction_peak_q1_p50" in rows[0]
    info = json.loads((out / "summary.json").read_text())
    assert info["montecarlo"][0]["runs"] == 2
    assert len(info["montecarlo"][0]["draws"]["tether_lqi"]["peak_q1"]) == 2
    assert "tether_lqi" in (out / "compare_montecarlo.md").read_text()
    assert (out / "compare_montecarlo.png").stat().st_size > 0


def test_compare_cli_needs_some_input(tmp_path, capsys):
    assert main(["compare", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "scenarios" in err and len(err.strip().splitlines()) == 1


# ---------------------------------------------------------------------------------------------
# the tethered LQI with the scenario's sensors
# ---------------------------------------------------------------------------------------------
def test_tension_q9_inverts_eq_28():
    """LN + TC / KC with TC from eq 28 (``tension_from_state``) is q9 while taut; slack, or
    KC = 0 in the settings, leaves the position source's q9."""
    ctrl = np.zeros(CTRL_SIZE)
    ctrl[CTRL_TENSION_K_C] = 40.0
    x = np.zeros(13)
    x[5], x[12] = 10.3, 9.375
    assert tension_q9(x, tension_from_state(10.3, 9.375, 40.0), ctrl) == pytest.approx(10.3)
    x_noisy = x.copy()
    x_noisy[5] = 13.0  # a GNSS q9 metres off
    assert tension_q9(x_noisy, tension_from_state(10.3, 9.375, 40.0), ctrl) == pytest.approx(10.3)
    x[5] = 9.0  # slack: the tension says only q9 <= LN
    assert tension_q9(x, tension_from_state(9.0, 9.375, 40.0), ctrl) == 9.0
    ctrl[CTRL_TENSION_K_C] = 0.0
    assert tension_q9(x_noisy, 37.0, ctrl) == 13.0


def test_tether_lqi_flies_with_the_tether_as_position_sensor():
    """sensing_tether.toml (Sec. IV-F: encoders, altimeter, IMU) under the tethered LQI: the
    run completes, the tether stays taut and the controller's position estimate stays within
    5 sigma of the predicted first-order error (``sensing.sensors.hover_error_std``) on every
    axis."""
    s = with_controller(load_scenario(_shipped("sensing_tether.toml")), "tether_lqi")
    r = simulate(s.replace(duration=20.0))
    assert r.ok and r.tension.min() > 0.0
    est = np.column_stack([r.extra[f"q{a}_est"] for a in (1, 2, 3)])
    err = np.abs(est - r.outputs[:, :3]).max(axis=0)
    assert np.all(err <= 5.0 * hover_error_std(s.sensors, q9=s.q9))


def test_tether_lqi_with_gnss_needs_the_load_cell_length():
    """sensing_gps.toml (consumer GNSS, 3 m vertical correlated error): fed back with the
    GNSS q9, the tension term KC (q9 - LN) of the tethered LQI errs by ~200 N at the start
    and the run diverges; with q9 = LN + TC / KC (``q9_from_tension``, the default) it
    completes. With perfect sensors the setting changes nothing (bit for bit)."""
    s = with_controller(load_scenario(_shipped("sensing_gps.toml")), "tether_lqi")
    assert s.control.tether_lqi.q9_from_tension
    assert simulate(s).ok
    off = with_controller(s, "tether_lqi", q9_from_tension=False)
    assert not simulate(off).ok
    perfect = load_scenario(_shipped("paper_sim1_tethered.toml")).replace(duration=12.0)
    a = simulate(with_controller(perfect, "tether_lqi"))
    b = simulate(with_controller(perfect, "tether_lqi", q9_from_tension=False))
    assert np.array_equal(a.states, b.states) and np.array_equal(a.inputs, b.inputs)


# ---------------------------------------------------------------------------------------------
# the smallest cyclic limit per controller
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("controller", CONTROLLERS)
def test_cyclic_limit_search_per_controller_brackets_the_limit(controller):
    """The search flies the given controller (recorded in its configuration); a recorded
    run at the found hi meets the criterion (completes, peak q1 <= (1 + within) x the
    unlimited run's) and one at lo does not."""
    s = load_scenario(_shipped("paper_sim1_tethered.toml")).replace(duration=14.0)
    res = minimum_cyclic_limit(s, np.linspace(1.0, 8.0, 8), controller=controller, tol=0.02)
    assert res.configuration["control"]["controller"] == controller
    assert res.lo is not None and res.hi is not None and res.hi - res.lo <= 0.02

    def meets(limit: float) -> bool:
        r = simulate(with_controller(_with(s, "actuators.cyclic_limit", limit), controller))
        peak = float(np.max(np.abs(r.outputs[:, 0] - r.trim_output[0])))
        return bool(r.ok) and peak <= res.threshold

    ref = simulate(with_controller(s, controller))
    assert res.reference == pytest.approx(
        float(np.max(np.abs(ref.outputs[:, 0] - ref.trim_output[0]))), rel=1e-9
    )
    assert meets(res.hi) and not meets(res.lo)
    assert math.isfinite(res.threshold)


def test_compare_figure_leaves_failed_percentiles_out_without_warnings():
    """A Monte Carlo percentile among the failures is inf (``compare.markdown_table`` says
    "inf"); the bar chart draws no bar for it and Matplotlib is never handed inf (pytest turns
    its RuntimeWarning into an error)."""
    from tetherheli.viz.plots import figure_compare

    rows = [
        {"scenario": "mc p50", "controller": "paper", "peak_q1": 1.2, "peak_q2": 0.4,
         "peak_q3": 0.1, "rms_q1": 0.6, "rms_q2": 0.2, "rms_q3": 0.05},
        {"scenario": "mc p95", "controller": "paper", "peak_q1": math.inf, "peak_q2": math.inf,
         "peak_q3": math.inf, "rms_q1": math.inf, "rms_q2": math.inf, "rms_q3": math.inf},
    ]  # fmt: skip
    fig = figure_compare(rows)
    fig.canvas.draw()
    heights = [p.get_height() for p in fig.axes[0].patches]
    assert heights[:1] == [1.2] and all(math.isnan(h) for h in heights[1::2])


def test_compare_seed_workers_and_parquet(tmp_path, short_mc):
    """``compare --seed`` sets the Monte Carlo's draws: the same seed gives the same table
    (whatever --workers and --format; only the measured compute time differs), another seed
    other draws; ``--format parquet`` writes compare.parquet, read back by pyarrow equal to
    compare.csv, with the measures' units in its fields."""
    import csv

    import pyarrow.parquet as pq

    from tests.tables import assert_same_table

    base, _ = short_mc
    mc = tmp_path / "mc.toml"
    mc.write_text(
        base.replace(duration=11.0).to_toml()
        + '\n[montecarlo]\nruns = 50\nseed = 20261122\nparams = { "helicopter.m_F" = 5.0 }\n'
    )
    single = tmp_path / "single.toml"
    single.write_text(base.replace(name="single", duration=3.0).to_toml())
    argv = ["compare", str(single), "--montecarlo", str(mc), "--runs", "2", "--controllers",
            "paper", "--quiet"]  # fmt: skip
    a, b, c = (tmp_path / k for k in "abc")
    assert main([*argv, "--seed", "1", "--workers", "2", "--out", str(a)]) == 0
    assert (
        main([*argv, "--seed", "1", "--workers", "1", "--format", "parquet", "--out", str(b)]) == 0
    )
    assert main([*argv, "--seed", "2", "--workers", "2", "--out", str(c)]) == 0
    assert not (b / "compare.csv").exists()
    assert_same_table(a / "compare.csv", b / "compare.parquet", skip=("compute_us_per_sample",))
    schema = pq.read_schema(b / "compare.parquet")
    assert schema.field("peak_q1").metadata[b"units"] == b"m"
    assert schema.field("reduction_peak_q1_p50").metadata[b"units"] == b"%"
    for out, seed in ((a, 1), (c, 2)):
        assert json.loads((out / "summary.json").read_text())["montecarlo"][0]["seed"] == seed

    def rows(out):
        with open(out / "compare.csv", newline="") as fh:
            found = list(csv.DictReader(fh))
        for r in found:
            del r["compute_us_per_sample"]
        return [r for r in found if r["scenario"] == "single"], [
            r for r in found if r["scenario"] != "single"
        ]

    (single_a, drawn_a), (single_c, drawn_c) = rows(a), rows(c)
    assert single_a == single_c and len(single_a) == 1  # a single run has no draws
    assert [r["peak_q1"] for r in drawn_a] != [r["peak_q1"] for r in drawn_c]
