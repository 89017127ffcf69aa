"""Parameters: Tables II-III, eq 3, eqs 19-26, the strict loader."""

from __future__ import annotations

import math

import pytest

from tetherheli import ParameterError, Params


def test_eq3_centre_of_mass(paper):
    """Eq 3 with Table II: dO-HO,3 = (mF dO-FO,3 + mMR dO-MRO,3)/(mF + mMR) = -0.0954049 m."""
    assert paper.helicopter.d_O_HO3 == pytest.approx(-0.0954049, abs=5e-8)


def test_eqs_19_26_match_euler_inertia(paper):
    """Eqs 19-26 equal the J, h of docs/paper.md: K4p4 = J1, K456 = J2 - J3, K45 = -h, ..."""
    h = paper.helicopter
    mu = h.m_F * h.m_MR / (h.m_F + h.m_MR)
    d2 = (h.d_O_FO3 - h.d_O_MRO3) ** 2
    J1, J2, J3 = (
        h.I_F11 + h.I_MR11 + mu * d2,
        h.I_F22 + h.I_MR11 + mu * d2,
        h.I_F33 + 2 * h.I_MR11,
    )
    hr = 2 * h.I_MR11 * h.omega_MR
    assert (h.K4p4, h.K5p5, h.K6p6) == pytest.approx((J1, J2, J3), rel=1e-15)
    assert (h.K456, h.K546, h.K645) == pytest.approx((J2 - J3, J3 - J1, J1 - J2), rel=1e-14)
    assert (h.K45, h.K54) == pytest.approx((-hr, hr), rel=1e-15)


def test_table_ii_iii_values(paper):
    """Tables II and III as printed (KC in N/m, docs/paper.md)."""
    h, t = paper.helicopter, paper.tether
    assert (h.g, h.m_F, h.m_MR, h.I_F11, h.I_F22, h.I_F33, h.I_MR11) == (
        9.81,
        12.0,
        0.67,
        0.6,
        1.0,
        1.0,
        0.1159,
    )
    assert (h.omega_MR, h.d_O_FO3, h.d_O_MRO3, h.d_O_TRO1, h.d_O_P3) == (
        -141.37,
        -0.11,
        0.166,
        -1.08,
        -0.3,
    )
    assert (t.L_N0, t.K_C) == (9.375, 40.0)
    assert (paper.tension_control.T_ref, paper.tension_control.K_P, paper.tension_control.K_I) == (
        25.0,
        1.0,
        0.1,
    )
    assert h.rotor_drag_arm == 0.1 and h.t_TR2 == 0.0


def test_toml_override(tmp_path, paper):
    f = tmp_path / "p.toml"
    f.write_text("[tether]\nK_C = 60.0\n[helicopter]\nm_F = 11\n")
    p = Params.from_toml(f)
    assert p.tether.K_C == 60.0 and p.helicopter.m_F == 11.0
    assert p.helicopter.m_MR == paper.helicopter.m_MR  # untouched fields keep the paper's


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("[tether]\nKC = 1.0\n", "tether.KC"),
        ("[tether]\nK_C = 0.0\n", "tether.K_C = 0.0"),
        ("[helicopter]\nm_F = -1.0\n", "helicopter.m_F"),
        ("[helicopter]\nI_F11 = 0.0\n", "helicopter.I_F11"),
        ("[helicopter]\nm_F = 'heavy'\n", "a finite number > 0"),
        ("[helicopter]\nm_F = nan\n", "finite"),
        ("[rotor]\nx = 1\n", "rotor"),
        ("helicopter = 3\n", "a table"),
        ("[tether\n", "valid TOML"),
    ],
)
def test_toml_errors_name_field_value_allowed(tmp_path, text, needle):
    f = tmp_path / "bad.toml"
    f.write_text(text)
    with pytest.raises(ParameterError) as err:
        Params.from_toml(f)
    msg = str(err.value)
    assert needle in msg and "allowed" in msg and "\n" not in msg
    assert str(f) in msg


def test_missing_toml_file(tmp_path):
    with pytest.raises(ParameterError, match="an existing TOML file"):
        Params.from_toml(tmp_path / "nope.toml")


def test_params_are_frozen(paper):
    with pytest.raises(AttributeError):
        paper.tether.K_C = 3.0  # type: ignore[misc]
    assert math.isclose(paper.replace(tether={"K_C": 50}).tether.K_C, 50.0)
