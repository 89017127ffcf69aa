"""Issue 43 (findings 10, 11, 13): the public cable API (``tetherheli.tether``) checks what the
scenario's ``[tether]`` table checks, with the same rule and message (``tether.chain.CABLE_KEYS``,
``_validation.RK4_SUBSTEPS``, ``_validation.check_samples``), and bounds every size and step
count that follows from its input before allocating or looping: each case below crashed, hung
past 180 s or allocated gigabytes before."""

from __future__ import annotations

import importlib.util
import time

import pytest

from tetherheli.errors import ParameterError
from tetherheli.scenario.core import Scenario, TetherSettings
from tetherheli.tether import Cable, drive_cable, drive_moordyn

PAPER = Cable(unstretched_length=10.0, EA=375.0, segments=10)
RUN = {"anchor": (0.0, 0.0, 0.0), "duration": 0.1, "dt": 0.01}
_MOORDYN = pytest.mark.skipif(
    importlib.util.find_spec("moordyn") is None, reason="MoorDyn is an optional extra"
)


def _top(t: float) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    return (6.0, 0.0, 8.0), (0.0, 0.0, 0.0)


def _quick(call, *args, **kwargs) -> str:
    """The one-line message of the refusal ``call`` raises, within a second."""
    t0 = time.perf_counter()
    with pytest.raises(ParameterError) as info:
        call(*args, **kwargs)
    assert time.perf_counter() - t0 < 1.0
    text = str(info.value)
    assert "\n" not in text
    return text


def test_a_tiny_sample_time_is_refused_not_an_overflow():
    """Finding 10: drive_cable(dt=5e-324) raised OverflowError (floor of an infinite count)."""
    text = _quick(drive_cable, PAPER, top=_top, **{**RUN, "dt": 5e-324})
    assert text.startswith("duration = 0.1 is invalid; allowed: at most 1e+09 control samples")


@pytest.mark.parametrize("segments", [10**6, 10**12])
def test_segments_have_the_scenarios_bound_and_message(segments):
    """Finding 11: Cable(segments=10**6) ran past 180 s, 10**12 failed with MemoryError; the
    scenario caps segments at 1000 with the same rule (one Key, one message)."""
    api = _quick(Cable, unstretched_length=10.0, EA=375.0, segments=segments)
    assert api == f"cable.segments = {segments} is invalid; allowed: an integer in [2, 1000]"
    scenario = _quick(Scenario, tether=TetherSettings(model="lumped", segments=segments))
    assert scenario == api.replace("cable.", "tether.")


def test_substeps_have_the_scenarios_bound():
    """Finding 11: drive_cable(substeps=10**9) ran past 180 s; [control] substeps' rule."""
    text = _quick(drive_cable, PAPER, top=_top, substeps=10**9, **RUN)
    assert text == "substeps = 1000000000 is invalid; allowed: an integer in [1, 1000]"


def test_cable_messages_name_the_cables_fields():
    """Finding 13: the messages name the user's field (cable.EA, cable.unstretched_length), never
    an internal variable (EA_N, unstretched_length_m)."""
    assert _quick(Cable, unstretched_length=1.0, EA=-1.0).startswith("cable.EA = -1.0 ")
    slack = _quick(drive_cable, PAPER, top=lambda t: ((0.0, 0.0, 5.0), (0.0, 0.0, 0.0)), **RUN)
    assert slack.startswith("cable.unstretched_length = 10.0 is invalid; allowed: a length that")
    assert "unstretched_length_m" not in slack


@_MOORDYN
def test_moordyn_bounds_its_compiled_work():
    """Finding 11: drive_moordyn with EA = 1e30, dt_moordyn = 1e-300 ran past 180 s in C (no
    Ctrl-C); coupling = 10**9 failed after 5.2 GB. Each is refused in one line naming it."""
    huge = _quick(drive_moordyn, Cable(10.0, 1e30), top=_top, **RUN)
    assert huge.startswith("cable = ") and "EA=1e+30" in huge and "node steps" in huge
    stiff = _quick(drive_moordyn, Cable(10.0, 1e10), top=_top, **RUN)
    assert stiff.startswith("cable = ") and "node steps" in stiff
    tiny = _quick(drive_moordyn, PAPER, top=_top, dt_moordyn=1e-300, **RUN)
    assert tiny.startswith("dt_moordyn = 1e-300 is invalid; allowed: a finite number in [")
    coupling = _quick(drive_moordyn, PAPER, top=_top, coupling=10**9, **RUN)
    assert coupling == "coupling = 1000000000 is invalid; allowed: an integer in [1, 1000]"
    unstable = _quick(drive_moordyn, Cable(10.0, 1e6), top=_top, dt_moordyn=1e-3, **RUN)
    assert unstable.startswith("dt_moordyn = 0.001 is invalid") and "stable step" in unstable


def test_a_huge_integer_is_refused_by_the_shared_number_check():
    """The fuzzer's find: a Python int beyond the floats (10**400) raised OverflowError in
    ``check_number``, the check of every number field."""
    text = _quick(Cable, unstretched_length=10**400, EA=375.0)
    assert text.startswith("cable.unstretched_length = 1000")
