"""The controllers a scenario's ``[control] controller`` names, one record each
(``CONTROLLER_REGISTRY``): how the loop flies it (a compiled law of the engine or a Python
``Controller`` every sample), which configurations, tethers and manoeuvres it supports, and
how it is designed. The scenario's validation (``scenario.checks``), the run's set-up
(``runs.setup``, ``runs.closed_loop``, ``runs.batch``), ``compare`` and the controller
study read it; no other module spells a controller's abilities."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType

from ..errors import ParameterError

__all__ = ["CONTROLLERS", "CONTROLLER_REGISTRY", "ControllerEntry", "controller_entry"]


@dataclass(frozen=True)
class ControllerEntry:
    """What the run needs to know of one controller.

    Parameters
    ----------
    name : str
        Its name, the value of ``[control] controller``.
    law : str or None
        The compiled law that flies it (one of ``layout.CONTROL_LAWS``: the compiled loop and
        the lane engine run it), or None: a Python ``Controller`` called every sample through
        ``engine.stepping`` (one run at a time).
    configurations : tuple of str
        The configurations it flies ("free", "tethered").
    landing : bool
        Whether it flies a tethered landing's moving references (``control.landing``).
    ground_hold : bool
        Whether it holds a point of N over a moving base (``control.landing``'s
        ``GroundHoldController``: ``[control] reference = "ground"``).
    reference : bool
        Whether it flies a ``[reference]`` beyond hover (steps, waypoints, a CSV path, a
        take-off: ``control.flight.ReferenceController``).
    design : str
        How it is built: the design function and the paper's equations.
    """

    name: str
    law: str | None
    configurations: tuple[str, ...]
    landing: bool
    ground_hold: bool
    reference: bool
    design: str

    @property
    def compiled(self) -> bool:
        """Whether the compiled loop flies it (its law is compiled).

        Returns
        -------
        bool
            True for a law of ``layout.CONTROL_LAWS``; False for a Python controller.
        """
        return self.law is not None


#: Every controller ``[control] controller`` may name, in the order the documentation lists
#: them: the paper's scheme (Sec. V), the LQI on the tethered linearization with the reel
#: rate as a fifth input, and the constrained MPC on the same model.
CONTROLLER_REGISTRY: Mapping[str, ControllerEntry] = MappingProxyType(
    {
        entry.name: entry
        for entry in (
            ControllerEntry(
                name="paper",
                law="paper",
                configurations=("free", "tethered"),
                landing=True,
                ground_hold=True,
                reference=True,
                design="control.lqi.design_lqi on the free linearization (eqs 47-53) with "
                "feed-forward (eqs 54-55) and the winch PI (eq 56, control.tension)",
            ),
            ControllerEntry(
                name="tether_lqi",
                law="tether_lqi",
                configurations=("tethered",),
                landing=False,
                ground_hold=False,
                reference=False,
                design="control.tether_lqi.design_tether_lqi on the tethered linearization, "
                "the reel rate a fifth input ([control.tether_lqi])",
            ),
            ControllerEntry(
                name="mpc",
                law=None,
                configurations=("free", "tethered"),
                landing=False,
                ground_hold=False,
                reference=False,
                design="control.mpc_design.design_mpc and control.mpc.MPCController: the "
                "constrained, offset-free MPC on the same model, OSQP every sample "
                "([control.mpc])",
            ),
        )
    }
)
#: Their names, ``[control] controller``'s choices.
CONTROLLERS: tuple[str, ...] = tuple(CONTROLLER_REGISTRY)


def controller_entry(name: str) -> ControllerEntry:
    """The record of the controller ``name``.

    Parameters
    ----------
    name : str
        One of ``CONTROLLERS``.

    Returns
    -------
    ControllerEntry
        Its record.

    Raises
    ------
    ParameterError
        For a name not in ``CONTROLLERS``.
    """
    try:
        return CONTROLLER_REGISTRY[name]
    except (KeyError, TypeError):
        raise ParameterError("control.controller", name, f"one of {CONTROLLERS}") from None
