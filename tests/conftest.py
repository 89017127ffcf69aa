"""Shared fixtures: the paper's parameters and models; the compile cache warmed once."""

from __future__ import annotations

import os

import numpy as np
import pytest

from tetherheli import FreeHelicopter, Params, TetheredHelicopter


def pytest_configure(config: pytest.Config) -> None:
    """On the pytest-xdist controller (``-n N``), fill the Numba cache before the workers
    start (``tests/warm_cache.py``): the workers then load the engine instead of each
    compiling it at once. Nothing happens without xdist, in a worker, or with
    ``TETHERHELI_NO_WARM=1``; with a warm cache it costs the cache's loading only."""
    workers = getattr(config.option, "numprocesses", None)
    if hasattr(config, "workerinput") or not workers or os.environ.get("TETHERHELI_NO_WARM"):
        return
    from tests.warm_cache import warm

    warm()


@pytest.fixture(scope="session")
def paper() -> Params:
    return Params.paper()


@pytest.fixture(scope="session")
def tethered(paper: Params) -> TetheredHelicopter:
    return TetheredHelicopter(paper)


@pytest.fixture(scope="session")
def free(paper: Params) -> FreeHelicopter:
    return FreeHelicopter(paper)


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20261122)
