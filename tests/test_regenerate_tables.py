"""docs/regenerate_tables.py rebuilds the README's tables: the cheap "claim" table it prints
is the README's, row for row (the paper's four runs, `tetherheli paper`)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _script():
    spec = importlib.util.spec_from_file_location(
        "regenerate_tables", ROOT / "docs" / "regenerate_tables.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_claim_table_rows_are_the_readmes(tmp_path, capsys):
    script = _script()
    assert script.main(["--only", "claim", "--workdir", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    rows = [line for line in out.splitlines() if line.startswith("| simulation")]
    assert len(rows) == 4
    readme = (ROOT / "README.md").read_text()
    for row in rows:
        assert row in readme
    assert "tension of sim2 tethered: 24.84-25.17 N" in out
    assert "within 24.84-25.17 N in simulation 2" in readme


def test_unknown_table_is_refused(capsys):
    assert _script().main(["--only", "nope"]) == 2
    err = capsys.readouterr().err
    assert "nope" in err and len(err.splitlines()) == 1
