"""After the tether lets go: the paper controller's transient when the safety device (Sec.
IV-C) releases the tether, with the switch to the free trim (``engine.paper_sample``) against
the controller that keeps the tethered trim input u0|T (the behaviour before the switch).

On release the winch and the feed-forward (eq 55) stop and the LQI works about the free hover's
input u0|F (Table IV); kept at u0|T (Table V) the collective is about 25 N too high and the
helicopter climbs until the integrator (eq 50) has unwound the difference.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..control.paper import PaperController
from ..errors import ParameterError
from ..results.result import SimulationResult, SummaryRepr
from ..runs import simulate
from ..runs.setup import engine_setup
from ..scenario import Scenario

__all__ = ["ReleaseComparison", "altitude_excursion", "release_comparison"]


def altitude_excursion(result: SimulationResult) -> float:
    """max |q3 - q3_trim| [m] from the release on (the whole run without a release).

    Parameters
    ----------
    result : SimulationResult
        A tethered run.

    Returns
    -------
    float
        The altitude excursion [m].
    """
    k = 0 if result.release_time is None else int(np.searchsorted(result.time, result.release_time))
    return float(np.max(np.abs(result.outputs[k:, 2] - result.trim_output[2])))


@dataclass(frozen=True, repr=False)
class ReleaseComparison(SummaryRepr):
    """A tether release flown twice (``release_comparison``).

    Parameters
    ----------
    switched : SimulationResult
        The run as simulated (u0|F after the release).
    kept : SimulationResult
        The same run with the tethered trim input u0|T kept after the release (Python loop,
        same phases).
    """

    switched: SimulationResult
    kept: SimulationResult

    def _summary_rows(self) -> list[tuple[str, str]]:
        return [(q, f"kept u0|T {k}, switched to u0|F {s}") for q, k, s in self.rows()]

    def rows(self) -> list[tuple[str, str, str]]:
        """(quantity, kept u0|T, switched to u0|F) for a table.

        Returns
        -------
        list of (str, str, str)
            The release time [s], the altitude excursion [m] and fMR3 one sample after the
            release [N], formatted.
        """
        k, s = self.kept, self.switched
        return [
            ("tether released at [s]", f"{k.release_time:g}", f"{s.release_time:g}"),
            (
                "altitude excursion after the release, max abs(q3 - q3_trim) [m]",
                f"{altitude_excursion(k):.3f}",
                f"{altitude_excursion(s):.3f}",
            ),
            (
                "fMR3 one sample after the release [N]",
                f"{_after_release(k, 1)[0]:.1f}",
                f"{_after_release(s, 1)[0]:.1f}",
            ),
        ]


def _after_release(result: SimulationResult, samples: int) -> np.ndarray:
    assert result.release_time is not None  # a released run
    k = int(np.searchsorted(result.time, result.release_time)) + samples
    return result.inputs[k]


def release_comparison(scenario: Scenario) -> ReleaseComparison:
    """Simulate a tethered ``scenario`` whose tether is released (finite
    ``actuators.breaking_tension``), switched to the free trim and with u0|T kept.

    Parameters
    ----------
    scenario : Scenario
        A tethered scenario whose tether is released during the run.

    Returns
    -------
    ReleaseComparison
        The two runs.
    """
    if scenario.configuration != "tethered":
        raise ParameterError("configuration", scenario.configuration, "'tethered'")
    switched = simulate(scenario)
    if switched.release_time is None:
        raise ParameterError(
            "actuators.breaking_tension",
            scenario.actuators.breaking_tension,
            "a tension the run exceeds (the tether is never released)",
        )
    setup = engine_setup(scenario)
    t = setup.trim
    kept_controller = PaperController(
        setup.gain.K, t.x, t.y, t.u, setup.ctrl, setup.model.constants, free_trim_input=t.u
    )
    kept = simulate(scenario, controller=kept_controller)
    return ReleaseComparison(switched, kept)
