"""The lumped chain's ground (issue 23, item 4): the plane z = 0 under the free nodes, a
spring-damper with regularised Coulomb friction (``tether.lumped``, MoorDyn's
seabed). Independent routes: the static penetration weight / stiffness, Coulomb's sliding
distance v^2 / (2 mu g), the energy balance (the ground only takes energy out), and a
falling helicopter's chain that piles up on the ground without leaving it finite or
physical."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tetherheli.errors import ParameterError
from tetherheli.layout import (
    GROUND_DAMPING_PA_S_M,
    GROUND_STIFFNESS_PA_M,
    LUMPED_BA,
    LUMPED_CDN,
    LUMPED_CDT,
    LUMPED_DAMPING,
)
from tetherheli.tether import Cable, drive_cable
from tetherheli.tether.chain import LumpedTether, chain_energy
from tetherheli.tether.lumped import chain_interval, ros2_work

G = 9.81
MU, D = 0.02, 0.005  # the default cable [kg/m, m]
#: a node at rest on the ground sinks in by its weight over its contact stiffness
PENETRATION = MU * G / (GROUND_STIFFNESS_PA_M * D)


def _still_top(point):
    point = np.asarray(point, dtype=float)
    return lambda t: (point, np.zeros(3))


def test_a_slack_cable_dropped_on_the_ground_comes_to_rest_at_its_static_penetration():
    """A 10 m cable between an anchor and a top 0.3 m high and 9 m away (slack), laid 5 cm
    above the ground with a wiggle: it falls, stops (friction), and every free node rests at
    z = -mu g / (kbot d) (13 um), never below the impact's bound: the free fall's speed
    sqrt(2 g h) over the contact's frequency sqrt(kbot d / mu), plus the static sink."""
    n = 10
    cable = Cable(unstretched_length=10.0, EA=375.0, segments=n)
    start = np.zeros((n + 1, 3))
    start[:, 0] = np.linspace(0.0, 9.0, n + 1)
    start[1:-1, 2] = 0.05
    start[1:-1, 1] = 0.2 * np.sin(np.arange(1, n))
    run = drive_cable(cable, anchor=(0, 0, 0), top=_still_top((9.0, 0.0, 0.3)), duration=4.0,
                      dt=0.01, start=start)  # fmt: skip
    free = run.nodes[:, 1:-1]
    impact = math.sqrt(2.0 * G * 0.05) / math.sqrt(GROUND_STIFFNESS_PA_M * D / MU)
    assert free[:, :, 2].min() >= -(PENETRATION + impact)
    assert free[:, :, 2].min() < -PENETRATION  # it did hit the ground
    np.testing.assert_allclose(free[-1, :, 2], -PENETRATION, rtol=1e-3)
    assert np.abs(run.velocities[-1, 1:-1]).max() < 1e-6


def test_coulomb_friction_stops_a_sliding_cable_after_v2_over_2_mu_g():
    """Free nodes resting on the ground with slack segments (spacing below l0) and a sideways
    speed of 0.5 m/s slide independently; Coulomb friction decelerates each at mu g, so they
    stop after v^2 / (2 mu g) = 25.5 mm (mu = 0.5), to within the regularisation (viscous
    below v_f = 1 mm/s here) and the drag (off)."""
    n, L0, v0, mu = 10, 10.0, 0.5, 0.5
    tether = LumpedTether(segments=n, damping_ratio=0.0, ground_friction=mu,
                          ground_friction_speed_m_s=1e-3)  # fmt: skip
    p = tether.packed(G)
    p[LUMPED_CDN] = p[LUMPED_CDT] = 0.0
    x = np.zeros((n + 1, 3))
    x[:, 0] = 0.5 * np.arange(n + 1)  # segments of 0.5 m < l0 = 1 m: slack
    x[1:-1, 2] = -PENETRATION
    v = np.zeros_like(x)
    v[1:-1, 1] = v0
    air, work = np.zeros_like(x), ros2_work(n)
    for _ in range(100):  # 0.5 s, the slide takes v0 / (mu g) = 0.1 s
        chain_interval(x, v, air, L0, p, 0.005, x[n].copy(), np.zeros(3), work)
    slide = v0**2 / (2.0 * mu * G)
    np.testing.assert_allclose(x[1:-1, 1], slide, rtol=0.02)
    assert np.abs(v[1:-1]).max() < 1e-3
    np.testing.assert_allclose(x[1:-1, 2], -PENETRATION, rtol=1e-3)


@pytest.mark.parametrize("friction", [0.0, 0.5])
def test_the_ground_takes_energy_out_and_never_puts_it_in(friction):
    """Drag and axial damping off, both ends fixed: a cable falling onto the ground (from a
    taut-ish shape 1 m up, span 6 m, L0 = 8 m) exchanges potential, kinetic and elastic
    energy (``chain_energy``, with the ground's spring); the ground's damping and friction
    dissipate, so the energy never rises above where it was (beyond ROS2's own small
    exchange, 1e-4 of the drop) and ends well below the start."""
    n, L0 = 16, 8.0
    tether = LumpedTether(segments=n, damping_ratio=0.0, ground_friction=friction)
    p = tether.packed(G)
    p[LUMPED_CDN] = p[LUMPED_CDT] = 0.0
    assert p[LUMPED_DAMPING] == 0.0 and p[LUMPED_BA] == 0.0
    x = np.zeros((n + 1, 3))
    x[:, 0] = np.linspace(0.0, 6.0, n + 1)
    x[1:-1, 2] = 1.0 * np.sin(np.pi * np.arange(1, n) / n)
    x[1:-1, 1] = 0.3 * np.sin(2 * np.pi * np.arange(1, n) / n)
    v = np.zeros_like(x)
    air, work = np.zeros_like(x), ros2_work(n)
    e = [chain_energy(x, v, L0, p)]
    touched = False
    for _ in range(600):  # 3 s
        chain_interval(x, v, air, L0, p, 0.005, x[n].copy(), np.zeros(3), work)
        e.append(chain_energy(x, v, L0, p))
        touched |= bool(np.any(x[1:-1, 2] < 0.0))
    e = np.array(e)
    scale = MU * (L0 / n) * G * np.sum(np.sin(np.pi * np.arange(1, n) / n))  # the drop's energy
    assert touched
    assert np.all(np.isfinite(e))
    assert np.max(e - np.minimum.accumulate(e)) < 1e-4 * scale
    assert e[-1] < e[0] - 0.2 * scale


def test_a_sinking_helicopter_lays_its_chain_on_the_ground_and_stays_finite():
    """Closed loop, simulation 1 with an 8-segment chain: a 40 N downward force on HO that
    the thrust (capped 2 N above the hover's) cannot hold and a winch that can barely reel in
    (0.01 m/s): the helicopter sinks with its attitude controlled and the slack chain piles up
    on the ground. The run ends at the ground (status GROUND, not NONFINITE), every recorded
    node is finite and never deeper than the static sink plus the fastest possible impact
    (free fall from q9 over the contact's frequency), and the nodes lying on the ground at
    the end rest at the static penetration."""
    from tetherheli.runs.closed_loop import simulate
    from tetherheli.runs.setup import engine_setup
    from tetherheli.scenario.core import ActuatorSettings, TetherSettings, paper_scenario
    from tetherheli.status import Status
    from tetherheli.wind import ConstantForce

    s = paper_scenario(1, "tethered").replace(
        duration=20.0, wind=ConstantForce((0.0, 0.0, -40.0)),
        tether=TetherSettings(model="lumped", segments=8, record_nodes=True),
    )  # fmt: skip
    u = engine_setup(s).start.trim.u_total
    s = s.replace(actuators=ActuatorSettings(u_max=(u[0] + 2.0, math.inf, math.inf, math.inf),
                                             reel_rate_limit=0.01))  # fmt: skip
    r = simulate(s)
    assert r.status == Status.GROUND
    cols = r.columns()
    z = np.array([cols[f"node{i}_n3"] for i in range(9)]).T
    assert np.all(np.isfinite(z)) and np.all(np.isfinite(r.states))
    assert np.sum(z[-1, 1:-1] < 0.0) >= 6  # the chain lies on the ground
    impact = math.sqrt(2.0 * G * s.q9) / math.sqrt(GROUND_STIFFNESS_PA_M * D / MU)
    assert z[:, 1:-1].min() >= -(PENETRATION + impact)
    np.testing.assert_allclose(z[-1, 1:5], -PENETRATION, rtol=1e-3)


def test_ground_keys_are_validated_with_their_names():
    """Bad ground constants: one ParameterError naming the key (``[tether]`` and ``Cable``)."""
    from tetherheli.scenario.core import Scenario, TetherSettings

    with pytest.raises(ParameterError, match=r"tether\.ground_stiffness"):
        Scenario(tether=TetherSettings(model="lumped", ground_stiffness=-1.0))
    with pytest.raises(ParameterError, match=r"tether\.ground_friction"):
        Scenario(tether=TetherSettings(model="lumped", ground_friction=-0.1))
    with pytest.raises(ParameterError, match=r"cable\.ground_friction_speed"):
        Cable(unstretched_length=5.0, EA=100.0, ground_friction_speed=0.0)
    with pytest.raises(ParameterError, match=r"cable\.ground_damping"):
        Cable(unstretched_length=5.0, EA=100.0, ground_damping=-1.0)
    assert GROUND_DAMPING_PA_S_M == pytest.approx(2.0 * math.sqrt(GROUND_STIFFNESS_PA_M * MU / D),
                                                  rel=0.02)  # fmt: skip
