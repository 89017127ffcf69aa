"""The python-control export of the linearization (``LinearModel.to_statespace``): labels in
our order (names.py), A, B equal to our linearization and its ZOH discretization (eq 46),
``control.dlqr`` reproducing the paper's LQI gain (eqs 47-53), and stabilisability of the
tethered model by the PBH test (Hautus 1969) with and without the reel rate (eq 37)."""

from __future__ import annotations

import runpy
from pathlib import Path

import control
import numpy as np
import pytest

from tetherheli._linalg import discretize_zoh
from tetherheli.control.lqi import augment_lqi
from tetherheli.errors import ParameterError
from tetherheli.model import EXPORT_INPUTS, linearize
from tetherheli.names import (
    BASE_ACCELERATION,
    INPUT,
    OUTPUT,
    REEL_RATE,
    TETHERED_STATE,
    UNITS,
    WIND,
)
from tetherheli.runs.start import LQI_STATES, paper_gain
from tetherheli.scenario.core import ControlSettings

ROTOR_AND_REEL = (*INPUT, REEL_RATE)


@pytest.fixture(scope="module")
def taut(tethered):
    """The tethered model linearized at the tension-controlled hover (taut tether, eq 28)."""
    trim = tethered.trim(tethered.params.tension_control.T_ref, 10.0)
    assert trim.tension > 0.0
    return linearize(tethered, trim)


def _pbh_ranks(A: np.ndarray, B: np.ndarray) -> list[int]:
    """rank [A - sI, B] at each eigenvalue s of A with Re s >= 0 (Hautus test)."""
    n = A.shape[0]
    return [
        int(np.linalg.matrix_rank(np.hstack([A - s * np.eye(n), B]), tol=1e-9))
        for s in np.linalg.eigvals(A)
        if s.real >= -1e-9
    ]


def test_labels_are_our_names_in_our_order(taut) -> None:
    """States, inputs and outputs carry names.py's names, in the order of A, B, C."""
    inputs = (*INPUT, REEL_RATE, *WIND, *BASE_ACCELERATION)
    sys = taut.to_statespace(inputs=inputs)
    assert sys.state_labels == list(TETHERED_STATE)
    assert sys.input_labels == list(inputs)
    assert sys.output_labels == list(OUTPUT)
    assert set(EXPORT_INPUTS) == set(inputs)
    assert all(label in UNITS for label in [*sys.state_labels, *sys.input_labels])
    # a chosen order is kept, and the columns follow it
    sub = taut.to_statespace(inputs=("Fw2", "RC", "tMR1"))
    assert sub.input_labels == ["Fw2", "RC", "tMR1"]
    np.testing.assert_array_equal(sub.B[:, 0], taut.E_wind[:, 1])
    np.testing.assert_array_equal(sub.B[:, 1], taut.B_reel)
    np.testing.assert_array_equal(sub.B[:, 2], taut.B[:, 1])
    base = taut.to_statespace(inputs=("ab3",))  # a moving winch's acceleration (issue 26)
    np.testing.assert_array_equal(base.B[:, 0], taut.E_base[:, 2])


def test_exported_matrices_equal_our_linearization(taut) -> None:
    """Continuous A, B, C are ours; the discrete export equals our ZOH (eq 46) and
    python-control's own c2d."""
    sys = taut.to_statespace(inputs=ROTOR_AND_REEL)
    np.testing.assert_array_equal(sys.A, taut.A)
    np.testing.assert_array_equal(sys.B, np.column_stack([taut.B, taut.B_reel]))
    np.testing.assert_array_equal(sys.C, taut.C)
    np.testing.assert_array_equal(sys.D, 0.0)
    dt = 0.01
    sysd = taut.to_statespace(dt, inputs=ROTOR_AND_REEL)
    assert sysd.dt == dt
    # One path: the export is our ZOH of the same (A, B), so equal to the last bit.
    G5, H5 = discretize_zoh(taut.A, taut.input_matrix(ROTOR_AND_REEL), dt)
    np.testing.assert_array_equal(sysd.A, G5)
    np.testing.assert_array_equal(sysd.B, H5)
    # Two paths: the 4-input model's exponential is a block matrix of another size, so
    # LAPACK/BLAS may round it differently (2.8e-17 under OpenBLAS's SkylakeX kernel). The
    # exponential of ||A dt|| ~ 0.1 is well conditioned (Higham 2005: relative error a small
    # multiple of n u), so allow 10 n u ||G||_1 (about 3e-14 here).
    G, H = taut.select(TETHERED_STATE).discretize(dt)
    n = G.shape[0]
    tol = 10 * n * np.finfo(float).eps * np.linalg.norm(G, 1)
    np.testing.assert_allclose(sysd.A, G, rtol=0.0, atol=tol)
    np.testing.assert_allclose(sysd.B[:, :4], H, rtol=0.0, atol=tol * max(1.0, np.abs(H).max()))
    other = control.c2d(sys, dt, method="zoh")
    np.testing.assert_allclose(sysd.A, other.A, rtol=0.0, atol=1e-12)
    np.testing.assert_allclose(sysd.B, other.B, rtol=0.0, atol=1e-12)
    assert other.state_labels == sysd.state_labels


def test_dlqr_on_the_export_is_the_paper_lqi_gain(paper, tethered) -> None:
    """eqs 47-53: control.dlqr on the labelled export with integral_action = -dt C and
    Q = C_LQI' Qy C_LQI reproduces the gain the simulator flies (runs.start.paper_gain)."""
    c = ControlSettings()
    gain = paper_gain(paper, c.dt, c.Qy, c.Ru)
    lin = linearize(tethered, tethered.trim(0.0, 10.0)).select(LQI_STATES)
    sysd = lin.to_statespace(c.dt)
    _, _, C_lqi = augment_lqi(sysd.A, sysd.B, sysd.C, c.dt)
    Q = C_lqi.T @ np.diag(c.Qy) @ C_lqi
    K, _, _ = control.dlqr(sysd, Q, np.diag(c.Ru), integral_action=-c.dt * sysd.C)
    np.testing.assert_allclose(K, gain.K, rtol=0.0, atol=1e-9 * np.max(np.abs(gain.K)))


def test_tethered_export_is_stabilisable_only_with_the_reel_rate(taut) -> None:
    """PBH: with the rotor inputs alone, rank [A - sI, B] < 13 at s = 0 (LN: eq 37 makes
    dLN/dt = RC, so its row of A and B is zero); adding RC restores rank 13 at every
    eigenvalue with Re s >= 0."""
    n = taut.A.shape[0]
    assert min(_pbh_ranks(taut.A, taut.input_matrix(INPUT))) == n - 1
    assert min(_pbh_ranks(taut.A, taut.input_matrix(ROTOR_AND_REEL))) == n
    assert taut.uncontrollable_modes(INPUT) == ((0j, "LN"),)
    assert taut.uncontrollable_modes(ROTOR_AND_REEL) == ()
    # the wind is not a control: it does not make LN controllable
    assert taut.uncontrollable_modes((*INPUT, *WIND)) == ((0j, "LN"),)
    with pytest.raises(ParameterError, match=r"s = 0\+0j \(mostly LN\).*add 'RC'") as info:
        taut.to_statespace(inputs=INPUT, require_stabilisable=True)
    assert "\n" not in str(info.value) and str(info.value).startswith("inputs = ('fMR3'")
    sys = taut.to_statespace(inputs=ROTOR_AND_REEL, require_stabilisable=True)
    # and a continuous LQR then exists on all 13 states (it fails without RC)
    K, _, E = control.lqr(sys, np.eye(n), np.eye(5))
    assert K.shape == (5, n) and np.all(E.real < 0.0)
    with pytest.raises(Exception):  # noqa: B017 - python-control's own error type
        control.lqr(taut.to_statespace(inputs=INPUT), np.eye(n), np.eye(4))


def test_default_tethered_export_has_the_reel_rate_and_lqr_succeeds(taut, free) -> None:
    """Issue 47 item 7: the default export of the tethered model is its controls, the rotor
    inputs and the reel rate RC, so control.lqr and control.dlqr with identity weights find a
    stabilising gain on all 13 states; the free model's default is the rotor inputs."""
    assert taut.control_inputs == ROTOR_AND_REEL
    sys = taut.to_statespace(require_stabilisable=True)
    assert sys.input_labels == list(ROTOR_AND_REEL) and taut.uncontrollable_modes() == ()
    np.testing.assert_array_equal(taut.input_matrix(), np.column_stack([taut.B, taut.B_reel]))
    n, m = sys.nstates, sys.ninputs
    K, _, E = control.lqr(sys, np.eye(n), np.eye(m))
    assert K.shape == (m, n) and np.all(E.real < 0.0)
    dt = ControlSettings().dt
    sysd = taut.to_statespace(dt)
    assert sysd.input_labels == list(ROTOR_AND_REEL)
    Kd, _, Ed = control.dlqr(sysd, np.eye(n), np.eye(m))
    assert Kd.shape == (m, n) and np.all(np.abs(Ed) < 1.0)
    lin_free = linearize(free, free.trim())
    assert lin_free.control_inputs == INPUT
    assert lin_free.to_statespace().input_labels == list(INPUT)


def test_bad_inputs_are_named(taut, free) -> None:
    with pytest.raises(ParameterError, match=r"inputs = .*'wind'.*allowed: names from"):
        taut.to_statespace(inputs=("fMR3", "wind"))
    with pytest.raises(ParameterError, match="at most once"):
        taut.to_statespace(inputs=("fMR3", "fMR3"))
    lin_free = linearize(free, free.trim())
    with pytest.raises(ParameterError, match="'RC' only on a model whose state has LN"):
        lin_free.to_statespace(inputs=ROTOR_AND_REEL)
    assert lin_free.to_statespace().state_labels == list(lin_free.state_names)


def test_docs_example_runs(capsys) -> None:
    """docs/python_control.md shows docs/python_control_example.py verbatim, and it runs:
    its dlqr gain equals ours exactly as printed there."""
    docs = Path(__file__).resolve().parents[1] / "docs"
    script = (docs / "python_control_example.py").read_text()
    page = (docs / "python_control.md").read_text()
    assert "```python\n" + script + "```" in page
    runpy.run_path(str(docs / "python_control_example.py"), run_name="__main__")
    out = capsys.readouterr().out
    assert "max |K_dlqr - K_ours| =" in out
    diff = float(out.split("max |K_dlqr - K_ours| =")[1].split()[0])
    assert diff <= 1e-9
    assert out.strip().splitlines()[-1] in page
