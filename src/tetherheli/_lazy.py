"""Names of a package loaded on first use (PEP 562), shared by the packages that defer their
imports (``tetherheli``, its rooms, ``tetherheli.studies``)."""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Mapping
from typing import Any


def lazy_getattr(package: str, homes: Mapping[str, str]) -> Callable[[str], Any]:
    """A module ``__getattr__`` for ``package`` that imports ``homes[name]`` (relative to the
    package) on first use of ``name`` and binds the name in the package, so later uses are
    plain attribute look-ups.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    homes : mapping of str to str
        Public name -> the module (relative import path) that defines it.

    Returns
    -------
    callable
        The ``__getattr__(name)`` to assign in the package.
    """

    def __getattr__(name: str) -> Any:
        module = homes.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module, package), name)
        setattr(sys.modules[package], name, value)
        return value

    return __getattr__
