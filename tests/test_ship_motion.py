"""A ship in six degrees of freedom as the winch's base (issue 46, ``tetherheli.base.ship``):
response statistics against an outside code (waveresponse), the small-angle pad motion, the
encounter frequency, the RAO file's reader, a scenario flown and the STANAG 4154 figures."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from tetherheli.base.motion import MOTION_KEYS, SeaStateBase, base_motion_from, sea_components
from tetherheli.base.ship import (
    DEFAULT_RAO_FILE,
    RAO_DOFS,
    RAO_HEADER,
    ShipBase,
    default_raos,
    encounter_frequency,
    read_rao_csv,
    write_rao_csv,
)
from tetherheli.errors import ParameterError
from tetherheli.scenario.core import load_scenario
from tetherheli.scenario.tables import BaseSettings

ROOT = Path(__file__).resolve().parents[1]
SHIPPED_RAOS = ROOT / "src" / "tetherheli" / DEFAULT_RAO_FILE


def _record(ship: ShipBase, duration: float, dt: float) -> dict[str, np.ndarray]:
    """The six degrees of freedom of the centre of motion (``pad`` at the origin) over a
    record: translations from ``state`` less the speed's drift, rotations from
    ``attitude``."""
    t = np.arange(0.0, duration, dt)
    b = ship.state(t)[:, 0, :]
    b[:, 0] -= ship.speed * t
    att = ship.attitude(t)[:, 0, :]
    return dict(zip(RAO_DOFS, [*b.T, *att.T], strict=True))


@pytest.mark.filterwarnings("ignore:The `Grid.reshape` method is deprecated:DeprecationWarning")
def test_standard_deviations_match_waveresponse():
    """Each degree of freedom's standard deviation over a long record equals
    sqrt(int |RAO(w)|^2 S(w) dw) (the response spectrum's m0, e.g. DNV-RP-C205 7.3) computed
    by waveresponse (its own JONSWAP and RAO interpolation), within 3%; under way, so the
    encounter frequencies (folded or not) must keep each component's variance."""
    wr = pytest.importorskip("waveresponse", reason="waveresponse (pip install waveresponse)")
    hs, tp, heading = 2.0, 7.0, 30.0
    ship = ShipBase(significant_wave_height=hs, peak_period=tp, seed=3, wave_heading=heading,
                    speed=5.0)  # fmt: skip
    # one period of the evenly spaced wave frequencies is 2 pi / dw; three of them
    omega, _ = sea_components(hs, tp, 3.3, ship.components)
    record = _record(ship, 3 * 2 * math.pi / (omega[1] - omega[0]), 0.1)
    table = default_raos()
    freq = np.linspace(table.frequencies[0], table.frequencies[-1], 2000)
    _, spectrum = wr.JONSWAP(freq)(hs, tp, gamma=3.3)
    wave = wr.WaveBinSpectrum(freq, [heading], spectrum[:, None], degrees=True)
    # the RAO over the full circle: ours 0-180 deg (waves from port), mirrored to starboard
    # (the hull is symmetric: |H| of every degree of freedom is the same)
    dirs = np.concatenate([table.headings, 360.0 - table.headings[-2:0:-1]])
    for d, dof in enumerate(RAO_DOFS):
        vals = table.values[:, :, d]
        vals = np.concatenate([vals, vals[:, -2:0:-1]], axis=1)
        rao = wr.RAO(table.frequencies, dirs, vals, degrees=True)
        m0 = wr.calculate_response(rao, wave, 0.0, reshape="rao").var()
        expected = math.sqrt(m0)
        if expected < 1e-6:  # none by symmetry at 30 deg? (never: every dof responds)
            continue
        assert np.std(record[dof]) == pytest.approx(expected, rel=0.03), dof


def test_pad_motion_is_translation_plus_rotation_cross_r():
    """The pad's displacement is the centre of motion's translation plus rotation x r_pad
    (small angles; Faltinsen 1990 eq 3.2 s = xi + omega x r), at random times: the pad's
    motion less the centre's equals the cross product of the recorded angles with r."""
    kw = dict(significant_wave_height=2.0, peak_period=7.0, seed=5, wave_heading=60.0,
              speed=4.0, components=64)  # fmt: skip
    r = np.array([-18.0, 2.5, 3.0])
    centre, pad = ShipBase(**kw), ShipBase(**kw, pad=tuple(r))
    t = np.random.default_rng(7).uniform(0.0, 500.0, 40)
    angles = centre.attitude(t)
    rel = pad.state(t) - centre.state(t)  # position, velocity, acceleration
    np.testing.assert_allclose(rel[:, 0], np.cross(angles[:, 0], r), atol=1e-10)
    np.testing.assert_allclose(rel[:, 1], np.cross(angles[:, 1], r), atol=1e-10)
    assert np.abs(angles[:, 0, :2]).max() > 1e-3  # roll and pitch move it
    # and the heading of the translations: the pad moves with the ship's speed along n1
    np.testing.assert_allclose(pad.state(t)[:, 1].mean(axis=0)[0], 4.0, atol=1.0)


def test_encounter_frequency():
    """w_e = w at zero speed; under way w_e = w - k U cos(mu), k = w^2 / g, mu = 180 deg -
    heading (Lewis 1989, PNA vol III, eq 8.62): head seas raise it, following seas lower it,
    beam seas leave it."""
    w = np.array([0.3, 0.8, 1.5])
    np.testing.assert_array_equal(encounter_frequency(w, 0.0, 37.0), w)
    k = w**2 / 9.81
    for heading, mu in ((0.0, 180.0), (180.0, 0.0), (45.0, 135.0)):
        np.testing.assert_allclose(
            encounter_frequency(w, 6.0, heading),
            w - k * 6.0 * math.cos(math.radians(mu)), rtol=1e-12,
        )  # fmt: skip
    np.testing.assert_allclose(encounter_frequency(w, 6.0, 90.0), w, atol=1e-12)


def test_following_seas_fold_the_encounter_frequency():
    """In following seas w_e < 0 beyond w = g / U: the components are folded to |w_e| with
    the phase mirrored (the same signal), so the packed frequencies are >= 0 and the heave
    at the centre is the same function of time as the unfolded sum."""
    ship = ShipBase(significant_wave_height=1.0, peak_period=5.0, seed=2, wave_heading=180.0,
                    speed=10.0, components=32)  # fmt: skip
    waves = ship.parts().waves
    assert (waves[:, 2] >= 0.0).all()
    omega, amp = sea_components(1.0, 5.0, 3.3, 32)
    we = encounter_frequency(omega, 10.0, 180.0)
    assert (we < 0).any() and (we > 0).any()
    h = default_raos().at(omega, 180.0)[:, 2]
    from tetherheli.base.motion import sea_phases

    phase = sea_phases(2, 1, 32)[0]
    t = np.linspace(0.0, 30.0, 50)
    direct = (np.abs(h) * amp * np.sin(np.outer(t, we) + phase + np.angle(h))).sum(axis=1)
    np.testing.assert_allclose(ship.state(t)[:, 0, 2], direct, atol=1e-12)


def test_sea_state_phases_are_the_ships():
    """One source of the sea: the ship's wave components (frequencies, phases) are
    SeaStateBase's heave components (a pad at the centre, zero speed, RAOs of 1 in heave
    would give its heave)."""
    sea = SeaStateBase(significant_wave_height=2.0, peak_period=7.0, seed=4, components=16)
    ship = ShipBase(significant_wave_height=2.0, peak_period=7.0, seed=4, components=16)
    heave = ship.parts().waves[ship.parts().waves[:, 0] == 2]
    np.testing.assert_array_equal(heave[:, 2], sea.parts().waves[:16, 2])
    h = default_raos().at(heave[:, 2], 0.0)[:, 2]
    np.testing.assert_allclose(heave[:, 1], np.abs(h) * sea.parts().waves[:16, 1], rtol=1e-12)
    np.testing.assert_allclose(
        np.mod(heave[:, 3] - np.angle(h) - sea.parts().waves[:16, 3] + 1, 2 * math.pi), 1.0,
        atol=1e-12,
    )  # fmt: skip


def _csv(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "raos.csv"
    path.write_text(text, encoding="ascii")
    return path


def _good_rows() -> np.ndarray:
    rows = []
    for w in (0.5, 1.0):
        for h in (0.0, 90.0, 180.0):
            rows.append([w, h, *([0.5, 0.25] * 6)])
    return np.array(rows)


def test_rao_reader_reads_what_the_writer_writes(tmp_path):
    path = _csv(tmp_path, write_rao_csv(_good_rows()))
    table = read_rao_csv(path)
    assert table.values.shape == (2, 3, 6)
    np.testing.assert_array_equal(table.headings, [0.0, 90.0, 180.0])
    np.testing.assert_allclose(table.values, 0.5 * np.exp(0.25j))
    assert len(table.sha256) == 64 and table.source == str(path.resolve())
    with pytest.raises(ParameterError, match="rao_file_sha256"):
        read_rao_csv(path, sha256="0" * 64)


@pytest.mark.parametrize(
    ("edit", "where"),
    [
        (lambda lines: ["frequency,heading", *lines[1:]], "row 1"),
        (lambda lines: [*lines[:3], lines[3].replace("0.5,", "secret,", 1), *lines[4:]],
         "row 4 column frequency"),
        (lambda lines: [*lines[:2], lines[2] + ",1", *lines[3:]], "row 3"),
        (lambda lines: [*lines[:5], lines[5].replace(",0.5,", ",-0.5,", 1), *lines[6:]],
         "row 6 column surge_amplitude"),
        (lambda lines: [*lines[:4], lines[4].replace("1,0,", "0.2,0,", 1), *lines[5:]],
         "row 5 column frequency"),
        (lambda lines: [*lines[:6], lines[6].replace(",180,", ",170,", 1)],
         "row 7 column heading"),
        (lambda lines: [*lines[:2], lines[2].replace("0.25", "nan", 1), *lines[3:]],
         "row 3 column surge_phase"),
    ],
)  # fmt: skip
def test_rao_reader_refuses_bad_files_in_one_line(tmp_path, edit, where):
    """A bad file is refused in one line naming the row and column, never echoing it."""
    lines = write_rao_csv(_good_rows()).splitlines()
    path = _csv(tmp_path, "\n".join(edit(lines)) + "\n")
    with pytest.raises(ParameterError) as info:
        read_rao_csv(path)
    message = str(info.value)
    assert where in message and "\n" not in message and "secret" not in message


def test_a_ship_refuses_a_heading_outside_its_file(tmp_path):
    rows = _good_rows()
    path = _csv(tmp_path, write_rao_csv(rows[rows[:, 1] <= 90.0]))
    assert ShipBase(rao_file=str(path), wave_heading=90.0).rao_file == str(path.resolve())
    with pytest.raises(ParameterError, match=r"base\.wave_heading = 120.0 .*\[0, 90\] deg"):
        ShipBase(rao_file=str(path), wave_heading=120.0)
    with pytest.raises(ParameterError, match=r"base\.rao_file_sha256"):
        ShipBase(rao_file_sha256="0" * 64)


def test_rao_reader_refuses_a_missing_or_huge_file(tmp_path):
    with pytest.raises(ParameterError, match=r"base\.rao_file"):
        read_rao_csv(tmp_path / "none.csv")
    big = tmp_path / "big.csv"
    big.write_bytes(b"0" * 2_000_001)
    with pytest.raises(ParameterError, match=r"base\.rao_file"):
        read_rao_csv(big)


def test_ship_keys_are_checked_in_one_line():
    for kw, field in (
        ({"speed": 30.0}, "base.speed"),
        ({"wave_heading": -10.0}, "base.wave_heading"),
        ({"pad": (0.0, 0.0)}, "base.pad"),
    ):
        with pytest.raises(ParameterError, match=field):
            ShipBase(**kw)  # type: ignore[arg-type]
    assert base_motion_from(BaseSettings(motion="ship", speed=3.0)).to_dict()["speed"] == 3.0
    assert set(ShipBase().to_dict()) == {"motion", *MOTION_KEYS["ship"]}


def test_ship_scenario_flies_and_records_the_deck(tmp_path, blank_figures):
    """``[base] motion = "ship"`` loads, flies in ``simulate`` and records the deck's attitude
    (the same components as ``ShipBase.attitude``), and the summary's STANAG 4154 figures
    equal a direct computation from the recorded series."""
    from tetherheli import simulate

    rao = _csv(tmp_path, SHIPPED_RAOS.read_text(encoding="ascii"))
    toml = tmp_path / "ship.toml"
    toml.write_text(
        'name = "ship"\nconfiguration = "tethered"\nduration = 2.0\n'
        '[base]\nmotion = "ship"\nsignificant_wave_height = 2.0\npeak_period = 7.0\n'
        f'speed = 5.0\nwave_heading = 30.0\npad = [-18.0, 0.0, 3.0]\nrao_file = "{rao.name}"\n',
        encoding="utf-8",
    )
    scenario = load_scenario(toml)
    assert scenario.base.rao_file == str(rao.resolve())
    assert scenario.input_files == {str(rao.resolve()): scenario.base.rao_file_sha256}
    result = simulate(scenario)
    assert result.ok, result.message
    deck = scenario.base_motion.attitude(result.time)
    for i, name in enumerate(("deck_roll", "deck_pitch", "deck_yaw")):
        np.testing.assert_allclose(result.extra[name], deck[:, 0, i], atol=1e-15)
        np.testing.assert_allclose(result.extra[f"{name}_rate"], deck[:, 1, i], atol=1e-15)
    figures = result.deck_motion()
    x = result.extra
    assert figures["deck_roll_rms"] == pytest.approx(
        math.degrees(math.sqrt(sum(v * v for v in x["deck_roll"]) / x["deck_roll"].size))
    )
    assert figures["deck_pitch_rms"] == pytest.approx(
        math.degrees(math.sqrt(sum(v * v for v in x["deck_pitch"]) / x["deck_pitch"].size))
    )
    assert figures["deck_heave_velocity_rms"] == pytest.approx(
        math.sqrt(sum(v * v for v in x["base_v3"]) / x["base_v3"].size))  # fmt: skip
    assert "deck motion (RMS)" in repr(result)
    assert result.column_units()["deck_roll"] == "rad"
    # the command's summary.json carries them too
    from tetherheli import cli

    assert cli.main(["simulate", str(toml), "--out", str(tmp_path / "out")]) == 0
    summary = json.loads((tmp_path / "out" / "summary.json").read_text(encoding="utf-8"))
    assert summary["deck_motion"] == pytest.approx(figures)


@pytest.mark.slow
@pytest.mark.extra("ship")
def test_shipped_raos_are_what_the_script_writes():
    """The shipped CSV is benchmarks/ship_raos.py's output: Capytaine recomputes one of its
    rows (one frequency near the roll resonance, waves 30 deg off the bow; two BEM solves,
    10-30 s)."""
    sys.path.insert(0, str(ROOT / "benchmarks"))
    try:
        import ship_raos
    finally:
        sys.path.remove(str(ROOT / "benchmarks"))
    table = default_raos()
    rows = ship_raos.ship_raos(table.frequencies[[10]], table.headings[[1]])
    got = rows[0, 2::2] * np.exp(1j * rows[0, 3::2])
    np.testing.assert_allclose(got, table.values[10, 1], rtol=0, atol=1e-6)
    np.testing.assert_allclose(ship_raos.FREQUENCIES, table.frequencies, rtol=1e-8)
    np.testing.assert_array_equal(ship_raos.HEADINGS, table.headings)
    assert SHIPPED_RAOS.read_text(encoding="ascii").splitlines()[0] == ",".join(RAO_HEADER)


def test_script_refuses_a_wrong_argument():
    out = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / "ship_raos.py"), "--frobnicate"],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    assert out.returncode == 2 and len(out.stderr.strip().splitlines()) == 1
