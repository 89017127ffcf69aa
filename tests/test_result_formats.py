"""Time series as CSV or Parquet (issue 12, item 3): ``save(format=)``, ``load_result`` of
either, ``--format`` on ``simulate``, ``paper`` and ``montecarlo``."""

from __future__ import annotations

import csv
import json
import sys

import numpy as np
import pytest

from tetherheli import ParameterError, cli, load_result, simulate
from tetherheli.report import run_montecarlo
from tetherheli.results import list_results
from tetherheli.results.result import RESULT_COLUMNS, RESULT_FORMATS, TABLE_FORMATS
from tetherheli.scenario.core import Scenario
from tetherheli.studies.montecarlo import load_montecarlo
from tetherheli.wind import Pulse

from .test_montecarlo import SHORT
from .test_result import _assert_same

pytest.importorskip("pyarrow")
pd = pytest.importorskip("pandas")

PULSE = Pulse(start=0.1, duration=0.2, magnitude=20.0, direction=(0.6, 0.8, 0.0))


@pytest.fixture(scope="module")
def run():
    return simulate(Scenario(name="fmt_run", duration=0.4, wind=PULSE))


def test_parquet_round_trips_like_csv(run, tmp_path):
    """Both formats give back the saved result exactly (every float64 is stored as is)."""
    for fmt in RESULT_FORMATS:
        (tmp_path / fmt).mkdir()
        paths = run.save(tmp_path / fmt, format=fmt)
        assert paths[fmt] == tmp_path / fmt / f"fmt_run.{fmt}"
        assert list_results(tmp_path / fmt) == ["fmt_run"]
        _assert_same(load_result(tmp_path / fmt), run)
        _assert_same(load_result(paths[fmt]), run)  # the file's path names the run too
        _assert_same(load_result(paths["json"]), run)
    table = pd.read_parquet(tmp_path / "parquet" / "fmt_run.parquet")
    assert list(table.columns) == list(RESULT_COLUMNS)
    np.testing.assert_array_equal(table["q3"].to_numpy(), run.outputs[:, 2])
    from_csv = pd.read_csv(tmp_path / "csv" / "fmt_run.csv")
    pd.testing.assert_frame_equal(from_csv, table, check_exact=True)


def test_parquet_fields_carry_units_and_descriptions_for_pyarrow_alone(run, tmp_path):
    """Issue 25, item 7: each Arrow field of the saved Parquet carries its unit and
    description (before: units only in pandas' attrs blob); pandas still gets df.attrs."""
    import pyarrow.parquet as pq

    from tetherheli.results.result import RESULT_DESCRIPTIONS

    path = run.save(tmp_path, format="parquet")["parquet"]
    schema = pq.read_schema(path)
    assert schema.field("q1").metadata[b"units"] == b"m"
    assert schema.field("q1").metadata[b"description"].startswith(b"position of HO in N")
    units = run.column_units()
    for name in RESULT_COLUMNS:
        meta = schema.field(name).metadata
        assert meta[b"units"].decode() == units[name], name
        assert meta[b"description"].decode() == RESULT_DESCRIPTIONS[name] != "", name
    assert pd.read_parquet(path).attrs["units"] == units


def test_bad_format_and_both_files_are_refused(run, tmp_path, monkeypatch):
    with pytest.raises(ParameterError, match="format = 'xlsx'"):
        run.save(tmp_path, format="xlsx")
    run.save(tmp_path)
    run.save(tmp_path, format="parquet")
    with pytest.raises(ParameterError, match=r"not both fmt_run\.csv and fmt_run\.parquet"):
        load_result(tmp_path)
    (tmp_path / "fmt_run.csv").unlink()
    bad = load_result(tmp_path).to_dataframe().reset_index()
    bad.loc[3, "TC"] = np.nan
    bad.to_parquet(tmp_path / "fmt_run.parquet", index=False)
    with pytest.raises(ParameterError, match="parquet row 3 column TC"):
        load_result(tmp_path)
    bad.drop(columns=["RC"]).to_parquet(tmp_path / "fmt_run.parquet", index=False)
    with pytest.raises(ParameterError, match="parquet columns = 'RC'"):
        load_result(tmp_path)
    monkeypatch.setitem(sys.modules, "pyarrow", None)
    with pytest.raises(ParameterError, match=r"format = 'parquet'.*pyarrow is needed"):
        run.save(tmp_path / "x", format="parquet")


def test_cli_format_choices_are_the_result_formats():
    commands = cli.build_parser()._subparsers._group_actions[0].choices
    for command in ("simulate", "paper", "montecarlo"):
        action = next(a for a in commands[command]._actions if a.dest == "data_format")
        formats = TABLE_FORMATS if command == "montecarlo" else RESULT_FORMATS
        assert tuple(action.choices) == formats and action.default == "csv"


def test_simulate_cli_writes_parquet_that_load_result_reads(tmp_path, capsys):
    scenario = tmp_path / "s.toml"
    scenario.write_text(
        'name = "cli_pq"\nduration = 0.3\n[[wind]]\ntype = "pulse"\nstart = 0.1\n'
        "duration = 0.1\nmagnitude = 10.0\ndirection = [1.0, 0.0, 0.0]\n"
    )
    out = tmp_path / "out"
    assert cli.main(["simulate", str(scenario), "--out", str(out), "--format", "parquet"]) == 0
    assert (out / "cli_pq.parquet").is_file() and not (out / "cli_pq.csv").exists()
    loaded = load_result(out)
    assert loaded.name == "cli_pq" and loaded.time.size == 31
    from tetherheli.viz.animation import load_run

    drawn = load_run(out)  # the animation reads runs through load_result
    np.testing.assert_array_equal(drawn.position, loaded.outputs[:, :3])
    assert cli.main(["simulate", str(scenario), "--out", str(out), "--format", "xls"]) == 2
    err = capsys.readouterr().err
    assert "--format" in err and len(err.strip().splitlines()) == 1


@pytest.mark.usefixtures("blank_figures")  # the tables under test, not the plots
def test_montecarlo_results_table_in_parquet_equals_the_csv(tmp_path):
    path = tmp_path / "mc.toml"
    path.write_text(SHORT)
    base, config = load_montecarlo(path)
    config = config.__class__(**{**config.__dict__, "runs": 3})
    kw = {"chunk_size": 2, "progress": False}
    s_csv = run_montecarlo(base, config, tmp_path / "c", **kw)
    s_pq = run_montecarlo(base, config, tmp_path / "p", table_format="parquet", **kw)
    assert s_csv == s_pq
    assert not (tmp_path / "p" / "results.csv").exists()
    table = pd.read_parquet(tmp_path / "p" / "results.parquet")
    with open(tmp_path / "c" / "results.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert list(table.columns) == list(rows[0]) and len(table) == len(rows) == 6
    assert table["run"].dtype == np.int64 and table["status"].dtype == np.int64
    for name in table.columns:
        mine = table[name].tolist()
        if pd.api.types.is_string_dtype(table[name]):
            assert mine == [r[name] for r in rows], name
        else:
            np.testing.assert_array_equal(mine, [float(r[name]) for r in rows], err_msg=name)
    record = json.loads((tmp_path / "p" / ".tetherheli-output.json").read_text())
    assert "results.parquet" in json.dumps(record)
    # the units (issue 25, item 7): in the Arrow schema, readable by pyarrow alone, and in
    # summary.json for the CSV, from the parameters' own documentation and names.METRIC_UNITS
    import pyarrow.parquet as pq

    schema = pq.read_schema(tmp_path / "p" / "results.parquet")
    units = {f.name: f.metadata[b"units"].decode() for f in schema}
    summary = json.loads((tmp_path / "c" / "summary.json").read_text())
    assert summary["units"] == units and set(units) == set(rows[0])
    assert units["peak_q1"] == "m" and units["peak_q4_deg"] == "deg"
    assert units["tension_max"] == "N" and units["release_time"] == "s"
    assert units["value:helicopter.m_F"] == "kg" and units["factor:helicopter.m_F"] == "1"
    assert units["value:tether.K_C"] == "N/m" and units["configuration"] == ""
