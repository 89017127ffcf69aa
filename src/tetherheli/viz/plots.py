"""Every figure of the package: the paper's Figs. 6-9 (free and tethered overlaid), the
sweep, the Monte Carlo and the sensing figures.

These functions only read results and return Matplotlib ``Figure`` objects built without
pyplot, so importing them leaves the process's Matplotlib backend alone (notebooks keep their
inline figures); ``save_figure`` writes one as PNG. A failed run is drawn up to its last
recorded sample and says so in the legend; samples that cannot be drawn (non-finite, or beyond
``PLOT_LIMIT``) are left out as gaps, with a note on the figure.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from .._io import atomic_write_bytes
from ..names import INPUT, INPUT_UNITS
from ..sim.result import SimulationResult

__all__ = [
    "PLOT_LIMIT",
    "figure_inputs",
    "figure_limit_search",
    "figure_montecarlo",
    "figure_outputs",
    "figure_release",
    "figure_sensing",
    "figure_sweep",
    "plottable",
    "save_figure",
]

_STYLE = {
    "free": dict(color="tab:red", lw=1.1, label="free"),
    "tethered": dict(color="tab:blue", lw=1.1, label="tethered"),
}


#: samples beyond this magnitude (or non-finite) are not drawn: Matplotlib cannot place ticks
#: on such ranges, and no physical signal of the model reaches them
PLOT_LIMIT = 1e100


def _style(result: SimulationResult) -> dict:
    st = dict(_STYLE.get(str(result.configuration.get("configuration")), dict(lw=1.1)))
    label = st.get("label", result.name)
    if not result.ok:  # a failed run is drawn up to its last recorded sample
        label += f" (stopped at t = {result.end_time:g} s)"
    elif result.released:
        label += f" (tether released at t = {result.release_time:g} s)"
    st["label"] = label
    return st


def plottable(values: np.ndarray) -> tuple[np.ndarray, int]:
    """A copy of ``values`` with the samples that cannot be drawn (non-finite, or beyond
    ``PLOT_LIMIT``) set to NaN (gaps in the line), and how many there were."""
    a = np.array(values, dtype=float)
    with np.errstate(invalid="ignore"):
        bad = ~(np.abs(a) <= PLOT_LIMIT)
    a[bad] = np.nan
    return a, int(bad.sum())


class _Plotter:
    """``ax.plot`` of ``plottable`` samples, counting those left out for the figure's note."""

    def __init__(self) -> None:
        self.dropped = 0

    def __call__(self, ax, t: np.ndarray, y: np.ndarray, **style) -> None:
        clean, n = plottable(y)
        self.dropped += n
        ax.plot(t, clean, **style)


def _stacked(rows: int, size: tuple[float, float]) -> tuple[Figure, np.ndarray]:
    """A figure of ``rows`` axes stacked over a shared time axis (no pyplot)."""
    fig = Figure(figsize=size, layout="constrained")
    return fig, np.atleast_1d(fig.subplots(rows, 1, sharex=True))


def _finish(fig: Figure, axes: np.ndarray, title: str, dropped: int = 0) -> Figure:
    """Shared time axis label, legend, grid and title of the stacked time-series figures;
    a note when samples could not be drawn."""
    axes[-1].set_xlabel("t [s]")
    axes[0].legend(loc="upper right", fontsize=8)
    for ax in axes:
        ax.grid(alpha=0.3)
    if dropped:
        fig.text(
            0.01,
            0.002,
            f"{dropped} sample{'s' if dropped != 1 else ''} not drawn (non-finite or "
            f"beyond {PLOT_LIMIT:g})",
            fontsize=7,
            color="tab:red",
        )
    if title:
        fig.suptitle(title)
    return fig


def figure_outputs(runs: list[SimulationResult], title: str = "") -> Figure:
    """Figs. 6 and 8: wind force, q1, q2, q3 [m] and q4, q5 [deg] against time."""
    fig, axes = _stacked(6, (7.5, 10.5))
    plot = _Plotter()
    for r in runs:
        st = _style(r)
        with np.errstate(invalid="ignore"):
            peak = np.nan_to_num(np.abs(r.wind), nan=0.0).max(axis=0) if r.wind.size else 0
        wind_axis = int(np.argmax(peak)) if r.wind.size else 0
        plot(axes[0], r.time, r.wind[:, wind_axis], **st)
        axes[0].set_ylabel(f"Fw{wind_axis + 1} [N]")
        for i, ax in enumerate(axes[1:4]):
            plot(ax, r.time, r.outputs[:, i], **st)
            ax.set_ylabel(f"q{i + 1} [m]")
        plot(axes[4], r.time, np.degrees(r.states[:, 0]), **st)
        axes[4].set_ylabel("q4 [deg]")
        plot(axes[5], r.time, np.degrees(r.states[:, 1]), **st)
        axes[5].set_ylabel("q5 [deg]")
    return _finish(fig, axes, title, plot.dropped)


def figure_inputs(runs: list[SimulationResult], title: str = "") -> Figure:
    """Figs. 7 and 9: tension TC and inputs fMR3, tMR1, tMR2 (with feed-forward)."""
    fig, axes = _stacked(4, (7.5, 8.0))
    plot = _Plotter()
    for r in runs:
        st = _style(r)
        plot(axes[0], r.time, r.tension, **st)
        for i, (ax, name, unit) in enumerate(
            zip(axes[1:], INPUT[:3], INPUT_UNITS[:3], strict=True)
        ):
            plot(ax, r.time, r.inputs[:, i], **st)
            ax.set_ylabel(f"{name} [{unit}]")
    axes[0].set_ylabel("TC [N]")
    return _finish(fig, axes, title, plot.dropped)


def figure_sweep(result: Any) -> Figure:
    """A sweep's metric against the swept values (``sweep.SweepResult``), with eq 40's tension
    bound, the best value, and the failed or invalid points marked. For a tethered sweep a
    second panel compares the tether's measured peak moment about HO with the cyclic authority
    and eq 40's worst case |arm| TC."""
    moments = result.peak_tether_moment is not None and np.any(
        np.isfinite(result.peak_tether_moment)
    )
    fig = Figure(figsize=(7.0, 6.5 if moments else 4.0), layout="constrained")
    axes = np.atleast_1d(fig.subplots(2 if moments else 1, 1, sharex=True))
    ax = axes[0]
    ax.plot(result.values, result.metric, "o-", color="tab:blue", label=result.metric_name)
    if result.bound is not None:
        how = "" if result.limit_applied else ", 20% rule, runs unsaturated"
        ax.axvline(
            result.bound,
            color="tab:red",
            ls="--",
            label=f"eq 40 bound: TC < {result.bound:.2f} N{how}",
        )
    if result.best_value is not None:
        ax.axvline(
            result.best_value, color="tab:green", ls=":", label=f"best: {result.best_value:g}"
        )
    if result.failed:
        bad = result.values[list(result.failed)]
        ax.plot(
            bad,
            np.full(bad.size, 0.03),
            "x",
            color="tab:red",
            transform=ax.get_xaxis_transform(),
            label=f"failed or invalid ({bad.size})",
        )
    ax.set_ylabel(result.metric_name)
    if moments:
        m = axes[1]
        m.plot(
            result.values,
            result.peak_tether_moment,
            "o-",
            color="tab:blue",
            label="peak tether moment about HO (measured, f1 or f2)",
        )
        m.plot(
            result.values,
            result.peak_worst_case_moment,
            "s--",
            color="tab:gray",
            label="eq 40 worst case |arm| max TC",
        )
        if result.cyclic_limit is not None:
            applied = "applied" if result.limit_applied else "20% rule, not applied"
            m.axhline(
                result.cyclic_limit,
                color="tab:red",
                ls="--",
                label=f"cyclic authority {result.cyclic_limit:.3f} N m ({applied})",
            )
        m.set_ylabel("moment [N m]")
    axes[-1].set_xlabel(result.parameter)
    for a in axes:
        a.grid(alpha=0.3)
        a.legend(loc="upper right", fontsize=8)
    return fig


def figure_limit_search(search: Any) -> Figure:
    """A minimum-cyclic-limit search (``studies.cyclic_limit.LimitSearch``): the metric of
    every limited run against the limit, the threshold (1 + within) x the unlimited run's, the
    interval found, and the runs that did not complete."""
    fig = Figure(figsize=(7.0, 4.0), layout="constrained")
    ax = fig.add_subplot()
    order = np.argsort(search.values)
    v, mtr, meets = search.values[order], search.metric[order], search.meets[order]
    ax.semilogy(v, mtr, ".-", color="tab:blue", lw=0.8, label=search.metric_name)
    ax.semilogy(v[meets], mtr[meets], "o", color="tab:green", ms=4, label="meets the criterion")
    ax.axhline(
        search.threshold,
        color="tab:red",
        ls="--",
        label=f"{1 + search.within:g} x unlimited ({search.reference:.3f})",
    )
    failed = ~np.isfinite(mtr)
    if np.any(failed):
        ax.plot(
            v[failed],
            np.full(int(failed.sum()), 0.03),
            "x",
            color="tab:red",
            transform=ax.get_xaxis_transform(),
            label=f"did not complete ({int(failed.sum())})",
        )
    if search.hi is not None:
        ax.axvline(search.hi, color="tab:green", ls=":", label=f"minimum: {search.interval_text()}")
    ax.set_xlabel("cyclic limit tmax_MR1,2 [N m]")
    ax.set_ylabel(search.metric_name)
    ax.set_title(search.scenario_name, fontsize=9)
    ax.grid(alpha=0.3, which="both")
    ax.legend(loc="upper right", fontsize=8)
    return fig


def figure_release(comparison: Any) -> Figure:
    """The transient after a tether release (``studies.release.ReleaseComparison``): altitude
    deviation q3 - q3_trim, collective fMR3 and tension, with the controller switched to the
    free trim (u0|F) against one that keeps the tethered trim input (u0|T)."""
    fig, axes = _stacked(3, (8.0, 6.5))
    plot = _Plotter()
    runs = (
        (comparison.kept, dict(color="tab:gray", lw=1.1, label="u0|T kept (before)")),
        (comparison.switched, dict(color="tab:blue", lw=1.1, label="switched to u0|F")),
    )
    for r, st in runs:
        plot(axes[0], r.time, r.outputs[:, 2] - r.trim_output[2], **st)
        plot(axes[1], r.time, r.inputs[:, 0], **st)
        plot(axes[2], r.time, r.tension, **st)
    t_rel = comparison.switched.release_time
    for ax in axes:
        ax.axvline(t_rel, color="tab:red", ls=":", lw=1.0)
    axes[0].set_ylabel("q3 - trim [m]")
    axes[1].set_ylabel("fMR3 [N]")
    axes[2].set_ylabel("TC [N]")
    _finish(fig, axes, "After the tether release (Sec. IV-C)", plot.dropped)
    axes[0].legend(
        loc="upper right", fontsize=8, title=f"tether released at t = {t_rel:g} s", title_fontsize=8
    )
    return fig


_KIND_TITLES = {"hist": "histogram", "cdf": "empirical CDF"}


def figure_montecarlo(
    completed: Mapping[str, np.ndarray], totals: Mapping[str, int], kind: str
) -> Figure:
    """The Monte Carlo's peak q1 deviations per configuration: ``kind`` "hist" (histogram) or
    "cdf" (empirical CDF) of the ``completed`` runs' values [m]; ``totals`` counts every run,
    so failed runs are named in the legend."""
    data = {cfg: np.sort(np.asarray(v, dtype=float)) for cfg, v in completed.items()}
    everything = np.concatenate(list(data.values())) if data else np.zeros(0)
    bins = np.linspace(everything.min(), everything.max(), 41) if everything.size else 10
    fig = Figure(figsize=(6.4, 4.2))
    ax = fig.add_subplot()
    for cfg, v in data.items():
        color = _STYLE.get(cfg, {}).get("color")
        if not v.size:  # every run failed: say so in the legend
            ax.plot([], [], color=color, label=f"{cfg}: {totals[cfg]} runs, all failed")
            continue
        failed = totals[cfg] - v.size
        label = f"{cfg}: {v.size} runs" + (f", {failed} failed (not shown)" if failed else "")
        if kind == "hist":
            ax.hist(v, bins=bins, alpha=0.6, color=color, label=label)
            ax.set_ylabel("runs")
        else:
            frac = np.arange(1, v.size + 1) / v.size
            ax.step(v, frac, where="post", color=color, label=label)
            ax.set_ylabel("fraction of completed runs")
    ax.set_xlabel("peak |q1 - q1 trim| [m]")
    ax.set_title(f"Monte Carlo: peak q1 deviation, {_KIND_TITLES[kind]}")
    ax.legend(loc="upper right")  # "best" searches the data: slow, and warns so
    ax.grid(alpha=0.3)
    return fig


def figure_sensing(
    results: Mapping[str, SimulationResult],
    estimates: Mapping[str, Mapping[str, Any]] | None = None,
) -> Figure:
    """Sec. IV-F: the controller's q1 estimate error and the true q1 deviation of runs with
    different position sources (``extra["q1_est"]``); with ``estimates`` (run name ->
    fusion -> ``estimation.EstimateResult``) a middle panel with the Kalman filter's q1
    error for each fusion on the first run with a GNSS outage (else the first run), the
    outage shaded."""
    panels = 3 if estimates else 2
    fig, axes = _stacked(panels, (7.5, 3.0 * panels))
    for name, r in results.items():
        label = name if r.ok else f"{name} (failed at t = {r.end_time:g} s)"
        axes[0].plot(r.time, plottable(r.extra["q1_est"] - r.outputs[:, 0])[0], lw=0.6, label=label)
        axes[-1].plot(r.time, plottable(r.outputs[:, 0] - r.trim_output[0])[0], lw=1.0, label=label)
    axes[0].set_ylabel("controller's q1\nestimate error [m]")
    axes[-1].set_ylabel("true q1 deviation [m]")
    axes[-1].set_xlabel("t [s]")
    if estimates:

        def outage_of(name: str) -> list[float]:
            return list(results[name].configuration["sensors"].get("gps_outage", []))

        shown = [n for n in estimates if estimates[n] and outage_of(n)]
        shown = shown or [n for n in estimates if estimates[n]]
        if shown:
            name = shown[0]
            for fusion, e in estimates[name].items():
                axes[1].plot(e.time, e.error[:, 0], lw=0.8, label=f"IMU + {fusion}")
            axes[1].set_title(f"Kalman filter on {name}", fontsize=9)
            window = outage_of(name)
            if window:
                for ax in axes:
                    ax.axvspan(*window, color="0.85", zorder=0)
        axes[1].set_ylabel("Kalman filter q1\nestimate error [m]")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(loc="upper right", fontsize=8)
    fig.suptitle("Position from a GNSS against the tether as a sensor (Sec. IV-F)")
    return fig


def save_figure(fig: Figure, path: str | Path, dpi: int = 110) -> Path:
    """Save as PNG, atomically."""
    import io

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    atomic_write_bytes(Path(path), buf.getvalue())
    return Path(path)
