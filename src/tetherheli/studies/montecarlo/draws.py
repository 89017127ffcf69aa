"""The draws of a Monte Carlo: the seed of draw i and its dispersions (wind time shift,
rotation, scale and phase, parameter factors) applied to the base scenario."""

from __future__ import annotations

import dataclasses
import functools
import math
import operator
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...control.registry import controller_entry
from ...errors import TetherheliError
from ...params import Params
from ...scenario.core import Scenario, TetherSettings
from ...wind import (
    ConstantForce,
    Disturbance,
    NoWind,
    Pulse,
    Sine,
    SteadyWind,
    Step,
    Turbulence,
)
from .config import DRAW_SUFFIX, MonteCarloConfig, _wind_parts

__all__ = ["Draw", "draw", "draw_seed", "free_reference"]


def free_reference(scenario: Scenario) -> Scenario:
    """The free helicopter a tethered scenario is judged against (each draw's free run, the
    comparisons' reference): no tether at all (``[tether]`` at its defaults, so none of a
    lumped chain), the GNSS in place of the tether as position source (the free helicopter
    has no tether encoders; the same sensor presets otherwise), and the paper's law in place
    of the tethered LQI, which needs a tether.

    Parameters
    ----------
    scenario : Scenario
        The tethered (or nominal) scenario.

    Returns
    -------
    Scenario
        Its free configuration.
    """
    changes: dict = {"configuration": "free", "tether": TetherSettings()}
    if scenario.sensors.position_source == "tether":
        changes["sensors"] = dataclasses.replace(scenario.sensors, position_source="gps")
    if "free" not in controller_entry(scenario.control.controller).configurations:
        # a controller that needs the tether (control.registry): the paper's flies the free
        changes["control"] = dataclasses.replace(scenario.control, controller="paper")
    return scenario.replace(**changes)


@dataclass(frozen=True)
class Draw:
    """One dispersed draw (shared by its free and tethered runs).

    Parameters
    ----------
    index : int
        Spawn index i of the child ``SeedSequence``.
    entropy : int
        The root entropy.
    spawn_key : tuple of int
        The child's spawn key, ``(index,)``.
    amplitude_scale, direction_deg, phase_rad, start_shift_s : float
        Wind dispersions: magnitude factor, rotation about n3 [deg], sine phase [rad] (NaN
        when phases are not drawn) and time shift [s].
    param_factors : tuple of (str, float)
        Multiplicative factor of every dispersed parameter.
    param_values : tuple of float
        The dispersed parameters' values (nominal times factor).
    scenario : Scenario or None
        The dispersed scenario (configuration "tethered"); None when the dispersed values
        are physically impossible (e.g. a tension the dispersed tether cannot give), and
        ``reason`` says why: the draw is then a failed row, not an error of the job.
    reason : str, optional
        Why ``scenario`` is None (default "").
    """

    index: int
    entropy: int
    spawn_key: tuple[int, ...]
    amplitude_scale: float
    direction_deg: float
    phase_rad: float
    start_shift_s: float
    param_factors: tuple[tuple[str, float], ...]
    param_values: tuple[float, ...]
    scenario: Scenario | None
    reason: str = ""


def draw_seed(seed: int, index: int) -> np.random.SeedSequence:
    """The seed of draw ``index``: child ``index`` of ``SeedSequence(seed).spawn(N)`` for any
    N > ``index``, made on its own in O(1) (same entropy, spawn key ``(index,)``, pool size).

    Parameters
    ----------
    seed : int
        The root seed.
    index : int
        The draw's index, >= 0.

    Returns
    -------
    numpy.random.SeedSequence
        The draw's seed.
    """
    return np.random.SeedSequence(seed, spawn_key=(index,))


def _rot(v: tuple[float, ...], angle: float, scale: float = 1.0) -> tuple[float, float, float]:
    c, s = math.cos(angle), math.sin(angle)
    return (scale * (c * v[0] - s * v[1]), scale * (s * v[0] + c * v[1]), scale * v[2])


def draw(
    base: Scenario, config: MonteCarloConfig, child: np.random.SeedSequence, index: int
) -> Draw:
    """Disperse ``base`` with the random stream of ``child`` (see the package docstring).

    Parameters
    ----------
    base : Scenario
        The nominal scenario.
    config : MonteCarloConfig
        The dispersions.
    child : numpy.random.SeedSequence
        The draw's seed (``draw_seed``).
    index : int
        The draw's index.

    Returns
    -------
    Draw
        The dispersed draw (its ``scenario`` None with a ``reason`` when impossible).
    """
    rng = np.random.default_rng(child)
    # fixed draw order: amplitude, direction, phase, time shift, parameters (sorted)
    scale = max(0.0, 1.0 + config.amplitude_std_percent / 100.0 * rng.standard_normal())
    angle_deg = config.direction_std_deg * rng.standard_normal()
    phase_u = rng.uniform(0.0, 2.0 * math.pi)
    shift = config.start_jitter_s * rng.standard_normal()
    factors = tuple(
        (name, 1.0 + pct / 100.0 * rng.uniform(-1.0, 1.0)) for name, pct in config.params
    )
    phase = phase_u if config.random_phase else math.nan
    a = math.radians(angle_deg)
    parts: list[Disturbance] = []
    for d in _wind_parts(base.wind):
        if isinstance(d, Pulse):
            parts.append(
                Pulse(
                    max(0.0, d.start + shift), d.duration, d.magnitude * scale, _rot(d.direction, a)
                )
            )
        elif isinstance(d, Step):
            parts.append(Step(max(0.0, d.start + shift), d.magnitude * scale, _rot(d.direction, a)))
        elif isinstance(d, Sine):
            p0 = phase if config.random_phase else d.phase
            parts.append(
                Sine(
                    d.amplitude * scale,
                    d.frequency,
                    max(0.0, d.start + shift),
                    _rot(d.direction, a),
                    p0 - 2.0 * math.pi * d.frequency * shift,
                )
            )
        elif isinstance(d, ConstantForce):
            parts.append(ConstantForce(_rot(d.vector, a, scale)))
        elif isinstance(d, SteadyWind):  # the true wind turned with the draw's direction
            parts.append(dataclasses.replace(d, N_v_wind=_rot(d.N_v_wind, a)))
        elif isinstance(d, Turbulence):  # a fresh gust series per draw, mean wind rotated
            model: Any = d.model  # its gust axis u turns with the mean wind (a dataclass)
            if hasattr(model, "heading_rad"):
                model = dataclasses.replace(model, heading_rad=model.heading_rad + a)
            parts.append(
                dataclasses.replace(
                    d,
                    model=model,
                    seed=int(child.entropy),  # type: ignore[arg-type]
                    spawn_key=(*child.spawn_key, 0),
                    N_v_mean_wind=_rot(d.N_v_mean_wind, a),
                )
            )
    wind: Disturbance = functools.reduce(operator.add, parts) if parts else NoWind()
    values = {name: _param(base.params, name) * f for name, f in factors}
    scenario: Scenario | None = None
    reason = ""
    try:
        params = base.params.replace(values) if values else base.params
        scenario = base.replace(
            name=f"{base.name}{DRAW_SUFFIX}{index}",
            configuration="tethered",
            wind=wind,
            params=params,
        )
    except TetherheliError as exc:  # impossible dispersed values: a failed draw, with why
        reason = str(exc).splitlines()[0]
    return Draw(
        index=index,
        entropy=int(child.entropy),  # type: ignore[arg-type]
        spawn_key=tuple(int(k) for k in child.spawn_key),
        amplitude_scale=scale,
        direction_deg=angle_deg,
        phase_rad=phase,
        start_shift_s=shift,
        param_factors=factors,
        param_values=tuple(values.values()),
        scenario=scenario,
        reason=reason,
    )


def _param(params: Params, name: str) -> float:
    section, _, key = name.partition(".")
    return float(getattr(getattr(params, section), key))
