"""A position estimator a practitioner would fly: a linear Kalman filter per axis of N that
fuses the IMU's acceleration with position fixes from a GNSS receiver, the tether
(Sec. IV-F: encoders + altimeter + attitude) or both, each at its own rate and latency.

The filter runs after a closed-loop run, on what the run's sensors recorded
(``studies.estimation.estimate_run``): the controller itself flies on its
``position_source`` as before, so the estimate is evaluated, not flown. It is linear and per
axis because, in hover, the IMU's acceleration in N drives position and velocity linearly
and the axes decouple.

Model (per axis i of N, sample time dt)
---------------------------------------
State s = [p, v, b] (position of HO [m], velocity [m/s], accelerometer bias [m/s^2]), plus
e, the GNSS receiver's Gauss-Markov position error [m], when the GNSS is fused and has one.
Input: the accelerometer, a_m = a + b + w, held over the sample (w white, std
sigma_a = accel_density / sqrt(dt)). Exact discretisation of the simulated processes:

    p+ = p + dt v + dt^2/2 (a_m - b),  v+ = v + dt (a_m - b),  b+ = b + w_b,  e+ = phi e + w_e

with Var w_b = accel_random_walk^2 dt, phi = exp(-dt / tau), Var w_e = sigma^2 (1 - phi^2)
(``sensing.noise.random_walk``, ``sensing.noise.gauss_markov``), and Q = sigma_a^2 B B' + diag(0, 0,
Var w_b, Var w_e), B = [dt^2/2, dt, 0, 0]. Fixes: GNSS z = p + e + white (R = gps_std^2);
tether z = p + white (R from ``sensing.sensors.hover_error_std``): n1, n2 at the encoders' samples,
n3 at the altimeter's own (plus its Gauss-Markov variance, which the filter treats as white).

Latency: a fix taken at sample j reaches the filter at j + L. The filter then goes back to
sample j, applies the fix there, and re-runs the prediction (and the fixes of other sensors
already received) up to the present sample: the estimate at k uses exactly the data that has
arrived by k, as a filter with a state history does on board.

The IMU's acceleration here is HO's acceleration in N (the recorded velocity's change over
each sample, as a delta-velocity IMU output, rotated with the true attitude) plus the
accelerometer's errors (``sensing.noise.accelerometer_errors``); the error the attitude estimate
adds by projecting gravity is not modelled (it acts as a slowly varying bias, which the bias
state absorbs while fixes arrive).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..errors import ParameterError
from .config import SensorConfig

__all__ = [
    "FUSIONS",
    "ConsistencyTest",
    "EstimateResult",
    "Fixes",
    "KalmanConsistency",
    "PositionFilter",
    "chi2_mean_band",
    "normalized_squares",
    "position_filter",
    "run_filter",
]

#: the position sources a filter can fuse with the IMU
FUSIONS = ("gnss", "tether", "both")


class Fixes(NamedTuple):
    """One position sensor's fixes for ``run_filter``.

    Attributes
    ----------
    times : ndarray, shape (m,), int
        The sample j each fix was taken at (increasing).
    values : ndarray, shape (m, 3)
        The fix [m] along n1, n2, n3.
    latency : int
        Samples from taking a fix to its arrival (j + latency).
    H : ndarray, shape (ns,)
        The fix's row of the measurement matrix (the same on every axis).
    R : ndarray, shape (3,)
        The fix's white-noise variance per axis [m^2]; inf on an axis it does not fix.
    """

    times: np.ndarray
    values: np.ndarray
    latency: int
    H: np.ndarray
    R: np.ndarray


@dataclass(frozen=True)
class PositionFilter:
    """The per-axis model of the module docstring: F (ns, ns), B (ns,), Q (3, ns, ns) per
    axis, the initial state covariance P0 (3, ns, ns), and ``gm`` (the GNSS Gauss-Markov
    error is the state's 4th entry).

    Parameters
    ----------
    dt : float
        Sample time [s].
    F : ndarray, shape (ns, ns)
        State transition over one sample of [position, velocity, accelerometer bias(, GNSS
        Gauss-Markov error)] (ns = 3 or 4).
    B : ndarray, shape (ns,)
        Input column of the measured acceleration [m/s^2].
    Q : ndarray, shape (3, ns, ns)
        Process noise covariance per axis [m^2, m^2/s^2, m^2/s^4].
    P0 : ndarray, shape (3, ns, ns)
        Initial state covariance per axis.
    gm : bool
        Whether the state carries the GNSS Gauss-Markov error (ns = 4).
    """

    dt: float
    F: np.ndarray
    B: np.ndarray
    Q: np.ndarray
    P0: np.ndarray
    gm: bool

    @property
    def n_states(self) -> int:
        return self.F.shape[0]


def position_filter(config: SensorConfig, dt: float, *, gnss: bool) -> PositionFilter:
    """The filter model of ``config``'s IMU (and GNSS Gauss-Markov error, when ``gnss``).

    P0: 1 m (position, or the GNSS Gauss-Markov sigma when larger), 0.1 m/s, the bias's
    random walk over 100 s plus the constant ``accel_bias`` (at least 1e-3 m/s^2), and the
    Gauss-Markov variance: the filter starts at the trim's hover point, at rest.

    Parameters
    ----------
    config : SensorConfig
        The sensors' noise figures (accelerometer density, random walk and bias; GNSS
        Gauss-Markov sigma [m] and time constant [s]).
    dt : float
        Sample time [s].
    gnss : bool
        Whether GNSS fixes are fused (adds the Gauss-Markov state when its sigma > 0).

    Returns
    -------
    PositionFilter
        The per-axis model.
    """
    dt = float(dt)
    sig_gm = np.asarray(config.gps_markov_sigma, dtype=float)
    gm = bool(gnss and np.any(sig_gm > 0.0))
    ns = 4 if gm else 3
    F = np.eye(ns)
    F[0, 1], F[0, 2], F[1, 2] = dt, -0.5 * dt * dt, -dt
    B = np.zeros(ns)
    B[0], B[1] = 0.5 * dt * dt, dt
    sigma_a2 = config.accel_density**2 / dt
    Q = np.repeat((sigma_a2 * np.outer(B, B))[None], 3, axis=0)
    Q[:, 2, 2] += config.accel_random_walk**2 * dt
    bias0 = np.maximum(
        np.abs(config.accel_bias), max(1e-3, config.accel_random_walk * math.sqrt(100.0))
    )
    P0 = np.zeros((3, ns, ns))
    P0[:, 0, 0] = 1.0
    P0[:, 1, 1] = 0.01
    P0[:, 2, 2] = bias0**2
    if gm:
        phi = math.exp(-dt / config.gps_markov_tau)
        F[3, 3] = phi
        Q[:, 3, 3] = sig_gm**2 * (1.0 - phi * phi)
        P0[:, 0, 0] = np.maximum(1.0, sig_gm**2)
        P0[:, 3, 3] = sig_gm**2
    return PositionFilter(dt, F, B, Q, P0, gm)


def run_filter(
    model: PositionFilter,
    accel: np.ndarray,
    fixes: Sequence[Fixes],
    p0: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Run the filter over n samples with the accelerometer ``accel`` (n, 3) [m/s^2] (sample
    k's reading drives the prediction from k to k + 1) and the fixes, each arriving
    ``latency`` samples after it was taken (module docstring); the state starts at
    [p0, 0, 0(, 0)] with covariance P0. (Any number m of independent axes runs alike: Q and
    P0 (m, ns, ns), accel and fix values (., m), R (m,); the results are then (n, m).)

    Parameters
    ----------
    model : PositionFilter
        The filter model (``position_filter``).
    accel : ndarray, shape (n, 3)
        The accelerometer's reading at every sample [m/s^2].
    fixes : sequence of Fixes
        The position sensors' fixes, each with its latency.
    p0 : ndarray, shape (3,)
        The initial position estimate [m].

    Returns
    -------
    position : ndarray, shape (n, 3)
        The estimate of HO at every sample from the data arrived by then [m].
    velocity : ndarray, shape (n, 3)
        The velocity estimate [m/s].
    position_std : ndarray, shape (n, 3)
        The filter's own 1-sigma of the position estimate [m].
    """
    n, ns, axes = accel.shape[0], model.n_states, model.Q.shape[0]
    F, B, Q = model.F, model.B, model.Q
    FT = F.T
    prior_x = np.empty((n, axes, ns))
    prior_P = np.empty((n, axes, ns, ns))
    post_x = np.empty((n, axes, ns))
    post_P = np.empty((n, axes, ns, ns))
    out_x = np.empty((n, axes, 2))
    out_var = np.empty((n, axes))
    # per sample: the fixes taken there (index into fixes, row), and arrivals per sample
    taken: dict[int, list[tuple[int, int]]] = {}
    arriving: dict[int, int] = {}  # arrival sample -> earliest fix time arriving then
    for f, fx in enumerate(fixes):
        for r, j in enumerate(np.asarray(fx.times, dtype=int).tolist()):
            if j + fx.latency >= n:
                continue
            taken.setdefault(j, []).append((f, r))
            a = j + fx.latency
            arriving[a] = min(arriving.get(a, a), j)

    def correct(m: int, now: int, x: np.ndarray, P: np.ndarray) -> None:
        for f, r in taken.get(m, ()):
            fx = fixes[f]
            if m + fx.latency > now:
                continue  # not arrived yet
            H = fx.H
            PH = P @ H  # (3, ns)
            S = PH @ H + fx.R  # (3,)
            K = PH / S[:, None]
            x += K * (fx.values[r] - x @ H)[:, None]
            IKH = np.eye(ns)[None] - K[:, :, None] * H[None, None, :]
            R_used = np.where(np.isfinite(fx.R), fx.R, 0.0)  # K = 0 where R = inf
            P[:] = (
                IKH @ P @ IKH.transpose(0, 2, 1)
                + K[:, :, None] * K[:, None, :] * R_used[:, None, None]
            )

    x0 = np.zeros((axes, ns))
    x0[:, 0] = p0
    for k in range(n):
        start = min(k, arriving.get(k, k))
        for m in range(start, k + 1):
            if m == 0:
                x, P = x0.copy(), model.P0.copy()
            elif m == start and start < k:  # a late fix: back to its sample's prior
                x, P = prior_x[m].copy(), prior_P[m].copy()
            else:
                x = post_x[m - 1] @ FT + (accel[m - 1][:, None] * B[None, :])
                P = F @ post_P[m - 1] @ FT + Q
            prior_x[m], prior_P[m] = x, P
            correct(m, k, x, P)
            post_x[m], post_P[m] = x, P
        # the estimate at k is the one made at k (a later fix rewrites the history only)
        out_x[k], out_var[k] = post_x[k, :, :2], post_P[k, :, 0, 0]
    return out_x[:, :, 0], out_x[:, :, 1], np.sqrt(out_var)


@dataclass(frozen=True)
class EstimateResult:
    """A filter's estimate over a recorded run (``studies.estimation.estimate_run``): time
    (n,) [s], the estimate, its predicted 1-sigma and the truth, (n, 3) each [m] (HO along
    n1, n2, n3).

    Parameters
    ----------
    fusion : str
        The position sources fused with the IMU, one of ``FUSIONS``.
    time : ndarray, shape (n,)
        Sample times [s].
    position : ndarray, shape (n, 3)
        The estimate of HO [m].
    position_std : ndarray, shape (n, 3)
        Its predicted 1-sigma [m].
    truth : ndarray, shape (n, 3)
        The true position of HO [m].
    """

    fusion: str
    time: np.ndarray
    position: np.ndarray
    position_std: np.ndarray
    truth: np.ndarray

    @property
    def error(self) -> np.ndarray:
        """Estimate minus truth, (n, 3) [m]."""
        return self.position - self.truth

    def error_rms(self, window: Sequence[float] | None = None) -> dict[str, float] | None:
        """RMS of the estimate error per axis {"q1", "q2", "q3"} [m], over the run or over
        the samples with t in [t_start, t_end) of ``window`` (None without samples).

        Parameters
        ----------
        window : sequence of 2 floats, optional
            (t_start, t_end) [s]; default the whole run.

        Returns
        -------
        dict of str to float or None
            {"q1", "q2", "q3"} -> RMS error [m]; None when the window holds no sample.
        """
        err = self.error
        if window:
            err = err[(self.time >= window[0]) & (self.time < window[1])]
        if not err.shape[0]:
            return None
        rms = np.sqrt(np.mean(err**2, axis=0))
        return {f"q{i + 1}": float(v) for i, v in enumerate(rms)}


# --- the consistency of the MPC's Kalman filter (NEES, NIS) ----------------------------------


def normalized_squares(errors: np.ndarray, covariance: np.ndarray) -> np.ndarray:
    """e_k' P^-1 e_k per row of ``errors`` (n, d): the NEES of estimation errors with the
    filter's covariance P (or the NIS of innovations with theirs). A consistent filter has
    them chi-square with d degrees of freedom, mean d.

    Parameters
    ----------
    errors : ndarray, shape (n, d)
        Estimate minus truth (or innovations) per sample.
    covariance : ndarray, shape (d, d) or (n, d, d)
        The filter's covariance of them, one for all samples or one per sample.

    Returns
    -------
    ndarray, shape (n,)
        The normalized squares (NaN where a row is not finite).
    """
    e = np.atleast_2d(np.asarray(errors, dtype=float))
    P = np.asarray(covariance, dtype=float)
    if P.ndim == 2:
        sol = np.linalg.solve(P, np.where(np.isfinite(e), e, 0.0).T).T
    else:
        sol = np.linalg.solve(P, np.where(np.isfinite(e), e, 0.0)[:, :, None])[:, :, 0]
    out = np.einsum("ij,ij->i", e, sol)
    out[~np.all(np.isfinite(e), axis=1)] = np.nan
    return out


def chi2_mean_band(dim: int, samples: int, confidence: float = 0.95) -> tuple[float, float]:
    """The two-sided ``confidence`` band of the mean of ``samples`` independent chi-square
    variables with ``dim`` degrees of freedom: samples * mean ~ chi2(samples * dim), so the
    band is chi2.ppf((1 -+ confidence) / 2, samples dim) / samples (Bar-Shalom, Li and
    Kirubarajan, Estimation with Applications to Tracking and Navigation, Sec. 5.4.2).

    Parameters
    ----------
    dim : int
        Degrees of freedom of one sample (the state's or the measurement's dimension).
    samples : int
        Independent samples averaged, >= 1.
    confidence : float, optional
        Probability of the band, in (0, 1).

    Returns
    -------
    tuple of 2 floats
        (lower, upper) of the mean.
    """
    from scipy.stats import chi2

    if samples < 1:
        raise ParameterError("samples", samples, "an integer >= 1")
    if not 0.0 < confidence < 1.0:
        raise ParameterError("confidence", confidence, "a probability in (0, 1)")
    dof = dim * samples
    tail = 0.5 * (1.0 - confidence)
    return float(chi2.ppf(tail, dof) / samples), float(chi2.ppf(1.0 - tail, dof) / samples)


@dataclass(frozen=True)
class ConsistencyTest:
    """The time-averaged chi-square test of one normalized square (NEES or NIS) over a run.

    Parameters
    ----------
    values : ndarray, shape (n,)
        Per sample (NaN where not defined: the first sample's NIS, after a release).
    dim : int
        Degrees of freedom of one sample.
    stride : int
        Samples between the ones taken as independent (the filter's error correlation time
        in samples, ``KalmanConsistency``).
    confidence : float
        Probability of the band.
    """

    values: np.ndarray
    dim: int
    stride: int
    confidence: float = 0.95

    @property
    def mean(self) -> float:
        """The mean over every defined sample."""
        v = self.values[np.isfinite(self.values)]
        return float(np.mean(v)) if v.size else math.nan

    @property
    def samples(self) -> int:
        """The independent samples the band counts: the defined ones / ``stride``."""
        return max(1, int(np.count_nonzero(np.isfinite(self.values))) // self.stride)

    @property
    def band(self) -> tuple[float, float]:
        """The ``confidence`` band of the mean (``chi2_mean_band`` with ``samples``)."""
        return chi2_mean_band(self.dim, self.samples, self.confidence)

    @property
    def band_independent(self) -> tuple[float, float]:
        """The band if every sample were independent (narrower; correlated errors break it)."""
        n = max(1, int(np.count_nonzero(np.isfinite(self.values))))
        return chi2_mean_band(self.dim, n, self.confidence)

    @property
    def consistent(self) -> bool:
        """Whether the mean lies in ``band``."""
        lo, hi = self.band
        return bool(lo <= self.mean <= hi)

    def summary(self) -> str:
        """One line: the mean, its dimension and band, and the verdict.

        Returns
        -------
        str
        """
        lo, hi = self.band
        verdict = "consistent" if self.consistent else "NOT consistent"
        return (
            f"mean {self.mean:.2f} (dimension {self.dim}; 95 % band [{lo:.2f}, {hi:.2f}] over "
            f"{self.samples} independent samples, 1 per {self.stride}): {verdict}"
        )


@dataclass(frozen=True)
class KalmanConsistency:
    """NEES and NIS of the MPC's Kalman filter over a run
    (``studies.estimation.kalman_consistency``).

    Parameters
    ----------
    time : ndarray, shape (n,)
        Sample times [s].
    nees : ConsistencyTest
        The estimation error of [x; d] (the plant's n states and the wind force on HO) with
        the filter's posterior covariance; dimension n + 3 (16 tethered, 15 free).
    nis : ConsistencyTest
        The innovations with their covariance S = C P C' + R; dimension p.
    force_nees : ConsistencyTest
        The wind force's part alone (dimension 3).
    """

    time: np.ndarray
    nees: ConsistencyTest
    nis: ConsistencyTest
    force_nees: ConsistencyTest
