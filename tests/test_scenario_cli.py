"""Scenario files (strict TOML) and the simulate / paper commands."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from tetherheli import ParameterError, load_scenario
from tetherheli.cli import main
from tetherheli.scenario.core import paper_scenario

SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"

GOOD = """
name = "short"
configuration = "tethered"
duration = 2.0
[control]
dt = 0.01
[[wind]]
type = "pulse"
start = 0.5
duration = 0.5
magnitude = 10.0
direction = [1, 0, 0]
"""


@pytest.mark.parametrize("sim", [1, 2])
@pytest.mark.parametrize("cfg", ["free", "tethered"])
def test_shipped_paper_scenarios_equal_sec_vi(sim, cfg):
    """scenarios/paper_sim{1,2}_{free,tethered}.toml are Sec. VI's runs (1 s pulse assumed)."""
    s = load_scenario(SCENARIOS / f"paper_sim{sim}_{cfg}.toml")
    assert s == paper_scenario(sim, cfg)
    assert "assumed" in s.description


@pytest.mark.parametrize(
    ("text", "key"),
    [
        ("duration = 2.0\ncolour = 'red'\n", "colour"),
        ("duration = 'long'\n", "duration"),
        ("duration = -1.0\n", "duration"),
        ("duration = nan\n", "duration"),
        ("duration = 2.0\n[control]\ndt = -0.01\n", "control.dt"),
        ("duration = 2.0\n[control]\ndt = 5.0\n", "control.dt"),
        ("duration = 2.0\n[control]\ndt = inf\n", "control.dt"),
        ("duration = 2.0\n[control]\nsubsteps = 0\n", "control.substeps"),
        ("duration = 2.0\n[control]\nspeed = 1\n", "control.speed"),
        ("duration = 2.0\n[control]\nQy = [1, 2]\n", "control.Qy"),
        ("configuration = 'loose'\n", "configuration"),
        (
            "duration = 2.0\n[[wind]]\ntype = 'pulse'\nstart = 1.0\nduration = -1.0\n"
            "magnitude = 1.0\ndirection = [1, 0, 0]\n",
            "duration",
        ),
        ("duration = 2.0\n[[wind]]\ntype = 'hurricane'\n", "type"),
        ("duration = 2.0\n[params.tether]\nK_C = -4.0\n", "tether.K_C"),
        ("duration = 2.0\n[limits]\nmax_tension = 10.0\n", "T_ref"),
    ],
)
def test_bad_scenarios_name_file_and_key(tmp_path, text, key):
    f = tmp_path / "bad.toml"
    f.write_text(text)
    with pytest.raises(ParameterError) as err:
        load_scenario(f)
    msg = str(err.value)
    assert str(f) in msg and key in msg and "allowed" in msg and "\n" not in msg


@pytest.mark.parametrize(
    "content",
    [
        None,
        "this is = = not toml",
        "duration = 2.0\ncolour = 'red'\n",
        "duration = 2.0\n[control]\ndt = -1.0\n",
    ],
)
def test_simulate_cli_bad_file_exit_2_no_output(tmp_path, capsys, content):
    """Missing file, not TOML, unknown key, out-of-range value: one line, exit 2, no output."""
    f = tmp_path / "s.toml"
    if content is not None:
        f.write_text(content)
    out = tmp_path / "out"
    assert main(["simulate", str(f), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and str(f) in err and "Traceback" not in err
    assert not out.exists()
    assert not any(p.name.startswith(".out") for p in tmp_path.iterdir())


def test_simulate_cli_writes_run(tmp_path, capsys):
    f = tmp_path / "s.toml"
    f.write_text(GOOD)
    out = tmp_path / "out"
    assert main(["simulate", str(f), "--out", str(out)]) == 0
    names = {p.name for p in out.iterdir()}
    assert {
        "short.csv",
        "short.json",
        "summary.json",
        "report.md",
        "outputs.png",
        "inputs.png",
    } <= names
    meta = json.loads((out / "short.json").read_text())
    assert meta["tetherheli_version"] and meta["configuration"]["duration"] == 2.0
    data = np.genfromtxt(out / "short.csv", delimiter=",", names=True)
    assert data.shape == (201,) and data["TC"][0] == pytest.approx(25.0)


def test_simulate_cli_several_scenarios_overlaid(tmp_path, capsys):
    """Several scenarios: each run in OUT/<name>/, equal to its single run; overlay figures;
    a duplicate name or one bad file writes nothing."""
    a, b = tmp_path / "a.toml", tmp_path / "b.toml"
    a.write_text(GOOD)
    b.write_text(GOOD.replace('"short"', '"short_free"').replace('"tethered"', '"free"'))
    out = tmp_path / "out"
    assert main(["simulate", str(a), str(b), "--out", str(out)]) == 0
    assert {"short", "short_free", "outputs.png", "inputs.png", "summary.json"} <= {
        p.name for p in out.iterdir()
    }
    single = tmp_path / "single"
    assert main(["simulate", str(a), "--out", str(single)]) == 0
    assert (out / "short" / "short.csv").read_bytes() == (single / "short.csv").read_bytes()
    summary = json.loads((out / "summary.json").read_text())
    assert set(summary["runs"]) == {"short", "short_free"}
    assert "| rms_dev q1 [m] |" in (out / "report.md").read_text()
    capsys.readouterr()
    for args in ([str(a), str(a)], [str(a), str(tmp_path / "missing.toml")]):
        out2 = tmp_path / "out2"
        assert main(["simulate", *args, "--out", str(out2)]) == 2
        assert len(capsys.readouterr().err.strip().splitlines()) == 1
        assert not out2.exists()


def test_turbulence_scenarios_fly_the_same_air():
    """The shipped turbulence pair: same seeded gusts; the tethered run is steadier in q1."""
    from tetherheli import simulate

    free = load_scenario(SCENARIOS / "turbulence_hover_free.toml")
    tethered = load_scenario(SCENARIOS / "turbulence_hover_tethered.toml")
    assert free.wind == tethered.wind and free.duration == 120.0
    rf, rt = simulate(free), simulate(tethered)
    assert rf.ok and rt.ok
    rms = [float(np.sqrt(np.mean((r.outputs[:, 0] - r.trim_output[0]) ** 2))) for r in (rf, rt)]
    assert rms[1] < 0.8 * rms[0]  # measured: 0.2227 m free, 0.1564 m tethered


def test_simulate_cli_failed_run_reports(tmp_path, capsys):
    """A run that diverges is not reported as success (exit 1, message, status recorded)."""
    f = tmp_path / "s.toml"
    f.write_text(
        GOOD.replace("magnitude = 10.0", "magnitude = 2000.0").replace(
            "direction = [1, 0, 0]", "direction = [0, 0, -1]"
        )
    )
    out = tmp_path / "out"
    assert main(["simulate", str(f), "--out", str(out)]) == 1
    err = capsys.readouterr().err
    assert "stopped" in err and "ground" in err
    assert json.loads((out / "summary.json").read_text())["status"] != 0


def test_paper_command_writes_everything(tmp_path, capsys):
    """`tetherheli paper --out DIR`: Figs. 6-9, time series, report.md, summary.json with
    exactly the documented keys."""
    out = tmp_path / "paper"
    assert main(["paper", "--out", str(out)]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert set(s) == {"dt", "pulse_duration", "runs", "reduction_percent", "statuses"}
    assert all(st["completed"] and st["status"] == 0 for st in s["statuses"].values())
    assert set(s["runs"]) == {"sim1_free", "sim1_tethered", "sim2_free", "sim2_tethered"}
    for run in s["runs"].values():
        assert set(run) == {"peak_abs_dev", "rms_dev", "tension_min", "tension_max"}
        assert set(run["peak_abs_dev"]) == {"q1", "q2", "q3", "q4_deg", "q5_deg"}
        assert set(run["rms_dev"]) == {"q1", "q2", "q3"}
    assert set(s["reduction_percent"]) == {
        "sim1_q1_peak",
        "sim1_q1_rms",
        "sim2_q2_peak",
        "sim2_q2_rms",
    }
    assert s["dt"] == 0.01 and s["pulse_duration"] == 1.0
    for fig in ("fig6_sim1_outputs", "fig7_sim1_inputs", "fig8_sim2_outputs", "fig9_sim2_inputs"):
        assert (out / f"{fig}.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    report = (out / "report.md").read_text()
    assert "30%" in report and "assumption" in report
    assert f"{s['reduction_percent']['sim1_q1_peak']:.1f}%" in report


@pytest.mark.parametrize(
    "argv", [["paper", "--dt", "-1"], ["paper", "--pulse-duration", "x"], ["simulate", "x.toml"]]
)
def test_paper_cli_bad_args(argv, capsys, tmp_path):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1
