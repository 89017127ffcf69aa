"""The Monte Carlo's statistics: percentiles in which failed runs stay in the tail of the
failing side, the paired per-draw reduction of a metric by the tether, and bootstrap
confidence intervals on the reported percentiles.

Definitions:

- a failed run (diverged, hit the ground, could not be set up) has no metric; it is counted
  as the worst value, +inf for a metric where smaller is better (peak and RMS deviations,
  ``tension_max``) and -inf for ``tension_min``, so that a percentile lying among the
  failures is reported as infinite (null in JSON) instead of the failures being dropped;
- percentile p of n values is the linear interpolation between order statistics of
  ``numpy.percentile`` (its default "linear" method, Hyndman and Fan's definition 7); a
  percentile whose interpolation touches an infinite value is that value;
- the paired reduction of draw i is 100 (free_i - tethered_i) / free_i [%] (positive: the
  tether reduced the metric). A failed free run is no reference: its draw has no reduction
  (NaN; the percentiles of the reduction cover the draws whose free run completed, and the
  draws without a reference are counted beside them); a failed tethered run with a completed
  free one gives -inf (the worst side); free_i = 0 gives 0 when tethered_i = 0, else -inf;
- the confidence interval of a percentile is ``scipy.stats.bootstrap``'s percentile method
  over the draws (``n_resamples`` resamples, seeded by the Monte Carlo's seed so the numbers
  are reproducible). A bound beyond every finite value of the sample is infinite.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

__all__ = [
    "BOOTSTRAP_RESAMPLES",
    "CONFIDENCE",
    "bootstrap_interval",
    "paired_reduction",
    "tail_percentile",
    "with_failures",
]

#: resamples of every bootstrap interval
BOOTSTRAP_RESAMPLES = 999
#: confidence level of the bootstrap intervals
CONFIDENCE = 0.95
#: at most this many resampled values are held at once (the bootstrap's ``batch``)
_BATCH_VALUES = 20_000_000


def with_failures(values: np.ndarray, ok: np.ndarray, worst: float) -> np.ndarray:
    """``values`` with the failed entries (``ok`` False) replaced by ``worst`` (+inf or -inf).

    Parameters
    ----------
    values : (n,) array
        A metric of every run (NaN for a failed one).
    ok : (n,) bool array
        Whether each run completed.
    worst : float
        +inf when smaller is better, -inf when larger is better.

    Returns
    -------
    (n,) float array
    """
    return np.where(np.asarray(ok, dtype=bool), np.asarray(values, dtype=float), worst)


def tail_percentile(values: np.ndarray, q: Sequence[float] | float, axis: int = -1) -> np.ndarray:
    """Percentiles ``q`` [%] of ``values`` along ``axis`` by ``numpy.percentile``'s linear
    method, with infinite values allowed: a percentile whose interpolation needs an infinite
    order statistic is that infinity (numpy would give NaN, inf - inf or inf * 0).

    Parameters
    ----------
    values : array
        Finite or +-inf (no NaN).
    q : float or sequence of float
        Percentiles in [0, 100].
    axis : int
        Axis of the sample.

    Returns
    -------
    array
        Shape ``q``'s shape followed by ``values``' shape without ``axis``.
    """
    a = np.sort(np.moveaxis(np.asarray(values, dtype=float), axis, -1), axis=-1)
    if np.isnan(a).any():
        raise ValueError("tail_percentile: NaN in values (mark failures with +-inf)")
    n = a.shape[-1]
    qs = np.atleast_1d(np.asarray(q, dtype=float))
    h = (qs / 100.0) * (n - 1)  # numpy's virtual index, in its order of operations
    lo = np.floor(h).astype(int)
    hi = np.minimum(lo + 1, n - 1)
    frac = h - lo
    out = []
    for k in range(qs.size):
        a_lo, a_hi = a[..., lo[k]], a[..., hi[k]]
        with np.errstate(invalid="ignore"):  # numpy's _lerp, bit for bit
            diff = a_hi - a_lo
            t = frac[k]
            lin = a_hi - diff * (1.0 - t) if t >= 0.5 else a_lo + diff * t
        if frac[k] == 0.0:
            lin = a_lo
        else:
            lin = np.where(np.isinf(a_lo), a_lo, np.where(np.isinf(a_hi), a_hi, lin))
        out.append(lin)
    result = np.stack(out)
    return result if np.ndim(q) else result[0]


def paired_reduction(
    free: np.ndarray, tethered: np.ndarray, free_ok: np.ndarray, tethered_ok: np.ndarray
) -> np.ndarray:
    """The tether's reduction of a metric per draw, 100 (free - tethered) / free [%], with the
    failed runs placed as the module docstring says: no reduction (NaN) without a completed
    free reference, -inf for a failed tethered run against a completed one.

    Parameters
    ----------
    free, tethered : (n,) arrays
        The metric of each draw's free and tethered run (any value where failed).
    free_ok, tethered_ok : (n,) bool arrays
        Whether each run completed.

    Returns
    -------
    (n,) float array
        Finite or -inf where the free run completed; NaN where it failed.
    """
    f = np.asarray(free, dtype=float)
    t = np.asarray(tethered, dtype=float)
    fo = np.asarray(free_ok, dtype=bool)
    to = np.asarray(tethered_ok, dtype=bool)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = 100.0 * (f - t) / f
    r = np.where(fo & to & (f == 0.0), np.where(t == 0.0, 0.0, -np.inf), r)
    r = np.where(to, r, -np.inf)
    return np.where(fo, r, np.nan)


def bootstrap_interval(
    sample: np.ndarray,
    q: Sequence[float],
    seed: int,
    *,
    n_resamples: int = BOOTSTRAP_RESAMPLES,
    confidence: float = CONFIDENCE,
) -> tuple[np.ndarray, np.ndarray]:
    """Bootstrap confidence intervals of the percentiles ``q`` of ``sample`` (values +-inf
    allowed, see ``tail_percentile``): ``scipy.stats.bootstrap`` with the percentile method,
    resampling the draws with ``numpy.random.default_rng(seed)``.

    Parameters
    ----------
    sample : (n,) array
        One value per draw, n >= 2.
    q : sequence of float
        Percentiles [%].
    seed : int
        Seed of the resampling (same seed, same intervals).
    n_resamples : int
        Bootstrap resamples.
    confidence : float
        Confidence level of the two-sided intervals.

    Returns
    -------
    low, high : arrays of shape (len(q),)
        The interval of each percentile; +-inf where a bound lies among the failed runs.
    """
    from scipy.stats import bootstrap

    x = np.asarray(sample, dtype=float)
    finite = x[np.isfinite(x)]
    if x.size < 2 or np.all(x == x[0]):  # nothing to resample: the interval is the value
        v = tail_percentile(x, q)
        return v.copy(), v.copy()
    # scipy interpolates the bootstrap distribution linearly, which infinities break: stand
    # them in by values beyond every finite one, and map a bound beyond those back to +-inf
    top = float(finite.max()) if finite.size else 0.0
    bottom = float(finite.min()) if finite.size else 0.0
    span = max(top - bottom, 1.0)
    big, small = top + 1e3 * span, bottom - 1e3 * span
    stand_in = np.where(x == np.inf, big, np.where(x == -np.inf, small, x))

    def statistic(data: np.ndarray, axis: int = -1) -> np.ndarray:
        return tail_percentile(data, q, axis=axis)

    res = bootstrap(
        (stand_in,),
        statistic,
        n_resamples=n_resamples,
        batch=max(1, _BATCH_VALUES // x.size),
        vectorized=True,
        confidence_level=confidence,
        method="percentile",
        rng=np.random.default_rng(seed),
    )
    low = np.asarray(res.confidence_interval.low, dtype=float)
    high = np.asarray(res.confidence_interval.high, dtype=float)

    def back(v: np.ndarray) -> np.ndarray:
        return np.where(v > top, np.inf, np.where(v < bottom, -np.inf, v))

    return back(low), back(high)
