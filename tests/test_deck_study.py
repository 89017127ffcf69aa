"""The moving-deck study (issue 26 item 5, ``tetherheli.studies.deck``) on a small grid: the
rows it returns, and the physics they must show (the deck's heave makes the height error,
the feed-forward removes most of it, the tether damps it, a landing on a moderate sea lands).
The full grid is ``benchmarks/deck_study.py``'s (``docs/studies/deck.md``)."""

from __future__ import annotations

import pytest

from tetherheli.shipped import shipped_scenario
from tetherheli.studies.deck import landing_rows, sea_state, station_rows


@pytest.fixture(scope="module")
def rows():
    return station_rows((0.5, 2.0), (0,), sensings=("perfect",), duration=20.0)


def test_the_rows_cover_the_grid(rows):
    assert len(rows) == 2 * 2 * 2  # configurations x feed-forward x heights
    assert all(r.runs == 1 and r.failed == 0 for r in rows)
    assert {(r.configuration, r.feedforward, r.height) for r in rows} == {
        (c, f, h) for c in ("free", "tethered") for f in (False, True) for h in (0.5, 2.0)
    }


def _row(rows, configuration, feedforward, height):
    (row,) = [r for r in rows if (r.configuration, r.feedforward, r.height)
              == (configuration, feedforward, height)]  # fmt: skip
    return row


def test_heave_makes_the_height_error_and_the_feedforward_removes_it(rows):
    for configuration in ("free", "tethered"):
        calm, rough = (_row(rows, configuration, False, h) for h in (0.5, 2.0))
        # a linear response to the heave: four times the waves, about four times the error
        assert 3.0 < rough.rms_vertical / calm.rms_vertical < 5.0
        assert _row(rows, configuration, True, 2.0).rms_vertical < rough.rms_vertical / 5


def test_the_tether_lowers_the_errors_over_the_deck(rows):
    for ff in (False, True):
        tethered, free = (_row(rows, c, ff, 2.0) for c in ("tethered", "free"))
        assert tethered.rms_horizontal < free.rms_horizontal
        assert tethered.tension_min > 0.0  # taut throughout


def test_sea_state_sets_the_height_and_both_seeds():
    s = sea_state(shipped_scenario("deck_sea_state_free"), 2.5, 7)
    assert s.base.significant_wave_height == 2.5 and s.base.seed == 7 and s.seed == 7


def test_a_moderate_sea_lands_with_the_heave_fed_forward():
    (row,) = landing_rows((0.5,), (0,), feedforwards=(True,))
    assert row.success_rate == 1.0 and row.failures == {}
    assert row.speed_max == pytest.approx(0.3, rel=0.1)
