"""``analysis.pareto_front`` against an independent route (a sort-and-sweep) and hand cases."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tetherheli.analysis import pareto_front


def _front_by_sweep(cost: np.ndarray, benefit: np.ndarray) -> np.ndarray:
    """The textbook route: sort by cost (ties: best benefit first); a point is on the front
    when its benefit beats every cheaper point's, or equals the best at its own cost."""
    out = np.zeros(cost.size, dtype=bool)
    best = -math.inf
    for cost_value in np.unique(cost):
        at = np.flatnonzero(cost == cost_value)
        top = benefit[at].max()
        if top > best:
            out[at[benefit[at] == top]] = True
            best = top
    return out


def test_pareto_front_hand_case():
    # (cost, benefit): (1, 50) and (2, 70) trade; (2, 60) is beaten by (2, 70) and (3, 60) by
    # both; (0.5, 10) is the cheapest; the NaN point is never on the front
    cost = np.array([1.0, 2.0, 2.0, 3.0, 0.5, np.nan])
    benefit = np.array([50.0, 70.0, 60.0, 60.0, 10.0, 99.0])
    assert pareto_front(cost, benefit).tolist() == [True, True, False, False, True, False]


def test_pareto_front_equals_the_sort_and_sweep_on_random_points_with_ties():
    rng = np.random.default_rng(14)
    for _ in range(50):
        cost = rng.integers(0, 6, 40).astype(float)  # many ties on both axes
        benefit = rng.integers(0, 6, 40).astype(float)
        assert np.array_equal(pareto_front(cost, benefit), _front_by_sweep(cost, benefit))


def test_pareto_front_refuses_mismatched_shapes():
    with pytest.raises(ValueError, match="equal shapes"):
        pareto_front(np.zeros(3), np.zeros(4))
