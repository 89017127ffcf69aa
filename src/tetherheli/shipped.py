"""The scenarios shipped inside the package (``tetherheli/scenarios/*.toml``, read through
:mod:`importlib.resources`), so that an installed wheel keeps every README example.

``tetherheli scenarios`` lists them (name and the file's ``description``);
``tetherheli scenarios NAME --out PATH`` copies one out, never over a file tetherheli did not
write (``_io.check_output_file``). In a clone of the repository the top-level ``scenarios``
folder is a link to the same files.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

from ._io import atomic_write_text, check_output_file, record_output_file
from ._shipped_files import shipped_files
from .errors import ParameterError
from .scenario.core import Scenario, scenario_from_dict

__all__ = [
    "copy_scenario",
    "shipped_scenario",
    "shipped_scenario_text",
    "shipped_scenarios",
]


def _description(text: str) -> str:
    """The scenario's ``description`` key (one line), "" without one."""
    value = tomllib.loads(text).get("description", "")
    return " ".join(str(value).split())


def shipped_scenarios() -> dict[str, str]:
    """The shipped scenarios, name -> one-line description, sorted by name.

    Returns
    -------
    dict of str to str
        Scenario name -> its TOML ``description``, on one line.
    """
    files = shipped_files()
    return {name: _description(files[name].read_text(encoding="utf-8")) for name in sorted(files)}


def shipped_scenario_text(name: str) -> str:
    """The TOML text of a shipped scenario.

    Parameters
    ----------
    name : str
        One of ``shipped_scenarios()``.

    Returns
    -------
    str
        The scenario file's text.

    Raises
    ------
    ParameterError
        If ``name`` is not one of ``shipped_scenarios()``.
    """
    files = shipped_files()
    if name not in files:
        raise ParameterError("scenario", name, f"one of {sorted(files)}")
    return files[name].read_text(encoding="utf-8")


def shipped_scenario(name: str) -> Scenario:
    """A shipped scenario by name, loaded and validated as ``load_scenario`` loads a file
    (Monte Carlo scenarios: ``studies.montecarlo.load_montecarlo`` on a copied-out file).

    Parameters
    ----------
    name : str
        One of ``shipped_scenarios()``.

    Returns
    -------
    Scenario
        The validated scenario.
    """
    text = shipped_scenario_text(name)
    return scenario_from_dict(tomllib.loads(text), source=f"shipped scenario {name}")


def copy_scenario(name: str, out: str | Path) -> Path:
    """Write the shipped scenario ``name`` to the file ``out`` (atomically) and return it.

    A file at ``out`` is refused unless tetherheli wrote it (``_io.check_output_file``), so a
    user's file is never overwritten; a folder for ``out`` must exist.

    Parameters
    ----------
    name : str
        One of ``shipped_scenarios()``.
    out : str or Path
        The file to write, in an existing folder.

    Returns
    -------
    Path
        The file written.

    Raises
    ------
    ParameterError
        Unknown name.
    OutputPathError
        ``out`` is a directory or a file tetherheli did not write.
    """
    text = shipped_scenario_text(name)
    target = check_output_file(out)
    if not target.parent.is_dir():
        raise ParameterError("--out", str(out), "a file in an existing folder")
    atomic_write_text(target, text)
    record_output_file(target, writer="scenarios")
    return target
