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
    "from tetherheli.compare import _figure\n_figure([row])",
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
