"""Runs as MCAP (``--format mcap``, ``results.mcap``): written with the ``mcap`` package's
writer, read back by its reader and by plain JSON decoding, and by ``load_result`` exactly as
the CSV."""

from __future__ import annotations

import json
import math
import sys

import numpy as np
import pytest
from mcap.reader import make_reader

from tetherheli import ParameterError, cli, load_result, simulate
from tetherheli.results.mcap import MCAP_TOPICS, read_mcap_table, write_mcap
from tetherheli.scenario.core import Scenario
from tetherheli.scenario.tables import BaseSettings
from tetherheli.wind import Pulse

from .test_result import _assert_same

PULSE = Pulse(start=0.1, duration=0.2, magnitude=20.0, direction=(0.6, 0.8, 0.0))


@pytest.fixture(scope="module")
def run():
    """A short tethered run over a heaving base (base_n1..3 columns)."""
    return simulate(
        Scenario(
            name="mcap_run",
            configuration="tethered",
            duration=0.4,
            wind=PULSE,
            base=BaseSettings(motion="harmonic", amplitude=(0.0, 0.0, 0.3), frequency=(0, 0, 1.0)),
        )
    )


def _messages(path, topic):
    with open(path, "rb") as stream:
        return [
            (schema, channel, message)
            for schema, channel, message in make_reader(stream).iter_messages(topics=[topic])
        ]


def test_mcap_round_trips_like_csv(run, tmp_path):
    written = run.save(tmp_path, format="mcap")
    assert sorted(written) == ["json", "mcap"] and written["mcap"].suffix == ".mcap"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mcap_run.json", "mcap_run.mcap"]
    _assert_same(load_result(tmp_path), run)  # every column, bit for bit
    assert "base_n3" in run.extra


def test_mcap_holds_foxglove_messages_an_independent_reader_decodes(run, tmp_path):
    path = run.save(tmp_path, format="mcap")["mcap"]
    with open(path, "rb") as stream:
        summary = make_reader(stream).get_summary()
    topics = {c.topic: c for c in summary.channels.values()}
    assert tuple(sorted(topics)) == tuple(sorted(MCAP_TOPICS))
    names = {t: summary.schemas[c.schema_id].name for t, c in topics.items()}
    assert names == {
        "/signals": "tetherheli.Signals",
        "/tf": "foxglove.FrameTransform",
        "/scene": "foxglove.SceneUpdate",
    }
    for channel in topics.values():
        schema = summary.schemas[channel.schema_id]
        assert channel.message_encoding == "json" and schema.encoding == "jsonschema"
        assert json.loads(schema.data)["title"] == schema.name
    n = run.time.size
    counts = summary.statistics.channel_message_counts
    assert [counts[topics[t].id] for t in ("/signals", "/tf", "/scene")] == [n, 2 * n, n]

    # one sample decoded with plain JSON, no schema library
    k = 3
    _, _, message = _messages(path, "/signals")[k]
    row = json.loads(message.data)
    assert row["t"] == run.time[k] and row["q1"] == run.outputs[k, 0]
    assert row["TC"] == run.tension[k] and row["base_n3"] == run.extra["base_n3"][k]
    assert message.log_time == round(run.time[k] * 1e9)
    transforms = [json.loads(m.data) for _, _, m in _messages(path, "/tf")[2 * k : 2 * k + 2]]
    assert {f["child_frame_id"] for f in transforms} == {"base", "fuselage"}
    base = next(f for f in transforms if f["child_frame_id"] == "base")
    assert base["parent_frame_id"] == "world"
    assert base["translation"]["z"] == pytest.approx(run.extra["base_n3"][k])
    body = next(f for f in transforms if f["child_frame_id"] == "fuselage")
    q = body["rotation"]
    assert math.isclose(q["x"] ** 2 + q["y"] ** 2 + q["z"] ** 2 + q["w"] ** 2, 1.0)
    scenes = [json.loads(m.data) for _, _, m in _messages(path, "/scene")]
    assert [e["id"] for e in scenes[0]["entities"]] == ["deck", "helicopter", "tether", "wind"]
    tether = next(e for e in scenes[k]["entities"] if e["id"] == "tether")["lines"][0]
    top = tether["points"][-1]["z"]  # P, in N: over the moving base
    assert top == pytest.approx(run.extra["base_n3"][k] + run.outputs[k, 2], abs=0.5)
    with open(path, "rb") as stream:
        metadata = {m.name: m.metadata for m in make_reader(stream).iter_metadata()}
    assert metadata["units"]["q1"] == "m" and metadata["run"]["configuration"] == "tethered"


def test_non_finite_values_are_null_and_read_back_as_nan(tmp_path):
    t = np.linspace(0.0, 0.2, 3)
    columns = {name: np.zeros(3) for name in ("t", "q1", "q2", "q3", "q4", "q5", "q6")}
    columns.update(t=t, TC=np.array([1.0, np.nan, np.inf]), Fw1=np.zeros(3))
    columns.update(Fw2=np.zeros(3), Fw3=np.zeros(3))
    path = write_mcap(tmp_path / "x.mcap", columns, {}, {}, {"name": "x"}, tethered=True)
    rows = [json.loads(m.data) for _, _, m in _messages(path, "/signals")]
    assert [r["TC"] for r in rows] == [1.0, None, None]  # strict JSON: no NaN, no Infinity
    header, values = read_mcap_table(path)
    assert header == list(columns) and np.isnan(values[1:, header.index("TC")]).all()
    (tmp_path / "bad.mcap").write_bytes(b"not an mcap file")
    with pytest.raises(ParameterError, match=r"mcap = 'bad\.mcap'"):
        read_mcap_table(tmp_path / "bad.mcap")


def test_simulate_and_paper_take_format_mcap(tmp_path, capsys, monkeypatch):
    scenario = tmp_path / "s.toml"
    scenario.write_text(
        'name = "cli_mcap"\nduration = 0.3\n[[wind]]\ntype = "pulse"\nstart = 0.1\n'
        "duration = 0.1\nmagnitude = 10.0\ndirection = [1.0, 0.0, 0.0]\n"
    )
    out = tmp_path / "out"
    assert cli.main(["simulate", str(scenario), "--out", str(out), "--format", "mcap"]) == 0
    assert (out / "cli_mcap.mcap").is_file() and not (out / "cli_mcap.csv").exists()
    assert load_result(out).time.size == 31
    commands = cli.build_parser()._subparsers._group_actions[0].choices
    for command in ("simulate", "paper"):
        action = next(a for a in commands[command]._actions if a.dest == "data_format")
        assert "mcap" in action.choices
    capsys.readouterr()
    argv = ["montecarlo", str(scenario), "--format", "mcap", "--out", str(tmp_path / "m")]
    assert cli.main(argv) == 2  # a table of many runs is no MCAP
    assert "--format" in capsys.readouterr().err
    monkeypatch.setitem(sys.modules, "mcap", None)
    assert cli.main(["simulate", str(scenario), "--out", str(tmp_path / "o"), "--format", "mcap"])
    err = capsys.readouterr().err
    assert "format = 'mcap'" in err and "mcap is needed" in err and len(err.splitlines()) == 1
