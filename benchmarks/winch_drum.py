"""The drum winch (``[winch] model = "drum"``, issue 13 item 2): its accuracy and a study.

Run: python benchmarks/winch_drum.py [--reference] [--duration S]

Study (default): the paper's simulation 1 (Sec. VI, wind along n1), tethered, with the
paper's ideal winch and with drums of growing inertia and of shrinking torque limit (the
other keys at ``WinchSettings``' defaults); for each, the peak and RMS of q1 - q1_trim, the
tension range, and the disturbance reduction against the free helicopter (the paper's metric,
100 (free - tethered) / free, peak and RMS); then the torque limit below which the reduction
is lost, found by bisection (the smallest limit whose peak reduction keeps half the ideal
winch's). All runs go through ``run_batch`` (the lane engine).

``--reference``: the error of the engine's per-sample drum update (``tether.winch.drum_step``,
the tension held over the sample) against an adaptive solution of the joint helicopter,
tether and drum ODE (DOP853, rtol 1e-9, atol 1e-11; the drum speed a state, the tension
continuous, Coulomb stick and slip switched by events), both flying the same
sampled controller; the same comparison for the ideal winch (the engine's RK4 against
``simulate(method="adaptive")``) is printed beside it, as the integrator's own share.
Slow (about a minute per 60 s run).
"""

from __future__ import annotations

import argparse
import dataclasses
import itertools
import math
import time

import numpy as np
from scipy.integrate import solve_ivp

from tetherheli.analysis import reduction_percent
from tetherheli.base.compiled import STILL_BASE
from tetherheli.control.base import Measurement
from tetherheli.engine import loop as engine
from tetherheli.layout import (
    CFG_K_C,
    HELD_SIZE,
    SUMMARY_FIELDS,
    SUMMARY_PEAK_Q1,
    SUMMARY_SUMSQ_Q1,
    SUMMARY_TENSION_MAX,
    SUMMARY_TENSION_MIN,
    WindPack,
    no_gear,
)
from tetherheli.model.kernels import angle_trig, tension_from_state, tethered_outputs
from tetherheli.runs.batch import run_batch
from tetherheli.runs.closed_loop import simulate
from tetherheli.runs.setup import engine_setup
from tetherheli.scenario.core import WinchSettings, paper_scenario

DRUM = WinchSettings(model="drum")
INERTIAS = (0.005, 0.05, 0.5, 1.0, 2.0, 5.0)  # [kg m^2]
TORQUE_LIMITS = (2.5, 1.3, 1.25, 1.2, 1.0, 0.75, 0.5, 0.25, 0.1)  # [N m]; r Tref = 1.25 N m


def _sim1(winch: WinchSettings | None, duration: float, configuration: str = "tethered"):
    s = paper_scenario(1, configuration).replace(duration=duration)
    return s if winch is None else s.replace(winch=winch)


def _metrics(summary: np.ndarray) -> tuple[float, float, float, float]:
    """peak |q1 - trim| [m], RMS [m], tension min and max [N] of a run's summary."""
    n = summary[SUMMARY_FIELDS.index("n_samples")]
    return (
        summary[SUMMARY_PEAK_Q1],
        math.sqrt(summary[SUMMARY_SUMSQ_Q1] / n),
        summary[SUMMARY_TENSION_MIN],
        summary[SUMMARY_TENSION_MAX],
    )


def study(duration: float) -> None:
    free = _metrics(run_batch([_sim1(None, duration, "free")], workers=1).summaries[0])
    rows = [("ideal", None)]
    rows += [(f"J = {j:g} kg m^2", dataclasses.replace(DRUM, drum_inertia=j)) for j in INERTIAS]
    rows += [
        (f"tau_max = {t:g} N m", dataclasses.replace(DRUM, torque_limit=t))
        for t in TORQUE_LIMITS[1:]
    ]
    batch = run_batch([_sim1(w, duration) for _, w in rows], workers=1)
    print(f"paper simulation 1, {duration:g} s; free: peak q1 {free[0]:.4f} m, RMS {free[1]:.4f} m")
    print(f"drum defaults: {DRUM}")
    print("| winch | peak q1 [m] | RMS q1 [m] | tension [N] | reduction peak / RMS [%] |")
    print("|---|---|---|---|---|")
    ideal_reduction = None
    for (label, _), summary, ok, message in zip(
        rows, batch.summaries, batch.ok, batch.messages(), strict=True
    ):
        if not ok:
            print(f"| {label} | failed: {message} | | | |")
            continue
        peak, rms, t_min, t_max = _metrics(summary)
        red = reduction_percent(free[0], peak), reduction_percent(free[1], rms)
        ideal_reduction = red[0] if ideal_reduction is None else ideal_reduction
        print(
            f"| {label} | {peak:.4f} | {rms:.4f} | {t_min:.2f} to {t_max:.2f} | "
            f"{red[0]:.1f} / {red[1]:.1f} |"
        )

    def keeps_half(limit: float) -> bool:
        b = run_batch([_sim1(dataclasses.replace(DRUM, torque_limit=limit), duration)], workers=1)
        if not b.ok[0]:
            return False
        return reduction_percent(free[0], _metrics(b.summaries[0])[0]) >= 0.5 * ideal_reduction

    lo, hi = 0.05, 2.5  # [N m]: loses, keeps
    assert keeps_half(hi) and not keeps_half(lo)
    while hi - lo > 0.005:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if keeps_half(mid) else (mid, hi)
    r_t = DRUM.drum_radius * 25.0
    print(
        f"peak reduction keeps half the ideal winch's ({0.5 * ideal_reduction:.1f} %) down to "
        f"tau_max = {hi:.3f} N m (lost at {lo:.3f} N m); r Tref = {r_t:.3f} N m"
    )


# --- the adaptive reference of the joint helicopter, tether and drum ODE -------------------------


def _drum_torque(w, w_cmd, ffwd, winch):
    """The drive's torque along w (paying out), -tau_m, with ffwd the feed-forward along w."""
    gain = winch.drum_inertia * winch.speed_loop_bandwidth
    return min(max(gain * (w_cmd - w) + ffwd, -winch.torque_limit), winch.torque_limit)


def _piece(z0, ta, tb, mid, sign, held, setup, winch, tol):
    """Integrate the joint ODE z = [x, w] from ta towards tb in one mode (sign of w's
    Coulomb friction, 0: stuck) until tb or the first switching event (w through 0, the
    stick ending); the torque's saturation, a kink, is left to the step-size control.
    Returns (z, t reached, which event or None)."""
    inp, w_cmd, ffwd = held
    cfg, c, wind = setup.cfg, setup.model.constants, setup.wind
    r, inertia = winch.drum_radius, winch.drum_inertia
    b, tc = winch.viscous_friction, winch.coulomb_friction
    dx, sc = np.empty(13), np.empty(10)

    def pull(z):  # the tether's torque on the drum, paying out
        return r * tension_from_state(z[5], z[12], cfg[CFG_K_C])

    def rhs(tt, z):
        angle_trig(z[:13], sc)
        w = 0.0 if sign == 0.0 else z[13]
        side = 1 if tt < mid else -1
        engine.plant_derivative(
            z[:13], sc, inp, r * w, tt, side, cfg, (c, no_gear()),
            WindPack(wind.program, wind.gust, wind.drag, STILL_BASE), dx,
        )  # fmt: skip
        if sign == 0.0:
            return np.append(dx, 0.0)
        tau = _drum_torque(w, w_cmd, ffwd, winch)
        return np.append(dx, (tau + pull(z) - b * w - tc * sign) / inertia)

    def through_zero(tt, z):  # slip ends (the crossing against the slip: not at the start)
        return z[13] if sign != 0.0 else 1.0

    def breaks_free(tt, z):  # stick ends
        return tc - abs(_drum_torque(0.0, w_cmd, ffwd, winch) + pull(z)) if sign == 0.0 else 1.0

    through_zero.direction = -sign if sign != 0.0 else 0.0
    breaks_free.direction = -1.0
    events = [through_zero, breaks_free]
    for e in events:
        e.terminal = True
    sol = solve_ivp(rhs, (ta, tb), z0, method="DOP853", rtol=tol[0], atol=tol[1], events=events)
    if not sol.success:
        raise RuntimeError(sol.message)
    hit = None
    if sol.status == 1:
        hit = next(i for i, te in enumerate(sol.t_events) if len(te))
    return sol.y[:, -1].copy(), sol.t[-1], hit


def reference_run(scenario, rtol: float = 1e-9, atol: float = 1e-11):
    """The joint ODE [x (13), w] between samples; the paper's controller at every sample (as
    the engine samples it), the drive's speed reference and feed-forward held over the
    sample. Returns the sampled (q1, LN, tension) arrays."""
    setup = engine_setup(scenario)
    winch = scenario.winch
    r, tc = winch.drum_radius, winch.coulomb_friction
    cfg, c, act = setup.cfg, setup.model.constants, setup.act
    controller = setup.paper_controller()
    controller.reset()
    dt, n = scenario.control.dt, scenario.n_samples
    breaks = setup.wind.breakpoints(n * dt)
    z = np.append(setup.start.x, 0.0)  # the drum starts at rest, as the engine's
    held = np.zeros(HELD_SIZE)
    out_q1, out_ln, out_t = np.empty(n + 1), np.empty(n + 1), np.empty(n + 1)
    y = np.empty(4)
    for k in range(n + 1):
        t = k * dt
        tension = tension_from_state(z[5], z[12], cfg[CFG_K_C])
        tethered_outputs(z[:13], c, y)
        out_q1[k], out_ln[k], out_t[k] = y[0], z[12], tension
        if k == n:
            break
        cmd = controller.step(t, Measurement(state=z[:13].copy(), tension=tension, attached=True))
        inp = np.array(cmd.inputs, dtype=float)
        engine.apply_actuators(inp, held, act, dt, k == 0)
        ffwd = -r * tension if winch.tension_feedforward else 0.0  # along w
        sample = (inp, cmd.reel_rate / r, ffwd)
        edges = [t, *breaks[(breaks > t) & (breaks < t + dt)].tolist(), t + dt]
        for a, b in itertools.pairwise(edges):
            ta = a
            hit = None
            while ta < b:
                if z[13] == 0.0:  # at rest: stuck, or slipping towards the net torque
                    pull = r * tension_from_state(z[5], z[12], cfg[CFG_K_C])
                    net = _drum_torque(0.0, sample[1], ffwd, winch) + pull
                    stuck = abs(net) <= tc and hit != 1  # hit 1: the stick just ended
                    sign = 0.0 if stuck else math.copysign(1.0, net)
                else:
                    sign = math.copysign(1.0, z[13])
                z, t_end, hit = _piece(z, ta, b, 0.5 * (a + b), sign, sample, setup, winch,
                                       (rtol, atol))  # fmt: skip
                if hit == 0:
                    z[13] = 0.0  # through zero: the next piece decides stick or slip
                if hit is not None and t_end <= ta:  # an event at the start: step on
                    t_end = math.nextafter(ta, math.inf)
                ta = t_end
    return out_q1, out_ln, out_t


def reference(duration: float) -> None:
    s = _sim1(DRUM, duration)
    start = time.perf_counter()
    q1_ref, ln_ref, t_ref = reference_run(s)
    cost = time.perf_counter() - start
    r = simulate(s)
    print(f"paper simulation 1 tethered, default drum, {duration:g} s (reference: {cost:.0f} s)")
    err_q1 = np.abs(r.outputs[:, 0] - q1_ref).max()
    print(
        "drum, engine (RK4, 2 steps per sample, drum exact with the tension held) vs joint "
        f"ODE: max |error| LN {np.abs(r.states[:, 12] - ln_ref).max():.2e} m, tension "
        f"{np.abs(r.tension - t_ref).max():.2e} N, q1 {err_q1:.2e} m"
    )
    ideal = _sim1(None, duration)
    a, b = simulate(ideal), simulate(ideal, method="adaptive", rtol=1e-9, atol=1e-11)
    print(
        "ideal winch, engine vs adaptive: max |error| LN "
        f"{np.abs(a.states[:, 12] - b.states[:, 12]).max():.2e} m, tension "
        f"{np.abs(a.tension - b.tension).max():.2e} N, q1 "
        f"{np.abs(a.outputs[:, 0] - b.outputs[:, 0]).max():.2e} m"
    )
    print(
        f"drum vs ideal winch (the drum's effect, for scale): max |difference| q1 "
        f"{np.abs(r.outputs[:, 0] - a.outputs[:, 0]).max():.2e} m, tension "
        f"{np.abs(r.tension - a.tension).max():.2e} N"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--reference", action="store_true", help="the accuracy check")
    parser.add_argument("--duration", type=float, default=60.0, help="run length [s]")
    args = parser.parse_args()
    if args.reference:
        reference(args.duration)
    else:
        study(args.duration)


if __name__ == "__main__":
    main()
