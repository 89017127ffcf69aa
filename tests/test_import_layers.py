"""The import layers (``[tool.importlinter]`` in pyproject.toml, docs/architecture.md): a
lower layer never imports an upper one, imports inside functions included, checked by
``lint-imports`` on this source tree; and every module of the package sits in a layer, so a
new module cannot stand outside the contract."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src"
PACKAGE = SRC / "tetherheli"


def _contract() -> dict:
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    (contract,) = config["tool"]["importlinter"]["contracts"]
    return contract


def _layer_modules() -> set[str]:
    names = set()
    for layer in _contract()["layers"]:
        for part in layer.replace("|", ":").split(":"):
            names.add(part.strip())
    return names


def test_every_module_is_in_a_layer():
    """Each top-level module and package of tetherheli is named by one layer (and each
    layer's module exists)."""
    top = {
        f"tetherheli.{p.stem}"
        for p in PACKAGE.iterdir()
        if (p.suffix == ".py" and p.stem != "__init__") or (p / "__init__.py").is_file()
    }
    named = _layer_modules()
    assert top - named == set(), f"modules outside the import layers: {sorted(top - named)}"
    assert named - top == set(), f"layers naming no module: {sorted(named - top)}"


def test_lower_layers_never_import_upper_ones():
    """``lint-imports`` keeps the contract (its report is the failure message)."""
    pytest.importorskip("importlinter", reason="import-linter is not installed (test extra)")
    exe = shutil.which("lint-imports") or str(Path(sys.executable).with_name("lint-imports"))
    if not Path(exe).is_file():
        pytest.skip("import-linter's lint-imports is not on PATH")
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(SRC), os.environ.get("PYTHONPATH", "")]),
    }
    run = subprocess.run(
        [exe, "--no-cache", "--no-logo", str(ROOT / "pyproject.toml")],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert run.returncode == 0, run.stdout + run.stderr
    assert "0 broken" in run.stdout, run.stdout
