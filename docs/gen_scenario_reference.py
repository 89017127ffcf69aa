"""Write docs/scenario_reference.md from the code's key metadata (tetherheli.sim.reference).

Run ``PYTHONPATH=src python docs/gen_scenario_reference.py``; ``tests/test_docs.py`` checks
that the committed page is up to date.
"""

from pathlib import Path

from tetherheli.sim.reference import scenario_reference

if __name__ == "__main__":
    out = Path(__file__).with_name("scenario_reference.md")
    out.write_text(scenario_reference(), encoding="utf-8")
    print(f"wrote {out}")
