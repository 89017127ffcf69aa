"""``tetherheli compare``: scenarios under several controllers, one table (``compare``)."""

from __future__ import annotations

import csv

from tetherheli.cli import main
from tetherheli.scenario.core import Scenario
from tetherheli.studies.sweep import paper_cyclic_limit
from tetherheli.wind.profiles import Pulse


def _scenario_file(tmp_path):
    s = Scenario(name="short", duration=3.0, wind=Pulse(0.5, 1.0, 20.0, (0.0, 1.0, 0.0)))
    path = tmp_path / "short.toml"
    path.write_text(s.to_toml())
    return path, s


def test_bad_controller_name_is_a_usage_error(tmp_path, capsys):
    path, _ = _scenario_file(tmp_path)
    code = main(["compare", str(path), "--controllers", "paper,pid", "--out", str(tmp_path / "o")])
    assert code == 2
    err = capsys.readouterr().err
    assert "--controllers" in err and "pid" in err and len(err.strip().splitlines()) == 1


def test_compare_writes_one_row_per_controller_within_eq40(tmp_path):
    """Both controllers fly the run; with --eq40 no applied cyclic torque exceeds eq 40's
    limit (20% of the free hover lift times the arm), which the table records."""
    path, s = _scenario_file(tmp_path)
    out = tmp_path / "out"
    assert main(["compare", str(path), "--eq40", "--out", str(out)]) == 0
    with open(out / "compare.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert [r["controller"] for r in rows] == ["paper", "tether_lqi"]
    limit = paper_cyclic_limit(s.params)
    for r in rows:
        assert r["completed"] == "True"
        assert abs(float(r["cyclic_limit"]) - limit) < 1e-12
        assert float(r["peak_cyclic"]) <= limit * (1 + 1e-12)
        assert float(r["peak_q2"]) > 0.0 and float(r["tension_min"]) > 0.0
    assert (out / "compare.md").read_text().count("| short |") == 2
    assert (out / "compare.png").stat().st_size > 0
