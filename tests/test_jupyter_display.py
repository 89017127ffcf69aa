"""Issue 47 item 4 outside a kernel (tests/test_notebook.py runs the idioms in one): a figure
of the package gets pyplot's figure manager only when pyplot is already imported, never
inside a writer (``figures_for_files``), and never changes the backend; results show as a
short summary (``repr``, an HTML table in Jupyter), never their arrays."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from tetherheli.runs import simulate
from tetherheli.scenario import Scenario
from tetherheli.studies.cyclic_limit import LimitSearch
from tetherheli.studies.robust import MonteCarloComparison
from tetherheli.studies.sweep import SweepResult
from tetherheli.studies.tether_study import TetherStudy, TetherStudyConfig

ROOT = Path(__file__).resolve().parents[1]

_PYPLOT = """
import sys
import numpy as np
import matplotlib
matplotlib.use("agg")  # the user's backend, which the package must keep
from tetherheli.viz.plots import figure_pareto, figures_for_files

def pareto():
    return figure_pareto(np.array([1.0, 1.2]), np.array([40.0, 60.0]), np.array([True, True]),
                         np.array([10.0, 20.0]), "T [N]")

before = pareto()
assert "matplotlib.pyplot" not in sys.modules and before.canvas.manager is None
import matplotlib.pyplot as plt
fig = pareto()
assert plt.get_fignums() == [fig.number] and plt.gcf() is fig, plt.get_fignums()
assert type(fig).__name__ == "InlineFigure"
with figures_for_files():
    quiet = pareto()
assert quiet.canvas.manager is None and plt.get_fignums() == [fig.number]
plt.close("all")
print(matplotlib.get_backend())
"""


def test_figures_join_pyplot_only_when_it_is_imported():
    """Before ``import matplotlib.pyplot`` a figure is pyplot-free; after it, a figure is
    pyplot's current one (so ``plt.show()``, ``plt.savefig`` and ``plt.close`` work on it);
    within ``figures_for_files`` (every writer) it is not; the backend is the user's."""
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    env.pop("MPLBACKEND", None)
    out = subprocess.run(
        [sys.executable, "-c", _PYPLOT], capture_output=True, text=True, env=env, timeout=300
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "agg"


def _short(obj: object, *texts: str) -> None:
    text, html = repr(obj), obj._repr_html_()
    assert text.startswith(f"<{type(obj).__name__}") and len(text) < 800, text
    assert "array(" not in text and "\n" in text
    assert html.startswith(f"<table><caption>{type(obj).__name__}</caption>") and len(html) < 3000
    for t in texts:
        assert t in text and t in html, (t, text)


def test_simulation_result_repr_is_a_short_summary():
    scenario = Scenario(name="short_repr", duration=0.5)
    result = simulate(scenario)
    _short(result, "short_repr", "tethered", "0 (completed)", "51 (dt = 0.01 s)", "q1 ", "deg")
    peaks = result.peak_deviations()
    assert set(peaks) == {"q1", "q2", "q3", "q4_deg", "q5_deg"}
    assert peaks["q1"] == np.max(np.abs(result.deviations()["q1"]))
    assert "<" not in result._repr_html_().split("</caption>")[1].replace("<t", "").replace(
        "</t", ""
    )  # the values are escaped


def test_study_results_repr_is_a_short_summary():
    values = np.linspace(10.0, 40.0, 4)
    sweep = SweepResult(
        "tension_control.T_ref", "peak_q1", values, np.array([1.0, 0.5, np.nan, 0.7]),
        ("completed", "completed", "diverged", "completed"), 30.0, 20.0,
        (True, True, False, True),
    )  # fmt: skip
    _short(sweep, "tension_control.T_ref", "4 values", "1 of 4", "30 N")
    search = LimitSearch(
        "s", "peak_q1", 0.1, 0.01, 1.0, 1.1, 4.0, 4.5, np.array([3.0, 5.0, 4.5]),
        np.array([2.0, 1.05, 1.08]), ("completed",) * 3, np.array([False, True, True]), 2,
    )  # fmt: skip
    _short(search, "4.000-4.500 N m", "3 (2 on the grid)")
    mc = MonteCarloComparison(
        "mc", 3, 7, ("free", "paper"), {}, {"free": np.array([True, False, True]),
        "paper": np.ones(3, bool)}, {},
    )  # fmt: skip
    _short(mc, "3 (seed 7)", "free 1, paper 0")
    study = TetherStudy(TetherStudyConfig(), 100.0, (), (), (), (), {})
    _short(study, "lumped", "0 static, 0 dynamic (0 failed)")
