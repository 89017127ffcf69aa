"""Figures (``tetherheli.viz.plots``): importing the package leaves Matplotlib's backend
alone, every plot function draws into a caller's figure or axes and returns the figure,
``save_figure`` writes PNG at print resolution, PDF and SVG, one source of colours for
figures and animation, and the sweep and Monte Carlo figures carry what a reader needs."""

from __future__ import annotations

import os
import struct
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from matplotlib.figure import Figure

from tests.conftest import EXTRAS
from tetherheli.errors import ParameterError
from tetherheli.viz import plots

ROOT = Path(__file__).resolve().parents[1]

_IMPORT_ALL = """
import importlib, pkgutil, sys
import matplotlib
matplotlib.use("svg")  # a backend the package must not replace
import tetherheli
names = [m.name for m in pkgutil.walk_packages(tetherheli.__path__, "tetherheli.")]
names = [n for n in names if n != "tetherheli.__main__"]  # runs the command line
extras = set(sys.argv[1:])  # the optional extras' modules (tests/conftest.py EXTRAS)
for name in names:
    try:
        importlib.import_module(name)
    except ModuleNotFoundError as exc:  # a module of an optional extra that is absent
        if (exc.name or "").split(".")[0] not in extras:
            raise
print(len(names), matplotlib.get_backend(), "matplotlib.pyplot" in sys.modules)
"""


def test_importing_every_module_keeps_the_backend():
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    env.pop("MPLBACKEND", None)
    out = subprocess.run(
        [sys.executable, "-c", _IMPORT_ALL, *(m for modules in EXTRAS.values() for m in modules)],
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
    )
    assert out.returncode == 0, out.stderr
    count, backend, pyplot = out.stdout.split()
    assert int(count) > 30 and backend == "svg" and pyplot == "False"


_CHECK_FORMATS = """
import sys
from tetherheli.errors import ParameterError
from tetherheli.viz.formats import FIGURE_FORMATS, check_figure_format
assert [check_figure_format(f) for f in FIGURE_FORMATS] == list(FIGURE_FORMATS)
try:
    check_figure_format("jpg")
except ParameterError:
    pass
else:
    raise AssertionError("jpg accepted")
print(sorted(m for m in sys.modules if m.split(".")[0] == "matplotlib") or "-")
"""


def test_formats_and_their_check_import_no_matplotlib():
    """``viz.formats`` (the formats and ``check_figure_format``) imports no Matplotlib, so a
    study checks its figure format before the first run without loading it (a Matplotlib
    import there broke the Monte Carlo's memory bound when that test ran alone); a fresh
    interpreter, so the order of the tests does not matter."""
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    out = subprocess.run(
        [sys.executable, "-c", _CHECK_FORMATS], capture_output=True, text=True, env=env,
        timeout=300,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "-", out.stdout


def _png_size(data: bytes) -> tuple[int, int]:
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    return struct.unpack(">II", data[16:24])  # IHDR width, height


def _mc_data():
    rng = np.random.default_rng(4)
    free = rng.uniform(0.5, 1.0, 50)
    teth = 0.4 * free + rng.normal(0, 0.02, 50)
    ok_f = np.ones(50, bool)
    ok_t = np.ones(50, bool)
    ok_t[:3] = False
    return free, teth, ok_f, ok_t


def test_save_figure_formats_and_print_resolution(tmp_path):
    """PNG at print resolution (``PRINT_DPI``) unless Matplotlib's ``savefig.dpi`` is a
    number (the suite's own matplotlibrc sets 100: ``tests/conftest.py``); PDF without a
    creation date, SVG; any other format refused."""
    import matplotlib as mpl

    free, teth, ok_f, ok_t = _mc_data()
    fig = plots.figure_paired(free, teth, ok_f, ok_t, "peak_q1")
    inches = fig.get_size_inches()
    assert plots.PRINT_DPI >= 300
    for setting, dpi in (("figure", plots.PRINT_DPI), (150, 150), (100.0, 100)):
        with mpl.rc_context({"savefig.dpi": setting}):
            assert plots.figure_dpi() == dpi
            png = plots.save_figure(fig, tmp_path / "a.png")
        assert _png_size(png.read_bytes()) == (round(inches[0] * dpi), round(inches[1] * dpi))
    pdf = plots.save_figure(fig, tmp_path / "a.pdf").read_bytes()
    assert pdf.startswith(b"%PDF") and b"CreationDate" not in pdf
    assert b"<svg" in plots.save_figure(fig, tmp_path / "a.svg").read_bytes()
    with pytest.raises(ParameterError, match="figure format"):
        plots.save_figure(fig, tmp_path / "a.jpg")


def test_inline_figure_shows_matplotlibs_pixels():
    """A figure shown in Jupyter (``InlineFigure._repr_png_``) is drawn once, at the
    resolution ``savefig`` would take: the figure's own dpi by default, else the number
    ``savefig.dpi`` holds; its pixels are those of Matplotlib's PNG of an identical fresh
    figure (the alpha channel dropped where every pixel is opaque)."""
    import io

    import matplotlib as mpl
    from PIL import Image

    free, teth, ok_f, ok_t = _mc_data()

    def figure() -> Figure:
        return plots.figure_paired(free, teth, ok_f, ok_t, "peak_q1")

    for setting in ("figure", 72):
        with mpl.rc_context({"savefig.dpi": setting}):
            shown = figure()._repr_png_()
            reference = io.BytesIO()
            figure().savefig(reference, format="png")
        with Image.open(io.BytesIO(shown)) as a, Image.open(reference) as b:
            assert a.size == b.size
            pa, pb = np.asarray(a), np.asarray(b)
        assert (pb[:, :, 3] == 255).all()
        np.testing.assert_array_equal(pa, pb[:, :, :3])
    fig = figure()
    assert _png_size(fig._repr_png_()) == tuple(round(v * fig.dpi) for v in fig.get_size_inches())


@pytest.mark.parametrize("kind", ["paired", "outputs"])
def test_png_holds_matplotlibs_pixels_in_fewer_bytes(tmp_path, kind):
    """``save_figure``'s PNG (drawn once, ``viz.figure._agg_pixels``) against Matplotlib's own
    PNG (``savefig``: a layout pass, then a rendering pass) of an identical figure at the
    same resolution: equal pixels (the alpha channel dropped only where every pixel is
    opaque), Matplotlib's "Software" text and the resolution, and a file no larger; for a
    one-axes scatter at print resolution and for a run's stacked outputs (constrained
    layout, shared time axis, legend, title) at the suite's 100 dpi. The figure keeps its
    canvas and dpi. On the scatter: a transparent figure keeps its alpha; a cropped
    ``savefig.bbox`` or another ``savefig.facecolor`` leaves the PNG to Matplotlib. (Each
    side draws a fresh figure: Matplotlib's constrained layout moves a little on a figure's
    second drawing.)"""
    import io

    import matplotlib as mpl
    from PIL import Image

    free, teth, ok_f, ok_t = _mc_data()
    run = _result() if kind == "outputs" else None
    dpi = 100.0 if run is not None else plots.PRINT_DPI

    def figure(transparent: bool = False) -> Figure:
        if run is not None:
            fig = plots.figure_outputs([run], "a run's outputs")
        else:
            fig = plots.figure_paired(free, teth, ok_f, ok_t, "peak_q1")
        if transparent:
            for patch in [fig.patch, *(ax.patch for ax in fig.axes)]:
                patch.set_alpha(0.0)
        return fig

    def matplotlibs(fig: Figure) -> bytes:
        out = io.BytesIO()
        fig.savefig(out, format="png", dpi=dpi)
        return out.getvalue()

    fig = figure()
    canvas, figure_dpi = fig.canvas, fig.dpi
    ours = plots.save_figure(fig, tmp_path / "a.png", dpi=dpi).read_bytes()
    assert fig.canvas is canvas and fig.dpi == figure_dpi
    reference = matplotlibs(figure())
    with Image.open(io.BytesIO(ours)) as a, Image.open(io.BytesIO(reference)) as b:
        assert (a.mode, b.mode) == ("RGB", "RGBA")
        pa, pb = np.asarray(a), np.asarray(b)
        assert a.info["Software"] == b.info["Software"]
        assert a.info["dpi"] == pytest.approx(b.info["dpi"])
    assert (pb[:, :, 3] == 255).all()
    np.testing.assert_array_equal(pa, pb[:, :, :3])
    assert len(ours) <= len(reference)
    if run is not None:
        return

    ours = plots.save_figure(figure(True), tmp_path / "b.png", dpi=dpi).read_bytes()
    reference = matplotlibs(figure(True))
    with Image.open(io.BytesIO(ours)) as a, Image.open(io.BytesIO(reference)) as b:
        assert a.mode == "RGBA"
        np.testing.assert_array_equal(np.asarray(a), np.asarray(b))

    for rc in ({"savefig.bbox": "tight"}, {"savefig.facecolor": "lightyellow"}):
        with mpl.rc_context(rc):  # Matplotlib's own PNG
            ours = plots.save_figure(figure(), tmp_path / "c.png", dpi=dpi).read_bytes()
            assert ours == matplotlibs(figure()), rc


def test_plot_functions_draw_into_a_given_axes_or_figure():
    free, teth, ok_f, ok_t = _mc_data()
    fig = Figure()
    ax = fig.add_subplot(1, 2, 1)
    assert plots.figure_paired(free, teth, ok_f, ok_t, ax=ax) is fig
    values = {"free": free, "tethered": teth}
    ok = {"free": ok_f, "tethered": ok_t}
    assert plots.figure_montecarlo(values, ok, "cdf", ax=fig.add_subplot(1, 2, 2)) is fig
    blank = Figure()
    r = _result()
    assert plots.figure_inputs([r], fig=blank) is blank and len(blank.axes) == 4
    with pytest.raises(ParameterError, match="empty figure"):
        plots.figure_outputs([r], fig=blank)


def _result():
    from tetherheli.runs import simulate
    from tetherheli.scenario import Scenario
    from tetherheli.wind import Pulse

    return simulate(
        Scenario(duration=0.5, configuration="tethered", wind=Pulse(0.1, 0.2, 20.0, (1, 0, 0)))
    )


def test_paired_scatter_has_y_equals_x_and_marks_failed_draws():
    free, teth, ok_f, ok_t = _mc_data()
    fig = plots.figure_paired(free, teth, ok_f, ok_t, "rms_q2")
    ax = fig.axes[0]
    lines = {ln.get_label(): ln for ln in ax.get_lines()}
    diag = lines["y = x"]
    assert np.array_equal(diag.get_xdata(), diag.get_ydata())
    failed = [ln for label, ln in lines.items() if "failed run" in label]
    assert len(failed) == 1 and len(failed[0].get_xdata()) == 3
    below = int((teth[3:] < free[3:]).sum())
    assert any(f"{below} below y = x" in label for label in lines)
    assert ax.get_xlabel() == "free: RMS of q2 - q2 trim [m]"


def test_montecarlo_cdf_counts_failed_runs_in_the_tail():
    free, teth, ok_f, ok_t = _mc_data()
    fig = plots.figure_montecarlo(
        {"free": free, "tethered": teth}, {"free": ok_f, "tethered": ok_t}, "cdf", metric="peak_q2"
    )
    ax = fig.axes[0]
    steps = {ln.get_color(): ln for ln in ax.get_lines() if ln.get_linestyle() == "-"}
    blue = steps[plots.CONFIGURATION_COLOURS["tethered"]]
    assert blue.get_ydata()[-1] == pytest.approx(47 / 50)  # 3 failed runs: stops short of 1
    assert steps[plots.CONFIGURATION_COLOURS["free"]].get_ydata()[-1] == 1.0
    assert ax.get_xlabel() == "peak |q2 - q2 trim| [m]"
    with pytest.raises(ParameterError, match="kind"):
        plots.figure_montecarlo({}, {}, "box")


def test_metric_labels_carry_units():
    assert plots.metric_label("peak_q4_deg") == "peak |q4 - q4 trim| [deg]"
    assert plots.metric_label("tension_max") == "maximum tether tension TC [N]"
    assert plots.metric_label("tension_min") == "minimum tether tension TC [N]"


def test_sweep_figure_names_units_and_shades_the_infeasible_region():
    from tetherheli.studies.sweep import SweepResult

    values = np.array([10.0, 20.0, 30.0, 40.0, 50.0])
    result = SweepResult(
        "tension_control.T_ref",
        "rms_q1",
        values,
        np.array([0.3, 0.2, 0.15, np.nan, np.nan]),
        ("completed", "completed", "completed", "diverged", "invalid: no trim"),
        35.0,
        30.0,
        (True, True, True, False, False),
        cyclic_limit=1.0,
    )
    fig = plots.figure_sweep(result)
    ax = fig.axes[0]
    assert ax.get_xlabel() == "tension_control.T_ref: reference tether tension TrefC [N]"
    assert ax.get_ylabel() == "RMS of q1 - q1 trim [m]"
    spans = [p.get_x() for p in ax.patches]  # axvspan rectangles: start of each
    assert 35.0 in spans  # beyond eq 40's bound
    assert 45.0 in spans  # the invalid point at 50, from halfway to its neighbour
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "infeasible set-up (1)" in labels and "run failed (1)" in labels


def test_tension_panel_is_scaled_to_the_taut_tether():
    from tetherheli.runs import simulate
    from tetherheli.scenario import Scenario
    from tetherheli.wind import Pulse

    wind = Pulse(0.1, 0.2, 20.0, (1, 0, 0))
    runs = [
        simulate(Scenario(duration=0.5, configuration=c, wind=wind)) for c in ("free", "tethered")
    ]
    ax = plots.figure_inputs(runs).axes[0]
    lo, hi = ax.get_ylim()
    teth = runs[1].tension
    assert lo > 0.0 and lo <= teth.min() and teth.max() <= hi
    assert hi - lo < 1.5 * (teth.max() - teth.min()) + 1e-6
    assert any("free: TC = 0" in t.get_text() for t in ax.texts)


def test_animation_colours_are_the_figures():
    from tetherheli.viz.animation import run_colours

    class Run:
        def __init__(self, configuration):
            self.configuration = configuration

    runs = [Run("tethered"), Run("free"), Run("tethered"), Run("free")]
    colours = run_colours(runs)
    assert colours[:2] == [
        plots.CONFIGURATION_COLOURS["tethered"],
        plots.CONFIGURATION_COLOURS["free"],
    ]
    assert len(set(colours)) == 4


def test_pareto_figure_joins_the_admissible_front_and_shades_the_goal():
    effort = np.array([0.9, 1.1, 1.0, 0.95, 1.12, np.nan])
    reduction = np.array([40.0, 70.0, 60.0, 30.0, 75.0, np.nan])
    admissible = np.array([True, True, True, True, False, False])
    refs = {"paper": (1.0, 33.0)}
    fig = plots.figure_pareto(effort, reduction, admissible, np.arange(6.0), "T [N]",
                              references=refs)  # fmt: skip
    ax = fig.axes[0]
    lines = {ln.get_label(): ln for ln in ax.get_lines()}
    front = lines["Pareto front (3 designs)"]  # (0.9, 40), (1.0, 60), (1.1, 70); not (0.95, 30)
    assert front.get_xdata().tolist() == [0.9, 1.0, 1.1]
    assert front.get_ydata().tolist() == [40.0, 60.0, 70.0]
    assert lines["paper"].get_xdata().tolist() == [1.0]
    labels = [c.get_label() for c in ax.collections]
    assert "admissible designs (4)" in labels
    assert any(lb.startswith("inadmissible") and "; 1)" in lb for lb in labels)  # NaN: not drawn
    assert "goal: effort ratio <= 1, reduction >= 50 %" in labels


def test_pareto_figure_counts_a_far_off_design_instead_of_widening_the_view():
    effort = np.array([0.9, 1.1, 8.0])
    reduction = np.array([60.0, 70.0, -190.0])
    fig = plots.figure_pareto(effort, reduction, np.array([True, True, False]), np.zeros(3),
                              "T [N]")  # fmt: skip
    ax = fig.axes[0]
    assert ax.get_xlim()[1] < 2.0 and ax.get_ylim()[0] > 0.0
    labels = [c.get_label() for c in ax.collections]
    assert any("1 beyond the view" in lb for lb in labels)
