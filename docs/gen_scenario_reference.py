"""Write docs/scenario_reference.md from the code's key metadata (tetherheli.scenario.reference).

Run ``PYTHONPATH=src python docs/gen_scenario_reference.py``; ``tests/test_docs.py`` checks
that the committed page is up to date. The page is the project's own file, replaced whole
(``cli._script.write_docs_file``: never through a link).
"""

from __future__ import annotations

from pathlib import Path

from tetherheli.cli._script import run_script, script_parser, write_docs_file
from tetherheli.scenario.reference import scenario_reference

ROOT = Path(__file__).resolve().parents[1]
#: The page written (relative to ``ROOT``).
PAGE = "docs/scenario_reference.md"


def main(argv: list[str] | None = None) -> int:
    """Write the page; the exit code (2: one line, nothing written)."""

    def work(arguments: list[str]) -> int:
        script_parser(__file__, __doc__).parse_args(arguments)
        write_docs_file(ROOT, PAGE, scenario_reference())
        print(f"wrote {PAGE}")
        return 0

    return run_script(__file__, work, argv)


if __name__ == "__main__":
    raise SystemExit(main())
