"""The package's Numba compilation, with an on-disk cache that cannot go stale.

Numba keys a cached function on its own source file only, so a compiled function that
inlines or calls compiled code from another file (the engine inlines the controller, the
sensors and the generated model) would keep stale machine code after that other file
changes. Here every compiled function of the package is cached in one folder named after a
fingerprint of *all* the package's source files (and the Numba and Python versions): an edit
anywhere selects a fresh folder on the next import, so the edit takes effect with no manual
step. The folder is ``$NUMBA_CACHE_DIR`` (else ``$XDG_CACHE_HOME``, else ``~/.cache``)
``/tetherheli-numba/<fingerprint>``; folders of other fingerprints unused for
``STALE_AFTER_DAYS`` are removed. Where no cache folder can be written, functions compile
in memory (never from a stale cache).

Importing this module raises two of LLVM's loop-vectoriser thresholds for the process
(``VECTORIZER_OPTIONS``): a loop over the lanes of a block of runs reads and writes a few dozen
rows of separate arrays, and LLVM vectorises it only after checking at run time that none of
them overlap; its default budget of 8 such checks leaves the lane loops scalar. The options
only let more loops vectorise; they never change the arithmetic of a lane (the lane engine's
test compares lanes bit for bit with single runs).
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import shutil
import sys
import time
from collections.abc import Callable, Iterator
from functools import lru_cache
from pathlib import Path
from typing import Any

import llvmlite.binding as llvm
import numba
from numba import njit

__all__ = ["PACKAGE_ROOT", "cache_directory", "compiled", "source_fingerprint"]

PACKAGE_ROOT = Path(__file__).resolve().parent
STALE_AFTER_DAYS = 14
_CACHE_PARENT = "tetherheli-numba"

#: LLVM options set at import: the number of run-time alias checks the loop vectoriser may
#: emit (defaults 8 and 128); see the module docstring
VECTORIZER_OPTIONS = (
    "-runtime-memory-check-threshold=1024",
    "-vectorize-memory-check-threshold=1024",
)
for _option in VECTORIZER_OPTIONS:
    llvm.set_option("", _option)


def source_fingerprint(root: Path = PACKAGE_ROOT) -> str:
    """sha256 (16 hex digits) of every ``*.py`` below ``root`` (paths and contents), with
    the Numba and Python versions, the LLVM options and a ``TETHERHELI_LANES`` override."""
    lanes = os.environ.get("TETHERHELI_LANES", "")  # ``layout.LANES``: a compiled constant
    digest = hashlib.sha256(
        f"{numba.__version__} {sys.version} {VECTORIZER_OPTIONS} {lanes}".encode()
    )
    for path in sorted(root.rglob("*.py")):
        digest.update(path.relative_to(root).as_posix().encode() + b"\0")
        digest.update(path.read_bytes() + b"\0")
    return digest.hexdigest()[:16]


def _cache_base() -> Path:
    for variable in ("NUMBA_CACHE_DIR", "XDG_CACHE_HOME"):
        if os.environ.get(variable):
            return Path(os.environ[variable]) / _CACHE_PARENT
    return Path.home() / ".cache" / _CACHE_PARENT


@lru_cache(maxsize=1)
def cache_directory() -> Path | None:
    """This source tree's cache folder (created), or None where none can be written."""
    base = _cache_base()
    folder = base / source_fingerprint()
    try:
        folder.mkdir(parents=True, exist_ok=True)
        os.utime(folder)  # marks it as in use for the pruning below
    except OSError:
        return None
    _prune(base, keep=folder)
    return folder


def _prune(base: Path, keep: Path) -> None:
    """Remove the cache folders of other source trees unused for ``STALE_AFTER_DAYS``."""
    cutoff = time.time() - STALE_AFTER_DAYS * 86400
    with contextlib.suppress(OSError):
        for folder in base.iterdir():
            if folder != keep and folder.is_dir() and folder.stat().st_mtime < cutoff:
                shutil.rmtree(folder, ignore_errors=True)


@contextlib.contextmanager
def _numba_cache_in(folder: Path) -> Iterator[None]:
    """Numba's cache folder while a function is decorated (its locator is chosen then)."""
    previous = numba.config.CACHE_DIR
    numba.config.CACHE_DIR = str(folder)
    try:
        yield
    finally:
        numba.config.CACHE_DIR = previous


def compiled(**options: Any) -> Callable[[Callable], Any]:
    """``numba.njit(**options)`` with the package's cache (see the module docstring), e.g.
    ``compiled(error_model="numpy", inline="always")``."""

    def decorate(function: Callable) -> Any:
        folder = cache_directory()
        if folder is None:
            return njit(cache=False, **options)(function)
        with _numba_cache_in(folder):
            return njit(cache=True, **options)(function)

    return decorate
