"""Landing-gear contact (``model.contact.gear_contact``) against closed forms of the contact
literature, on a rigid body integrated here (NumPy RK4, quaternion attitude), not the engine:

- a body resting on n gear points sinks to the static deflection m g / (n k);
- a linear spring-damper contact rebounds with restitution exp(-zeta pi / sqrt(1 - zeta^2)),
  zeta = c / (2 sqrt(k m)) (the Kelvin-Voigt contact; e.g. Schwager and Poeschel, Phys. Rev. E
  2007);
- a gear sliding at v0 under Coulomb friction mu stops after v0^2 / (2 mu g);
- with no actuation the total energy (kinetic + gravity + the contacts' spring energy) never
  rises;
- a deck in uniform motion acts through relative velocities only (Galilean invariance).
"""

from __future__ import annotations

import numpy as np
import pytest

from tetherheli.layout import LOADS_FORCE_N, LOADS_MOMENT_F
from tetherheli.model import TetheredHelicopter, kernels
from tetherheli.model.contact import (
    body_array,
    deck_array,
    gear_contact,
    gear_law_array,
    tail_lever,
)

from .newton_euler import NewtonEuler

G = 9.81


def _rotation(q: np.ndarray) -> np.ndarray:
    """N_R_F of the unit quaternion q = (w, x, y, z)."""
    w, x, y, z = q / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


class Body:
    """A rigid body (mass m, inertia J about HO = its centre of mass) on gear points, under
    gravity along -n3, over a deck plane that may move with constant velocity."""

    def __init__(self, m, J, gear, law, deck_velocity=(0, 0, 0), g=G):
        self.m, self.J, self.gear, self.law, self.g = (
            m,
            np.asarray(J, float),
            np.asarray(gear),
            law,
            g,
        )
        self.normal = np.array([0.0, 0.0, 1.0])
        self.deck_velocity = np.asarray(deck_velocity, float)
        self.loads = np.empty(6)
        self.pen = np.empty(len(gear))
        self.body = body_array(np.zeros(3), np.zeros(3), np.eye(3), np.zeros(3))
        self.deck = deck_array(np.zeros(3), self.normal, self.deck_velocity)

    def loads_at(self, s: np.ndarray, t: float) -> np.ndarray:
        self.body[0:6] = s[0:6]
        self.body[6:15] = _rotation(s[6:10]).reshape(9)
        self.body[15:18] = s[10:13]
        self.deck[0:3] = self.deck_velocity * t
        gear_contact(self.gear, self.law, self.body, self.deck, self.loads, self.pen)
        return self.loads

    def derivative(self, s: np.ndarray, t: float) -> np.ndarray:
        loads = self.loads_at(s, t)
        w = s[10:13]
        q = s[6:10] / np.linalg.norm(s[6:10])
        a = loads[LOADS_FORCE_N : LOADS_FORCE_N + 3] / self.m - np.array([0.0, 0.0, self.g])
        dw = np.linalg.solve(self.J, loads[LOADS_MOMENT_F:] - np.cross(w, self.J @ w))
        qw, qx, qy, qz = q
        dq = 0.5 * np.array(
            [
                -qx * w[0] - qy * w[1] - qz * w[2],
                qw * w[0] + qy * w[2] - qz * w[1],
                qw * w[1] + qz * w[0] - qx * w[2],
                qw * w[2] + qx * w[1] - qy * w[0],
            ]
        )
        return np.concatenate([s[3:6], a, dq, dw])

    def energy(self, s: np.ndarray, t: float) -> float:
        self.loads_at(s, t)
        spring = 0.5 * self.law[0] * float(np.sum(np.maximum(self.pen, 0.0) ** 2))
        w = s[10:13]
        v = s[3:6] - self.deck_velocity
        return 0.5 * self.m * v @ v + 0.5 * w @ self.J @ w + self.m * self.g * s[2] + spring

    def fly(self, s: np.ndarray, h: float, steps: int, every=None):
        t = 0.0
        for i in range(steps):
            k1 = self.derivative(s, t)
            k2 = self.derivative(s + 0.5 * h * k1, t + 0.5 * h)
            k3 = self.derivative(s + 0.5 * h * k2, t + 0.5 * h)
            k4 = self.derivative(s + h * k3, t + h)
            s = s + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
            s[6:10] /= np.linalg.norm(s[6:10])
            t += h
            if every is not None:
                every(i, s, t)
        return s


def _state(z=0.0, v=(0, 0, 0), q=(1, 0, 0, 0), w=(0, 0, 0), x=0.0):
    return np.array([x, 0.0, z, *v, *q, *w], dtype=float)


SQUARE = np.array([[0.3, 0.3, -0.2], [0.3, -0.3, -0.2], [-0.3, 0.3, -0.2], [-0.3, -0.3, -0.2]])


def test_a_body_on_its_gear_rests_at_the_static_deflection():
    m, k = 12.0, 2.0e4
    c = 2 * 0.7 * np.sqrt(k * m / 4)  # zeta 0.7 per point
    body = Body(m, np.diag([0.4, 0.4, 0.6]), SQUARE, gear_law_array(k, c, 0.5, 0.01))
    s = body.fly(_state(z=0.2), 5e-4, 4_000)  # 2 s
    deflection = float(np.max(body.pen))
    assert deflection == pytest.approx(m * G / (4 * k), rel=1e-6)
    assert np.allclose(body.pen, deflection, rtol=1e-6)
    assert abs(s[5]) < 1e-6


@pytest.mark.parametrize("zeta", [0.05, 0.3])
def test_the_rebound_matches_the_restitution_of_a_linear_spring_damper(zeta):
    m, k = 2.0, 1.0e4
    c = 2 * zeta * np.sqrt(k * m)
    point = np.zeros((1, 3))
    # no gravity: the rebound of the contact alone
    body = Body(m, np.eye(3), point, gear_law_array(k, c, 0.0, 0.01), g=0.0)
    v0 = 1.5
    s = body.fly(_state(z=1e-9, v=(0, 0, -v0)), 4e-6, 12_500)  # 0.05 s
    omega_d = np.sqrt(k / m) * np.sqrt(1 - zeta**2)
    assert np.pi / omega_d < 0.05 and s[2] > 0  # the contact ended inside the run
    e = np.exp(-zeta * np.pi / np.sqrt(1 - zeta**2))
    assert s[5] / v0 == pytest.approx(e, rel=5e-4)


def test_a_sliding_gear_stops_after_v2_over_2_mu_g():
    m, k, mu, v0 = 5.0, 5.0e4, 0.4, 1.2
    c = 2 * 1.0 * np.sqrt(k * m)
    point = np.zeros((1, 3))
    body = Body(m, np.eye(3), point, gear_law_array(k, c, mu, 1e-3))
    rest = -m * G / k  # start at the static deflection: no bounce
    s = body.fly(_state(z=rest, v=(v0, 0, 0)), 1e-4, 6_000)  # 0.6 s; the slide lasts 0.31 s
    assert abs(s[3]) < 1e-3
    assert s[0] == pytest.approx(v0**2 / (2 * mu * G), rel=5e-3)


@pytest.mark.parametrize("deck_velocity", [(0.0, 0.0, 0.0), (3.0, -1.0, 0.0)])
def test_with_no_actuation_the_energy_never_rises(deck_velocity):
    """A tilted, spinning drop onto the gear (friction on): the energy in the deck's frame
    never rises by more than the integrator's error."""
    m, k = 10.0, 3.0e4
    c = 2 * 0.3 * np.sqrt(k * m / 4)
    body = Body(
        m, np.diag([0.5, 0.7, 0.9]), SQUARE, gear_law_array(k, c, 0.6, 0.02),
        deck_velocity=deck_velocity,
    )  # fmt: skip
    q = np.array([np.cos(0.1), np.sin(0.1) * 0.6, np.sin(0.1) * 0.8, 0.0])
    s0 = _state(z=0.35, v=(0.5, -0.2, -1.0), q=q, w=(0.5, -1.0, 2.0))
    s0[3:6] += deck_velocity
    energies = []
    body.fly(s0, 2e-4, 4_000, every=lambda i, s, t: energies.append(body.energy(s, t)))
    e = np.array(energies)
    assert e[-1] < e[0] - 1.0  # contact happened and dissipated
    assert np.max(np.diff(e)) < 1e-6 * e[0]


def test_a_moving_deck_acts_through_relative_velocities():
    """The loads over a deck moving at constant velocity, at the same relative pose and
    velocity, equal those over a still deck (Galilean invariance)."""
    rng = np.random.default_rng(7)
    law = gear_law_array(2e4, 300.0, 0.5, 0.05)
    for _ in range(20):
        q = rng.normal(size=4) * [1, 0.1, 0.1, 0.1] + [3, 0, 0, 0]
        R = _rotation(q)
        w = rng.normal(size=3)
        v_rel = rng.normal(size=3)
        p = np.array([0.1, -0.2, 0.15])
        u = rng.normal(size=3) * 5
        t = 2.0
        still = np.empty(6)
        moving = np.empty(6)
        pen = np.empty(4)
        gear_contact(SQUARE, law, body_array(p, v_rel, R, w), deck_array(np.zeros(3), [0, 0, 1]),
                     still, pen)  # fmt: skip
        gear_contact(SQUARE, law, body_array(p + u * t, v_rel + u, R, w),
                     deck_array(u * t, [0, 0, 1], u), moving, pen)  # fmt: skip
        assert np.allclose(moving, still, rtol=1e-12, atol=1e-9)


def test_a_wrench_as_loads_matches_newton_euler():
    """A force at HO and a moment about HO (all three axes) carried by equivalent rotor inputs
    and wind force (``kernels.wrench_loads_sc``, the one mapping): the generated tethered
    model's accelerations equal the Newton-Euler route (tests/newton_euler.py) with the
    wrench added (its torque enters J w' linearly)."""
    model = TetheredHelicopter()
    trim = model.trim(25.0)
    ne = NewtonEuler(model.params)
    tail = tail_lever(model.params.helicopter)
    rng = np.random.default_rng(11)
    for _ in range(10):
        x = trim.x.copy()
        x[:3] += rng.normal(0.0, 0.2, 3)
        x[6:12] += rng.normal(0.0, 0.5, 6)
        force, moment = rng.normal(0.0, 30.0, 3), rng.normal(0.0, 10.0, 3)
        wind = rng.normal(0.0, 5.0, 3)
        inp, wind_eq, sc = np.empty(4), np.empty(3), np.empty(10)
        kernels.angle_trig(x, sc)
        kernels.wrench_loads_sc(sc, trim.u_total, wind, force, moment, tail, inp, wind_eq)
        out = model.derivative(x, inp, wind=wind_eq)
        ref = ne.tethered(x, trim.u_total, wind + force)  # the tether's pull in both
        w_dot = ref[9:12] + np.linalg.solve(ne.J, moment)
        assert out[6:9] == pytest.approx(ref[6:9], rel=1e-10, abs=1e-10)
        assert out[9:12] == pytest.approx(w_dot, rel=1e-10, abs=1e-10)


def test_a_turning_deck_moves_the_contact_point_with_it():
    """A deck turning at w_d about its point d: the loads on a gear point at x equal those of
    a still deck with the point's velocity less w_d x (x - d) (the deck's velocity there)."""
    rng = np.random.default_rng(3)
    law = gear_law_array(2e4, 300.0, 0.5, 0.05)
    point = np.zeros((1, 3))
    for _ in range(10):
        p = np.array([0.4, -0.3, -0.01])  # 1 cm into the deck, off its reference point
        v, w_d = rng.normal(size=3), rng.normal(size=3)
        turning, still, pen = np.empty(6), np.empty(6), np.empty(1)
        gear_contact(point, law, body_array(p, v, np.eye(3), np.zeros(3)),
                     deck_array(np.zeros(3), [0, 0, 1], omega=w_d), turning, pen)  # fmt: skip
        gear_contact(point, law, body_array(p, v - np.cross(w_d, p), np.eye(3), np.zeros(3)),
                     deck_array(np.zeros(3), [0, 0, 1]), still, pen)  # fmt: skip
        assert np.allclose(turning, still, rtol=1e-12, atol=1e-12)
