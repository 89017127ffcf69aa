"""A scenario's ``[reference]`` flown (``scenario.flight``): the trajectory built from the
table and the start's trim, and the paper's controller that flies it
(``control.flight.ReferenceController``). The take-off's tension schedule mirrors the
landing's (``runs.landing``): T_ref goes linearly with the climb from the start's (the
scenario's T_ref, on its short tether) to ``top_tension``, with hover trims at tensions along
it interpolated."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..control.flight import ReferenceController
from ..control.trajectory import Climb
from ..model.kinematics import tether_direction
from ..model.trim import _hover_trim
from ..scenario.flight import build_trajectory
from .landing import LANDING_TRIMS

if TYPE_CHECKING:
    from ..scenario.core import Scenario
    from .setup import EngineSetup

__all__ = ["reference_controller"]


def reference_controller(scenario: Scenario, setup: EngineSetup) -> ReferenceController:
    """The paper's controller flying ``scenario``'s ``[reference]`` from its start's trim.

    Parameters
    ----------
    scenario : Scenario
        A run with a moving ``[reference]`` (checked: the paper's controller).
    setup : EngineSetup
        Its set-up (the start's trim and law).

    Returns
    -------
    ReferenceController
    """
    K, _, y_ref, u0, u0_free, z0 = setup.law
    trim = setup.trim
    q7, q8, q9 = trim.x[3:6]
    trim_P = q9 * tether_direction(q7, q8)  # P = q9 c3 (eq 27)
    r = scenario.trajectory
    path = build_trajectory(r, start_height=float(trim.y[2]))
    tension = tables = None
    if isinstance(path, Climb):  # the take-off's tension schedule (module docstring)
        T0 = scenario.params.tension_control.T_ref
        T1 = T0 if r.top_tension is None else r.top_tension
        climb = path

        def tension(t: float) -> tuple[float, float]:
            h = climb.at(t)
            w, rate = h.position[2] / climb.height, h.velocity[2] / climb.height
            return T0 + w * (T1 - T0), rate * (T1 - T0)

        tensions = np.linspace(min(T0, T1), max(T0, T1), LANDING_TRIMS)
        trims = [_hover_trim(setup.model.params, float(T), scenario.q9) for T in tensions]
        tables = (tensions, np.array([t.u for t in trims]), np.array([t.x for t in trims]))
    return ReferenceController(
        path, trim_P, scenario.params.tether.K_C, K, trim.x, y_ref, u0, setup.ctrl,
        setup.model.constants, free_trim_input=u0_free, z_init=z0, tension=tension,
        trim_tables=tables,
    )  # fmt: skip
