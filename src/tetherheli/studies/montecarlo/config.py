"""The dispersions of a Monte Carlo: ``MonteCarloConfig``, the strict loading and validation
of the ``[montecarlo]`` table (its keys: see ``tetherheli.studies.montecarlo``)."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..._validation import check_bool, check_integer, check_number
from ...errors import ParameterError
from ...params import Params
from ...scenario.core import Scenario, read_scenario_table, scenario_from_dict
from ...wind import (
    ConstantForce,
    Disturbance,
    NoWind,
    Pulse,
    Sine,
    SteadyWind,
    Step,
    Turbulence,
    WindSum,
)

__all__ = [
    "CONFIGURATIONS",
    "MAX_RUNS",
    "MonteCarloConfig",
    "load_montecarlo",
    "montecarlo_config_from_dict",
]

CONFIGURATIONS = ("free", "tethered")
MAX_RUNS = 10_000_000
MAX_JITTER_S = 3600.0
_MC_KEYS = {
    "runs",
    "seed",
    "amplitude_std_percent",
    "direction_std_deg",
    "random_phase",
    "start_jitter_s",
    "params",
}


@dataclass(frozen=True)
class MonteCarloConfig:
    """The dispersions of a Monte Carlo (the ``[montecarlo]`` table), validated.

    Parameters
    ----------
    runs : int
        Number of draws N (each run free and tethered).
    seed : int
        Root seed of ``numpy.random.SeedSequence``.
    amplitude_std_percent : float
        Standard deviation of the wind magnitude scale [%], in [0, 100].
    direction_std_deg : float
        Standard deviation of the wind direction's rotation about n3 [deg], in [0, 180].
    random_phase : bool
        Draw sine phases uniformly in [0, 2 pi).
    start_jitter_s : float
        Standard deviation of the wind profile's time shift [s], in [0, 3600].
    params : tuple of (str, float)
        ``("section.field", p)``: uniform uncertainty of +-p% (0 <= p < 100), sorted by name.
    """

    runs: int = 100
    seed: int = 0
    amplitude_std_percent: float = 0.0
    direction_std_deg: float = 0.0
    random_phase: bool = False
    start_jitter_s: float = 0.0
    params: tuple[tuple[str, float], ...] = ()

    def to_dict(self) -> dict[str, Any]:
        """Plain data (recorded in summary.json).

        Returns
        -------
        dict of str to object
            The fields, ``params`` as a dict "section.field" -> p [%].
        """
        d = dataclasses.asdict(self)
        d["params"] = dict(self.params)
        return d


def montecarlo_config_from_dict(data: Any, *, source: str | None = None) -> MonteCarloConfig:
    """Validate a ``[montecarlo]`` table (see the module docstring).

    Parameters
    ----------
    data : dict
        The table as TOML reads it.
    source : str, optional
        The file it came from, for the error messages.

    Returns
    -------
    MonteCarloConfig
        The validated dispersions.

    Raises
    ------
    ParameterError
        Unknown keys, wrong types, negative or absurd dispersions, unknown parameter names.
    """
    try:
        if not isinstance(data, dict):
            raise ParameterError("montecarlo", data, "a table")
        for k in data:
            if k not in _MC_KEYS:
                raise ParameterError(f"montecarlo.{k}", data[k], f"one of {sorted(_MC_KEYS)}")
        kw: dict[str, Any] = {}
        if "runs" in data:
            kw["runs"] = check_integer("montecarlo.runs", data["runs"], low=1, high=MAX_RUNS)
        if "seed" in data:
            kw["seed"] = check_integer("montecarlo.seed", data["seed"], low=0, high=2**63 - 1)
        if "amplitude_std_percent" in data:
            kw["amplitude_std_percent"] = check_number(
                "montecarlo.amplitude_std_percent",
                data["amplitude_std_percent"],
                low=0.0,
                high=100.0,
            )
        if "direction_std_deg" in data:
            kw["direction_std_deg"] = check_number(
                "montecarlo.direction_std_deg", data["direction_std_deg"], low=0.0, high=180.0
            )
        if "random_phase" in data:
            kw["random_phase"] = check_bool("montecarlo.random_phase", data["random_phase"])
        if "start_jitter_s" in data:
            kw["start_jitter_s"] = check_number(
                "montecarlo.start_jitter_s", data["start_jitter_s"], low=0.0, high=MAX_JITTER_S
            )
        if "params" in data:
            p = data["params"]
            if not isinstance(p, dict):
                raise ParameterError("montecarlo.params", p, 'a table {"section.field" = percent}')
            known = Params.field_docs()
            items = []
            for name, pct in p.items():
                if name not in known or name == "tether.EA":  # EA: the scenario's [tether]
                    raise ParameterError(
                        f"montecarlo.params.{name}", pct,
                        f"one of {sorted(set(known) - {'tether.EA'})}",
                    )  # fmt: skip
                pct = check_number(
                    f"montecarlo.params.{name}", pct, low=0.0, high=100.0, high_open=True
                )
                items.append((name, pct))
            kw["params"] = tuple(sorted(items))
        return MonteCarloConfig(**kw)
    except ParameterError as exc:
        if source is None:
            raise
        raise ParameterError(exc.field, exc.value, exc.allowed, source=source) from None


def load_montecarlo(path: str | Path) -> tuple[Scenario, MonteCarloConfig]:
    """Load a scenario TOML file with a ``[montecarlo]`` table.

    Parameters
    ----------
    path : str or Path
        The scenario file.

    Returns
    -------
    (Scenario, MonteCarloConfig)
        The nominal scenario and the dispersions.
    """
    data, source = read_scenario_table(path)
    if "montecarlo" not in data:
        raise ParameterError(
            "[montecarlo]", "missing", "a scenario file with a [montecarlo] table of "
            "dispersions (e.g. tetherheli scenarios montecarlo_paper_sim1)", source=source,
        )  # fmt: skip
    config = montecarlo_config_from_dict(data.pop("montecarlo"), source=source)
    maneuver = data.get("maneuver")
    if isinstance(maneuver, dict) and maneuver.get("type", "none") != "none":
        # each draw flies free and tethered; a landing has no free run (checked before the
        # scenario, whose free twin would be refused for a reason the file does not show)
        raise ParameterError(
            "maneuver.type", maneuver["type"], "'none' in a Monte Carlo (each draw is flown "
            "free and tethered, and a tethered landing has no free run: fly a landing with "
            "simulate, sweep or run_batch)", source=source,
        )  # fmt: skip
    reference = data.get("reference")
    if isinstance(reference, dict) and reference.get("type") == "takeoff":
        raise ParameterError(
            "reference.type", "takeoff", "another type in a Monte Carlo (each draw is flown "
            "free and tethered, and a take-off has no free run)", source=source,
        )  # fmt: skip
    scenario = scenario_from_dict(data, source=source)
    _wind_parts(scenario.wind, source)
    check_draw_names(scenario, source)
    return scenario, config


#: a draw's name is the scenario's with this suffix and its index (``draws.draw``)
DRAW_SUFFIX = "_mc"


def check_draw_names(scenario: Scenario, source: str | None = None) -> None:
    """Refuse a scenario ``name`` too long for its draws' names (``NAME_mcI``, at most 100
    characters up to ``MAX_RUNS`` draws), naming the field the user wrote, not a draw's.

    Parameters
    ----------
    scenario : Scenario
        The Monte Carlo's nominal scenario.
    source : str, optional
        Where it came from (a file name).
    """
    longest = 100 - len(DRAW_SUFFIX) - len(str(MAX_RUNS - 1))
    if len(scenario.name) > longest:
        raise ParameterError(
            "name", scenario.name, f"a name of at most {longest} characters in a Monte Carlo "
            f"(each draw is named NAME{DRAW_SUFFIX}I, a plain name of at most 100)",
            source=source,
        )  # fmt: skip


def _wind_parts(wind: Disturbance, source: str | None = None) -> tuple[Disturbance, ...]:
    parts = wind.components if isinstance(wind, WindSum) else (wind,)
    for d in parts:
        if not isinstance(d, (Pulse, Step, Sine, ConstantForce, NoWind, Turbulence, SteadyWind)):
            raise ParameterError(
                "wind",
                getattr(d, "type_name", type(d).__name__),
                "pulse, step, sine, constant, steady or turbulence profiles in a Monte Carlo",
                source=source,
            )
    return tuple(parts)
