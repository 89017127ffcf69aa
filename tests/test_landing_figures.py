"""A landing's figure, metrics and scene (issue 46 item 8): the landing figure carries the
recorded series and the touchdown at its recorded time; ``simulate``'s folder holds it in
place of the hover's figures (which the hovers keep); the summary, summary.json and the
report give the touchdown's figures, not the hover's peak deviations; the animation's deck
follows the recorded heave and tilt."""

from __future__ import annotations

import dataclasses
import json
import math
import re

import numpy as np
import pytest

from tetherheli import simulate
from tetherheli.report.paper import _run_figures, write_run
from tetherheli.shipped import shipped_scenario
from tetherheli.viz.plots import figure_inputs, figure_landing, figure_outputs


def _short_landing(base=None):
    """``landing_calm_deck`` from 2 m up, descending from t = 0.5 s: about 7 s, 0.1 s to fly;
    its touchdown a gate (no landing gear: the figure's gear panels are tested apart)."""
    s = shipped_scenario("landing_calm_deck")
    gate = dataclasses.replace(s.maneuver, start_time=0.5, after_touchdown="stop")
    return s.replace(q9=2.0, duration=10.0, landing_gear=None, maneuver=gate,
                     **({} if base is None else {"base": base}))  # fmt: skip


@pytest.fixture(scope="module")
def ship_landing():
    """The short landing over the shipped ship's pad (Hs = 1 m): heave, roll and pitch."""
    ship = shipped_scenario("ship_hover_tethered").base
    r = simulate(_short_landing(dataclasses.replace(ship, significant_wave_height=1.0)))
    assert r.touchdown is not None, r.message
    return r


def _lines(fig, gid):
    return [line for ax in fig.axes for line in ax.get_lines() if line.get_gid() == gid]


def _axes_of(fig, gid):
    (line,) = _lines(fig, gid)
    return line.axes


def test_the_landing_figure_draws_the_recorded_series(ship_landing):
    """Height above the pad (HO and the gear), the deck's heave, roll and pitch, the tension
    and the paid-out length, each line the run's own samples; no gear panel without its
    columns."""
    r = ship_landing
    fig = figure_landing([r], r.name)
    gear_height = r.configuration["maneuver"]["gear_height"]
    expected = {
        "height_HO": r.outputs[:, 2],
        "height_gear": r.outputs[:, 2] - gear_height,
        "deck_heave": r.extra["base_n3"],
        "deck_roll": np.degrees(r.extra["deck_roll"]),
        "deck_pitch": np.degrees(r.extra["deck_pitch"]),
        "tension_P": r.tension,
        "length": r.states[:, 12],
    }
    for gid, values in expected.items():
        (line,) = _lines(fig, gid)
        np.testing.assert_array_equal(line.get_xdata(), r.time, err_msg=gid)
        np.testing.assert_allclose(line.get_ydata(), values, rtol=0, atol=1e-12, err_msg=gid)
    assert np.ptp(r.extra["base_n3"]) > 0.1 and np.ptp(r.extra["deck_roll"]) > 0.0
    assert _axes_of(fig, "height_HO") is _axes_of(fig, "height_gear")
    assert _axes_of(fig, "deck_roll") is _axes_of(fig, "deck_pitch")
    assert "height above" in _axes_of(fig, "height_HO").get_ylabel()
    assert "heave" in _axes_of(fig, "deck_heave").get_ylabel()
    assert "LN" in _axes_of(fig, "length").get_ylabel()
    assert len(fig.axes) == 5  # height, heave, roll and pitch, tension, length
    assert not _lines(fig, "gear_penetration") and not _lines(fig, "gear_force")


def test_the_touchdown_is_marked_at_its_recorded_time(ship_landing):
    """A vertical line at the touchdown's time on every panel, and the point where the gear
    meets the deck; the settling too, when the record has it."""
    r = ship_landing
    fig = figure_landing([r])
    t = r.touchdown["time"]
    marks = _lines(fig, "touchdown")
    assert len(marks) == len({id(line.axes) for line in _lines(fig, "touchdown")}) >= 5
    for line in marks:
        assert np.allclose(line.get_xdata(), t)
    (point,) = _lines(fig, "touchdown_point")
    assert point.get_xdata()[0] == pytest.approx(t) and point.get_ydata()[0] == 0.0
    assert not _lines(fig, "settled")
    settled = {**r.touchdown, "settled_time": t + 1.0}
    fig = figure_landing([dataclasses.replace(r, touchdown=settled)])
    assert all(np.allclose(line.get_xdata(), t + 1.0) for line in _lines(fig, "settled"))
    assert _lines(fig, "settled")


def test_the_gear_panels_appear_with_the_gears_columns(ship_landing):
    """A run that records the gear's penetration and force gets their panels, with their
    samples; the landing metrics report their largest values."""
    r = ship_landing
    n = r.time.size
    pen, force = np.linspace(0.0, 0.01, n), np.linspace(0.0, 40.0, n)
    r = dataclasses.replace(r, extra={**r.extra, "gear_penetration": pen, "gear_force": force})
    fig = figure_landing([r])
    (p,) = _lines(fig, "gear_penetration")
    (f,) = _lines(fig, "gear_force")
    np.testing.assert_array_equal(p.get_ydata(), pen)
    np.testing.assert_array_equal(f.get_ydata(), force)
    assert p.axes is not f.axes
    m = r.landing_metrics()
    assert m["max_gear_penetration"] == pytest.approx(0.01)
    assert m["max_gear_force"] == pytest.approx(40.0)


def test_the_landing_metrics_are_the_touchdowns(ship_landing):
    """The touchdown's figures: the record's, and the speed across the deck and the tension
    interpolated linearly at its time between the samples on either side."""
    r = ship_landing
    m, td = r.landing_metrics(), r.touchdown
    assert m["touched_down"] and m["touchdown_time"] == td["time"]
    assert m["touchdown_vertical_speed"] == td["vertical_speed"]
    assert m["touchdown_offset"] == td["offset"]
    assert m["touchdown_attitude_deg"] == pytest.approx(math.degrees(td["attitude"]))
    k = int(np.searchsorted(r.time, td["time"]))  # the samples k - 1, k on either side
    w = (td["time"] - r.time[k - 1]) / (r.time[k] - r.time[k - 1])
    assert 0.0 < w < 1.0

    def at(values):
        return values[k - 1] + w * (values[k] - values[k - 1])

    assert m["touchdown_tension"] == pytest.approx(at(r.tension), rel=1e-12)
    u1, u2 = at(r.states[:, 6]), at(r.states[:, 7])
    assert m["touchdown_horizontal_speed"] == pytest.approx(math.hypot(u1, u2), rel=1e-12)
    assert m["touchdown_horizontal_speed"] > 1e-3  # not a vanishing term
    assert m["lowest_gear_height"] <= 0.0  # the gear reached the deck


def test_a_landings_summary_is_its_touchdown_not_a_hovers_peaks(ship_landing, tmp_path):
    """The repr, summary.json and report.md of a landing give the touchdown's figures and no
    peak deviation; ``simulate``'s folder holds the landing figure, not the hover's."""
    r = ship_landing
    text = repr(r)
    assert "touchdown speed" in text and "touchdown tension" in text
    assert "peak |deviation|" not in text and "q3" not in text
    write_run(r, tmp_path / "out", command="test")
    out = tmp_path / "out"
    assert (out / "landing.png").is_file()
    assert not (out / "outputs.png").exists() and not (out / "inputs.png").exists()
    summary = json.loads((out / "summary.json").read_text())
    assert summary["landing"]["touchdown_time"] == pytest.approx(r.touchdown["time"])
    assert list(summary)[:5] == ["name", "status", "message", "tether_release", "landing"]
    report = (out / "report.md").read_text()
    assert "touchdown speed" in report and "![landing](landing.png)" in report
    assert "peak_abs_dev" not in report


def test_a_hover_keeps_its_figures_and_peaks():
    """A hover (no maneuver) keeps Figs. 6-9's outputs and inputs and its peak deviations;
    it has no landing metrics."""
    r = simulate(shipped_scenario("paper_sim1_tethered").replace(duration=0.5))
    assert _run_figures(r) == {"outputs": figure_outputs, "inputs": figure_inputs}
    assert r.landing_metrics() == {}
    assert "peak |deviation|" in repr(r) and "touchdown" not in repr(r)


def _deck_run(*, moving: bool, landing: bool = True):
    """A synthetic tethered run 11 samples long over a deck heaving 0.5 sin(2 pi t) m and,
    when ``moving``, rolling 0.1 rad and pitching 0.05 rad (yaw 0)."""
    from tetherheli import Params
    from tetherheli.viz.run_data import RunData

    n = 11
    t = np.linspace(0.0, 1.0, n)
    q = np.zeros((n, 9))
    q[:, 2] = np.linspace(2.0, 0.35, n)
    q[:, 8] = q[:, 2]
    base = np.column_stack([0.0 * t, 0.0 * t, 0.5 * np.sin(2 * np.pi * t)]) if moving else None
    attitude = np.column_stack([0.1 + 0 * t, 0.05 + 0 * t, 0 * t]) if moving else None
    return RunData(
        stem="deck", name="deck", configuration="tethered", time=t, q=q,
        wind=np.zeros((n, 3)), tension=np.full(n, 20.0), trim_position=np.array([0, 0, 2.0]),
        helicopter=Params.paper().helicopter, status=0, message="ok", version="test",
        base=base, deck_attitude=attitude, gear_height=0.35 if landing else None,
    )  # fmt: skip


def test_the_animations_deck_follows_the_recorded_heave_and_tilt():
    """Over a moving base the drawn deck (whole scene and a landing's close-up) is centred on
    the recorded base at the frame's sample, tilted by the recorded roll and pitch (its
    normal R e3 = (cos r sin p, -sin r, cos r cos p) for Rz(0) Ry(p) Rx(r)), the pad's ring
    on it; no still ground is drawn."""
    from tetherheli.viz.scene import _Scene

    run = _deck_run(moving=True)
    times = np.array([0.0, 0.3, 0.7])
    scene = _Scene([run], times, rotor_radius=0.9, wind_scale=None, dpi=40)
    assert len(scene.decks) == 2  # the whole scene's and the landing's close-up's
    assert scene.decks[1].plate.axes is scene.views[-1].ax
    r, p = 0.1, 0.05
    normal = np.array([math.cos(r) * math.sin(p), -math.sin(r), math.cos(r) * math.cos(p)])
    for k, t in enumerate(times):
        scene.update(k)
        j = int(np.argmin(np.abs(run.time - t)))
        b = run.base[j]
        assert abs(b[2]) > 0.1 or t == 0.0  # the deck is away from n3 = 0 at these samples
        for i, deck in enumerate(scene.decks):
            corners = scene.deck_corners(i)
            np.testing.assert_allclose(corners.mean(axis=0), b, atol=1e-12)
            edge = np.cross(corners[1] - corners[0], corners[3] - corners[0])
            np.testing.assert_allclose(edge / np.linalg.norm(edge), normal, atol=1e-12)
            ring = np.column_stack(deck.pad.get_data_3d())
            np.testing.assert_allclose((ring - b) @ normal, 0.0, atol=1e-12)
            np.testing.assert_allclose(np.column_stack(deck.winch.get_data_3d())[0], b)
    ground = [c for c in scene.views[0].ax.collections if c.get_gid() == "ground"]
    assert not ground
    still = _Scene([_deck_run(moving=False)], times, rotor_radius=0.9, wind_scale=None, dpi=40)
    assert [c for c in still.views[0].ax.collections if c.get_gid() == "ground"]
    still.update(1)
    np.testing.assert_allclose(still.deck_corners(0)[:, 2], 0.0)  # level, at NO


def test_the_replay_tilts_the_deck_with_the_recorded_attitude():
    """The replay's frames carry the deck's attitude as a quaternion (scalar last) that
    turns n3 into the deck's normal; a level deck has none."""
    from scipy.spatial.transform import Rotation

    from tetherheli.viz.replay import replay_data

    frames = replay_data([_deck_run(moving=True)], fps=10)["runs"][0]["frames"]
    q = np.array(frames["deck_quaternion"]).reshape(-1, 4)
    normal = Rotation.from_quat(q[3]).apply([0.0, 0.0, 1.0])
    r, p = 0.1, 0.05
    expected = [math.cos(r) * math.sin(p), -math.sin(r), math.cos(r) * math.cos(p)]
    np.testing.assert_allclose(normal, expected, atol=1e-4)
    level = replay_data([_deck_run(moving=False)], fps=10)["runs"][0]["frames"]
    assert level["deck_quaternion"] is None


def test_a_saved_landing_reads_back_with_its_deck_and_gear(ship_landing, tmp_path):
    """``load_run`` of a saved landing over a ship: the deck's recorded roll, pitch and yaw
    and the maneuver's gear height, which the animation draws."""
    from tetherheli.viz.run_data import load_run

    r = ship_landing
    r.save(tmp_path)
    run = load_run(tmp_path)
    assert run.gear_height == r.configuration["maneuver"]["gear_height"]
    assert run.deck_attitude is not None
    for i, name in enumerate(("deck_roll", "deck_pitch", "deck_yaw")):
        np.testing.assert_allclose(run.deck_attitude[:, i], r.extra[name], rtol=1e-12)


def test_the_mcap_deck_frame_tilts_with_the_ship(ship_landing, tmp_path):
    """A run over a ship saved as MCAP: the ``base`` frame (where the deck and pad are
    drawn) is at the recorded base and turned by the recorded roll, pitch and yaw (extrinsic
    x-y-z: the normal Rz(yaw) (cos r sin p, -sin r, cos r cos p))."""
    pytest.importorskip("mcap")
    from mcap.reader import make_reader
    from scipy.spatial.transform import Rotation

    r = ship_landing
    path = r.save(tmp_path, format="mcap")["mcap"]
    with open(path, "rb") as stream:
        frames = [
            json.loads(m.data)
            for _, _, m in make_reader(stream).iter_messages(topics=["/tf"])
            if json.loads(m.data)["child_frame_id"] == "base"
        ]
    k = int(np.argmax(np.abs(r.extra["deck_roll"])))  # where the deck is tilted most
    q = frames[k]["rotation"]
    normal = Rotation.from_quat([q["x"], q["y"], q["z"], q["w"]]).apply([0.0, 0.0, 1.0])
    roll, pitch, yaw = (r.extra[f"deck_{a}"][k] for a in ("roll", "pitch", "yaw"))
    x, y, z = math.cos(roll) * math.sin(pitch), -math.sin(roll), math.cos(roll) * math.cos(pitch)
    expected = [math.cos(yaw) * x - math.sin(yaw) * y, math.sin(yaw) * x + math.cos(yaw) * y, z]
    np.testing.assert_allclose(normal, expected, atol=1e-6)  # Rz(yaw) Ry(pitch) Rx(roll) n3
    assert abs(roll) > 5e-3 and abs(yaw) > 0.0  # the deck is tilted there
    assert frames[k]["translation"]["z"] == pytest.approx(r.extra["base_n3"][k])


def test_simulate_writes_the_landing_figure_and_a_comparison_keeps_both_kinds(tmp_path, capsys):
    """``tetherheli simulate`` of a landing writes ``landing.svg`` and no hover figure; a
    landing beside a hover: the landing figure and the hover's outputs and inputs, the
    report's hover deviations "-" for the landing and its touchdown rows "-" for the hover."""
    from tetherheli.cli import main
    from tetherheli.scenario.core import scenario_toml

    landing, hover = tmp_path / "landing.toml", tmp_path / "hover.toml"
    landing.write_text(scenario_toml(_short_landing().to_dict()))
    short = shipped_scenario("paper_sim1_tethered").replace(duration=0.3)
    hover.write_text(scenario_toml(short.to_dict()))
    svg = ["--figure-format", "svg"]
    assert main(["simulate", str(landing), "--out", str(tmp_path / "one"), *svg]) == 0
    one = {p.name for p in (tmp_path / "one").iterdir()}
    assert "landing.svg" in one and not {"outputs.svg", "inputs.svg"} & one
    assert main(["simulate", str(landing), str(hover), "--out", str(tmp_path / "two"), *svg]) == 0
    two = tmp_path / "two"
    assert {"landing.svg", "outputs.svg", "inputs.svg"} <= {p.name for p in two.iterdir()}
    assert {p.name for p in (two / "paper_sim1_tethered").iterdir()} >= {
        "outputs.svg",
        "inputs.svg",
    }
    rows = {
        line.split("|")[1].strip(): [c.strip() for c in line.split("|")[2:-1]]
        for line in (two / "report.md").read_text().splitlines()
        if line.startswith("| ")
    }
    assert rows["peak_abs_dev q3 [m]"][0] == "-" and rows["peak_abs_dev q3 [m]"][1] != "-"
    assert rows["touchdown_time"][0] != "-" and rows["touchdown_time"][1] == "-"
    capsys.readouterr()


def test_a_landing_without_touchdown_or_moving_deck_draws_what_it_has(ship_landing):
    """A landing over a still deck (no base columns) that never touched down: the height,
    tension and length panels, no deck panel, no touchdown mark; its summary says "none"."""
    r = dataclasses.replace(ship_landing, touchdown=None, extra={})
    fig = figure_landing([r])
    assert len(fig.axes) == 3
    assert not _lines(fig, "touchdown") and not _lines(fig, "deck_heave")
    m = r.landing_metrics()
    assert m["touched_down"] is False and m["touchdown_time"] is None
    assert re.search(r"\n\s+touchdown\s+none\n", repr(r))
