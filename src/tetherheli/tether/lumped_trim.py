"""The hover trim of the tethered helicopter with a massive tether: the
tether hangs from P straight down to the winch in its static shape (the vertical elastic
catenary, ``tether.catenary``), the helicopter trims against the tension at P (eq 28's trim,
``model.trim.windless_trim``) and the lumped chain starts at its own exact equilibrium
(``tether.chain.static_chain``)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .._validation import check_number
from ..errors import InfeasibleError, ParameterError
from .catenary import ElasticCatenary
from .chain import LumpedTether, static_chain

if TYPE_CHECKING:
    from ..model.trim import TrimPoint
    from ..params import Params
__all__ = [
    "LumpedTrim",
    "hover_trim_lumped",
]

# ----------------------------------------------------------------------------------------------
# hover trim with a massive tether
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class LumpedTrim:
    """The hover trim of the tethered helicopter with a massive tether hanging from P straight
    down to the winch (the paper's geometry, q7 = q8 = 0).

    Parameters
    ----------
    trim : TrimPoint
        The helicopter's trim (``model.trim``): x with x[12] the unstretched length L0, u the
        hover input excluding the tether torque (Tables IV, V), ``u_total`` the rotors' actual
        inputs, ``tension`` the tension at P.
    catenary : ElasticCatenary
        The hanging tether, A the winch (the origin O) and B the point P.
    force_P : ndarray (3,)
        The force the tether exerts on P [N, in N]: -(T_ground + mu g L0) n3.
    nodes : ndarray (N+1, 3)
        The lumped chain's exact static equilibrium (``static_chain``) [m], row 0 the winch.
    """

    trim: TrimPoint
    catenary: ElasticCatenary
    force_P: np.ndarray
    nodes: np.ndarray

    @property
    def ground_tension_N(self) -> float:
        """Tension at the winch [N] (the load cell)."""
        return self.catenary.tension_A_N

    @property
    def top_tension_N(self) -> float:
        """Tension at P [N]: the ground tension plus the cable's weight."""
        return self.catenary.tension_B_N

    @property
    def unstretched_length_m(self) -> float:
        """Paid-out unstretched length L0 [m]."""
        return self.catenary.unstretched_length_m


def hover_trim_lumped(
    params: Params,
    tether: LumpedTether,
    ground_tension_N: float,
    q9: float = 10.0,
    *,
    u_min: object = None,
    u_max: object = None,
) -> LumpedTrim:
    """Hover trim with a massive tether: P at height q9 straight above the winch, the tether
    hanging in its static shape (the vertical elastic catenary) with tension
    ``ground_tension_N`` at the winch.

    The hanging cable's tension grows linearly with height, T(s) = T_g + mu g s, so the
    unstretched length L0 solves q9 = L0 + (T_g L0 + mu g L0^2 / 2) / EA (Irvine's catenary at
    zero span) and the force at P is -(T_g + mu g L0) n3: radial along c3 = n3, so the
    helicopter's trim is eq 28's trim (``trim.windless_trim``) with that tension at P.

    Parameters
    ----------
    params : Params or a model with ``.params``
        The helicopter and tether parameters.
    tether : LumpedTether
        The massive tether.
    ground_tension_N : float
        Tension at the winch [N], > 0 (the tension PI's reference, eq 56).
    q9 : float
        Height of P above the winch [m] (``params.TETHER_LENGTH_RANGE``); the paper's 10 m.
    u_min, u_max : (4,) or None
        Rotor input limits [fMR3 N, tMR1 N m, tMR2 N m, fTR2 N] (``actuators.u_min/u_max``);
        the trim's actual inputs ``u_total`` must lie strictly within them.

    Returns
    -------
    LumpedTrim
        The helicopter's trim, the hanging catenary, the force at P and the chain's nodes.

    Raises
    ------
    ParameterError
        Bad input.
    InfeasibleError
        A hover outside the rotor limits or with no trim.
    """
    from ..params import check_tether_length

    params = getattr(params, "params", params)
    if not isinstance(tether, LumpedTether):
        raise ParameterError("tether", tether, "a LumpedTether")
    T_g = check_number("ground_tension_N", ground_tension_N, low=0.0, low_open=True, unit="[N]")
    q9 = check_tether_length(q9, "q9")
    return _hover_trim_lumped(params, tether, T_g, q9, u_min=u_min, u_max=u_max)


def _hover_trim_lumped(
    params: Params,
    tether: LumpedTether,
    T_g: float,
    q9: float,
    *,
    u_min: object = None,
    u_max: object = None,
) -> LumpedTrim:
    """``hover_trim_lumped`` of arguments already checked (a run's set-up from its
    ``Scenario``: T_ref > 0 and q9 checked when it was built); the hover's own failures
    (outside the rotor limits, no trim) still raise."""
    from ..model.trim import windless_trim

    g = params.helicopter.g
    w = tether.mass_per_length_kg_m * g
    EA = tether.EA_N
    b = 1.0 + T_g / EA
    L0 = 2.0 * q9 / (b + math.sqrt(b * b + 2.0 * w * q9 / EA))  # the root of the quadratic
    # the vertical catenary with V = T_g at the winch, as solved (not recomputed from L0:
    # (q9 - L0) EA / L0 cancels to nothing for a stiff cable, e.g. EA = 1e30 N)
    cat = ElasticCatenary(0.0, q9, w, EA, L0, 0.0, T_g)
    top = cat.tension_B_N
    trim = windless_trim(params, top, q9, L0)
    u = trim.u_total
    lo = np.full(4, -np.inf) if u_min is None else np.asarray(u_min, dtype=float)
    hi = np.full(4, np.inf) if u_max is None else np.asarray(u_max, dtype=float)
    for i, name in enumerate(("fMR3", "tMR1", "tMR2", "fTR2")):
        if not lo[i] < u[i] < hi[i]:  # named as actuator_array names the massless hover's
            raise InfeasibleError(
                "actuators.u_min/u_max",
                f"{name} in [{lo[i]:g}, {hi[i]:g}]",
                f"limits around the hover need {name} = {u[i]:.6g} (the hover with the "
                f"cable's weight and {top:.6g} N at P, {T_g:g} N at the winch)",
            )
    nodes = static_chain(np.zeros(3), np.array([0.0, 0.0, q9]), L0, tether, g, ground_tension_N=T_g)
    return LumpedTrim(trim=trim, catenary=cat, force_P=np.array([0.0, 0.0, -top]), nodes=nodes)
