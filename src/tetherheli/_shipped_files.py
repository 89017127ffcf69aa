"""Where the shipped scenarios lie: ``tetherheli/scenarios/*.toml`` inside the package, read
through :mod:`importlib.resources` (so a wheel keeps them). The one lookup of their files,
used by ``shipped`` (listing, copying) and by ``scenario.core.load_scenario`` (a scenario by
name wherever a scenario file is taken)."""

from __future__ import annotations

from importlib import resources
from importlib.resources.abc import Traversable
from pathlib import Path

__all__ = ["SUFFIX", "shipped_files", "shipped_name"]

#: the shipped scenario files' suffix
SUFFIX = ".toml"


def shipped_files() -> dict[str, Traversable]:
    """The shipped scenario files by name (the file name without ``SUFFIX``).

    Returns
    -------
    dict of str to Traversable
        Name -> the file inside the package.
    """
    folder = resources.files("tetherheli").joinpath("scenarios")
    return {
        f.name.removesuffix(SUFFIX): f
        for f in folder.iterdir()
        if f.is_file() and f.name.endswith(SUFFIX)
    }


def shipped_name(path: str | Path) -> str | None:
    """The shipped scenario that ``path`` names, or None: a bare name (``paper_sim1_tethered``
    or ``paper_sim1_tethered.toml``, no folder) of a shipped scenario, where no such file
    exists in the working folder (a file the user has always wins).

    Parameters
    ----------
    path : str or Path
        What the user gave for a scenario file.

    Returns
    -------
    str or None
        The shipped scenario's name, or None for a path to read as a file.
    """
    given = Path(path)
    if given.parent != Path(".") or given.exists():
        return None
    name = given.name.removesuffix(SUFFIX)
    return name if name in shipped_files() else None
