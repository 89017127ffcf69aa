"""Shared fixtures: the paper's parameters and models."""

from __future__ import annotations

import numpy as np
import pytest

from tetherheli import FreeHelicopter, Params, TetheredHelicopter


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
