"""Results as data (issue 12, item 3): ``SimulationResult.to_dataframe`` / ``to_xarray`` carry
the run CSV's columns, in order, with their units, and survive ``save`` -> ``load_result``."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from tetherheli import load_result, simulate
from tetherheli.names import INPUT_UNITS, TETHERED_STATE, TETHERED_STATE_UNITS
from tetherheli.results.result import RESULT_COLUMNS
from tetherheli.scenario.core import Scenario
from tetherheli.wind import Pulse

PULSE = Pulse(start=0.1, duration=0.2, magnitude=20.0, direction=(0.6, 0.8, 0.0))


@pytest.fixture(scope="module")
def run():
    return simulate(Scenario(name="data_run", duration=0.3, wind=PULSE))


def test_units_follow_names(run):
    """Every column has a unit, and those of the state and inputs are names.py's."""
    units = run.column_units()
    assert list(units) == list(RESULT_COLUMNS)
    assert all(units.values())
    for name, unit in zip(TETHERED_STATE, TETHERED_STATE_UNITS, strict=True):
        assert units[name] == unit
    assert units["tMR1"] == INPUT_UNITS[1] == units["C1_ffwd"]
    assert (units["t"], units["TC"], units["RC"], units["Fw3"]) == ("s", "N", "m/s", "N")


def test_to_dataframe_round_trips_through_save_and_load(run, tmp_path):
    pd = pytest.importorskip("pandas")
    df = run.to_dataframe()
    assert df.index.name == "t"
    assert ["t", *df.columns] == list(RESULT_COLUMNS)
    np.testing.assert_array_equal(df.index.to_numpy(), run.time)
    np.testing.assert_array_equal(df["TC"].to_numpy(), run.tension)
    np.testing.assert_array_equal(df["q3"].to_numpy(), run.outputs[:, 2])
    assert df.attrs["units"] == run.column_units()
    assert df.attrs["scenario"] == "data_run"
    assert df.attrs["tetherheli_version"] == run.version
    run.save(tmp_path)
    back = load_result(tmp_path).to_dataframe()
    pd.testing.assert_frame_equal(back, df, check_exact=True)
    assert back.attrs == df.attrs


def test_to_xarray_has_dimension_t_and_units(run, tmp_path):
    pytest.importorskip("xarray")
    ds = run.to_xarray()
    assert tuple(ds.sizes) == ("t",)
    assert ds.sizes["t"] == run.time.size
    assert list(ds.data_vars) == list(RESULT_COLUMNS[1:])
    assert ds["t"].attrs["units"] == "s"
    assert ds["q7"].attrs["units"] == "rad"
    np.testing.assert_array_equal(ds["Fw2"].to_numpy(), run.wind[:, 1])
    assert ds.attrs["scenario"] == "data_run"
    run.save(tmp_path)
    assert load_result(tmp_path).to_xarray().identical(ds)


@pytest.mark.parametrize(
    ("method", "module"), [("to_dataframe", "pandas"), ("to_xarray", "xarray")]
)
def test_missing_package_is_named(run, monkeypatch, method, module):
    monkeypatch.setitem(sys.modules, module, None)  # import now raises ImportError
    with pytest.raises(ImportError, match=rf"^{module} is needed .* pip install {module}"):
        getattr(run, method)()
