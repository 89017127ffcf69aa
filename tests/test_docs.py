"""The documentation: the generated scenario reference is current and agrees with the loader,
and the public API carries numpydoc sections (issue 12, item 6)."""

from __future__ import annotations

import ast
import dataclasses
import enum
import importlib
import inspect
import math
import re
import textwrap
from pathlib import Path

import pytest
from griffe import Docstring

from tetherheli.errors import ParameterError
from tetherheli.params import Params
from tetherheli.scenario import core as scenario_module
from tetherheli.scenario.core import scenario_from_dict
from tetherheli.scenario.reference import scenario_reference
from tetherheli.sensing.config import SensorConfig
from tetherheli.sensing.presets import SENSOR_PRESETS
from tetherheli.wind import loader as wind_loader

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "scenario_reference.md"


def test_scenario_reference_is_current():
    """docs/scenario_reference.md is what docs/gen_scenario_reference.py writes today."""
    assert PAGE.read_text(encoding="utf-8") == scenario_reference(), (
        "docs/scenario_reference.md is stale: run PYTHONPATH=src python "
        "docs/gen_scenario_reference.py"
    )


def _documented_keys() -> set[str]:
    return set(re.findall(r"^\| `([^`]+)` \|", PAGE.read_text(encoding="utf-8"), re.M))


def test_every_key_the_loader_accepts_is_documented():
    """Every key the strict loader accepts (its own key sets and the tables it builds) has a
    row in the reference."""
    keys = _documented_keys()
    expected = {k for k in scenario_module._TOP_KEYS if k not in _TABLE_KEYS}
    for table, cls in (
        ("control", scenario_module.ControlSettings),
        ("control.tether_lqi", scenario_module.TetherLQISettings),
        ("control.mpc", scenario_module.MPCSettings),
        ("limits", scenario_module.Limits),
        ("actuators", scenario_module.ActuatorSettings),
        ("tether", scenario_module.TetherSettings),
        ("winch", scenario_module.WinchSettings),
        ("base", scenario_module.BaseSettings),
        ("maneuver", scenario_module.ManeuverSettings),
        ("landing_gear", scenario_module.LandingGearSettings),
        ("reference", scenario_module.ReferenceSettings),
    ):
        # a nested table (a dataclass default) is documented by its own keys
        expected |= {
            f"{table}.{f.name}"
            for f in dataclasses.fields(cls)
            if not dataclasses.is_dataclass(getattr(cls(), f.name))
        }
    for section in dataclasses.fields(Params):
        cls = type(getattr(Params.paper(), section.name))
        expected |= {f"params.{section.name}.{f.name}" for f in dataclasses.fields(cls)}
    expected |= {f"sensors.{f.name}" for f in dataclasses.fields(SensorConfig)}
    expected.add("sensors.presets")
    for cls in wind_loader._DISTURBANCES.values():
        expected |= {f"wind.{f.name}" for f in dataclasses.fields(cls) if f.init}
    for cls in (*wind_loader._GUST_MODELS.values(), wind_loader.CalibratedGaussMarkovTurbulence):
        expected |= {f"wind.model.{f.name}" for f in dataclasses.fields(cls) if f.init}
    expected |= {f"wind.drag.{f.name}" for f in dataclasses.fields(wind_loader.DragModel)}
    assert expected - keys == set()
    page = PAGE.read_text(encoding="utf-8")
    for type_name in (*wind_loader._DISTURBANCES, *wind_loader._GUST_MODELS):
        assert f'`type = "{type_name}"`' in page
    for preset in SENSOR_PRESETS:
        assert f"`{preset}`" in page


_TABLE_KEYS = {"control", "limits", "wind", "params", "actuators", "sensors", "tether", "winch",
               "base", "maneuver", "landing_gear", "reference"}  # fmt: skip
_ROW = re.compile(r"^\| `([^`]+)` \| [^|]*(?:\\\|[^|]*)* \| [^|]* \| `([^`]*)` \| (.*) \|$", re.M)
_RANGE = re.compile(
    r"^an? (?:nonzero )?(?:finite number|number|integer)"
    r"(?: (?P<op>>=|>|<=|<) (?P<bound>-?[\d.e+]+)"
    r"| in (?P<lo_br>[\[(])(?P<lo>-?[\d.e+]+), (?P<hi>-?[\d.e+]+)(?P<hi_br>[\])]))?"
)


def _nest(key: str, value: object) -> dict:
    out: dict = {}
    node = out
    parts = key.split(".")
    for part in parts[:-1]:
        node = node.setdefault(part, {})
    node[parts[-1]] = value
    return out


def _numeric_rows() -> list[tuple[str, float, str]]:
    rows = []
    for key, default, cell in _ROW.findall(PAGE.read_text(encoding="utf-8")):
        allowed = cell.replace("\\[", "[").replace("\\|", "|")
        if key.startswith(("wind.", "sensors.")) or not _RANGE.match(allowed):
            continue
        if default == "unset":  # no number to probe (a key whose default follows another)
            continue
        value = {"inf": math.inf, "-inf": -math.inf}.get(default)
        rows.append((key, float(default) if value is None else value, allowed))
    return rows


@pytest.mark.parametrize("key, default, allowed", _numeric_rows(), ids=lambda v: str(v)[:40])
def test_documented_range_is_the_checked_one(key, default, allowed):
    """The documented default loads, and a value just outside the documented range is
    refused naming the key (the page and the validation share one ``Key``)."""
    integer = allowed.startswith("an integer")
    scenario_from_dict(_nest(key, int(default) if integer else default))
    m = _RANGE.match(allowed)
    outside = []
    if m.group("op") in (">", ">="):
        b = float(m.group("bound"))
        outside.append(b if m.group("op") == ">" else b - (1 if integer else 1e-3))
    elif m.group("op") in ("<", "<="):
        b = float(m.group("bound"))
        outside.append(b if m.group("op") == "<" else b + 1e-3)
    elif m.group("lo") is not None:
        lo, hi = float(m.group("lo")), float(m.group("hi"))
        outside.append(lo if m.group("lo_br") == "(" else lo - (1 if integer else 1e-3))
        outside.append(hi if m.group("hi_br") == ")" else hi + (1 if integer else 1e-3))
    if "finite" in allowed:
        outside.append(math.nan)
    assert outside, f"{key}: no range to probe in {allowed!r}"
    for value in outside:
        bad = int(value) if integer and math.isfinite(value) else value
        with pytest.raises(ParameterError) as err:
            scenario_from_dict(_nest(key, bad))
        # parameters are named by section and field (the loader drops the "params." prefix)
        assert err.value.field in (key, key.removeprefix("params."))


# --- numpydoc sections on the public API ----------------------------------------------------

#: The modules the API reference (docs/api.md) documents, with the names it lists; the
#: docstrings of these are converted to numpydoc. Not yet converted (other work in progress):
#: engine/loop.py,
#: model/derive.py, model/codegen.py, model/kernels.py and the
#: private helpers (_io, _validation, _compile, _linalg).
API = {
    "tetherheli.params": ["Params", "HelicopterParams", "TetherParams", "TensionControlParams",
                          "check_tether_length"],
    "tetherheli.model.dynamics": ["FreeHelicopter", "TetheredHelicopter"],
    "tetherheli.model.trim": ["TrimPoint", "hover_trim", "windless_trim"],
    "tetherheli.model.kinematics": ["HelicopterPoints", "helicopter_points", "direction_cosines",
                                    "tethered_HO_position", "tether_length_from_altitude"],
    "tetherheli.model.linearization": ["LinearModel", "linearize"],
    "tetherheli.model.multirotor": ["Multirotor", "MultirotorTrim"],
    "tetherheli.model.multirotor_kernels": ["multirotor_derivative"],
    "tetherheli.control.se3": ["SE3Controller"],
    "tetherheli.tether.winch": ["drum_step"],
    "tetherheli.scenario.core": ["Scenario", "ControlSettings", "TetherLQISettings",
                                "MPCSettings", "Limits", "ActuatorSettings", "WinchSettings",
                                "load_scenario", "paper_scenario",
                                "scenario_toml", "metrics_first_sample"],
    "tetherheli.runs.closed_loop": ["simulate", "check_run_memory"],
    "tetherheli.results.result": ["SimulationResult", "load_result", "list_results",
                              "check_result_format"],
    "tetherheli.scenario.reference": ["scenario_reference"],
    "tetherheli._validation": ["Key"],
    "tetherheli.errors": ["ParameterError", "InfeasibleError"],
    "tetherheli.control.tether_lqi": ["design_tether_lqi", "tethered_design", "tether_lqi_gain",
                                      "TetherLQIGain", "pack_gain"],
    "tetherheli.control.mpc_design": ["design_mpc", "mpc_plant", "hover_design",
                                      "design_mpc_kalman", "MPCDesign"],
    "tetherheli.control.mpc": ["MPCController"],
    "tetherheli.control.observer": ["DisturbanceKalman", "measurement_covariance",
                                    "steady_state_kalman"],
    "tetherheli.control.lqi": ["design_lqi", "augment_lqi", "LQIGain"],
    "tetherheli.control.base": ["Controller", "Command", "Measurement"],
    "tetherheli.control.paper": ["PaperController"],
    "tetherheli.control.tension": ["TensionPI", "limit_rate_change"],
    "tetherheli.envs.env": ["TetheredHoverEnv", "register_envs", "RenderModeError"],
    "tetherheli.envs.kernels": ["finish_step", "observe_into", "start_episode", "tether_tension"],
    "tetherheli.envs.vector": ["TetheredHoverVectorEnv"],
    "tetherheli.viz.plots": ["figure_outputs", "figure_inputs", "figure_sweep",
                             "figure_limit_search", "figure_release", "figure_montecarlo",
                             "figure_paired", "figure_pareto", "figure_sensing", "save_figure",
                             "metric_label", "plottable", "new_figure", "figures_for_files",
                             "figure_landing"],
    "tetherheli.results.landing": ["landing_metrics", "landing_rows", "is_landing",
                                   "gear_columns"],
    "tetherheli.viz.formats": ["check_figure_format"],
    "tetherheli.sensing.estimation": ["Fixes", "PositionFilter", "position_filter",
                                      "run_filter", "EstimateResult", "normalized_squares",
                                      "chi2_mean_band", "ConsistencyTest", "KalmanConsistency"],
    "tetherheli.studies.estimation": ["estimate_run", "kalman_consistency"],
    "tetherheli.runs.mpc_setup": ["mpc_controller", "mpc_kalman", "uses_kalman"],
    "tetherheli.shipped": ["shipped_scenarios", "shipped_scenario_text", "shipped_scenario",
                           "copy_scenario"],
    "tetherheli.compare": ["compare", "write_compare"],
    "tetherheli.studies.controllers": ["eq40_saturated", "with_controller",
                                       "controller_metrics", "fly"],
    "tetherheli.tether.lumped": ["chain_forces", "ros2_step", "ros2_work", "ros2_work_size"],
    "tetherheli.tether.chain": ["LumpedTether", "static_chain", "chain_energy", "end_forces"],
    "tetherheli.tether.coupling": ["force_at_P_as_loads", "tethered_derivative_force_at_P"],
    "tetherheli.tether.catenary": ["ElasticCatenary", "StaticCable", "initial_chain",
                                   "static_cable", "elastic_catenary",
                                   "catenary_position_estimate", "straight_tether_estimates"],
    "tetherheli.tether.lumped_trim": ["LumpedTrim", "hover_trim_lumped"],
    "tetherheli.wind.profiles": ["Disturbance", "NoWind", "ConstantForce", "Step", "Pulse",
                                 "Sine", "WindSum", "paper_wind"],
    "tetherheli.wind.turbulence": ["GustModel", "GaussMarkovTurbulence", "DrydenGust",
                                   "CalibratedGaussMarkovTurbulence", "GustCalibration",
                                   "gust_calibration", "Turbulence", "check_wind_covers",
                                   "heading_axes", "initial_wind_force"],
    "tetherheli.wind.drag": ["DragModel"],
    "tetherheli.wind.loader": ["disturbance_from_dict"],
    "tetherheli.wind.compiled": ["CompiledWind", "compile_wind"],
    "tetherheli.cli": ["main"],
    "tetherheli.layout": ["default_actuators"],
    "tetherheli.studies.montecarlo.statistics": ["bootstrap_interval", "paired_reduction",
                                                 "tail_percentile", "with_failures"],
    "tetherheli.viz.animation": ["RunData", "animate", "frame_rgb", "load_run", "render_frame",
                                 "run_colours"],
    "tetherheli.viz.replay": ["replay_data", "replay_html", "write_replay"],
    "tetherheli.results.mcap": ["write_mcap", "read_mcap_table", "tension_colour"],
    "tetherheli.studies.release": ["ReleaseComparison", "altitude_excursion",
                                   "release_comparison"],
    "tetherheli.analysis": ["RunMetrics", "TetherMoment", "metric_samples", "reduction_percent",
                            "run_metrics", "tether_moment", "pareto_front"],
    "tetherheli.studies.sweep": ["sweep", "SweepResult", "tension_bound",
                                 "paper_cyclic_limit", "scenario_cyclic_limit",
                                 "parameter_label"],
    "tetherheli.status": ["Status", "status_message", "release_sentence"],
    "tetherheli.studies.cyclic_limit": ["minimum_cyclic_limit", "LimitSearch",
                                        "bisect_criterion",
                                        "bracket_from_above"],
    "tetherheli.studies.montecarlo.config": ["MonteCarloConfig", "load_montecarlo",
                                             "montecarlo_config_from_dict"],
    "tetherheli.studies.montecarlo.draws": ["Draw", "draw", "draw_seed"],
    "tetherheli.studies.tether_study": ["StudyCable", "check_grid", "dynamic_rows",
                                        "hover_limits", "json_ready", "lateral_stiffness",
                                        "select_cables", "static_rows", "study_scenarios",
                                        "TetherStudyConfig", "TetherStudy", "tether_study"],
    "tetherheli.studies.tether_sensing": ["sensing_errors", "sensing_study"],
    "tetherheli.viz.tether_study": ["figure_study_reduction", "figure_study_sensing",
                                    "figure_study_static"],
    "tetherheli.studies.montecarlo.runner": ["run_montecarlo_chunks", "MonteCarloJob",
                                             "MonteCarloColumns", "paired_metric",
                                             "column_units", "check_nominal_designs"],
    "tetherheli.sensing.config": ["SensorConfig", "sensor_config_from_dict"],
    "tetherheli.sensing.noise": ["noise_table", "gauss_markov", "random_walk",
                                 "accelerometer_errors"],
    "tetherheli.sensing.schedules": ["sample_schedule", "group_samples", "ring_rows"],
    "tetherheli.sensing.sensors": ["measure", "measure_into", "measure_sampled",
                                   "measure_batch", "true_channels_into", "measured_channels",
                                   "tether_position_estimate", "hover_error_std"],
    "tetherheli.tether": ["Cable", "CableRun", "drive_cable", "drive_moordyn", "buoyant_gravity",
                          "moordyn_input"],
    "tetherheli.progress": ["Progress"],
    "tetherheli.resources": ["check_memory", "memory_limit", "format_bytes"],
    "tetherheli.report.sweep": ["write_sweep"],
    "tetherheli.report.cyclic_limit": ["write_limit_search"],
    "tetherheli.report.montecarlo": ["run_montecarlo", "result_files"],
    "tetherheli.report.tether_study": ["run_tether_study", "write_tether_study", "study_table",
                                       "sensing_table"],
    "tetherheli.report.paper": ["run_paper", "paper_summary", "run_status", "write_run",
                                "write_comparison", "run_sensing", "sensing_scenario"],
    "tetherheli.runs.setup": ["engine_setup", "EngineSetup", "run_setup", "RunSetup", "paper_gain",
                             "free_trim_input", "paper_law", "start_point", "StartPoint",
                             "actuator_array", "sensor_noise", "sensor_schedule",
                             "sensor_tuple", "lane_program_into", "winch_into"],
    "tetherheli.runs.batch": ["run_batch", "BatchResult", "summary_metrics", "connect",
                             "disconnect", "run_block", "run_unrecorded"],
}  # fmt: skip


def _public_callables():
    for module_name, names in API.items():
        module = importlib.import_module(module_name)
        for name in names:
            obj = getattr(module, name)
            yield f"{module_name}.{name}", obj
            if inspect.isclass(obj):
                for attr, value in vars(obj).items():
                    if isinstance(value, (staticmethod, classmethod)):
                        value = value.__func__
                    if not attr.startswith("_") and inspect.isfunction(value):
                        yield f"{module_name}.{name}.{attr}", value


def _numpydoc(doc: str | None) -> dict[str, set[str]]:
    """Each numpydoc section of ``doc`` (by kind: "parameters", "returns", "attributes", ...)
    -> the names it documents, read by griffe, the API reference's own reader."""
    parsed = Docstring(inspect.cleandoc(doc or ""), lineno=1).parse("numpy", warnings=False)
    out: dict[str, set[str]] = {}
    for section in parsed:
        entries = section.value if isinstance(section.value, list) else []
        out.setdefault(section.kind.value, set()).update(getattr(e, "name", "") for e in entries)
    return out


def _missing_sections(obj) -> list[str]:
    """What numpydoc requires of ``obj`` and its docstring lacks: a Parameters entry for every
    argument (a class: its constructor's), Returns for a function that returns a value. A
    NamedTuple's fields may be under Attributes (the API reference's reader, griffe, does not
    see them as a signature). An Enum has no constructor of its own to document: every member
    must be under Attributes instead."""
    found = _numpydoc(obj.__doc__)
    documented = set(found.get("parameters", ()))
    if inspect.isclass(obj) and issubclass(obj, enum.Enum):
        members = found.get("attributes", set())
        return [f"member {m} undocumented" for m in obj.__members__ if m not in members]
    if inspect.isclass(obj) and issubclass(obj, tuple) and hasattr(obj, "_fields"):
        documented |= found.get("attributes", set())
    problems = []
    signature = inspect.signature(obj)
    for p in signature.parameters.values():
        if p.name in ("self", "cls"):
            continue
        star = {p.VAR_POSITIONAL: "*", p.VAR_KEYWORD: "**"}.get(p.kind, "")
        if p.name not in documented and star + p.name not in documented:
            problems.append(f"parameter {p.name} undocumented")
    gives = "returns" in found or "yields" in found  # a generator or context manager: Yields
    if not inspect.isclass(obj) and _returns_a_value(obj) and not gives:
        problems.append("no Returns section")
    return problems


def _returns_a_value(function) -> bool:
    """Whether ``function`` returns a value: by its annotation, or without one (compiled
    kernels are not annotated) by a ``return <value>`` or ``yield`` in its own body."""
    returns = inspect.signature(function).return_annotation
    if returns is not inspect.Signature.empty:
        return returns not in (None, "None")
    try:
        tree = ast.parse(textwrap.dedent(inspect.getsource(function)))
    except (OSError, TypeError, SyntaxError):
        return True
    body = tree.body[0]
    nested = {id(n) for node in ast.walk(body) if node is not body
              and isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda))
              for n in ast.walk(node)}  # fmt: skip
    return any(
        (isinstance(node, ast.Return) and node.value is not None)
        or isinstance(node, (ast.Yield, ast.YieldFrom))
        for node in ast.walk(body)
        if id(node) not in nested
    )


_CALLABLES = list(_public_callables())


@pytest.mark.parametrize("name, obj", _CALLABLES, ids=[name for name, _ in _CALLABLES])
def test_public_api_has_numpydoc_sections(name, obj):
    assert _missing_sections(obj) == [], name


def _package_callables():
    """Every public function, compiled kernel (its Python function), class and public method
    defined in a public module of the package (a module or name starting with "_" is
    private; modules of an optional extra that is not installed are left out)."""
    import pkgutil

    import tetherheli

    for info in pkgutil.walk_packages(tetherheli.__path__, "tetherheli."):
        name = info.name
        if name == "tetherheli.__main__" or any(p.startswith("_") for p in name.split(".")[1:]):
            continue
        try:
            module = importlib.import_module(name)
        except ModuleNotFoundError:  # an optional extra's module (tetherheli.envs.sb3)
            continue
        for attr, value in list(vars(module).items()):
            obj = getattr(value, "py_func", value)  # a Numba dispatcher's Python function
            if attr.startswith("_") or getattr(obj, "__module__", None) != name:
                continue
            if not (inspect.isfunction(obj) or inspect.isclass(obj)):
                continue
            yield f"{name}.{attr}", obj
            if inspect.isclass(obj):
                for method, member in vars(obj).items():
                    if isinstance(member, (staticmethod, classmethod)):
                        member = member.__func__
                    if (
                        not method.startswith("_")
                        and inspect.isfunction(member)
                        and member.__module__ == name  # not one a base class generates
                    ):
                        yield f"{name}.{attr}.{method}", member


def test_every_public_callable_has_numpydoc_sections():
    """Issue 44 item 5: every public function, kernel, class and method of the package has a
    Parameters entry for each argument and a Returns section when it returns a value."""
    missing = {}
    for name, obj in _package_callables():
        try:
            problems = _missing_sections(obj)
        except (TypeError, ValueError):  # no signature to read (a builtin's)
            continue
        if problems:
            missing[name] = problems
    assert not missing, f"{len(missing)} callables lack numpydoc sections: {missing}"


def test_numpydoc_check_fails_on_a_bare_docstring():
    """The check above can fail: a function without sections is reported."""

    def bare(x: float, *, scale: float = 1.0) -> float:
        """Scale x."""
        return x * scale

    assert _missing_sections(bare) == [
        "parameter x undocumented",
        "parameter scale undocumented",
        "no Returns section",
    ]

    class BareStatus(enum.IntEnum):
        """An end state."""

        OK = 0
        FAILED = 1

    assert _missing_sections(BareStatus) == [
        "member OK undocumented",
        "member FAILED undocumented",
    ]


def test_no_submodule_shadows_a_lazy_name():
    """Importing a submodule sets its package's attribute of that name: a lazy name equal to a
    submodule's (``tetherheli.model.linearize`` was both) became the module once any test had
    imported the submodule, and later callers got "'module' object is not callable"."""
    import importlib
    import pkgutil

    packages = ("tetherheli", "tetherheli.model", "tetherheli.scenario", "tetherheli.runs",
                "tetherheli.results", "tetherheli.envs", "tetherheli.studies",
                "tetherheli.report")  # fmt: skip
    for package in packages:
        pkg = importlib.import_module(package)
        submodules = {m.name for m in pkgutil.iter_modules(pkg.__path__)}
        lazy = set(getattr(pkg, "__all__", ()))
        assert not lazy & submodules, (package, lazy & submodules)
