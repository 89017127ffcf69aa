"""Where a lane block's time goes (issue 24 item 4): per lane and control sample, in ns.

One block of ``layout.LANES`` dispersed 60 s tethered paper runs (pulse and sine scaled by
U(0.8, 1.2): ``bench_minimal_loop.dispersed_runs``) is timed whole (``lanes.run_lanes``), then two
of its parts alone, each in a compiled loop of the block's sample count:

- ``rk4``: ``lanes.rk4_lanes`` over every lane, the state put back to the start before each
  sample (so that the lanes fly the hover, not an uncontrolled fall);
- ``sample``: the block's control sample (``lane_sample.lane_sample``: sensing, the paper's
  law, actuators, checks and metrics of every lane at once), at the start state.

``rest`` = whole - rk4 - sample is the lane loop's own bookkeeping (finished lanes, parking).
Each figure is the best of ``--repeat`` timings, the parts interleaved over ``--rounds``; a
shared machine drifts, so compare figures of one run only.

Run: python benchmarks/lane_profile.py [--repeat 15] [--rounds 3]
"""

from __future__ import annotations

import argparse
import json

import numpy as np
from bench_minimal_loop import best_warm, dispersed_runs
from numba import njit

from tetherheli.engine import lane_sample, lanes
from tetherheli.layout import (
    ACT_DRUM,
    ACT_SIZE,
    CFG_ATTACHED,
    CFG_DT,
    CFG_GUST_DT,
    CFG_K_C,
    CFG_N_SUB,
    CTRL_LAW,
    HELD_SIZE,
    LANES,
    SUMMARY_FIELDS,
    LaneWind,
)
from tetherheli.model.kernels import angle_trig
from tetherheli.runs.batch import lane_block
from tetherheli.runs.setup import engine_setup
from tetherheli.scenario.core import paper_scenario


@njit(error_model="numpy", cache=True)
def rk4_only(n, x0, sc00, inp, rate, h, n_sub, attached, k_c, c, wind):
    """``rk4_lanes`` n times, each from the block's start state at the sample's time."""
    work = lanes.lane_work()
    x, sc0, t0 = x0.copy(), sc00.copy(), np.zeros(h.shape[0])
    for k in range(n):
        for i in range(x.shape[0]):
            x[i] = x0[i]
        for i in range(sc0.shape[0]):
            sc0[i] = sc00[i]
        for j in range(h.shape[0]):
            t0[j] = k * 2.0 * h[j]
        lanes.rk4_lanes((x, sc0, inp, rate, t0, attached), h, n_sub, k_c, c, wind, work)
    return x[0]


@njit(error_model="numpy", cache=True)
def sample_only(n, x_init, cfg, ctrl, act, sensors, c, law):
    """The block's control sample (``lane_sample.lane_sample``: sensing, the law, actuators,
    checks and metrics of every lane at once) n times at the start state."""
    gain, x_ref, y_ref, u0, u0_free, z0 = law
    x = np.empty(13 * LANES)
    c_lanes = np.empty(c.shape[1] * LANES)
    for j in range(LANES):
        for i in range(13):
            x[i * LANES + j] = x_init[j, i]
        for i in range(c.shape[1]):
            c_lanes[i * LANES + j] = c[j, i]
    sensed = sensors[1] > 0
    drum = act[:, ACT_DRUM] > 0.5
    tether_law = ctrl[0, CTRL_LAW] > 0.5
    state = lane_sample.lane_state(cfg, ctrl, act, z0, x, sensed.any(), len(SUMMARY_FIELDS))
    block_law = lane_sample.lane_law(gain, x_ref, y_ref, u0, u0_free, tether_law)
    rows = (np.empty(13), np.empty(13), np.empty(HELD_SIZE), np.empty(ACT_SIZE))
    active = np.ones(LANES, np.bool_)
    total = 0.0
    for k in range(n):
        lane_sample.lane_sample(k, x, state, block_law, c_lanes, active, sensed, sensors, drum,
                                rows, tether_law)  # fmt: skip
        total += state.rate[0] + state.status[0]
    return total


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=15, help="timings of each part")
    parser.add_argument("--rounds", type=int, default=3, help="interleaved rounds")
    options = parser.parse_args()
    scenario = paper_scenario(1, "tethered")
    runs = dispersed_runs(scenario, LANES)
    setups = [engine_setup(run) for run in runs]
    n = scenario.n_samples
    block = lane_block(setups, [n] * LANES)
    x_init, _, cfg, _, c, law, wind, _, _ = block
    summary = np.zeros((LANES, len(SUMMARY_FIELDS)))
    status, done = np.zeros(LANES, np.int64), np.zeros(LANES, np.int64)

    def flat(rows: np.ndarray) -> np.ndarray:  # (lane, variable) -> flat (variable, lane)
        return np.ascontiguousarray(rows.T).ravel()

    sc_init = np.empty((LANES, 10))
    for j in range(LANES):
        angle_trig(x_init[j], sc_init[j])
    inp = flat(law[3])  # the trim inputs, held
    h = cfg[:, CFG_DT] / cfg[0, CFG_N_SUB]
    lane_wind = LaneWind(
        wind[0], wind[1], wind[2], wind[3], cfg[:, CFG_GUST_DT].copy(), flat(wind[4])
    )
    rk4_args = (
        n, flat(x_init), flat(sc_init), inp, np.zeros(LANES), h, int(cfg[0, CFG_N_SUB]),
        cfg[:, CFG_ATTACHED].copy(), cfg[:, CFG_K_C].copy(), flat(c), lane_wind,
    )  # fmt: skip
    sample_args = (n, x_init, cfg, block[3], block[7], block[8], c, law)
    parts = {
        "whole": lambda: lanes.run_lanes(*block, (summary, status, done)),
        "rk4": lambda: rk4_only(*rk4_args),
        "sample": lambda: sample_only(*sample_args),
    }
    best = dict.fromkeys(parts, np.inf)
    for _ in range(options.rounds):
        for name, function in parts.items():
            best[name] = min(best[name], best_warm(function, options.repeat))
    per = 1e9 / (LANES * n)  # s per block -> ns per lane and sample
    figures = {
        "whole_ns": best["whole"] * per,
        "rk4_ns": best["rk4"] * per,
        "sample_ns": best["sample"] * per,
    }
    figures["rest_ns"] = figures["whole_ns"] - figures["rk4_ns"] - figures["sample_ns"]
    figures["sample_share"] = figures["sample_ns"] / figures["whole_ns"]
    figures["rk4_share"] = figures["rk4_ns"] / figures["whole_ns"]
    print(json.dumps(figures, indent=1))


if __name__ == "__main__":
    main()
