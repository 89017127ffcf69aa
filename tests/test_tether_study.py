"""The tether study (issue 13, items 5 and 6): ``studies.tether_study``,
``studies.tether_sensing`` and ``tetherheli tether-study``.

Independent routes: the lateral stiffness of a hanging cable against the shooting solution of
``static_cable``; the ground tension for 25 N at P against Irvine's elastic catenary; the
sensing bias of a vertical cable in a light wind against the taut-string hand calculation;
the cable's K_C against Table III; the study's metrics against a direct ``simulate``.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from tetherheli.analysis import run_metrics
from tetherheli.cli import main
from tetherheli.errors import ParameterError
from tetherheli.runs import simulate
from tetherheli.scenario.core import paper_scenario
from tetherheli.studies import tether_sensing as sn
from tetherheli.studies import tether_study as ts
from tetherheli.tether.catenary import elastic_catenary, static_cable
from tetherheli.tether.chain import LumpedTether
from tetherheli.tether.lumped_trim import hover_trim_lumped

G = 9.81


def _cable(key: str) -> ts.StudyCable:
    return ts.select_cables([key])[0]


@pytest.mark.parametrize("key", ["paper", "power", "data"])
@pytest.mark.parametrize("q9", [10.0, 100.0])
def test_lateral_stiffness_against_static_cable(key, q9):
    """k = 1 / (ln(T_P/T_g)/(mu g) + L0/EA) of a vertical hanging cable equals H / dx of the
    static cable (``static_cable``: shooting on the ODE of the cable) with P moved sideways by
    dx = 1e-4 q9 at the same winch tension: within 1e-3."""
    t = _cable(key).tether
    vertical = static_cable((0.0, 0.0, q9), 25.0, t, G)
    k = ts.lateral_stiffness(25.0, t, G, vertical.unstretched_length_m)
    dx = 1e-4 * q9
    moved = static_cable((dx, 0.0, q9), 25.0, t, G)
    assert k == pytest.approx(moved.top_tension[0] / dx, rel=1e-3)
    # and more than the massless pendulum T / q9 the paper's tether gives (heavier at the top)
    assert k > 25.0 / q9


def test_lateral_stiffness_massless_limit_is_the_pendulum():
    """mu -> 0: k -> T / q9 with q9 = L0 (1 + T / EA), the paper's string (eq 28 taut)."""
    t = LumpedTether(mass_per_length_kg_m=1e-12, EA_N=375.0)
    L0 = 10.0 / (1.0 + 25.0 / 375.0)
    assert ts.lateral_stiffness(25.0, t, G, L0) == pytest.approx(2.5, rel=1e-9)


def test_ground_tension_for_25N_at_P_against_irvine(paper):
    """The ground tension that keeps 25 N at P (static_rows' quadratic in L0) against Irvine's
    elastic catenary (``elastic_catenary``) of that unstretched length: 25 N at the top, the
    row's tension at the winch, height q9."""
    rows = ts.static_rows(paper, [_cable("paper"), _cable("power")], [10.0, 70.0])
    for r in rows:
        t = _cable(r["cable"]).tether
        cat = elastic_catenary(
            0.0, r["length_m"], t.mass_per_length_kg_m * G, t.EA_N,
            unstretched_length_m=r["L0_m"],
        )  # fmt: skip
        assert cat.tension_B_N == pytest.approx(25.0, rel=1e-9)
        assert cat.tension_A_N == pytest.approx(r["ground_tension_for_top_N"], rel=1e-9)


def test_static_rows_extra_lift_is_the_cable_weight(paper):
    """With 25 N at the winch, the helicopter carries the hanging cable: its extra thrust over
    the massless tether equals the cable's weight mu g L0 (the tension at P minus 25 N) to
    within the trim's small roll (0.5 %), and the margin is the maximum minus fMR3."""
    (r,) = ts.static_rows(paper, [_cable("power")], [50.0], max_thrust_N=200.0)
    assert r["top_tension_N"] - 25.0 == pytest.approx(0.03 * G * 50.0, rel=2e-3)
    assert r["extra_lift_N"] == pytest.approx(r["top_tension_N"] - 25.0, rel=5e-3)
    assert r["lift_margin_N"] == pytest.approx(200.0 - r["fMR3_N"], abs=1e-12)


def test_hover_limits_hand_calculation(paper):
    """25 N at P: the ground tension reaches 0 when the cable weighs 25 N, L0 = 25 / (mu g),
    at q9 = L0 (1 + 25 / (2 EA)) (the hanging cable stretches by w L0^2 / (2 EA)); there
    hover_trim_lumped with a vanishing ground tension puts 25 N at P. 25 N at the winch: at
    the thrust limit, fMR3 has grown by the cable's weight over the massless tether's."""
    (lim,) = ts.hover_limits(paper, [_cable("paper")], max_thrust_N=170.0)
    L0 = 25.0 / (0.02 * G)
    assert lim["max_length_top_tension_m"] == pytest.approx(L0 * (1 + 25.0 / 750.0), rel=1e-12)
    lt = hover_trim_lumped(paper, _cable("paper").tether, 1e-9, lim["max_length_top_tension_m"])
    assert lt.top_tension_N == pytest.approx(25.0, rel=1e-6)
    q9 = lim["max_length_thrust_m"]
    from tetherheli.model.trim import hover_trim

    massless = hover_trim(paper, 25.0, q9).u_total[0]
    lt = hover_trim_lumped(paper, _cable("paper").tether, 25.0, q9)
    assert 170.0 - massless == pytest.approx(0.02 * G * lt.unstretched_length_m, rel=5e-3)


def test_sensing_bias_vertical_cable_in_light_wind_hand_calculation():
    """A light cable (mu -> 0) straight up to P in a light wind W along n1: a taut string
    under the uniform normal load f = rho d Cd W^2 / 2 per length is the parabola
    x = f z (q9 - z) / (2 T), its slope at the winch f q9 / (2 T); Sec. IV-F's estimate
    h tan(slope) is off by f q9^2 / (2 T) (Irvine 1981, the taut-string limit): within 1 %."""
    t = LumpedTether(mass_per_length_kg_m=1e-9, EA_N=1e6)
    q9, W, T = 50.0, 2.0, 25.0
    f = 0.5 * t.air_density_kg_m3 * t.diameter_m * t.drag_coefficient * W * W
    err = sn.sensing_errors(t, q9, W, 90.0, T, G)
    assert err["ivf"] == pytest.approx(f * q9 * q9 / (2.0 * T), rel=1e-2)
    assert math.radians(err["ground_angle_deg"]) == pytest.approx(f * q9 / (2 * T), rel=1e-2)
    assert err["catenary_wind_known"] < 1e-6  # the estimator with the true wind is exact
    assert err["catenary_wind_ignored"] == pytest.approx(err["ivf"], rel=2e-2)


def test_sensing_study_rows_and_an_infeasible_cable():
    """One row per grid point; a cable that cannot lift off at that tension gets its reason
    as status and NaN errors, never a silent number."""
    heavy = ts.StudyCable("heavy", "heavy", LumpedTether(mass_per_length_kg_m=0.5), "test")
    rows = sn.sensing_study([heavy], [2.0, 100.0], [0.0], [30.0], 25.0, G)
    assert [r["status"] == "ok" for r in rows] == [True, False]
    assert "ground_tension_N" in rows[1]["status"]
    assert all(math.isnan(rows[1][e]) for e in sn.ESTIMATES)


def test_paper_cable_K_C_is_table_III():
    """The massless stand-in's K_C = (EA + T_ref) / q9: the paper's cable at 10 m gives
    Table III's 40 N/m."""
    runs = ts.study_scenarios(_cable("paper"), 10.0, model="massless")
    assert runs["sim1_tethered"].params.tether.K_C == pytest.approx(40.0, rel=1e-12)
    assert runs["sim1_tethered"].tether.model == "elastic"
    assert runs["sim1_free"].configuration == "free"
    assert runs["turbulence_tethered"].q9 == 10.0
    # the turbulence metrics start after the settling time, in both configurations
    for conf in ("free", "tethered"):
        assert runs[f"turbulence_{conf}"].metrics_start == ts.TURBULENCE_SETTLE_S
    assert runs["sim1_tethered"].metrics_start == 0.0


def test_pipeline_tiny_grid(tmp_path):
    """The whole study on one cable, one length, 12 s runs (the pulse at 10 s): every file,
    the configuration in summary.json, and the sim-1 metrics equal a direct ``simulate`` of
    the same scenario."""
    out = tmp_path / "study"
    code = main(
        [
            "tether-study", "--out", str(out), "--cables", "paper", "--lengths", "20",
            "--winds", "5", "--elevations", "90", "--duration", "12", "--workers", "1",
            "--quiet",
        ]
    )  # fmt: skip
    assert code == 0
    names = {p.name for p in out.iterdir()}
    for f in ("study.md", "static.csv", "dynamic.csv", "sensing.csv", "sensing.md",
              "reduction.png", "static.png", "sensing.png", "summary.json"):  # fmt: skip
        assert f in names
    summary = json.loads((out / "summary.json").read_text())
    assert summary["lengths_m"] == [20.0]
    assert summary["cables"][0]["tether"]["EA_N"] == 375.0
    assert set(summary["scenarios"]) == {
        f"paper/20/{c}_{k}" for c, _ in ts.DYNAMIC_CASES for k in ("free", "tethered")
    }
    (row,) = summary["dynamic"]
    assert row["completed"]
    assert row["tether_model"] == "lumped"
    lumped = ts.study_scenarios(_cable("paper"), 20.0, duration_s=12.0)["sim1_tethered"]
    assert lumped.tether.model == "lumped" and lumped.tether.EA == 375.0
    for conf in ("free", "tethered"):
        s = paper_scenario(1, conf).replace(q9=20.0, duration=12.0)
        s = lumped if conf == "tethered" else s
        m = run_metrics(simulate(s))
        assert row[f"sim1_peak_q1_{conf}"] == pytest.approx(m.peak_abs_dev["q1"], rel=1e-9)
    (srow,) = summary["sensing"]
    assert srow["ivf"] > 0.0
    assert "| paper | 20 |" in (out / "study.md").read_text()


@pytest.mark.parametrize(
    ("values", "match"),
    [
        ([], "lengths"),
        ([50.0, 10.0], "ascending"),
        ([10.0, 10.0], "ascending"),
        ([0.1], r"\[0.5, 1000\]"),
        ([float("nan")], "lengths"),
    ],
)
def test_check_grid_refuses(values, match):
    with pytest.raises(ParameterError, match=match):
        ts.check_grid("lengths", values, low=0.5, high=1000.0, unit="[m]")


def test_default_grids_are_valid():
    """The command's default grids pass its own check (ascending, in range)."""
    ts.check_grid("lengths", ts.DEFAULT_LENGTHS_M, low=0.5, high=1000.0, unit="[m]")
    ts.check_grid("winds", ts.DEFAULT_WINDS_M_S, low=0.0, high=30.0, unit="[m/s]")
    ts.check_grid("elevations", ts.DEFAULT_ELEVATIONS_DEG, low=1.0, high=90.0, unit="[deg]")


@pytest.mark.parametrize(
    ("bad", "match"),
    [
        ({"lengths_m": [50.0, 10.0]}, "lengths"),
        ({"winds_m_s": [-1.0]}, "winds"),
        ({"elevations_deg": [0.0]}, "elevations"),
        ({"model": "rigid"}, "model"),
        ({"winch_gain": "fast"}, "winch_gain"),
        ({"duration_s": 0.015}, "duration"),
    ],
)
def test_study_config_is_checked_when_built(bad, match):
    """``TetherStudyConfig`` checks every choice when it is built, before any work (the report
    claims the output folder only after it); the grids come back as tuples of floats."""
    with pytest.raises(ParameterError, match=rf"^{match} = "):
        ts.TetherStudyConfig(**bad)
    good = ts.TetherStudyConfig(lengths_m=[10, 20], duration_s=12)
    assert good.lengths_m == (10.0, 20.0) and good.duration_s == 12.0
    assert good.cables == ts.STUDY_CABLES


@pytest.mark.parametrize("keys", [[], ["paper", "paper"], ["steel"]])
def test_select_cables_refuses(keys):
    with pytest.raises(ParameterError, match="cables"):
        ts.select_cables(keys)


@pytest.mark.parametrize(
    "args",
    [
        ["--lengths", "50,10"],
        ["--lengths", "2000"],
        ["--cables", "steel"],
        ["--winds", "-1"],
        ["--duration", "0"],
        ["--duration", "90"],
        ["--lengths", "ten"],
        ["--model", "rigid"],
        ["--winch-gain", "fast"],
    ],
)
def test_cli_refuses_bad_grids(tmp_path, capsys, args):
    """Each bad option: exit 2, one line on stderr naming it, nothing written."""
    out = tmp_path / "o"
    assert main(["tether-study", "--out", str(out), "--quiet", *args]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "Traceback" not in err
    assert not out.exists()


@pytest.mark.parametrize(("K_C", "stable"), [(190.0, True), (210.0, False)])
def test_tension_loop_bound_hand_calculation(K_C, stable):
    """Eq 56's PI with the reel rate held over a sample: T_(k+1) - T_ref = (1 - K_C K_P dt)
    (T_k - T_ref), stable only for K_C K_P dt < 2, i.e. K_C < 200 N/m with the paper's
    K_P = 1 m/(s N) and dt = 10 ms. Simulation 1 (massless tether, 30 s): 5 % below the bound
    the tension stays within 1 N of 25 N; 5 % above it the loop rings up until the tether
    goes slack (tension 0)."""
    assert ts.tension_loop_gain(K_C, 1.0, 0.01) == pytest.approx(K_C / 100.0)
    s = paper_scenario(1, "tethered", dt=0.01).replace(duration=30.0)
    s = s.replace(params=s.params.replace(tether={"K_C": K_C}))
    tension = simulate(s).tension
    if stable:
        assert np.abs(tension - 25.0).max() < 1.0
    else:
        assert tension.min() == 0.0


def test_scaled_winch_gain_keeps_the_papers_loop_gain():
    """ "scaled" lowers K_P and K_I by the same factor to the paper's loop gain 0.4 where the
    cable is stiffer (power cable, 10 m: K = 2002.5 N/m); the paper's cable at 10 m keeps the
    paper's gains (its K is Table III's 40 N/m)."""
    for key, q9, factor in (("power", 10.0, 0.4 / 20.025), ("paper", 10.0, 1.0)):
        s = ts.study_scenarios(_cable(key), q9, winch_gain="scaled")["sim1_tethered"]
        tc = s.params.tension_control
        assert tc.K_P == pytest.approx(factor, rel=1e-12)
        assert tc.K_I == pytest.approx(0.1 * factor, rel=1e-12)
    with pytest.raises(ParameterError, match="winch gain"):
        ts.study_scenarios(_cable("paper"), 10.0, winch_gain="fast")


def test_json_ready_writes_nan_as_null():
    """summary.json is strict JSON: NaN (a failed run's metric) becomes null."""
    assert ts.json_ready([{"a": math.nan, "b": 1.0}]) == [{"a": None, "b": 1.0}]


def test_tables_as_parquet_equal_the_csv(tmp_path):
    """``tether-study --format parquet`` writes static, dynamic and sensing.parquet, each read
    back by pyarrow equal to its CSV (the same study), units in the fields named by them."""
    import pyarrow.parquet as pq

    from tests.tables import assert_same_table

    argv = [
        "tether-study", "--cables", "paper", "--lengths", "20", "--winds", "5",
        "--elevations", "90", "--duration", "11", "--model", "massless", "--workers", "1",
        "--quiet",
    ]  # fmt: skip
    csv_out, pq_out = tmp_path / "csv", tmp_path / "pq"
    assert main([*argv, "--out", str(csv_out)]) == 0
    assert main([*argv, "--format", "parquet", "--out", str(pq_out)]) == 0
    for table in ("static", "dynamic", "sensing"):
        assert not (pq_out / f"{table}.csv").exists()
        assert_same_table(csv_out / f"{table}.csv", pq_out / f"{table}.parquet")
    units = {
        ("static", "length_m"): b"m",
        ("static", "k_lateral_N_m"): b"N/m",
        ("dynamic", "sim1_peak_q1_free"): b"m",
        ("dynamic", "sim1_peak_q1_reduction_pct"): b"%",
        ("sensing", "wind_m_s"): b"m/s",
        ("sensing", "ivf"): b"m",
    }
    for (table, column), unit in units.items():
        field = pq.read_schema(pq_out / f"{table}.parquet").field(column)
        assert field.metadata[b"units"] == unit, (table, column)
