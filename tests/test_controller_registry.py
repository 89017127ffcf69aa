"""The controller registry (``control.registry``) is the one place a controller's abilities
are written: the scenario's checks refuse exactly the combinations its records exclude
(configuration, tethered landing, a ground hold over a moving base), the set-up flies a
record's compiled law in the compiled loop and the others from Python, and the scenario's
``[control] controller`` choices are its names."""

from __future__ import annotations

import dataclasses

import pytest

from tetherheli.control.registry import CONTROLLER_REGISTRY, CONTROLLERS, controller_entry
from tetherheli.errors import ParameterError
from tetherheli.layout import CONTROL_LAWS
from tetherheli.runs.setup import python_controlled
from tetherheli.scenario.core import Scenario, field_key
from tetherheli.scenario.tables import ControlSettings
from tetherheli.shipped import shipped_scenario


def test_the_names_and_laws_are_the_scenario_s_and_the_engine_s():
    assert CONTROLLERS == tuple(CONTROLLER_REGISTRY)
    assert field_key(ControlSettings, "controller").choices == CONTROLLERS
    for name, entry in CONTROLLER_REGISTRY.items():
        assert entry.name == name
        assert entry.law is None or entry.law in CONTROL_LAWS
        assert entry.compiled == (entry.law is not None)
    with pytest.raises(ParameterError, match=r"control\.controller = 'lqr'"):
        controller_entry("lqr")


@pytest.mark.parametrize("name", CONTROLLERS)
@pytest.mark.parametrize("configuration", ["free", "tethered"])
def test_the_checks_follow_the_configurations_of_each_record(name, configuration):
    """A scenario is refused exactly when the record does not fly its configuration; an
    accepted one flies from Python exactly when the record has no compiled law."""
    control = dataclasses.replace(Scenario().control, controller=name)
    if configuration in controller_entry(name).configurations:
        s = Scenario(configuration=configuration, control=control)
        assert python_controlled(s) == (not controller_entry(name).compiled)
    else:
        with pytest.raises(ParameterError, match=r"control\.controller"):
            Scenario(configuration=configuration, control=control)


@pytest.mark.parametrize("name", CONTROLLERS)
def test_a_landing_and_a_ground_hold_follow_the_record(name):
    """The tethered landing is refused to a controller whose record does not fly it, and so
    is a point of N held over a moving base (``[control] reference = "ground"``)."""
    entry = controller_entry(name)
    landing = shipped_scenario("landing_calm_deck")
    over_deck = shipped_scenario("deck_sea_state_tethered")
    for s, able in ((landing, entry.landing), (over_deck, entry.ground_hold)):
        control = dataclasses.replace(s.control, controller=name)
        if s is over_deck:
            control = dataclasses.replace(control, reference="ground")
        if able:
            s.replace(control=control)
        else:
            with pytest.raises(ParameterError):
                s.replace(control=control)
