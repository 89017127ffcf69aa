"""Tethered landing on a moving deck (issue 26 item 4): the shipped landings land, the
touchdown's figures are what the maneuver set, a landing under way equals the still deck's
(Galilean), a hard or missing touchdown is a failure with its reason, the record survives a
save, and bad ``[base]``, ``[control] reference`` and ``[maneuver]`` input is one line,
exit 2."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from tetherheli import simulate
from tetherheli.cli import main
from tetherheli.errors import ParameterError
from tetherheli.results.result import load_result
from tetherheli.runs.batch import run_batch
from tetherheli.scenario.core import scenario_from_dict
from tetherheli.scenario.tables import BaseSettings, ManeuverSettings
from tetherheli.shipped import shipped_scenario
from tetherheli.status import Status


@pytest.fixture(scope="module")
def calm():
    return shipped_scenario("landing_calm_deck")


@pytest.fixture(scope="module")
def calm_run(calm):
    return simulate(calm)


def test_the_calm_deck_landing_touches_down_as_the_maneuver_set(calm, calm_run):
    """Ship under way at 5 m/s, calm water: status "landed"; the touchdown at the descent's
    rate (0.3 m/s, within 2 %), over the pad (< 5 cm), at the hover trim's own tilt (its roll
    of Table V, within 0.01 rad), when the schedule brings the gear to the deck (within
    0.5 s; the tilted skid's lowest point first); the run settles on the gear after it,
    the tension at the schedule's 15 N."""
    r, m = calm_run, calm.maneuver
    assert r.status == Status.LANDED and r.ok and r.message.startswith("landed")
    td = r.touchdown
    assert td["reasons"] == []
    assert td["vertical_speed"] == pytest.approx(m.descent_rate, rel=0.02)
    assert td["offset"] < 0.05
    trim_tilt = math.acos(math.cos(r.trim_state[0]) * math.cos(r.trim_state[1]))
    assert td["attitude"] == pytest.approx(trim_tilt, abs=0.01)
    expected = m.start_time + (r.trim_output[2] - m.gear_height) / m.descent_rate
    assert td["time"] == pytest.approx(expected, abs=0.5)
    # the run goes on settle_time on the gear (tests/test_landing_contact.py), the gear
    # at the deck and the tension at the schedule's 15 N at its end
    assert r.time[-1] == pytest.approx(td["time"] + m.settle_time, abs=calm.control.dt)
    k = np.searchsorted(r.time, td["time"])
    depth = np.array([r.extra[f"gear_penetration{i}"] for i in range(4)]).max(axis=0)
    assert depth[k - 1] <= 0.0 < depth[k]  # the first contact of a gear point
    assert r.tension[-1] == pytest.approx(m.landing_tension, rel=0.1)
    # relative to the deck the helicopter came down; in N it flew with the ship
    assert r.extra["base_n1"][-1] == pytest.approx(5.0 * r.time[-1])


def test_a_landing_under_way_equals_the_still_decks(calm, calm_run):
    """Galilean invariance of the whole maneuver: the deck at rest gives the same relative
    run (1e-9) and the same touchdown."""
    control = dataclasses.replace(calm.control, reference=None)  # 'ground' over a still deck
    still = simulate(calm.replace(base=BaseSettings(), control=control))
    np.testing.assert_allclose(calm_run.states, still.states, rtol=0, atol=1e-9)
    for key in ("time", "vertical_speed", "offset", "attitude"):
        assert calm_run.touchdown[key] == pytest.approx(still.touchdown[key], abs=1e-9)


def test_the_sea_state_landing_lands():
    """Hs = 1 m, the deck's heave fed forward: landed at the descent's rate (within 10 %)."""
    s = shipped_scenario("landing_sea_state")
    r = simulate(s)
    assert r.status == Status.LANDED, r.message
    assert np.ptp(r.extra["base_n3"]) > 0.5  # the deck heaved [m]
    assert r.touchdown["vertical_speed"] == pytest.approx(s.maneuver.descent_rate, rel=0.1)


def test_the_landing_gain_scaled_to_a_length_is_the_design_at_that_length(calm):
    """``LandingController``'s gain schedule: the paper's LQI (designed on the free
    helicopter in tethered coordinates) designed at q9 = 1 m equals the 10 m design with its
    q7, q8 columns scaled by 1/10 (q1 ~ q9 q8, q2 ~ -q9 q7), to 1e-9 relative."""
    from tetherheli.runs.start import paper_gain

    c = calm.control
    at_10 = paper_gain(calm.params, c.dt, c.Qy, c.Ru, 10.0).K
    at_1 = paper_gain(calm.params, c.dt, c.Qy, c.Ru, 1.0).K
    scaled = at_10.copy()
    scaled[:, 3:5] *= 0.1
    np.testing.assert_allclose(at_1, scaled, rtol=1e-9, atol=1e-9 * np.abs(at_1).max())
    assert not np.allclose(at_1, at_10)


def test_the_decks_heave_fed_forward_keeps_the_helicopter_on_it():
    """Station-keeping over a 2 m sea state: the deck's vertical acceleration fed forward to
    the thrust (``control.deck``) cuts the RMS height error relative to the deck from 0.59 m
    to 0.05 m (measured); the test asks a factor of 5."""
    base = shipped_scenario("deck_sea_state_tethered")
    seas = dataclasses.replace(base.base, significant_wave_height=2.0, seed=0)
    runs = [simulate(base.replace(base=seas, control=dataclasses.replace(base.control,
            base_feedforward=ff))) for ff in (False, True)]  # fmt: skip
    rms = [np.sqrt(np.mean((r.outputs[:, 2] - r.trim_output[2]) ** 2)) for r in runs]
    assert all(r.status == Status.OK for r in runs)
    assert rms[1] < rms[0] / 5, rms


def test_a_hard_touchdown_fails_naming_the_limit(calm):
    s = calm.replace(maneuver=ManeuverSettings(
        type="tethered_landing", landing_tension=15.0, max_touchdown_speed=0.1))  # fmt: skip
    r = simulate(s)
    assert r.status == Status.HARD_TOUCHDOWN and not r.ok
    assert "maneuver.max_touchdown_speed = 0.1" in r.message
    assert r.touchdown["reasons"] and "vertical_speed" in r.touchdown["reasons"][0]


def test_a_landing_that_never_touches_down_is_not_landed(calm):
    r = simulate(calm.replace(duration=20.0))
    assert r.status == Status.NOT_LANDED and not r.ok and r.touchdown is None
    assert r.time[-1] == pytest.approx(20.0)


def test_the_touchdown_survives_a_save_and_a_batch(calm, calm_run, tmp_path):
    calm_run.save(tmp_path / "r")
    back = load_result(tmp_path / "r")
    assert back.status == Status.LANDED and back.touchdown == calm_run.touchdown
    batch = run_batch([calm, calm.replace(duration=20.0)], workers=1)
    assert list(batch.status) == [Status.LANDED, Status.NOT_LANDED]


@pytest.mark.parametrize(
    ("tables", "match"),
    [
        ({"base": {"motion": "boat"}}, r"base\.motion = 'boat'"),
        ({"base": {"motion": "sea_state", "significant_wave_height": -1.0}},
         r"base\.significant_wave_height = -1"),
        ({"base": {"motion": "sea_state", "peak_period": 0.0}}, r"base\.peak_period = 0"),
        ({"base": {"motion": "fixed", "amplitude": [0.0, 0.0, 1.0]}},
         r"base\.amplitude .*used by motion = 'harmonic'"),
        ({"control": {"reference": "base"}}, r"control\.reference = 'base'"),
        ({"maneuver": {"type": "tethered_landing", "descent_rate": 5.0}},
         r"maneuver\.descent_rate = 5"),
        ({"maneuver": {"type": "tethered_landing", "gear_height": 0.1}},
         r"maneuver\.gear_height = 0\.1 .*at least"),
        ({"maneuver": {"type": "tethered_landing"}, "tether": {"law": "paper"}},  # eq 28 at 40 N/m
         r"maneuver\.landing_tension = 25.0 .*KC q9 / 2"),
        ({"maneuver": {"type": "tethered_landing"}, "configuration": "free"},
         r"maneuver\.type = 'tethered_landing' .*free"),
        ({"maneuver": {"type": "hover"}}, r"maneuver\.type = 'hover'"),
    ],
)  # fmt: skip
def test_bad_base_and_maneuver_input_is_one_line_exit_2(tables, match, tmp_path, capsys):
    with pytest.raises(ParameterError, match=match):
        scenario_from_dict(tables)
    import tomli_w

    path = tmp_path / "bad.toml"
    path.write_bytes(tomli_w.dumps(tables).encode())
    assert main(["simulate", str(path), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err and "bad.toml" in err
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize(
    ("rows", "match"),
    [
        ("0,0,0,0\n1,0,0,0\n1,0,0,0\n2,0,0,0\n", "row 4.*strictly increasing"),
        ("0,0,0,0\n0.1,0,0,0\n0.2,0,0,0\n9,0,0,0\n", "row 5.*gap"),
        ("0,0,0,0\n1,0,0,0\n2,0,0,0\n3,0,0,0\n", "covering the run"),
    ],
)
def test_a_bad_track_file_is_one_line_exit_2(rows, match, tmp_path, capsys):
    (tmp_path / "deck.csv").write_text("t,n1,n2,n3\n" + rows)
    path = tmp_path / "s.toml"
    path.write_text('duration = 10.0\n[base]\nmotion = "file"\nfile = "deck.csv"\n')
    assert main(["simulate", str(path), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and re_search(match, err), err


def re_search(pattern: str, text: str) -> bool:
    import re

    return re.search(pattern, text) is not None
