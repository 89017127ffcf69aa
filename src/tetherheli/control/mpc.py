"""A constrained linear MPC on the tethered model, offset-free, solved by OSQP every sample.

Its design (the plant, x_{k+1} = G x_k + H u_k + H_d d_k with the wind force on HO as an
input disturbance d, augmented by the paper's integrators of eq 50, xi = [x; z]; the
steady-state target of d; the condensed prediction and the cost, whose unconstrained law is
the tethered LQI's) is ``control.mpc_design``'s; this module flies it.

Offset-free. Two routes together: (1) the integral action of eq 50 (a closed loop that
settles has z constant, hence y = r whatever the model error); (2) an estimate of d, a
Luenberger observer of the augmented model that uses the measured state: the one-step
residual of the model gives a least-squares reading of d, d_raw = H_d^+ (x_k - G x_{k-1} -
H u_{k-1}), and d_hat follows it with the time constant ``disturbance_time_constant``
(gain 1 - exp(-dt / tau)). The estimate enters as the steady-state target (x_s, u_s)
(``mpc_design``). With imperfect sensors the one-step residual turns their noise into
hundreds of newtons (0.05 m/s of velocity noise over 10 ms is 5 m/s^2), so
``[control.mpc] observer`` selects instead a steady-state Kalman filter of the same augmented
model on the scenario's sensors (``control.observer``: it estimates x and d together, and the
MPC starts from its estimate); "auto" takes it with imperfect sensors or the lumped tether.

Constraints: rotor inputs within ``[actuators] u_min, u_max`` (with ``--eq40``, eq 40's cyclic
limit), |RC| <= ``reel_rate_limit``, |RC_j - RC_{j-1}| <= ``reel_acceleration_limit`` dt
(the first against the rate applied at the previous sample), and the predicted tension
T_j = T_ref + c_T' x_j, j = 1..N, within ``tension_bounds`` softened by slacks s_j >= 0.

Solving. The condensed Hessian and the constraint matrix do not depend on the sample, so
OSQP is set up once per run and each sample only updates q, l, u (``OSQP.update``) and
warm-starts from the previous plan, shifted. OSQP's adaptive step is updated every 25
iterations (not by time), so a run gives the same numbers every time.

If OSQP fails or reaches its iteration limit the controller flies the previous plan's next
move (or, at the first sample, the LQ law), clipped to the bounds, and counts it
(``MPCController.recorded``: the ``mpc_fallback`` column of the result); more than 1 % of
the samples so flown make the run ``DEGRADED``, more than 10 % ``SOLVER_FAILED``
(``status.solver_status``). After a tether
release it flies the paper's free law (``tether_lqi`` does the same).
"""

from __future__ import annotations

import math
import time

import numpy as np
import osqp
from scipy import sparse

from ..model.kernels import tethered_outputs
from ..names import TETHERED_STATE
from ..status import FALLBACK_COLUMN
from .base import Command, Controller, Measurement
from .mpc_design import (
    MPCDesign,
    design_mpc,
    design_mpc_kalman,
    hover_design,
    mpc_plant,
    mpc_sample_seconds,
)
from .observer import DisturbanceKalman

__all__ = [
    "KALMAN_FORCE_COLUMNS",
    "KALMAN_NIS_COLUMN",
    "KALMAN_STATE_COLUMNS",
    "MPCController",
    "MPCDesign",
    "design_mpc",
    "design_mpc_kalman",
    "hover_design",
    "mpc_plant",
    "mpc_sample_seconds",
]

#: The recorded columns of the Kalman filter's state estimate (``MPCController.recorded``):
#: ``<state>_est`` for q4..q9, u1..u6, LN (the free configuration's 12 stop at u6) and the
#: wind force on HO, with the units and descriptions of their signals (``results.result``)
KALMAN_STATE_COLUMNS: tuple[str, ...] = tuple(f"{name}_est" for name in TETHERED_STATE)
KALMAN_FORCE_COLUMNS: tuple[str, ...] = ("Fw1_est", "Fw2_est", "Fw3_est")
#: The recorded column of the Kalman filter's normalized innovation squared per sample
KALMAN_NIS_COLUMN = "kalman_nis"

#: OSQP's adaptive step size is updated every this many iterations (a fixed count: OSQP's
#: default sets it from the measured set-up time, which makes runs differ)
ADAPTIVE_RHO_INTERVAL = 25


class MPCController(Controller):
    """The MPC of the module docstring as a ``Controller`` (flown by ``simulate``'s Python
    loop); a scenario's is built by ``runs.mpc_setup.mpc_controller``.

    Parameters
    ----------
    design : MPCDesign
        Prediction and cost.
    x_ref : ndarray, shape (13,)
        The windless trim's state (references; LN too when tethered).
    y_ref : ndarray, shape (4,)
        The trim's outputs [q1, q2, q3 in m, q6 in rad].
    u_trim : ndarray, shape (4,)
        The trim's total rotor input [N, N m, N m, N].
    constants : ndarray
        The model constants of ``kernels.tethered_outputs``.
    dt : float
        Sample time [s].
    u_min, u_max : ndarray, shape (4,)
        Rotor-input bounds [N, N m, N m, N] (+-inf: none).
    reel_rate_limit, reel_acceleration_limit : float
        Winch bounds [m/s], [m/s^2] (inf: none).
    tension_ref : float
        Trim tension [N].
    tension_bounds : tuple of 2 floats
        Soft bounds on the predicted tension [N].
    slack_weight : float
        w of the slack penalty w (s + s^2).
    disturbance_time_constant : float
        Of the disturbance estimate [s] (0: none).
    max_iterations : int
        OSQP's iteration limit.
    tolerance : float
        OSQP's absolute and relative tolerance.
    free_gain : ndarray, shape (4, 16)
        The paper's free law flown after a release (``runs.start.paper_gain``).
    free_trim_input : ndarray, shape (4,)
        u0|F [N, N m, N m, N].
    d_init : ndarray, shape (3,), optional
        The disturbance estimate at the start [N] (the wind of the start trim).
    kalman : DisturbanceKalman, optional
        The estimator of state and disturbance from the measurements (``control.observer``);
        None: the measured state as it is and the residual estimate of d
        (``disturbance_time_constant``).
    """

    def __init__(
        self,
        design: MPCDesign,
        *,
        x_ref: np.ndarray,
        y_ref: np.ndarray,
        u_trim: np.ndarray,
        constants: np.ndarray,
        dt: float,
        u_min: np.ndarray,
        u_max: np.ndarray,
        reel_rate_limit: float = math.inf,
        reel_acceleration_limit: float = math.inf,
        tension_ref: float = 0.0,
        tension_bounds: tuple[float, float] = (-math.inf, math.inf),
        slack_weight: float = 100.0,
        disturbance_time_constant: float = 0.0,
        max_iterations: int = 400,
        tolerance: float = 1e-5,
        free_gain: np.ndarray | None = None,
        free_trim_input: np.ndarray | None = None,
        d_init: np.ndarray | None = None,
        kalman: DisturbanceKalman | None = None,
    ) -> None:
        self.design = design
        self.kalman = kalman
        if kalman is not None:
            self._S_inv = np.linalg.inv(kalman.innovation_covariance)
        n, m, N = design.n_states, design.n_inputs, design.horizon
        self.tethered = design.c_aug is not None
        self.x_ref = np.array(x_ref[:n], dtype=float)
        self.y_ref = np.array(y_ref, dtype=float)
        self.c = np.ascontiguousarray(constants, dtype=float)
        self.dt = float(dt)
        # input bounds as deviations from the trim (the reel's trim rate is 0)
        lo = np.full(m, -math.inf)
        hi = np.full(m, math.inf)
        lo[:4] = np.asarray(u_min, dtype=float) - u_trim
        hi[:4] = np.asarray(u_max, dtype=float) - u_trim
        if m == 5:
            lo[4], hi[4] = -reel_rate_limit, reel_rate_limit
        self.u_trim = np.array(u_trim, dtype=float)
        self.du_min, self.du_max = lo, hi
        self.reel_step = reel_acceleration_limit * self.dt if m == 5 else math.inf
        self.tension_ref = float(tension_ref)
        self.tension_bounds = tuple(float(b) for b in tension_bounds)
        self.slack_weight = float(slack_weight)
        tau = float(disturbance_time_constant)
        self.alpha = 0.0 if tau <= 0.0 else 1.0 - math.exp(-self.dt / tau)
        self.Hd_pinv = np.linalg.pinv(design.Hd)
        self.free_gain = None if free_gain is None else np.asarray(free_gain, dtype=float)
        self.u0_free = None if free_trim_input is None else np.asarray(free_trim_input, float)
        estimated = self.alpha > 0.0 or kalman is not None
        self.d_init = np.zeros(3) if d_init is None or not estimated else np.array(d_init)
        self.n, self.m, self.N = n, m, N
        self.soft = self.tethered and any(math.isfinite(b) for b in self.tension_bounds)
        self.reel_rows = m == 5 and math.isfinite(self.reel_step)
        self._build_qp(max_iterations, tolerance)
        self.reset()

    # --- the QP, set up once ----------------------------------------------------------------

    def _build_qp(self, max_iterations: int, tolerance: float) -> None:
        d, m, N = self.design, self.m, self.N
        nu = N * m
        ns = N if self.soft else 0
        self.n_var = nu + ns
        blocks = [sparse.hstack([sparse.eye(nu), sparse.csc_matrix((nu, ns))])]
        if self.reel_rows:  # RC_j - RC_{j-1}, j = 0..N-1 (RC_{-1}: the applied rate, in l, u)
            D = np.zeros((N, nu))
            for j in range(N):
                D[j, j * m + 4] = 1.0
                if j > 0:
                    D[j, (j - 1) * m + 4] = -1.0
            blocks.append(sparse.hstack([sparse.csc_matrix(D), sparse.csc_matrix((N, ns))]))
        if self.soft:
            assert d.c_aug is not None  # soft bounds only when tethered
            na = d.G_aug.shape[0]
            Ct = np.kron(np.eye(N), d.c_aug.reshape(1, na))  # (N, N na)
            self.tension_x = Ct @ d.Sx  # (N, na): the tensions' response to xi_0
            Tu = Ct @ d.Su  # (N, nu)
            eye = np.eye(N)
            blocks.append(sparse.csc_matrix(np.hstack([Tu, -eye])))  # <= upper + s
            blocks.append(sparse.csc_matrix(np.hstack([Tu, eye])))  # >= lower - s
            blocks.append(sparse.hstack([sparse.csc_matrix((N, nu)), sparse.eye(N)]))  # s >= 0
        self.A = sparse.vstack(blocks, format="csc")
        Pq = np.zeros((self.n_var, self.n_var))
        Pq[:nu, :nu] = 2.0 * d.hessian
        if self.soft:
            Pq[nu:, nu:] = 2.0 * self.slack_weight * np.eye(N)
        self.P_qp = sparse.csc_matrix(Pq)
        self._q = np.zeros(self.n_var)
        if self.soft:
            self._q[nu:] = self.slack_weight
        rows = self.A.shape[0]
        self._l = np.full(rows, -np.inf)
        self._u = np.full(rows, np.inf)
        self.max_iterations = int(max_iterations)
        self.tolerance = float(tolerance)
        self._solver = osqp.OSQP()
        self._solver.setup(
            sparse.triu(self.P_qp, format="csc"), self._q, self.A, self._l, self._u,
            eps_abs=self.tolerance, eps_rel=self.tolerance, max_iter=self.max_iterations,
            warm_starting=True, polishing=False, verbose=False,
            adaptive_rho_interval=ADAPTIVE_RHO_INTERVAL,
        )  # fmt: skip

    def qp_data(self) -> tuple:
        """The last QP posed, (P, q, A, l, u) as OSQP took them (P full, not triangular), for
        checks of its solution (KKT conditions).

        Returns
        -------
        tuple
            P (n_var, n_var) sparse, q (n_var,), A (rows, n_var) sparse, l (rows,), u (rows,).
        """
        return self.P_qp, self._q.copy(), self.A, self._l.copy(), self._u.copy()

    # --- the Controller contract -------------------------------------------------------------

    def reset(self) -> None:
        """Integrators to zero, the disturbance estimate to ``d_init``, no previous plan."""
        self.z = np.zeros(4)
        self.d_hat = self.d_init.copy()
        self._estimate: np.ndarray | None = None  # the Kalman filter's [dx; d]
        self._dx_prev: np.ndarray | None = None
        self._du_prev = np.zeros(self.m)
        self._plan: np.ndarray | None = None  # (N, m) deviations from trim
        self.solution: tuple[np.ndarray, np.ndarray] | None = None  # last OSQP x, y
        self.fallbacks: list[int] = []
        self.iterations: list[int] = []
        self.solve_times: list[float] = []  # wall clock of update + solve [s]
        self.solve_cpu_times: list[float] = []  # this thread's CPU time of the same [s]
        self._estimates: list[np.ndarray] = []  # the filter's [x; d] per sample (absolute x)
        self._nis: list[float] = []

    def recorded(self) -> dict[str, np.ndarray]:
        """Per-sample columns for the result: ``mpc_fallback`` (1: OSQP failed or hit its
        iteration limit and the previous plan flew) and ``mpc_iterations`` (OSQP's).

        With the Kalman filter also its estimate at every sample (after the sample's
        measurements): ``<state>_est`` for the model's states (q4..q9, u1..u6 and, tethered,
        LN; ``KALMAN_STATE_COLUMNS``), ``Fw1_est``..``Fw3_est`` (the wind force on HO [N]) and
        ``kalman_nis`` (the innovation's NIS, ``KALMAN_NIS_COLUMN``); NaN after a release.

        Returns
        -------
        dict of str to ndarray
            One value per ``step`` call since ``reset``.
        """
        out = {
            FALLBACK_COLUMN: np.array(self.fallbacks, dtype=float),
            "mpc_iterations": np.array(self.iterations, dtype=float),
        }
        if self.kalman is not None:
            k = len(self.fallbacks)
            est = np.full((k, self.n + 3), np.nan)
            nis = np.full(k, np.nan)
            if self._estimates:
                est[: len(self._estimates)] = self._estimates
                nis[: len(self._nis)] = self._nis
            for i, name in enumerate(KALMAN_STATE_COLUMNS[: self.n] + KALMAN_FORCE_COLUMNS):
                out[name] = est[:, i]
            out[KALMAN_NIS_COLUMN] = nis
        return out

    def step(self, t: float, measurement: Measurement) -> Command:
        """One sample of the MPC (module docstring); after a release the paper's free law.

        Parameters
        ----------
        t : float
            Sample time [s] (the law is time-invariant).
        measurement : Measurement
            The measured state, tension and attachment.

        Returns
        -------
        Command
            Rotor inputs [N, N m, N m, N] and reel rate [m/s]; no feed-forward.
        """
        x = np.asarray(measurement.state, dtype=float)
        if self.tethered and not measurement.attached:
            return self._free_law(x, self._outputs(x))
        n, m = self.n, self.m
        dx = x[:n] - self.x_ref
        if self.kalman is not None:
            dx = self._filter(dx, measurement.tension)
            x = x.copy()
            x[:n] = self.x_ref + dx  # the outputs below are the estimate's
        elif self._dx_prev is not None and self.alpha > 0.0:
            G, H = self.design.G_aug[:n, :n], self.design.H_aug[:n]
            d_raw = self.Hd_pinv @ (dx - G @ self._dx_prev - H @ self._du_prev)
            self.d_hat += self.alpha * (d_raw - self.d_hat)
        y = self._outputs(x)
        xu_s = self.design.target @ self.d_hat
        x_s, u_s = xu_s[:n], xu_s[n:]
        xi0 = np.concatenate([dx - x_s, self.z])
        du = self._solve(xi0, x_s, u_s)
        cmd = self.u_trim + du[:4]
        rate = float(du[4]) if m == 5 else 0.0
        self._dx_prev, self._du_prev = dx, du
        self.z += self.dt * (self.y_ref - y)  # eq 50
        return Command(inputs=cmd, reel_rate=rate)

    def _outputs(self, x: np.ndarray) -> np.ndarray:
        """[q1, q2, q3, q6] (4,) of the state x (13,) (``kernels.tethered_outputs``)."""
        y = np.empty(4)
        tethered_outputs(x, self.c, y)
        return y

    def _filter(self, dx_measured: np.ndarray, tension: float) -> np.ndarray:
        """The Kalman filter's sample (``control.observer``): sets ``d_hat``; returns the
        estimated state deviation (n,)."""
        assert self.kalman is not None  # called only with a Kalman filter
        measured = dx_measured
        if self.kalman.C.shape[0] > self.n:  # the load cell
            measured = np.append(dx_measured, tension - self.tension_ref)
        if self._estimate is None:
            s = self.kalman.start(self.d_init, measured)
            nis = math.nan  # no prediction at the first sample
        else:
            s, nu = self.kalman.step(self._estimate, self._du_prev, measured)
            nis = float(nu @ self._S_inv @ nu)
        self._estimate = s
        self._estimates.append(np.concatenate([self.x_ref + s[: self.n], s[self.n : self.n + 3]]))
        self._nis.append(nis)
        self.d_hat = s[self.n : self.n + 3].copy()
        return s[: self.n]

    def _solve(self, xi0: np.ndarray, x_s: np.ndarray, u_s: np.ndarray) -> np.ndarray:
        """The first move (deviation from trim, (m,)) of the QP at xi0, or the fallback."""
        d, m, N = self.design, self.m, self.N
        nu = N * m
        self._q[:nu] = 2.0 * (d.linear @ xi0)
        # the input bounds of every move, less the steady input (views (N, m) of l, u)
        self._l[:nu].reshape(N, m)[:] = self.du_min - u_s
        self._u[:nu].reshape(N, m)[:] = self.du_max - u_s
        row = nu
        if self.reel_rows:
            prev = self._du_prev[4] if m == 5 else 0.0
            self._l[row : row + N] = -self.reel_step
            self._u[row : row + N] = self.reel_step
            self._l[row] += prev - u_s[4]
            self._u[row] += prev - u_s[4]
            row += N
        if self.soft:
            assert d.c_aug is not None  # soft bounds only when tethered
            lo, hi = self.tension_bounds
            # the predicted tensions without input: T_ref + c_T' (x_s + dx_j)
            free = self.tension_ref + d.c_aug[: self.n] @ x_s + self.tension_x @ xi0
            self._u[row : row + N] = hi - free
            self._l[row + N : row + 2 * N] = lo - free
            self._l[row + 2 * N : row + 3 * N] = 0.0
        t0, c0 = time.perf_counter(), time.thread_time()
        self._solver.update(q=self._q, l=self._l, u=self._u)
        if self._plan is not None:
            warm = np.zeros(self.n_var)
            shifted = np.vstack([self._plan[1:], self._plan[-1:]]) - u_s
            warm[:nu] = shifted.ravel()
            self._solver.warm_start(x=warm)
        res = self._solver.solve(raise_error=False)  # a failure is handled: the fallback
        self.solve_times.append(time.perf_counter() - t0)
        self.solve_cpu_times.append(time.thread_time() - c0)
        self.iterations.append(int(res.info.iter))
        ok = res.info.status_val == osqp.SolverStatus.OSQP_SOLVED and np.all(np.isfinite(res.x))
        if ok:
            U = res.x[:nu].reshape(N, m) + u_s
            self.solution = (res.x.copy(), res.y.copy())
            self.fallbacks.append(0)
        else:
            self.fallbacks.append(1)
            if self._plan is not None:
                U = np.vstack([self._plan[1:], self._plan[-1:]])
            else:
                U = np.tile(u_s - d.K @ xi0, (N, 1))
        U = np.clip(U, self.du_min, self.du_max)
        if m == 5:  # the winch's acceleration limit on the first move
            prev = self._du_prev[4]
            U[0, 4] = min(max(U[0, 4], prev - self.reel_step), prev + self.reel_step)
        self._plan = U
        return U[0].copy()

    def _free_law(self, x: np.ndarray, y: np.ndarray) -> Command:
        """After a release: the paper's free LQI about u0|F (as ``tether_lqi`` does), its
        integrators continuing those of the MPC."""
        K = self.free_gain
        assert K is not None  # given whenever the tether can be released
        x_ref = self.x_ref[:12]
        inp = self.u0_free - K[:, :12] @ (x[:12] - x_ref) - K[:, 12:] @ self.z
        self.z += self.dt * (self.y_ref - y)
        self.fallbacks.append(0)
        self.iterations.append(0)
        self.solve_times.append(0.0)
        self.solve_cpu_times.append(0.0)
        return Command(inputs=inp, reel_rate=0.0)
