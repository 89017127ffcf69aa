"""Hover trim: the paper's Tables IV and V to every printed digit."""

from __future__ import annotations

import numpy as np
import pytest

from tetherheli import ParameterError


def _check_table(trim, fMR3, tMR1, fTR2):
    assert np.degrees(trim.x[0]) == pytest.approx(5.29, abs=0.005)  # q4
    assert trim.x[1:5] == pytest.approx(0.0, abs=1e-12)  # q5 = q7 = q8 = 0, q6 = 0
    assert trim.x[5] == 10.0  # q9
    assert trim.x[6:12] == pytest.approx(0.0, abs=0)  # speeds
    assert trim.y[0] == pytest.approx(0.0, abs=5e-5)  # q1
    assert trim.y[1] == pytest.approx(-0.0189, abs=5e-5)  # q2
    assert trim.y[2] == pytest.approx(10.2037, abs=5e-5)  # q3
    assert trim.y[3] == 0.0  # q6
    assert trim.u[0] == pytest.approx(fMR3, abs=5e-5)
    assert trim.u[1] == pytest.approx(tMR1, abs=5e-5)
    assert trim.u[2] == pytest.approx(0.0, abs=5e-5)
    assert trim.u[3] == pytest.approx(fTR2, abs=5e-5)


def test_table_iv_free_hover(tethered):
    """Table IV (TC = 0): fMR3 = 123.7633 N, tMR1 = 1.0933 N m, fTR2 = 11.4596 N, q4 = 5.29 deg."""
    _check_table(tethered.trim(0.0), 123.7633, 1.0933, 11.4596)


def test_table_v_tethered_hover(tethered):
    """Table V (TC = 25 N): fMR3 = 148.6568 N, tMR1 = 1.3132 N m, fTR2 = 13.7645 N."""
    trim = tethered.trim(25.0)
    _check_table(trim, 148.6568, 1.3132, 13.7645)
    # Table V excludes the tether moment: the total is u0's tMR1 minus the feed-forward C1.
    arm = tethered.params.helicopter.tether_arm
    c1 = 25.0 * arm * np.sin(trim.x[0])  # eq 55 at q5 = q6 = q7 = q8 = 0
    assert trim.feedforward[1] == pytest.approx(c1, rel=1e-12)
    assert trim.t_MR1_total == pytest.approx(1.3132 - c1, abs=5e-5)


def test_trim_is_equilibrium(tethered, free):
    """At trim the full nonlinear derivative vanishes (with the eq-54 input u0 - C_f-fwd)."""
    for tension in (0.0, 25.0, 40.0):
        trim = tethered.trim(tension)
        assert np.abs(tethered.derivative(trim.x, trim.u_total)).max() < 1e-12
    ft = free.trim()
    assert np.abs(free.derivative(ft.x, ft.u)).max() < 1e-12
    np.testing.assert_allclose(ft.y, tethered.trim(0.0).y, atol=0)


def test_rotor_drag_consistency(tethered):
    """docs/paper.md: tMR3 = 0.1 m x fMR3 balances the tail rotor: 1.08 fTR2 = 0.1 fMR3."""
    for tension in (0.0, 25.0):
        u = tethered.trim(tension).u
        assert 1.08 * u[3] == pytest.approx(0.1 * u[0], rel=1e-12)


def test_free_trim_position(free):
    trim = free.trim(position=(1.0, 2.0, 3.0))
    np.testing.assert_array_equal(trim.x[:3], [1.0, 2.0, 3.0])


@pytest.mark.parametrize(
    ("tension", "q9"), [(-1.0, 10.0), (np.nan, 10.0), (25.0, 0.0), (25.0, -2.0)]
)
def test_trim_bad_input(tethered, tension, q9):
    with pytest.raises(ParameterError):
        tethered.trim(tension, q9)


def test_kept_windless_trim_is_the_solved_one_and_a_copy(tethered):
    """``hover_trim`` solves the windless trim once per parameters, tension and length (every
    trim in wind starts from it): what it returns equals ``windless_trim`` solved anew, and
    is the caller's own (changing it changes no later trim)."""
    from tetherheli.model.trim import windless_trim

    params = tethered.params
    first = tethered.trim(31.0, 12.0)
    solved = windless_trim(params, 31.0, 12.0, params.tether.natural_length(12.0, 31.0))
    for name in ("x", "u", "y", "feedforward"):
        np.testing.assert_array_equal(getattr(first, name), getattr(solved, name))
    first.x[:] = np.nan
    first.u[:] = np.nan
    again = tethered.trim(31.0, 12.0)
    np.testing.assert_array_equal(again.x, solved.x)
    np.testing.assert_array_equal(again.u, solved.u)
    windy = tethered.trim(31.0, 12.0, N_F_wind=(3.0, -1.0, 0.0))  # starts from the kept one
    np.testing.assert_allclose(windy.y[:3], solved.y[:3], atol=1e-9)
    assert np.abs(tethered.derivative(windy.x, windy.u_total, (3.0, -1.0, 0.0))).max() < 1e-9


def test_plain_python_trim_equals_the_compiled_kernels(monkeypatch):
    """The trim evaluates the generated code as plain Python (no Numba, ``model.trim``);
    solved on the compiled kernels instead (the route before issue 24 item 5), the windless
    trims of Tables IV and V and a trim in wind agree to 1e-12."""
    from types import SimpleNamespace

    import numba

    from tetherheli import Params
    from tetherheli.model import _generated as gen
    from tetherheli.model import kernels
    from tetherheli.model import trim as trim_module

    params = Params.paper()
    cases = [(0.0, 10.0, None), (25.0, 10.0, None), (25.0, 12.0, (3.0, -2.0, 0.5))]
    plain = [trim_module.hover_trim(params, t, q9, N_F_wind=w) for t, q9, w in cases]

    compiled_constants = numba.njit(fastmath={"nnan", "ninf"}, error_model="numpy")(
        gen.tethered_constants
    )

    def constants(kind, helicopter):
        assert kind == "tethered"
        c = np.empty(gen.N_TETHERED_CONSTANTS)
        compiled_constants(helicopter.as_array(), c)
        return c

    compiled_gen = SimpleNamespace(
        tethered_rhs=kernels.tethered_rhs,
        tethered_tether_torque=kernels.tethered_tether_torque,
        tethered_outputs=kernels.tethered_outputs,
    )
    monkeypatch.setattr(trim_module, "gen", compiled_gen)
    monkeypatch.setattr(trim_module, "model_constants", constants)
    # the kept windless trims (``_kept_trim``) are the plain route's: solve anew, and keep
    # none of the compiled route's for later tests
    trim_module._kept_trim.cache_clear()
    try:
        for (t, q9, w), ours in zip(cases, plain, strict=True):
            theirs = trim_module.hover_trim(params, t, q9, N_F_wind=w)
            for field in ("x", "u", "y", "feedforward"):
                a, b = getattr(ours, field), getattr(theirs, field)
                np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12, err_msg=f"{field} {t}")
            assert ours.tension == theirs.tension
    finally:
        trim_module._kept_trim.cache_clear()
    assert kernels.tethered_rhs.signatures  # the second route did run compiled code
