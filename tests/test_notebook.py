"""Issue 25, item 4: the package's figures display inline in a fresh Jupyter kernel, and
library code never changes the kernel's Matplotlib backend (``compare.write_compare`` used
to switch it to Agg, after which no figure showed). A small notebook runs with nbclient."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")
pytest.importorskip("ipykernel")

SRC = Path(__file__).resolve().parents[1] / "src"

CELLS = [
    # a plot function's figure as the cell's last expression
    "import matplotlib\n"
    "backend = matplotlib.get_backend()\n"
    "import numpy as np\n"
    "from tetherheli.viz.plots import figure_pareto\n"
    "figure_pareto(np.array([1.0, 1.2]), np.array([40.0, 60.0]), np.array([True, True]),\n"
    "              np.array([10.0, 20.0]), 'T [N]')",
    # write_compare (which draws compare.png) leaves the backend alone ...
    "from tetherheli.compare import write_compare\n"
    "row = {'scenario': 's', 'controller': 'c', 'completed': False, 'runs': 1, 'failures': 1}\n"
    "write_compare([row], {out!r}, command='test', inputs=())\n"
    "assert matplotlib.get_backend() == backend, (backend, matplotlib.get_backend())\n"
    "print(backend)",
    # ... so a figure made after it still shows
    "from tetherheli.viz.plots import figure_compare\nfigure_compare([row])",
]


def test_figures_display_inline_in_a_fresh_kernel(tmp_path: Path, monkeypatch) -> None:
    nb = nbformat.v4.new_notebook()
    out = str(tmp_path / "compare")
    nb.cells = [nbformat.v4.new_code_cell(c.replace("{out!r}", repr(out))) for c in CELLS]
    # the kernel inherits this environment: our sources first, and its own (inline) backend
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(SRC), os.environ.get("PYTHONPATH", "")]))
    monkeypatch.delenv("MPLBACKEND", raising=False)
    client = nbclient.NotebookClient(
        nb, timeout=120, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}}
    )
    client.execute()
    outputs = [c["outputs"] for c in nb.cells]
    assert any("image/png" in o.get("data", {}) for o in outputs[0]), outputs[0]
    printed = "".join(o.get("text", "") for o in outputs[1])
    assert "inline" in printed, printed
    assert any("image/png" in o.get("data", {}) for o in outputs[2]), outputs[2]
    assert (tmp_path / "compare" / "compare.png").is_file()


ROOT = SRC.parent
QUICKSTART = ROOT / "docs" / "tutorials" / "quickstart.ipynb"
#: a figure of the package, cheap to draw (no run)
PARETO = (
    "figure_pareto(np.array([1.0, 1.2]), np.array([40.0, 60.0]), np.array([True, True]),"
    " np.array([10.0, 20.0]), 'T [N]')"
)
#: pyplot's idioms (issue 47 item 4), one per cell; each cell's images are counted
IDIOMS = [
    # 0: no pyplot imported: the figure is not pyplot's, and an assignment shows nothing
    "import sys\nimport numpy as np\nfrom tetherheli.viz.plots import figure_pareto\n"
    f"fig = {PARETO}\nprint('matplotlib.pyplot' in sys.modules, fig.canvas.manager)",
    # 1: ... as the cell's last expression it shows
    "fig",
    # 2: %matplotlib inline, then pyplot's show
    f"%matplotlib inline\nimport matplotlib.pyplot as plt\nfig = {PARETO}\nplt.show()",
    # 3: an assignment shows at the cell's end, as a pyplot figure does under inline
    f"fig = {PARETO}",
    # 4: display(fig): once, not again at the cell's end
    f"fig = {PARETO}\ndisplay(fig)",
    # 5: the last expression: once
    PARETO,
    # 6: a writer's figures are files: none shows, none stays in pyplot, the backend stays
    "from tetherheli.compare import write_compare\n"
    "row = {'scenario': 's', 'controller': 'c', 'completed': False, 'runs': 1, 'failures': 1}\n"
    "write_compare([row], 'compare', command='test', inputs=())\n"
    "import matplotlib\nprint(plt.get_fignums(), matplotlib.get_backend())",
]


def _images(outputs: list) -> int:
    return sum("image/png" in o.get("data", {}) for o in outputs)


def _run(nb, folder: Path, monkeypatch, timeout: int = 120) -> None:
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(SRC), os.environ.get("PYTHONPATH", "")]))
    monkeypatch.delenv("MPLBACKEND", raising=False)
    nbclient.NotebookClient(
        nb, timeout=timeout, kernel_name="python3", resources={"metadata": {"path": str(folder)}}
    ).execute()


def test_pyplot_idioms_show_each_figure_once(tmp_path: Path, monkeypatch) -> None:
    """``plt.show()``, ``display(fig)``, an assignment under ``%matplotlib inline`` and a
    last expression each show a figure of the package exactly once, in a fresh kernel whose
    backend (inline) nothing changes; before pyplot is imported the figures stay out of it."""
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell(c) for c in IDIOMS]
    _run(nb, tmp_path, monkeypatch)
    outputs = [c["outputs"] for c in nb.cells]
    printed = ["".join(o.get("text", "") for o in out) for out in outputs]
    assert printed[0].strip() == "False None" and _images(outputs[0]) == 0, outputs[0]
    assert [_images(out) for out in outputs[1:6]] == [1] * 5, outputs
    assert _images(outputs[6]) == 0 and printed[6].startswith("[] "), outputs[6]
    assert "inline" in printed[6], printed[6]
    assert (tmp_path / "compare" / "compare.png").is_file()


def test_quickstart_notebook_runs(tmp_path: Path, monkeypatch) -> None:
    """docs/tutorials/quickstart.ipynb runs from a scratch working folder without an error
    (the shipped scenario, simulate, the result's summary, plt.show, to_dataframe) and shows
    each figure once; it is committed with the outputs the docs site shows (after a change:
    ``PYTHONPATH=$PWD/src jupyter nbconvert --to notebook --execute --inplace
    docs/tutorials/quickstart.ipynb``)."""
    pytest.importorskip("pandas")
    nb = nbformat.read(QUICKSTART, as_version=4)
    stored = [c.get("outputs", []) for c in nb.cells if c.cell_type == "code"]
    assert all(stored), "the committed notebook has every code cell's outputs (the docs show)"
    _run(nb, tmp_path, monkeypatch, timeout=600)
    code = [c for c in nb.cells if c.cell_type == "code"]
    errors = [o for c in code for o in c["outputs"] if o.get("output_type") == "error"]
    assert not errors, errors
    summary = next(c for c in code if c.source.rstrip().endswith("\nresult"))["outputs"]
    html = "".join(o.get("data", {}).get("text/html", "") for o in summary)
    assert html.startswith("<table><caption>SimulationResult</caption>"), summary
    shows = [c for c in code if "plt.show()" in c.source or "figure_inputs([" in c.source]
    assert [_images(c["outputs"]) for c in shows] == [1, 1]
    assert list(tmp_path.iterdir()) == []  # the notebook writes no file
