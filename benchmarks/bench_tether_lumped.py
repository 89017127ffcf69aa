"""Cost of one step of the lumped-mass tether (issue 13), against the massless model.

Run: python benchmarks/bench_tether_lumped.py [--accuracy]
Prints, measured in this run: the time of one ROS2 step of the tether's free nodes
(``tether.lumped.ros2_step``, P moving, wind, drag) for N = 5, 10, 20, 40 segments and of
one derivative of today's tethered helicopter with its massless tether
(``model.kernels.tethered_derivative``; an RK4 step of the helicopter is four of them), and the
ratio. With ``--accuracy`` also the largest node-position error and the relative error of the
force at P after 0.5 s of 10 ms ROS2 steps against SciPy's Radau (rtol 1e-10) for a soft
(EA = 375 N, the paper's K_C L0N) and a stiff (EA = 20 kN) cable at N = 5, 10 (slow: about a
minute). Timings vary with the machine;
no test asserts them.
"""

from __future__ import annotations

import argparse

import numpy as np

# the massless baseline and the timer of bench_derivative.py (this folder is on sys.path when a
# script here runs)
from bench_derivative import _loop, best_of
from numba import njit
from scipy.integrate import solve_ivp

from tetherheli import TetheredHelicopter
from tetherheli.tether import lumped as tl
from tetherheli.tether.chain import LumpedTether, end_forces, static_chain

G = 9.81
H = 0.01  # the control sample [s]


def _path(time_s: float) -> tuple[np.ndarray, np.ndarray]:
    """P's test motion: a 3D Lissajous path about (1, 0, 10) m."""
    w = np.array([2.0, 3.0, 5.0])
    amp = np.array([0.3, 0.2, 0.1])
    pos = np.array([1.0, 0.0, 10.0]) + amp * np.sin(w * time_s)
    return pos, amp * w * np.cos(w * time_s)


@njit  # not cached: a benchmark must measure the current kernels
def _steps(x, v, wind, L0, p, h, xP, vP, n):
    work = np.empty(tl.ros2_work_size(x.shape[0] - 1))
    for k in range(n):
        tl.ros2_step(x, v, wind, L0, p, h, xP[k], vP[k], work)


def _case(n: int, EA: float):
    t = LumpedTether(segments=n, EA_N=EA, damping_ratio=0.1, diameter_m=0.006)
    L0 = 10.0 * (1.0 - 10.0 / EA)
    x0 = static_chain(np.zeros(3), _path(0.0)[0], L0, t, G)
    wind = np.zeros_like(x0)
    wind[:, 0] = 5.0
    return t, t.packed(G), L0, x0, wind


def timing() -> None:
    model = TetheredHelicopter()
    trim = model.trim(25.0)
    xh, u, c = trim.x.copy(), trim.u_total.copy(), model.constants
    out = np.empty(13)
    m = 1_000_000
    _loop(xh, u, np.zeros(3), c, 40.0, out, 10)
    t_deriv = best_of(lambda: _loop(xh, u, np.zeros(3), c, 40.0, out, m)) / m
    steps = 2000
    path = [_path((k + 1) * H) for k in range(steps)]
    xP = np.array([q[0] for q in path])
    vP = np.array([q[1] for q in path])
    print(f"massless tethered helicopter, one derivative: {t_deriv * 1e6:8.3f} us")
    print(" N   ROS2 step [us]   per free node [us]   step / derivative")
    for n in (5, 10, 20, 40):
        _, p, L0, x0, wind = _case(n, 375.0)
        v0 = np.zeros_like(x0)
        v0[-1] = _path(0.0)[1]
        _steps(x0.copy(), v0.copy(), wind, L0, p, H, xP, vP, 2)

        def run(x0=x0, v0=v0, wind=wind, L0=L0, p=p):
            _steps(x0.copy(), v0.copy(), wind, L0, p, H, xP, vP, steps)

        t_step = best_of(run) / steps
        print(
            f"{n:2d}   {t_step * 1e6:14.2f}   {t_step * 1e6 / (n - 1):18.3f}"
            f"   {t_step / t_deriv:17.1f}"
        )


def accuracy(t_end: float = 0.5) -> None:
    print(f"ROS2 at {H * 1e3:g} ms vs Radau (rtol 1e-10), largest errors after {t_end} s:")
    for EA in (375.0, 20000.0):
        for n in (5, 10):
            t, p, L0, x0, wind = _case(n, EA)
            m = t.mass_per_length_kg_m * L0 / n
            F = np.empty((n + 1, 3))
            T = np.empty(n)
            blocks = [np.empty((n, 3, 3)) for _ in range(3)]

            def rhs(time_s, y, n=n, x0=x0, L0=L0, p=p, wind=wind, m=m, F=F, T=T, blocks=blocks):
                x = x0.copy()
                v = np.zeros_like(x0)
                x[1:-1] = y[: 3 * (n - 1)].reshape(-1, 3)
                v[1:-1] = y[3 * (n - 1) :].reshape(-1, 3)
                x[-1], v[-1] = _path(time_s)
                tl.chain_forces(x, v, wind, L0, p, F, T, tuple(blocks), False)
                return np.concatenate([v[1:-1].ravel(), (F[1:-1] / m).ravel()])

            y0 = np.concatenate([x0[1:-1].ravel(), np.zeros(3 * (n - 1))])
            ref = solve_ivp(rhs, (0.0, t_end), y0, method="Radau", rtol=1e-10, atol=1e-12)
            x, v = x0.copy(), np.zeros_like(x0)
            v[-1] = _path(0.0)[1]
            work = tl.ros2_work(n)
            for k in range(round(t_end / H)):
                tl.ros2_step(x, v, wind, L0, p, H, *_path((k + 1) * H), work)
            err = np.abs(x[1:-1].ravel() - ref.y[: 3 * (n - 1), -1]).max()
            x_ref, v_ref = x0.copy(), np.zeros_like(x0)
            x_ref[1:-1] = ref.y[: 3 * (n - 1), -1].reshape(-1, 3)
            v_ref[1:-1] = ref.y[3 * (n - 1) :, -1].reshape(-1, 3)
            x_ref[-1], v_ref[-1] = _path(t_end)
            force = end_forces(x, v, wind, L0, p)[1]
            force_ref = end_forces(x_ref, v_ref, wind, L0, p)[1]
            rel = np.linalg.norm(force - force_ref) / np.linalg.norm(force_ref)
            print(f"  EA = {EA:7.0f} N, N = {n:2d}: nodes {err:.2e} m, force at P {rel:.2e} rel.")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--accuracy", action="store_true", help="also the error vs Radau")
    args = parser.parse_args()
    timing()
    if args.accuracy:
        accuracy()


if __name__ == "__main__":
    main()
