"""The geometry generated from the derivation (``model.kinematics``, ``kernels.kinematics_*``):
equal to the hand-written formulas it replaced (sensors, animation) to 1e-14, and checked
against independent routes (Table I, rotations, P = HO + N_R_F d_HO_P)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tetherheli import Params
from tetherheli.model import kernels
from tetherheli.model.kinematics import (
    direction_cosines,
    helicopter_points,
    tether_angles,
    tether_direction,
    tether_length_from_altitude,
    tethered_HO_position,
)
from tetherheli.sensing.config import (
    CH_ALTIMETER,
    CH_ENCODER_Q7,
    CH_ENCODER_Q8,
    CH_GPS,
    N_CHANNELS,
    SOURCE_GPS,
    SOURCE_TETHER,
)
from tetherheli.sensing.sensors import measure, tether_position_estimate

from .newton_euler import dcm_table_i

H = Params.paper().helicopter
ARM = H.tether_arm


# --- the hand-written versions that the generated code replaced (as they stood in 75df058) ---


def old_direction_cosines(q4, q5, q6):  # viz/animation.py
    q4, q5, q6 = np.broadcast_arrays(*(np.asarray(q, dtype=float) for q in (q4, q5, q6)))
    s4, c4 = np.sin(q4), np.cos(q4)
    s5, c5 = np.sin(q5), np.cos(q5)
    s6, c6 = np.sin(q6), np.cos(q6)
    rows = (
        (c5 * c6, -c5 * s6, s5),
        (c4 * s6 + s4 * s5 * c6, c4 * c6 - s4 * s5 * s6, -s4 * c5),
        (s4 * s6 - c4 * s5 * c6, s4 * c6 + c4 * s5 * s6, c4 * c5),
    )
    return np.stack([np.stack(r, axis=-1) for r in rows], axis=-2)


def old_helicopter_points(position, angles, h):  # viz/animation.py: HO, O, MRO, TRO, P
    N_p_HO = np.asarray(position, dtype=float)
    q = np.asarray(angles, dtype=float)
    R = old_direction_cosines(q[..., 0], q[..., 1], q[..., 2])
    f1, f3 = R[..., :, 0], R[..., :, 2]
    N_p_O = N_p_HO - h.d_O_HO3 * f3
    return (N_p_HO, N_p_O, N_p_O + h.d_O_MRO3 * f3, N_p_O + h.d_O_TRO1 * f1, N_p_O + h.d_O_P3 * f3)


def old_tether_position_estimate(q7, q8, h, q4, q5, arm):  # sensors.py
    c4, c5, c7, c8 = np.cos(q4), np.cos(q5), np.cos(q7), np.cos(q8)
    q9 = (h + arm * c4 * c5) / (c7 * c8)
    return np.stack(
        [
            q9 * np.sin(q8) - arm * np.sin(q5),
            -q9 * np.sin(q7) * c8 + arm * np.sin(q4) * c5,
            q9 * c7 * c8 - arm * c4 * c5,
        ],
        axis=-1,
    )


def old_measured_position(x, x_est, noise, source, arm):  # sensors.measure, q7..q9
    s4, c4, s5, c5 = math.sin(x[0]), math.cos(x[0]), math.sin(x[1]), math.cos(x[1])
    s7, c7, s8, c8 = math.sin(x[3]), math.cos(x[3]), math.sin(x[4]), math.cos(x[4])
    if source == SOURCE_GPS:
        h = np.array([x[5] * s8 - arm * s5, -x[5] * s7 * c8 + arm * s4 * c5,
                      x[5] * c7 * c8 - arm * c4 * c5]) + noise[CH_GPS : CH_GPS + 3]  # fmt: skip
        s4m, c4m, s5m, c5m = (f(x_est[i]) for i in (0, 1) for f in (math.sin, math.cos))
        p = h + arm * np.array([s5m, -s4m * c5m, c4m * c5m])
        q9 = math.sqrt(p @ p)
        return [math.atan2(-p[1], p[2]), math.asin(max(-1.0, min(1.0, p[0] / q9))), q9]
    altitude = x[5] * c7 * c8 - arm * c4 * c5 + noise[CH_ALTIMETER]
    q7m, q8m = x[3] + noise[CH_ENCODER_Q7], x[4] + noise[CH_ENCODER_Q8]
    q9 = (altitude + arm * math.cos(x_est[0]) * math.cos(x_est[1])) / (
        math.cos(q7m) * math.cos(q8m)
    )
    return [q7m, q8m, q9]


@pytest.fixture
def angles(rng) -> np.ndarray:
    """(50, 6): q4, q5, q6, q7, q8 in +-1 rad, q9 in [0.5, 50] m."""
    q = rng.uniform(-1.0, 1.0, (50, 6))
    q[:, 5] = rng.uniform(0.5, 50.0, 50)
    return q


# --- equal to the replaced code -------------------------------------------------------------


def test_dcm_and_points_equal_the_former_animation_code(angles, rng):
    position = rng.uniform(-20.0, 20.0, (50, 3))
    np.testing.assert_allclose(
        direction_cosines(*angles[:, :3].T), old_direction_cosines(*angles[:, :3].T), atol=1e-14
    )
    pts = helicopter_points(position, angles[:, :3], H)
    old = old_helicopter_points(position, angles[:, :3], H)
    new = (pts.N_p_HO, pts.N_p_O, pts.N_p_MRO, pts.N_p_TRO, pts.N_p_P)
    for a, b in zip(new, old, strict=True):
        np.testing.assert_allclose(a, b, rtol=0.0, atol=1e-14)
    one = helicopter_points(position[0], angles[0, :3], H)  # a single sample
    assert one.N_p_P.shape == (3,) and one.N_R_F.shape == (3, 3)
    np.testing.assert_allclose(one.N_p_P, pts.N_p_P[0], atol=1e-14)


def test_tether_position_estimate_equals_the_former_sensor_code(angles, rng):
    q4, q5, _, q7, q8, _ = angles.T
    altitude = rng.uniform(1.0, 30.0, 50)
    np.testing.assert_allclose(
        tether_position_estimate(q7, q8, altitude, q4, q5, ARM),
        old_tether_position_estimate(q7, q8, altitude, q4, q5, ARM),
        rtol=1e-14,
        atol=1e-14,
    )


@pytest.mark.parametrize("source", [SOURCE_GPS, SOURCE_TETHER])
def test_compiled_measurement_equals_the_former_sensor_code(source, angles, rng):
    for q in angles[:10]:
        x = np.concatenate([q, rng.normal(size=6), [q[5] - 0.5]])
        noise = rng.normal(scale=0.05, size=N_CHANNELS)
        x_est = np.empty(13)
        measure(x, 25.0, noise, source, ARM, x_est)
        expected = old_measured_position(x, x_est, noise, source, ARM)
        np.testing.assert_allclose(x_est[3:6], expected, rtol=1e-14, atol=1e-14)


# --- independent routes -----------------------------------------------------------------------


def test_dcm_is_a_rotation_whose_columns_are_table_i(angles):
    R = direction_cosines(*angles[:, :3].T)
    np.testing.assert_allclose(R @ np.swapaxes(R, -1, -2), np.broadcast_to(np.eye(3), R.shape),
                               atol=1e-14)  # fmt: skip
    np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=1e-14)
    for k in range(5):
        np.testing.assert_allclose(R[k], dcm_table_i(*angles[k, :3]), atol=1e-15)
    # body-1-2-3 from elementary rotations
    q4, q5, q6 = angles[0, :3]
    c, s = np.cos, np.sin
    R1 = np.array([[1, 0, 0], [0, c(q4), -s(q4)], [0, s(q4), c(q4)]])
    R2 = np.array([[c(q5), 0, s(q5)], [0, 1, 0], [-s(q5), 0, c(q5)]])
    R3 = np.array([[c(q6), -s(q6), 0], [s(q6), c(q6), 0], [0, 0, 1]])
    np.testing.assert_allclose(R[0], R1 @ R2 @ R3, atol=1e-15)


def test_points_are_the_f_axis_offsets_of_eq_2(angles, rng):
    """P = HO + N_R_F [0, 0, dO-P,3 - dO-HO,3]; TRO = O + N_R_F [dO-TRO,1, 0, 0] (eqs 2-3)."""
    position = rng.uniform(-20.0, 20.0, (50, 3))
    pts = helicopter_points(position, angles[:, :3], H)
    R = pts.N_R_F
    np.testing.assert_allclose(pts.N_p_HO, position, atol=0.0)
    np.testing.assert_allclose(pts.N_p_P, position + R @ [0.0, 0.0, ARM], atol=1e-13)
    np.testing.assert_allclose(pts.N_p_O, position - R @ [0.0, 0.0, H.d_O_HO3], atol=1e-13)
    np.testing.assert_allclose(pts.N_p_TRO - pts.N_p_O, R @ [H.d_O_TRO1, 0.0, 0.0], atol=1e-13)
    np.testing.assert_allclose(pts.N_p_MRO - pts.N_p_O, R @ [0.0, 0.0, H.d_O_MRO3], atol=1e-13)


def test_tethered_HO_puts_P_at_q9_c3_and_the_altitude_inverts(angles):
    """HO + arm f3 = q9 c3 (eqs 27, 43-45); eq 45 solved for q9 gives q9 back."""
    q4, q5, q6, q7, q8, q9 = angles.T
    HO = tethered_HO_position(q4, q5, q7, q8, q9, ARM)
    c3 = np.column_stack([np.sin(q8), -np.sin(q7) * np.cos(q8), np.cos(q7) * np.cos(q8)])
    f3 = direction_cosines(q4, q5, q6)[..., :, 2]
    np.testing.assert_allclose(HO + ARM * f3, q9[:, None] * c3, atol=1e-13)
    np.testing.assert_allclose(
        tether_length_from_altitude(HO[:, 2], q4, q5, q7, q8, ARM), q9, rtol=1e-13
    )
    pts = helicopter_points(HO, angles[:, :3], H)  # the free points agree with the tether's
    np.testing.assert_allclose(pts.N_p_P, q9[:, None] * c3, atol=1e-12)


def test_compiled_kernels_equal_the_numpy_form(angles):
    p = H.as_array()
    for q in angles[:5]:
        R, pts, HO = np.empty((3, 3)), np.empty((5, 3)), np.empty(3)
        kernels.kinematics_dcm(q, R)
        np.testing.assert_array_equal(R, direction_cosines(*q[:3]))
        free = np.array([1.0, -2.0, 9.0, *q[:3]])
        kernels.kinematics_points(free, p, pts)
        ref = helicopter_points(free[:3], free[3:], H)
        np.testing.assert_allclose(pts[[1, 4]], [ref.N_p_O, ref.N_p_P], rtol=0.0, atol=1e-15)
        kernels.kinematics_tethered_HO(q, ARM, HO)
        np.testing.assert_allclose(HO, tethered_HO_position(*q[[0, 1, 3, 4, 5]], ARM), atol=1e-15)
        length = kernels.kinematics_tether_length(q, HO[2], ARM)
        assert length == pytest.approx(q[5], rel=1e-13)


def _c3_by_rotations(q7, q8):
    """c3 = R1(q7) R2(q8) e3: C turned by q7 about n1, then by q8 about the new 2-axis
    (eq 27), by explicit rotation matrices."""
    s7, c7, s8, c8 = np.sin(q7), np.cos(q7), np.sin(q8), np.cos(q8)
    R1 = np.array([[1.0, 0.0, 0.0], [0.0, c7, -s7], [0.0, s7, c7]])
    R2 = np.array([[c8, 0.0, s8], [0.0, 1.0, 0.0], [-s8, 0.0, c8]])
    return R1 @ R2 @ np.array([0.0, 0.0, 1.0])


def test_tether_direction_is_eq_27_and_the_angles_invert_it(angles):
    """c3(q7, q8) equals the rotations of eq 27; (q7, q8, q9) of q9 c3 gives them back
    (the inverse the GNSS position source, the landing's references and the encoders use);
    the compiled kernels equal the NumPy form."""
    q7, q8, q9 = angles[:, 3], angles[:, 4], angles[:, 5]
    c3 = tether_direction(q7, q8)
    ref = np.array([_c3_by_rotations(a, b) for a, b in zip(q7, q8, strict=True)])
    np.testing.assert_allclose(c3, ref, rtol=0.0, atol=1e-15)
    back = tether_angles(q9[:, None] * c3)
    np.testing.assert_allclose(back, [q7, q8, q9], rtol=1e-13, atol=1e-13)
    e, a = np.empty(3), np.empty(3)
    for q in angles[:5]:
        kernels.kinematics_tether_direction(q, e)
        np.testing.assert_array_equal(e, tether_direction(q[3], q[4]))
        kernels.kinematics_tether_angles(q[5] * e, a)
        np.testing.assert_allclose(a, q[3:6], rtol=1e-13, atol=1e-14)


def test_P_motion_is_q9_c3_and_v_HO_plus_omega_cross_arm_f3(angles, rng):
    """P = q9 c3 and v_P = v_HO + N_R_F (w x arm e3) (eqs 7-8, 27, 43-45), with N_R_F of
    Table I (``newton_euler.dcm_table_i``) and the cross product by NumPy."""
    out, sc = np.empty(6), np.empty(10)
    for q in angles[:10]:
        x = np.concatenate([q, rng.normal(size=6), [q[5]]])
        kernels.angle_trig(x, sc)
        kernels.kinematics_P_motion_sc(x, sc, ARM, out)
        np.testing.assert_allclose(out[:3], q[5] * _c3_by_rotations(q[3], q[4]), atol=1e-13)
        R = dcm_table_i(*q[:3])
        v_P = x[6:9] + R @ np.cross(x[9:12], [0.0, 0.0, ARM])
        np.testing.assert_allclose(out[3:], v_P, rtol=0.0, atol=1e-14)
