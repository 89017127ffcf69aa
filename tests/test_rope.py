"""The rope law of a short tether (issue 46, item 4): TC = EA (q9 - LN) / LN, against its
analytic values (the tension-length curve, the trim's natural length LN = q9 EA / (EA + TC),
the stiffness EA / LN of the linearizations by finite differences), against the lumped chain
of ``tether.chain`` in its limit of zero mass (the chain's statics, Irvine's elastic catenary
at vanishing weight: its tension is EA times the strain), and flown in a landing (the issue's
4 % strain at touchdown). The paper's EA: Table III's KC = 40 N/m at L0N = 9.375 m, EA =
KC L0N = 375 N."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tetherheli import ParameterError, TetheredHelicopter, simulate
from tetherheli.control.tether_lqi import _tethered_design
from tetherheli.model import kernels
from tetherheli.model.linearization import linearize
from tetherheli.model.trim import hover_trim
from tetherheli.params import Params
from tetherheli.scenario.core import scenario_from_dict
from tetherheli.shipped import shipped_scenario
from tetherheli.status import Status
from tetherheli.tether.chain import LumpedTether, end_forces, static_chain
from tetherheli.tether.lumped_trim import hover_trim_lumped

EA = 40.0 * 9.375  # [N] Table III: KC L0N
G = 9.81


@pytest.fixture(scope="module")
def rope() -> Params:
    """The paper's parameters with the rope law at the paper's EA."""
    return Params.paper().replace(tether={"EA": EA})


def test_tension_length_curve(rope):
    """T(q9) at fixed LN is EA (q9 - LN) / LN when taut and 0 when slack, in Python
    (``TetherParams.tension``), compiled (``kernels.tether_tension``) and the model's
    (``TetheredHelicopter.tension``); the issue's figure: EA / LN = 3.4 kN/m at LN = 0.11 m."""
    model = TetheredHelicopter(rope)
    for L_N in (0.11, 2.0, 9.375):
        for q9 in np.linspace(0.5 * L_N, 1.5 * L_N, 11):
            expected = EA * (q9 - L_N) / L_N if q9 > L_N else 0.0
            assert rope.tether.tension(q9, L_N) == pytest.approx(expected, rel=1e-14, abs=0.0)
            assert kernels.tether_tension(q9, L_N, 40.0, EA) == rope.tether.tension(q9, L_N)
            x = np.zeros(13)
            x[5], x[12] = q9, L_N
            assert model.tension(x) == rope.tether.tension(q9, L_N)
    assert rope.tether.stiffness(0.12, 0.11)[0] == pytest.approx(3409.09, abs=0.01)
    # the paper's law is unchanged: KC (q9 - LN), whatever LN
    assert kernels.tether_tension(10.3, 9.375, 40.0, 0.0) == 40.0 * (10.3 - 9.375)
    assert Params.paper().tether.law == "paper" and rope.tether.law == "rope"


@pytest.mark.parametrize(("tension", "q9"), [(25.0, 10.0), (8.0, 0.5), (25.0, 50.0)])
def test_hover_trim_natural_length_is_analytic(rope, tension, q9):
    """The trim's LN is the rope's LN = q9 EA / (EA + TC); the rest of the trim (attitude,
    inputs, outputs) is the paper law's at the same tension: the law only sets LN."""
    trim = hover_trim(rope, tension, q9)
    assert trim.x[12] == pytest.approx(q9 * EA / (EA + tension), rel=1e-14)
    assert rope.tether.tension(trim.x[5], trim.x[12]) == pytest.approx(tension, rel=1e-12)
    paper = hover_trim(Params.paper(), tension, q9)
    assert trim.x[:12] == pytest.approx(paper.x[:12], abs=1e-12)
    assert trim.u_total == pytest.approx(paper.u_total, abs=1e-12)
    assert trim.y == pytest.approx(paper.y, abs=1e-12)


def test_trim_in_wind_keeps_the_rope_law(rope):
    """In a steady wind the trim's q9 moves; its LN is still the rope's at that q9."""
    trim = hover_trim(rope, 25.0, 10.0, N_F_wind=(5.0, 0.0, 0.0))
    assert trim.x[12] == pytest.approx(trim.x[5] * EA / (EA + 25.0), rel=1e-12)


@pytest.mark.parametrize("q9", [10.0, 1.0])
def test_linearization_stiffness_against_finite_differences(rope, q9):
    """The tethered linearization's columns on q9 and LN (eqs 41-46 with the rope's dTC/dq9 =
    EA / LN, dTC/dLN = -EA q9 / LN^2) against central differences of the model's derivative;
    the tethered LQI's tension row (``_tethered_design``) against those of the tension."""
    model = TetheredHelicopter(rope)
    trim = hover_trim(rope, 25.0, q9)
    lin = linearize(model, trim)
    x0, u0 = trim.x, trim.u_total
    for col in (5, 12):
        h = 1e-6 * x0[col]
        xp, xm = x0.copy(), x0.copy()
        xp[col] += h
        xm[col] -= h
        fd = (model.derivative(xp, u0) - model.derivative(xm, u0)) / (2 * h)
        assert lin.A[:, col] == pytest.approx(fd, rel=1e-6, abs=1e-6)
    # the rope differs from eq 28 here: KC = 40 N/m would give another column
    L_N = x0[12]
    assert EA / L_N != pytest.approx(40.0, rel=0.01) or q9 == 10.0
    *_, c_t = _tethered_design(rope, 25.0, q9, 0.01)
    h = 1e-7 * q9
    T = rope.tether.tension
    assert c_t[5] == pytest.approx((T(x0[5] + h, L_N) - T(x0[5] - h, L_N)) / (2 * h), rel=1e-7)
    assert c_t[12] == pytest.approx((T(x0[5], L_N + h) - T(x0[5], L_N - h)) / (2 * h), rel=1e-7)


@pytest.mark.parametrize(("L0", "strain", "offset"), [(0.11, 0.04, 0.0), (9.375, 0.0667, 0.3)])
def test_lumped_chain_tends_to_the_rope_without_mass(L0, strain, offset):
    """The lumped chain (``static_chain``, ``end_forces``) at the same EA and unstretched
    length, its mass per length going to zero: the tension at P tends to the rope's
    EA (L - L0) / L0 at the chain's span L (the weight mu g L0 is the difference); the
    landing's 0.11 m at 4 % and a paper-length tether P off the vertical."""
    L = L0 * (1.0 + strain)
    direction = np.array([offset, 0.0, 1.0]) / math.hypot(offset, 1.0)
    r_P = L * direction
    rope = EA * (L - L0) / L0
    errors = []
    for mu in (1e-2, 1e-4, 1e-6):
        chain = LumpedTether(segments=10, mass_per_length_kg_m=mu, EA_N=EA, damping_ratio=0.0,
                             ground_stiffness_Pa_m=0.0)  # fmt: skip
        guess = rope if offset == 0.0 else None
        x = static_chain(np.zeros(3), r_P, L0, chain, G, ground_tension_N=guess)
        zero = np.zeros_like(x)
        _, force_P, _ = end_forces(x, zero, zero, L0, chain.packed(G))
        top = float(np.linalg.norm(force_P))
        errors.append(abs(top - rope))
        assert 0.0 < top - rope <= 0.5 * mu * G * L0 * (1.0 + 1e-6)  # P carries half the weight
    assert errors[1] < 0.02 * errors[0] and errors[2] < 0.02 * errors[1]  # ~ mu


@pytest.mark.parametrize("q9", [10.0, 50.0])
def test_lumped_trim_tends_to_the_rope_trim(rope, q9):
    """The massive tether's hover trim (``hover_trim_lumped``) at mu -> 0 with EA = 375 N:
    its unstretched length is the rope's trim LN = q9 EA / (EA + TC) (eq 28's q9 - TC / KC
    agrees only at the paper's q9 = 10 m, where KC = EA / L0N)."""
    chain = LumpedTether(segments=10, mass_per_length_kg_m=1e-12, EA_N=EA, damping_ratio=0.0,
                         ground_stiffness_Pa_m=0.0)  # fmt: skip
    lt = hover_trim_lumped(Params.paper(), chain, 25.0, q9)
    assert lt.unstretched_length_m == pytest.approx(hover_trim(rope, 25.0, q9).x[12], rel=1e-9)


def test_landing_with_the_rope_lands_at_the_issues_strain():
    """The shipped calm-deck landing flies the rope (the landing's default law, the paper's
    EA): it lands, and at touchdown the tether's strain (q9 - LN) / LN = TC / EA is near the
    issue's 4 % at the landing tension 15 N (15 / 375; measured 3.96 %), where eq 28 at
    KC = 400 N/m strained it 34.6 %."""
    s = shipped_scenario("landing_calm_deck")
    assert s.params.tether.law == "rope" and s.params.tether.EA == EA
    r = simulate(s)
    assert r.status == Status.LANDED, r.message
    k = int(np.searchsorted(r.time, r.touchdown["time"]))
    q9, L_N = r.states[k, 5], r.states[k, 12]
    strain = (q9 - L_N) / L_N
    assert strain == pytest.approx(0.04, abs=0.003)
    assert strain == pytest.approx(r.tension[k] / EA, rel=1e-9)


def _hover(**tether) -> dict:
    return {"name": "rope", "duration": 1.0, "tether": tether}


def test_scenario_law_rules():
    """``[tether] law`` and ``EA``: the paper's law by default, the rope by default in a
    landing (EA 375 N unless given), EA required with the rope and refused with eq 28's law,
    the rope refused on the lumped chain; [params.tether] EA, a record's echo of the law, must
    agree with [tether]'s."""
    assert scenario_from_dict(_hover()).params.tether.EA == 0.0
    assert scenario_from_dict(_hover(law="rope", EA=500.0)).params.tether.EA == 500.0
    echo = {**_hover(law="rope", EA=500.0), "params": {"tether": {"EA": 500.0}}}
    assert scenario_from_dict(echo).params.tether.EA == 500.0
    landing = shipped_scenario("landing_calm_deck")
    paper = landing.replace(
        tether=landing.tether.__class__(law="paper"),
        params=landing.params.replace(tether={"K_C": 400.0}),
    )
    assert paper.params.tether.EA == 0.0 and paper.params.tether.K_C == 400.0
    cases = [
        (_hover(law="rope"), "tether.EA"),
        (_hover(EA=375.0), "tether.EA"),
        (_hover(law="rope", EA=375.0, model="lumped"), "tether.law"),
        (_hover(law="string"), "tether.law"),
        ({**_hover(), "params": {"tether": {"EA": 375.0}}}, "params.tether.EA"),  # not [tether]'s
    ]
    for data, field in cases:
        with pytest.raises(ParameterError) as info:
            scenario_from_dict(data)
        assert info.value.field == field and "\n" not in str(info.value)


def test_sweeps_and_dispersions_reach_the_law_through_the_scenario():
    """The law's EA is the scenario's ``[tether] EA``: a sweep of ``tether.EA`` sets it there
    (the rope's EA flown), a Monte Carlo dispersion of it is refused (one line)."""
    from tetherheli.studies.montecarlo.config import montecarlo_config_from_dict
    from tetherheli.studies.sweep import _with

    landing = shipped_scenario("landing_calm_deck")
    assert _with(landing, "tether.EA", 500.0).params.tether.EA == 500.0
    with pytest.raises(ParameterError) as info:
        montecarlo_config_from_dict({"params": {"tether.EA": 10.0}})
    assert info.value.field == "montecarlo.params.tether.EA"


def test_rope_in_the_lanes_equals_the_single_run():
    """A batch of rope runs in the lane engine (``engine.lanes``: the law per lane) gives the
    single compiled runs' summaries; at q9 = 2 m the rope (EA / LN = 200 N/m) and eq 28 (40
    N/m) fly differently."""
    from tetherheli.runs.batch import run_batch
    from tetherheli.scenario.core import paper_scenario

    base = paper_scenario(1, "tethered").replace(duration=20.0, q9=2.0)  # the pulse at 10 s
    rope = base.replace(tether=base.tether.__class__(law="rope", EA=EA))
    runs = [rope, rope.replace(q9=3.0), base]
    batch = run_batch(runs, workers=1)
    for i, s in enumerate(runs):
        single = simulate(s)
        assert bool(batch.ok[i]) and single.ok
        assert batch.metrics(i)["tension_max"] == pytest.approx(single.tension.max(), rel=1e-12)
        assert batch.metrics(i)["peak_q1"] == pytest.approx(
            np.abs(single.outputs[:, 0] - single.trim_output[0]).max(), rel=1e-12
        )
    assert batch.metrics(0)["tension_max"] != pytest.approx(
        batch.metrics(2)["tension_max"], rel=1e-3
    )
