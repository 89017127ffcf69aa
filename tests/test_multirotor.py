"""The multirotor (issue 45 item 1) against RotorPy 3.0.0, against a Newton-Euler route written
here, at a taut-tether equilibrium (Tognon and Franchi, T-RO 2017) and in its checks."""

from __future__ import annotations

import importlib
import math

import numpy as np
import pytest
import sympy as sp
from scipy.spatial.transform import Rotation

from tetherheli import layout as L
from tetherheli.errors import InfeasibleError, ParameterError
from tetherheli.model import _multirotor_generated, multirotor_derive
from tetherheli.model.multirotor import MULTIROTOR_PRESETS, Multirotor

#: RotorPy's module of each preset's parameters
ROTORPY_MODULES = {
    "crazyflie": "crazyflie_params",
    "hummingbird": "hummingbird_params",
    "px4_quadx": "px4_sihsim_quadx_params",
}
rotorpy_only = pytest.mark.extra("validation", "rotorpy")


def random_state(rng, vehicle: Multirotor, *, wind: bool = True) -> dict:
    """A random RotorPy state above RotorPy's ground (z > 0) with rotor speeds in range."""
    q = rng.normal(size=4)
    return {
        "x": rng.normal(size=3) + np.array([0.0, 0.0, 5.0]),
        "v": rng.normal(size=3) * 3.0,
        "q": q / np.linalg.norm(q),
        "w": rng.normal(size=3) * 2.0,
        "wind": rng.normal(size=3) * 3.0 if wind else np.zeros(3),
        "rotor_speeds": rng.uniform(0.3, 0.9, vehicle.n_rotors) * vehicle.rotor_speed_max,
    }


def assert_blocks_close(ours: dict, ref: dict, rtol: float = 1e-9) -> None:
    """Each block of the derivative equal to rtol of its largest entry."""
    for key in ("x", "v", "q", "w", "rotor_speeds"):
        scale = max(np.max(np.abs(ref[key])), 1e-300)
        np.testing.assert_allclose(ours[key], ref[key], rtol=0, atol=rtol * scale, err_msg=key)


@rotorpy_only
@pytest.mark.parametrize("name", sorted(MULTIROTOR_PRESETS))
def test_presets_are_rotorpy_3_0_0s(name):
    """The presets copy RotorPy 3.0.0's ``rotorpy/vehicles/*_params.py`` values."""
    theirs = importlib.import_module(f"rotorpy.vehicles.{ROTORPY_MODULES[name]}").quad_params
    ours = MULTIROTOR_PRESETS[name]
    for key, value in ours.items():
        if key == "rotor_pos":
            for r in value:
                np.testing.assert_array_equal(value[r], theirs[key][r], err_msg=r)
        else:
            np.testing.assert_array_equal(value, theirs[key], err_msg=key)


def rotorpy_params(name: str) -> dict:
    """RotorPy's dictionary of a preset, or "modified": the Hummingbird with every term of
    RotorPy's model non-zero (flapping, products of inertia, rotors above the centre of
    mass), which the presets leave out."""
    if name != "modified":
        return importlib.import_module(f"rotorpy.vehicles.{ROTORPY_MODULES[name]}").quad_params
    params = dict(importlib.import_module("rotorpy.vehicles.hummingbird_params").quad_params)
    params.update(k_flap=2e-6, Ixy=1e-4, Ixz=-2e-4, Iyz=5e-5)
    params["rotor_pos"] = {
        k: r + np.array([0.0, 0.0, 0.02]) for k, r in params["rotor_pos"].items()
    }
    return params


@rotorpy_only
@pytest.mark.parametrize("aero", [False, True])
@pytest.mark.parametrize("name", [*sorted(MULTIROTOR_PRESETS), "modified"])
def test_state_derivative_equals_rotorpy(name, aero, rng):
    """state_derivative = RotorPy 3.0.0's ``Multirotor(quad_params, aero)._s_dot_fn`` at random
    states (wind included), commands within the rotors' limits, to 1e-9."""
    from rotorpy.vehicles.multirotor import Multirotor as RotorPyMultirotor

    quad_params = rotorpy_params(name)
    theirs = RotorPyMultirotor(quad_params, aero=aero)
    ours = Multirotor.from_rotorpy(quad_params, aero=aero)
    for _ in range(8):
        state = random_state(rng, ours)
        cmd = rng.uniform(0.05, 0.95, ours.n_rotors) * ours.rotor_speed_max
        s_dot = theirs._s_dot_fn(0.0, RotorPyMultirotor._pack_state(state), cmd)
        ref = {
            "x": s_dot[0:3],
            "v": s_dot[3:6],
            "q": s_dot[6:10],
            "w": s_dot[10:13],
            "rotor_speeds": s_dot[16:],
        }
        assert_blocks_close(ours.state_derivative(state, cmd), ref)


def newton_euler(vehicle: Multirotor, state: dict, f_p: np.ndarray) -> dict:
    """m dv/dt = R sum_i k_eta w_i^2 b3 - m g n3 + f_p; J dw/dt + w x J w = sum_i (r_i x
    k_eta w_i^2 b3 + dir_i k_m w_i^2 b3) + r_P x R^T f_p; dq/dt = q (x) (w, 0) / 2 (Hamilton);
    no drag (``aero=False``), the commands equal to the rotor speeds."""
    R = Rotation.from_quat(state["q"]).as_matrix()
    speeds = state["rotor_speeds"]
    thrust = vehicle.k_eta * speeds**2
    force_b = np.array([0.0, 0.0, thrust.sum()])
    moment_b = np.zeros(3)
    for r, t, d, w_i in zip(
        vehicle.rotor_positions, thrust, vehicle.rotor_directions, speeds, strict=True
    ):
        moment_b += np.cross(r, [0.0, 0.0, t]) + np.array([0.0, 0.0, d * vehicle.k_m * w_i**2])
    moment_b += np.cross(vehicle.tether_point, R.T @ f_p)
    w = state["w"]
    J = vehicle.inertia
    qv, qs = state["q"][:3], state["q"][3]
    return {
        "x": state["v"],
        "v": (R @ force_b + f_p) / vehicle.mass - [0.0, 0.0, vehicle.g],
        "q": 0.5 * np.concatenate((qs * w + np.cross(qv, w), [-qv @ w])),
        "w": np.linalg.solve(J, moment_b - np.cross(w, J @ w)),
        "rotor_speeds": np.zeros(vehicle.n_rotors),
    }


def test_kane_equals_newton_euler_with_a_tether(rng):
    """Kane's equations with the tether's pull at P = the Newton-Euler route above (a full
    inertia matrix, P off the centre of mass), to 1e-9; with no pull, the tethered vehicle is
    the free one."""
    J = np.array([[3.65e-3, 2e-4, -1e-4], [2e-4, 3.68e-3, 3e-4], [-1e-4, 3e-4, 7.03e-3]])
    free = Multirotor.preset("hummingbird", aero=False).replace(inertia=J)
    tethered = free.replace(tether_point=(0.02, -0.03, -0.06))
    for _ in range(10):
        state = random_state(rng, tethered, wind=False)
        f_p = rng.normal(size=3) * 3.0
        cmd = state["rotor_speeds"]
        ours = tethered.state_derivative(state, cmd, tether_force=f_p)
        assert_blocks_close(ours, newton_euler(tethered, state, f_p))
        assert_blocks_close(
            tethered.state_derivative(state, cmd), free.state_derivative(state, cmd), rtol=1e-15
        )
    # the pull's moment matters here: the same pull at the centre of mass differs
    moved = free.state_derivative(state, cmd, tether_force=f_p)
    assert not np.allclose(moved["w"], ours["w"], rtol=1e-3)


@pytest.mark.parametrize("aero", [False, True])
def test_tilted_equilibrium_on_a_taut_tether(aero):
    """On a taut tether the vehicle hovers in place tilted (Tognon and Franchi, T-RO 2017,
    Sec. III; Nicotra et al. 2017): thrust balances weight plus pull; ds/dt = 0 to 1e-9."""
    vehicle = Multirotor.preset("hummingbird", aero=aero, tether_point=(0.01, -0.02, -0.05))
    trim = vehicle.hover_trim(tension=2.0, elevation=math.radians(40), azimuth=0.5, yaw=0.3)
    d = vehicle.state_derivative(trim.state, trim.rotor_speeds, tether_force=trim.tether_force)
    for key, scale in (("x", 1.0), ("v", vehicle.g), ("q", 1.0), ("w", 1.0)):
        np.testing.assert_allclose(d[key], 0.0, atol=1e-9 * scale, err_msg=key)
    np.testing.assert_allclose(d["rotor_speeds"], 0.0, atol=1e-9 * vehicle.rotor_speed_max)
    b3 = Rotation.from_quat(trim.state["q"]).as_matrix()[:, 2]
    tilt = math.degrees(math.acos(b3[2]))
    assert tilt > 10.0  # tilted: 2 N of pull at 40 deg against 4.9 N of weight
    # the thrust's magnitude |m g n3 - f_p|, by the law of cosines
    T, mg, e = 2.0, vehicle.mass * vehicle.g, math.radians(40)
    assert trim.thrust == pytest.approx(math.sqrt(mg**2 + T**2 + 2 * mg * T * math.sin(e)))
    # the rotors differ: P off the centre of mass, the pull has a moment
    assert np.ptp(trim.rotor_speeds) > 1.0


def test_free_hover_and_its_linearization():
    """Free hover: every rotor gives m g / n; the linearization's eigenvalues are 0 (the rigid
    body at hover, without drag) and -1/tau_m (the motors), and dv3/dw_i = 2 k_eta w_i / m."""
    vehicle = Multirotor.preset("crazyflie", aero=False)
    trim = vehicle.hover_trim()
    np.testing.assert_allclose(
        vehicle.k_eta * trim.rotor_speeds**2, vehicle.mass * vehicle.g / 4, rtol=1e-12
    )
    A, B = vehicle.linearize(trim)
    n = vehicle.n_rotors
    eig = np.sort(np.linalg.eigvals(A).real)
    np.testing.assert_allclose(eig[:n], -1 / vehicle.tau_m, rtol=1e-6)
    np.testing.assert_allclose(eig[n:], 0.0, atol=1e-4)
    np.testing.assert_allclose(B[L.MRS_ROTORS :], np.eye(n) / vehicle.tau_m, rtol=1e-6)
    np.testing.assert_allclose(
        A[L.MRS_V + 2, L.MRS_ROTORS :],
        2 * vehicle.k_eta * trim.rotor_speeds / vehicle.mass,
        rtol=1e-6,
    )


def test_a_hover_the_rotors_cannot_hold_is_infeasible():
    with pytest.raises(InfeasibleError, match="tension"):
        Multirotor.preset("crazyflie").hover_trim(tension=5.0, elevation=1.0)


@pytest.mark.parametrize(
    ("field", "change"),
    [
        ("mass", {"mass": -0.5}),
        ("rotor_positions", {"rotor_positions": np.zeros((0, 3))}),
        ("rotor_directions", {"rotor_directions": (1, -1, 1)}),
        ("rotor_directions", {"rotor_directions": (1, -1, 1, 0.5)}),
        ("inertia", {"inertia": np.diag([1.0, -1.0, 1.0])}),
        ("inertia", {"inertia": np.eye(2)}),
        ("rotor_speed_max", {"rotor_speed_max": -1.0}),
        ("tether_point", {"tether_point": (0.0, 0.0)}),
        ("drag", {"drag": (0.0, -1.0, 0.0)}),
    ],
)
def test_bad_parameters_name_their_field(field, change):
    with pytest.raises(ParameterError, match=rf"^{field} = "):
        Multirotor.preset("hummingbird").replace(**change)


def test_bad_rotorpy_dictionaries_and_states_name_their_field():
    params = dict(MULTIROTOR_PRESETS["hummingbird"])
    params["num_rotors"] = 6
    with pytest.raises(ParameterError, match=r"quad_params\['num_rotors'\]"):
        Multirotor.from_rotorpy(params)
    params["num_rotors"] = 4
    del params["k_eta"]
    with pytest.raises(ParameterError, match=r"quad_params\['k_eta'\]"):
        Multirotor.from_rotorpy(params)
    vehicle = Multirotor.preset("hummingbird")
    state = vehicle.hover_trim().state
    with pytest.raises(ParameterError, match=r"state\['rotor_speeds'\]"):
        vehicle.state_derivative({**state, "rotor_speeds": np.ones(3)}, np.ones(4))
    with pytest.raises(ParameterError, match="rotor_speed_command"):
        vehicle.state_derivative(state, np.ones(5))


def test_generated_code_matches_fresh_derivation(rng):
    """The committed ``_multirotor_generated.py`` equals a fresh Kane derivation (textually
    with the SymPy that generated it, numerically always)."""
    source = multirotor_derive.generate_source()
    if _multirotor_generated.SYMPY_VERSION == sp.__version__:
        assert multirotor_derive.MR_GENERATED_PATH.read_text() == source
    fresh: dict = {}
    exec(compile(source, "fresh", "exec"), fresh)
    p = np.array(Multirotor.preset("hummingbird", tether_point=(0.1, 0.2, -0.3)).packed)
    q = rng.normal(size=4)
    args = (q / np.linalg.norm(q), *rng.normal(size=(4, 3)))
    wrench = rng.normal(size=6)
    a, b = np.empty(6), np.empty(6)
    fresh["mr_forcing"](args[0], args[1], args[2], wrench, args[3], p, a)
    _multirotor_generated.mr_forcing(args[0], args[1], args[2], wrench, args[3], p, b)
    np.testing.assert_array_equal(a, b)
