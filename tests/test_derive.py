"""Kane's method (sympy.physics.mechanics) reproduces the paper's printed equations."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from sympy.physics.mechanics import ReferenceFrame, dynamicsymbols, inertia

from tetherheli.model import _generated, codegen
from tetherheli.model.derive import derive, parameter_symbols, rotor_inertia_dyadic

from .newton_euler import dcm_table_i


@pytest.fixture(scope="module")
def free_d():
    return derive("free")


@pytest.fixture(scope="module")
def tethered_d():
    return derive("tethered")


def _paper_forms(d):
    """The right-hand sides of eqs 13-18 (and 30-35 for the tethered model), typed here."""
    p = parameter_symbols()
    s = {
        i: sp.sin(q)
        for i, q in zip(range(4, 7), d.q[-6:][:3] if d.kind == "tethered" else d.q[3:], strict=True)
    }
    c = {
        i: sp.cos(q)
        for i, q in zip(range(4, 7), d.q[-6:][:3] if d.kind == "tethered" else d.q[3:], strict=True)
    }
    f_MR3, t_MR1, t_MR2, f_TR2 = d.inputs
    u = d.u
    m = p["m_F"] + p["m_MR"]
    mu_d2 = p["m_F"] * p["m_MR"] * (p["d_O_FO3"] - p["d_O_MRO3"]) ** 2 / m
    d_HO = (p["m_F"] * p["d_O_FO3"] + p["m_MR"] * p["d_O_MRO3"]) / m
    K4p4 = mu_d2 + p["I_F11"] + p["I_MR11"]  # eq 19
    K456 = mu_d2 + p["I_F22"] - p["I_F33"] - p["I_MR11"]  # eq 20
    K45 = -2 * p["I_MR11"] * p["omega_MR"]  # eq 21
    K5p5 = mu_d2 + p["I_F22"] + p["I_MR11"]  # eq 22
    K546 = -mu_d2 + p["I_F33"] - p["I_F11"] + p["I_MR11"]  # eq 23
    K54 = 2 * p["I_MR11"] * p["omega_MR"]  # eq 24
    K6p6 = p["I_F33"] + 2 * p["I_MR11"]  # eq 25
    K645 = p["I_F11"] - p["I_F22"]  # eq 26
    t_MR3 = p["rotor_drag_arm"] * f_MR3
    rhs = [
        (f_MR3 * s[5] - f_TR2 * c[5] * s[6]) / m,  # eq 13
        (f_TR2 * (c[4] * c[6] - s[4] * s[5] * s[6]) - f_MR3 * s[4] * c[5]) / m,  # eq 14
        (f_MR3 * c[4] * c[5] + f_TR2 * (s[4] * c[6] + c[4] * s[5] * s[6]) - m * p["g"]) / m,
        (t_MR1 + d_HO * f_TR2 + (K456 * u[5] + K45) * u[4]) / K4p4,  # eq 16
        (t_MR2 + p["t_TR2"] + (K546 * u[5] + K54) * u[3]) / K5p5,  # eq 17
        (t_MR3 + p["d_O_TRO1"] * f_TR2 + K645 * u[3] * u[4]) / K6p6,  # eq 18
    ]
    if d.kind == "tethered":
        T = d.tension
        s7, c7 = sp.sin(d.q[3]), sp.cos(d.q[3])
        s8, c8 = sp.sin(d.q[4]), sp.cos(d.q[4])
        arm = p["d_O_P3"] - d_HO
        rhs[0] += -T * s8 / m  # eq 30
        rhs[1] += T * s7 * c8 / m  # eq 31
        rhs[2] += -T * c7 * c8 / m  # eq 32
        rhs[3] += (
            T
            * arm
            * (
                c7 * c8 * (s[4] * c[6] + s[5] * s[6] * c[4])
                - s7 * c8 * (c[4] * c[6] - s[4] * s[5] * s[6])
                - s[6] * s8 * c[5]
            )
            / K4p4
        )  # eq 33
        rhs[4] += (
            T
            * arm
            * (
                s7 * c8 * (s[6] * c[4] + s[4] * s[5] * c[6])
                - c7 * c8 * (s[4] * s[6] - s[5] * c[4] * c[6])
                - s8 * c[5] * c[6]
            )
            / K5p5
        )  # eq 34
    return rhs


@pytest.mark.parametrize("kind", ["free", "tethered"])
def test_dynamics_equal_paper_eqs_13_18_and_30_35(kind, free_d, tethered_d):
    """Eqs 13-18 (free) and 30-35 (tethered): derived minus printed simplifies to zero.

    ``sp.cancel`` brings the difference to one fraction of polynomials in the symbols, sines
    and cosines: zero there is zero identically (about 1 s for all twelve, where
    ``sp.simplify`` took 25 s); ``sp.simplify`` remains the judge of any difference it leaves."""
    d = free_d if kind == "free" else tethered_d
    no_wind = dict.fromkeys(d.wind, 0)
    for derived, printed in zip(d.udot, _paper_forms(d), strict=True):
        difference = derived.subs(no_wind) - printed
        assert sp.cancel(difference) == 0 or sp.simplify(sp.expand(difference)) == 0


@pytest.mark.parametrize("kind", ["free", "tethered"])
def test_euler_kinematics_eqs_10_12(kind, free_d, tethered_d):
    """Eqs 10-12: q4' = -(s6 u5 - c6 u4)/c5, q5' = s6 u4 + c6 u5,
    q6' = u6 + s5 (s6 u5 - c6 u4)/c5."""
    d = free_d if kind == "free" else tethered_d
    _q4, q5, q6 = d.q[:3] if kind == "tethered" else d.q[3:]
    u4, u5, u6 = d.u[3:]
    s5, c5, s6, c6 = sp.sin(q5), sp.cos(q5), sp.sin(q6), sp.cos(q6)
    printed = [-(s6 * u5 - c6 * u4) / c5, s6 * u4 + c6 * u5, u6 + s5 * (s6 * u5 - c6 * u4) / c5]
    offset = 0 if kind == "tethered" else 3
    for i in range(3):
        assert sp.simplify(d.qdot[offset + i] - printed[i]) == 0
    if kind == "free":
        assert list(d.qdot[:3]) == list(d.u[:3])  # eq 9


def test_dcm_is_table_i(free_d):
    """Table I: N.dcm(F) from body-fixed 1-2-3 Euler angles equals the printed matrix."""
    q4, q5, q6 = free_d.q[3:]
    vals = {q4: 0.3, q5: -0.7, q6: 1.1}
    got = np.array(free_d.dcm.subs(vals).evalf(), dtype=float)
    np.testing.assert_allclose(got, dcm_table_i(0.3, -0.7, 1.1), atol=1e-15)


def test_rotor_dyadic_identity():
    """Eq 1: the spinning thin-disc dyadic written in MR equals the same dyadic in F."""
    t = dynamicsymbols._t
    I11, w = sp.symbols("I11 w")
    F = ReferenceFrame("F")
    MR = ReferenceFrame("MR")
    MR.orient_axis(F, F.z, w * t)
    in_mr = inertia(MR, I11, I11, 2 * I11).to_matrix(F)
    assert sp.simplify(in_mr - rotor_inertia_dyadic(F, I11).to_matrix(F)) == sp.zeros(3, 3)


def test_tethered_outputs_eqs_43_45(tethered_d):
    """Eqs 43-45 with the eq-43 typo fixed (s5, docs/paper.md)."""
    p = parameter_symbols()
    q4, q5, _q6, q7, q8, q9 = tethered_d.q
    m = p["m_F"] + p["m_MR"]
    arm = p["d_O_P3"] - (p["m_F"] * p["d_O_FO3"] + p["m_MR"] * p["d_O_MRO3"]) / m
    printed = [
        q9 * sp.sin(q8) - arm * sp.sin(q5),
        -q9 * sp.sin(q7) * sp.cos(q8) + arm * sp.sin(q4) * sp.cos(q5),
        q9 * sp.cos(q7) * sp.cos(q8) - arm * sp.cos(q4) * sp.cos(q5),
    ]
    for i in range(3):
        assert sp.simplify(tethered_d.outputs[i] - printed[i]) == 0


def test_eq29_kinematics_reproduce_velocity(tethered_d, rng):
    """Eq 29: d/dt of HO's position (eqs 43-45) with q' = M u gives back u1..u3 (eq 7)."""
    d = tethered_d
    t = dynamicsymbols._t
    qdot_map = {qi.diff(t): d.qdot[i] for i, qi in enumerate(d.q)}
    vel = [sp.diff(d.outputs[i], t).subs(qdot_map) for i in range(3)]
    params = dict(
        zip(
            d.params,
            [9.81, 12, 0.67, 0.6, 1, 1, 0.1159, -141.37, -0.11, 0.166, -1.08, -0.3, 0.1, 0.0],
            strict=True,
        )
    )
    for _ in range(3):
        vals = dict(zip(d.q, rng.uniform(-0.6, 0.6, 6), strict=True))
        vals[d.q[5]] = 8.0
        vals.update(zip(d.u, rng.normal(size=6), strict=True))
        for i in range(3):
            assert float(vel[i].subs(params).subs(vals)) == pytest.approx(
                float(vals[d.u[i]]), abs=1e-12
            )


def test_generated_code_matches_fresh_derivation(rng):
    """The committed generated code equals a fresh derivation (numerically always, and
    textually when the SymPy version is the one that generated it)."""
    if _generated.SYMPY_VERSION == sp.__version__:
        assert codegen.GENERATED_PATH.read_text() == codegen.generate_source()
    fresh: dict = {}
    exec(compile(codegen.generate_source(), "fresh", "exec"), fresh)
    p = np.array([9.81, 12, 0.67, 0.6, 1, 1, 0.1159, -141.37, -0.11, 0.166, -1.08, -0.3, 0.1, 0.0])
    for kind in ("free", "tethered"):
        for _ in range(5):
            x = rng.uniform(-0.5, 0.5, 12)
            x[5] = 9.0
            inp, wind, tension = rng.normal(size=4) * 10, rng.normal(size=3), 17.0
            a, b = np.empty(12), np.empty(12)
            c_fresh = np.empty(fresh[f"N_{kind.upper()}_CONSTANTS"])
            c_ours = np.empty(getattr(_generated, f"N_{kind.upper()}_CONSTANTS"))
            fresh[f"{kind}_constants"](p, c_fresh)
            getattr(_generated, f"{kind}_constants")(p, c_ours)
            fresh[f"{kind}_rhs"](x, inp, wind, tension, c_fresh, a)
            getattr(_generated, f"{kind}_rhs")(x, inp, wind, tension, c_ours, b)
            np.testing.assert_array_equal(a, b)
