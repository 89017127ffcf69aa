"""The Monte Carlo's statistics (``studies.montecarlo.statistics``) against independent
routes: numpy's percentile on finite samples, the known quantiles of a distribution, a
bootstrap written out by hand on a tiny sample, and the definition of the paired reduction."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from tetherheli.studies.montecarlo.statistics import (
    bootstrap_interval,
    paired_reduction,
    tail_percentile,
    with_failures,
)

PCTS = [1, 5, 25, 50, 75, 95, 99]


def test_tail_percentile_is_numpys_on_finite_samples():
    x = np.random.default_rng(0).gamma(2.0, size=(3, 37))
    assert np.array_equal(tail_percentile(x, PCTS), np.percentile(x, PCTS, axis=-1))
    assert tail_percentile(x[0], 50) == np.percentile(x[0], 50)


def test_tail_percentile_of_a_large_sample_is_the_distributions_quantile():
    x = np.random.default_rng(1).standard_normal(400_000)
    got = tail_percentile(x, [5, 50, 95])
    assert got == pytest.approx(stats.norm.ppf([0.05, 0.5, 0.95]), abs=0.01)


def test_failed_runs_fill_the_failing_tail():
    # 10 values 1..10 and 3 failures (+inf): 13 order statistics, h = 12 p / 100
    x = with_failures(
        np.r_[np.arange(1.0, 11.0), np.nan, np.nan, np.nan], np.arange(13) < 10, math.inf
    )
    got = tail_percentile(x, [0, 50, 75, 76, 100])
    # p50: h = 6 -> 7.0; p75: h = 9 -> 10.0 exactly; p76: h = 9.12 -> between 10 and +inf
    assert got.tolist() == [1.0, 7.0, 10.0, math.inf, math.inf]
    # the other side (larger is better): -inf at the bottom
    low = with_failures(
        np.r_[np.nan, 1.0, 2.0, 3.0], np.array([False, True, True, True]), -math.inf
    )
    assert tail_percentile(low, [0, 20, 50, 100]).tolist() == [-math.inf, -math.inf, 1.5, 3.0]
    with pytest.raises(ValueError, match="NaN"):
        tail_percentile(np.array([1.0, np.nan]), 50)


def test_paired_reduction_follows_its_definition():
    free = np.array([2.0, 4.0, 1.0, np.nan, np.nan, 0.0, 0.0, 1.0])
    teth = np.array([1.0, 5.0, np.nan, 3.0, np.nan, 0.0, 1.0, 0.0])
    f_ok = np.array([True, True, True, False, False, True, True, True])
    t_ok = np.array([True, True, False, True, False, True, True, True])
    r = paired_reduction(free, teth, f_ok, t_ok)
    # a failed free run is no reference (NaN), never a 100 % reduction (issue 22, class 4)
    np.testing.assert_array_equal(
        r, [50.0, -25.0, -math.inf, np.nan, np.nan, 0.0, -math.inf, 100.0]
    )


def _hand_bootstrap(x: np.ndarray, q: float, seed: int, n: int, level: float):
    """The percentile bootstrap written out: resample the draws with scipy's generator
    calls (integers(0, n, (B, n)) on default_rng(seed)), take each resample's percentile, and
    the (1 -+ level) / 2 percentiles of those."""
    rng = np.random.default_rng(seed)
    idx = rng.integers(0, x.size, (n, x.size))
    theta = np.percentile(x[idx], q, axis=-1)
    a = (1 - level) / 2
    return np.percentile(theta, [100 * a, 100 * (1 - a)])


def test_bootstrap_interval_equals_a_hand_computed_bootstrap():
    x = np.array([0.3, 1.1, 0.7, 2.4, 1.9, 0.2, 1.4])
    for q in (25, 50, 90):
        lo, hi = bootstrap_interval(x, [q], seed=11, n_resamples=400)
        ref = _hand_bootstrap(x, q, 11, 400, 0.95)
        assert [lo[0], hi[0]] == pytest.approx(ref, rel=1e-12)


def test_bootstrap_interval_is_reproducible_and_covers_the_truth():
    x = np.random.default_rng(5).exponential(size=300)
    a = bootstrap_interval(x, [50, 90], seed=3)
    b = bootstrap_interval(x, [50, 90], seed=3)
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])
    truth = stats.expon.ppf([0.5, 0.9])
    assert np.all(a[0] < truth) and np.all(truth < a[1])
    assert np.all(a[0] <= np.percentile(x, [50, 90])) and np.all(np.percentile(x, [50, 90]) <= a[1])


def test_bootstrap_bound_among_the_failures_is_infinite():
    x = np.r_[np.linspace(1.0, 2.0, 40), np.full(10, np.inf)]  # 20% failed
    lo, hi = bootstrap_interval(x, [50, 90], seed=2, n_resamples=500)
    assert np.isfinite(lo[0]) and np.isfinite(hi[0]) and 1.0 <= lo[0] <= hi[0] <= 2.0
    assert hi[1] == math.inf  # p90 lies among the failures
    # a degenerate sample: the interval is the value
    one = bootstrap_interval(np.array([3.0]), [50], seed=0)
    assert one[0].tolist() == one[1].tolist() == [3.0]
