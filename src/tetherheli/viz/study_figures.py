"""The studies' figures: a sweep (``figure_sweep``), the cyclic-limit search, the tether
release, the Monte Carlo's histograms, CDFs and paired scatter, the controllers' trade-off
(``figure_pareto``), the sensing comparison and ``tetherheli compare``'s bars and box plots
(``figure_compare``, ``figure_compare_spread``). Re-exported by ``viz.plots``, where callers
import them.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any, NamedTuple

import numpy as np
from matplotlib.figure import Figure

from ..errors import ParameterError
from ..results.result import SimulationResult
from .figure import (
    CONFIGURATION_COLOURS,
    _finish,
    _new_figure,
    _Plotter,
    _single_axes,
    _stacked,
    metric_label,
    new_figure,
    plottable,
)

__all__ = [
    "ControllerSpread",
    "figure_compare",
    "figure_compare_spread",
    "figure_limit_search",
    "figure_montecarlo",
    "figure_paired",
    "figure_pareto",
    "figure_release",
    "figure_sensing",
    "figure_sweep",
]


def _shade_invalid(ax: Any, values: np.ndarray, invalid: np.ndarray, label: str) -> None:
    """Shade the stretches of the swept axis around the ``invalid`` points (each point's
    span reaches halfway to its neighbours), labelled once."""
    order = np.argsort(values)
    v, bad = values[order], invalid[order]
    edges = np.concatenate([[v[0]], (v[:-1] + v[1:]) / 2, [v[-1]]])
    if v.size == 1:
        edges = np.array([v[0] - 0.5, v[0] + 0.5])
    for i in np.flatnonzero(bad):
        ax.axvspan(edges[i], edges[i + 1], color="0.8", alpha=0.6, lw=0, label=label)
        label = "_"  # one legend entry


def figure_sweep(result: Any, *, fig: Figure | None = None) -> Figure:
    """A sweep's metric against the swept values (``sweep.SweepResult``), into ``fig`` if
    given: the axes named with their units, the region beyond eq 40's tension bound shaded
    red (the cyclic authority cannot hold the tether moment there), the points the physics
    cannot meet (no trim, beyond the actuator limits) shaded grey, the failed runs marked and
    the best value. For a tethered sweep a second panel compares the tether's measured peak
    moment about HO with the cyclic authority and eq 40's worst case |arm| TC.

    Parameters
    ----------
    result : SweepResult
        The sweep (``studies.sweep.run_sweep``'s result).
    fig : matplotlib.figure.Figure, optional
        The figure to draw into (cleared); default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn.
    """
    from ..studies.sweep import parameter_label

    moments = result.peak_tether_moment is not None and np.any(
        np.isfinite(result.peak_tether_moment)
    )
    fig = _new_figure(fig, (7.0, 6.5 if moments else 4.0))
    # ignore: NumPy's stubs take no Axes (subplots gives one Axes or an array of them)
    axes = np.atleast_1d(fig.subplots(2 if moments else 1, 1, sharex=True))  # type: ignore[arg-type]
    ax = axes[0]
    tethered = CONFIGURATION_COLOURS["tethered"]
    ax.plot(result.values, result.metric, "o-", color=tethered, label=result.metric_name)
    invalid = np.array([s.startswith("invalid") for s in result.statuses], dtype=bool)
    if invalid.any():
        for a in axes:
            _shade_invalid(a, result.values, invalid, f"infeasible set-up ({int(invalid.sum())})")
    if result.bound is not None:
        how = "" if result.limit_applied else ", 20% rule, runs unsaturated"
        top = max(float(np.max(result.values)), result.bound)
        for a in axes:
            a.axvspan(result.bound, top, color="tab:red", alpha=0.08, lw=0)
        ax.axvline(
            result.bound,
            color="tab:red",
            ls="--",
            label=f"eq 40 bound: TC < {result.bound:.2f} N{how} (beyond: shaded)",
        )
    if result.best_value is not None:
        ax.axvline(
            result.best_value, color="tab:green", ls=":", label=f"best: {result.best_value:g}"
        )
    ran_failed = np.array([i for i in result.failed if not invalid[i]], dtype=int)
    if ran_failed.size:
        bad = result.values[ran_failed]
        ax.plot(
            bad,
            np.full(bad.size, 0.03),
            "x",
            color="tab:red",
            transform=ax.get_xaxis_transform(),
            label=f"run failed ({bad.size})",
        )
    ax.set_ylabel(metric_label(result.metric_name))
    if moments:
        m = axes[1]
        m.plot(
            result.values,
            result.peak_tether_moment,
            "o-",
            color=tethered,
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
        m.set_ylabel("moment about HO [N m]")
    axes[-1].set_xlabel(parameter_label(result.parameter))
    lo, hi = float(np.min(result.values)), float(np.max(result.values))
    for a in axes:
        if hi > lo:  # the shading must not widen the axis
            a.set_xlim(lo, hi)
        a.grid(alpha=0.3)
        a.legend(loc="upper right", fontsize=8)
    return fig


def figure_limit_search(search: Any, *, ax: Any = None) -> Figure:
    """A minimum-cyclic-limit search (``studies.cyclic_limit.LimitSearch``), on ``ax`` if
    given: the metric of every limited run against the limit, the threshold (1 + within) x
    the unlimited run's, the interval found, and the runs that did not complete.

    Parameters
    ----------
    search : LimitSearch
        The search's result (limits [N m], metric, threshold, interval).
    ax : matplotlib.axes.Axes, optional
        The axes to draw on; default those of a new figure.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn (``ax``'s if given).
    """
    fig, ax = _single_axes(ax, (7.0, 4.0))
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
    ax.set_ylabel(metric_label(search.metric_name))
    ax.set_title(search.scenario_name, fontsize=9)
    ax.grid(alpha=0.3, which="both")
    ax.legend(loc="upper right", fontsize=8)
    return fig


def figure_release(comparison: Any, *, fig: Figure | None = None) -> Figure:
    """The transient after a tether release (``studies.release.ReleaseComparison``), into
    ``fig`` if given: altitude deviation q3 - q3_trim, collective fMR3 and tension, with the
    controller switched to the free trim (u0|F) against one that keeps the tethered trim
    input (u0|T).

    Parameters
    ----------
    comparison : ReleaseComparison
        The two runs, ``kept`` (u0|T) and ``switched`` (u0|F).
    fig : matplotlib.figure.Figure, optional
        The figure to draw into (cleared); default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn.
    """
    fig, axes = _stacked(3, (8.0, 6.5), fig)
    plot = _Plotter()
    runs = (
        (comparison.kept, dict(color="tab:gray", lw=1.1, label="u0|T kept (before)")),
        (comparison.switched, dict(color="tab:green", lw=1.1, label="switched to u0|F")),
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


def _failed_note(cfg: str, n: int, failed: int) -> str:
    return f"{cfg}: {n} runs" + (f", {failed} failed" if failed else "")


def figure_montecarlo(
    values: Mapping[str, np.ndarray],
    ok: Mapping[str, np.ndarray],
    kind: str,
    *,
    metric: str = "peak_q1",
    ax: Any = None,
) -> Figure:
    """A Monte Carlo metric per configuration, on ``ax`` if given: ``kind`` "hist"
    (histogram of the completed runs; the failed ones counted in the legend and as a bar past
    the right edge) or "cdf" (empirical CDF over every run, a failed run counted as +inf, so
    the curve stops short of 1 by the failed fraction).

    Parameters
    ----------
    values : mapping of str to ndarray, shape (n,)
        Configuration -> the metric of every run, in the metric's unit (any value where
        failed).
    ok : mapping of str to ndarray, shape (n,), bool
        Whether each run completed.
    kind : str
        "hist" or "cdf".
    metric : str
        The metric's name (``runs.batch.METRIC_NAMES``), for the labels.
    ax : matplotlib Axes, optional
        Where to draw.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn (``ax``'s if given).
    """
    if kind not in _KIND_TITLES:
        raise ParameterError("kind", kind, f"one of {list(_KIND_TITLES)}")
    fig, ax = _single_axes(ax, (6.4, 4.2))
    done = {
        cfg: np.sort(np.asarray(v, dtype=float)[np.asarray(ok[cfg])]) for cfg, v in values.items()
    }
    everything = np.concatenate(list(done.values())) if done else np.zeros(0)
    lo, hi = (everything.min(), everything.max()) if everything.size else (0.0, 1.0)
    bins = np.linspace(lo, hi if hi > lo else lo + 1.0, 41)
    width = bins[1] - bins[0]
    for cfg, v in done.items():
        color = CONFIGURATION_COLOURS.get(cfg)
        total = int(np.asarray(values[cfg]).size)
        failed = total - v.size
        if not v.size:  # every run failed: say so in the legend
            ax.plot([], [], color=color, label=f"{cfg}: {total} runs, all failed")
            continue
        label = _failed_note(cfg, total, failed)
        if kind == "hist":
            ax.hist(v, bins=bins, alpha=0.6, color=color, label=label)
            if failed:
                ax.bar(hi + 1.5 * width, failed, width=width, color=color, alpha=0.6, hatch="//")
            ax.set_ylabel("runs")
        else:
            frac = np.arange(1, v.size + 1) / total
            ax.step(v, frac, where="post", color=color, label=label)
            if failed:
                ax.axhline(v.size / total, color=color, ls=":", lw=0.8)
            ax.set_ylabel("fraction of all runs")
    if kind == "hist" and any(np.asarray(values[c]).size > done[c].size for c in done):
        ax.text(
            1.0,
            -0.12,
            "hatched: failed runs",
            transform=ax.transAxes,
            ha="right",
            fontsize=7,
        )
    ax.set_xlabel(metric_label(metric))
    ax.set_title(f"Monte Carlo: {metric}, {_KIND_TITLES[kind]}")
    ax.legend(loc="upper right" if kind == "hist" else "lower right")  # not "best": slow
    ax.grid(alpha=0.3)
    return fig


def figure_paired(
    free: np.ndarray,
    tethered: np.ndarray,
    free_ok: np.ndarray,
    tethered_ok: np.ndarray,
    metric: str = "peak_q1",
    *,
    ax: Any = None,
) -> Figure:
    """The Monte Carlo's paired comparison, on ``ax`` if given: one point per draw at
    (free, tethered) value of ``metric`` with the line y = x (below it the tether helped);
    a draw whose free or tethered run failed is drawn as a cross on the top or right edge.

    Parameters
    ----------
    free, tethered : ndarray, shape (n,)
        The metric of each draw's two runs, in the metric's unit.
    free_ok, tethered_ok : ndarray, shape (n,), bool
        Whether each run completed.
    metric : str
        The metric's name, for the labels.
    ax : matplotlib Axes, optional
        Where to draw.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn (``ax``'s if given).
    """
    fig, ax = _single_axes(ax, (5.2, 5.0))
    f = np.asarray(free, dtype=float)
    t = np.asarray(tethered, dtype=float)
    fo, to = np.asarray(free_ok, dtype=bool), np.asarray(tethered_ok, dtype=bool)
    both = fo & to
    known = np.concatenate([f[fo], t[to]])
    lo, hi = (float(known.min()), float(known.max())) if known.size else (0.0, 1.0)
    pad = 0.05 * (hi - lo) if hi > lo else 0.5
    lo, hi = lo - pad, hi + pad
    edge = hi + pad  # failed runs sit on the edge
    below = int((t[both] < f[both]).sum())
    ax.plot(
        f[both],
        t[both],
        ".",
        ms=3,
        color=CONFIGURATION_COLOURS["tethered"],
        alpha=0.6,
        label=f"{int(both.sum())} draws with both runs completed, {below} below y = x (the "
        "tether reduced it)",
    )
    ax.plot([lo, edge], [lo, edge], color="0.3", lw=0.8, label="y = x")
    failed = ~both
    if failed.any():
        x = np.where(fo, f, edge)[failed]
        y = np.where(to, t, edge)[failed]
        ax.plot(
            x,
            y,
            "x",
            color=CONFIGURATION_COLOURS["free"],
            label=f"{int(failed.sum())} draw{'s' if failed.sum() != 1 else ''} with a failed run "
            "(on the edge)",
        )
    ax.set_xlim(lo, edge + pad)
    ax.set_ylim(lo, edge + pad)
    ax.set_aspect("equal", adjustable="box")
    label = metric_label(metric)
    ax.set_xlabel(f"free: {label}")
    ax.set_ylabel(f"tethered: {label}")
    ax.set_title(f"Monte Carlo: {metric} per draw, free against tethered", fontsize=9)
    ax.legend(loc="upper left", fontsize=7)
    ax.grid(alpha=0.3)
    return fig


def figure_pareto(
    effort: np.ndarray,
    reduction: np.ndarray,
    admissible: np.ndarray,
    colour: np.ndarray,
    colour_label: str,
    *,
    references: Mapping[str, tuple[float, float]] | None = None,
    goal: tuple[float, float] = (1.0, 50.0),
    ax: Any = None,
) -> Figure:
    """A controller design sweep's trade-off, on ``ax`` if given: each design at (worst effort
    ratio, worst reduction), coloured by ``colour``; the inadmissible designs hollow; the
    Pareto front of the admissible ones (``analysis.pareto_front``: least effort, most
    reduction) joined by a line; the goal's corner (effort ratio <= goal[0], reduction >=
    goal[1]) shaded green; ``references`` (e.g. the paper's controller) as labelled stars.

    Parameters
    ----------
    effort : ndarray, shape (n,)
        Each design's worst effort ratio (RMS input deviation against a reference controller's).
    reduction : ndarray, shape (n,)
        Each design's worst reduction against the free helicopter [%] (NaN: the run failed,
        not drawn).
    admissible : ndarray of bool, shape (n,)
        Whether each design meets the side constraints (tension range, no solver fallback...).
    colour : ndarray, shape (n,)
        The value that colours each point (e.g. the operating tension [N]).
    colour_label : str
        Its colour bar's label, with the unit.
    references : mapping of str to (float, float), optional
        Labelled (effort ratio, reduction [%]) points drawn as stars.
    goal : (float, float)
        The goal's largest effort ratio and smallest reduction [%].
    ax : matplotlib Axes, optional
        Where to draw.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn (``ax``'s if given).
    """
    from ..analysis import pareto_front

    fig, ax = _single_axes(ax, (6.4, 4.6))
    e = np.asarray(effort, dtype=float)
    r = np.asarray(reduction, dtype=float)
    ok = np.asarray(admissible, dtype=bool) & np.isfinite(e) & np.isfinite(r)
    c = np.asarray(colour, dtype=float)
    drawn = np.isfinite(e) & np.isfinite(r)
    # the view: the admissible designs, the references and the goal's corner with a quarter
    # of their span around (a far-off inadmissible design would squeeze the rest into a
    # corner; it is counted, not drawn)
    ref_x = [v[0] for v in (references or {}).values()]
    ref_y = [v[1] for v in (references or {}).values()]
    xs = np.concatenate([e[ok], [goal[0]], ref_x])
    ys = np.concatenate([r[ok], [goal[1]], ref_y])
    x_pad = 0.25 * max(float(np.ptp(xs)), 0.1)
    y_pad = 0.25 * max(float(np.ptp(ys)), 10.0)
    x_lim = (float(xs.min()) - x_pad, float(xs.max()) + x_pad)
    y_lim = (float(ys.min()) - y_pad, float(ys.max()) + y_pad)
    ax.fill_between(
        [x_lim[0], goal[0]],
        goal[1],
        y_lim[1],
        color="tab:green",
        alpha=0.12,
        lw=0,
        label=f"goal: effort ratio <= {goal[0]:g}, reduction >= {goal[1]:g} %",
    )
    vmin, vmax = (float(np.min(c[ok])), float(np.max(c[ok]))) if ok.any() else (0.0, 1.0)
    art = ax.scatter(
        e[ok],
        r[ok],
        c=c[ok],
        cmap="viridis",
        vmin=vmin,
        vmax=vmax,
        s=22,
        label=f"admissible designs ({int(ok.sum())})",
    )
    bad = drawn & ~ok
    if bad.any():
        inside = (x_lim[0] <= e) & (e <= x_lim[1]) & (y_lim[0] <= r) & (r <= y_lim[1])
        out = int((bad & ~inside).sum())
        ax.scatter(
            e[bad & inside],
            r[bad & inside],
            facecolors="none",
            edgecolors="0.5",
            s=22,
            lw=0.8,
            label=f"inadmissible (tension, solver, off-axis; {int(bad.sum())}"
            + (f", {out} beyond the view)" if out else ")"),
        )
    front = pareto_front(np.where(ok, e, np.nan), np.where(ok, r, np.nan))
    order = np.argsort(e[front])
    if front.any():
        ax.step(
            e[front][order],
            r[front][order],
            where="post",
            color="k",
            lw=1.0,
            label=f"Pareto front ({int(front.sum())} designs)",
        )
    for k, (name, (x, y)) in enumerate((references or {}).items()):
        ax.plot(x, y, "*", ms=11, color=f"C{k + 1}", mec="k", mew=0.5, label=name)
    fig.colorbar(art, ax=ax, label=colour_label)
    ax.axvline(goal[0], color="tab:green", lw=0.8, ls="--")
    ax.axhline(goal[1], color="tab:green", lw=0.8, ls="--")
    ax.set_xlim(*x_lim)
    ax.set_ylim(*y_lim)
    ax.set_xlabel("worst effort ratio (RMS input deviation / the paper's tethered controller's)")
    ax.set_ylabel("worst reduction against the free helicopter [%]")
    ax.legend(loc="lower right", fontsize=7)
    ax.grid(alpha=0.3)
    return fig


def figure_sensing(
    results: Mapping[str, SimulationResult],
    estimates: Mapping[str, Mapping[str, Any]] | None = None,
    *,
    fig: Figure | None = None,
) -> Figure:
    """Sec. IV-F: the controller's q1 estimate error and the true q1 deviation of runs with
    different position sources (``extra["q1_est"]``); with ``estimates`` (run name ->
    fusion -> ``sensing.estimation.EstimateResult``) a middle panel with the Kalman filter's q1
    error for each fusion on the first run with a GNSS outage (else the first run), the
    outage shaded. Drawn into ``fig`` if given.

    Parameters
    ----------
    results : mapping of str to SimulationResult
        Run name -> a run recording ``extra["q1_est"]`` [m].
    estimates : mapping of str to mapping of str to EstimateResult, optional
        Run name -> fusion -> the Kalman filter's estimate (default none: two panels).
    fig : matplotlib.figure.Figure, optional
        The figure to draw into (cleared); default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn.
    """
    panels = 3 if estimates else 2
    fig, axes = _stacked(panels, (7.5, 3.0 * panels), fig)
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


def _empty(fig: Figure) -> Figure:
    """A caller's figure, refused unless empty."""
    if fig.axes:
        raise ParameterError("fig", "a figure with axes", "an empty figure")
    return fig


def figure_compare(rows: Sequence[Mapping[str, Any]], *, fig: Figure | None = None) -> Figure:
    """``tetherheli compare``'s bars: the peak and RMS deviations of q1, q2, q3 per row
    (scenario and controller), into ``fig`` if given. A value that is not finite (a Monte
    Carlo percentile among its failures) draws no bar.

    Parameters
    ----------
    rows : sequence of mappings of str to object
        One per bar group: ``scenario`` and ``controller`` (the tick label) and the
        deviations ``peak_q1`` .. ``rms_q3`` [m]; a missing one draws no bar.
    fig : Figure, optional
        An empty figure to draw into (default: a new one).

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn.
    """
    labels = [f"{r['scenario']}\n{r['controller']}" for r in rows]
    if fig is None:
        fig = new_figure(figsize=(max(8.0, 1.1 * len(rows) + 4), 4.5))
    else:
        fig = _empty(fig)
    axes = fig.subplots(1, 2)
    x = np.arange(len(rows))
    for ax, kind in zip(axes, ("peak", "rms"), strict=True):
        for a, off in zip((1, 2, 3), (-0.27, 0.0, 0.27), strict=True):
            # a percentile among a Monte Carlo's failures is inf: no bar (the table says so)
            vals = np.array([r.get(f"{kind}_q{a}", np.nan) for r in rows], dtype=float)
            vals[~np.isfinite(vals)] = np.nan
            ax.bar(x + off, vals, width=0.27, label=f"q{a}")
        ax.set_xticks(x, labels, rotation=60, ha="right", fontsize=7)
        ax.set_ylabel(f"{kind} deviation [m]")
        ax.legend()
        ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    return fig


class ControllerSpread(NamedTuple):
    """One Monte Carlo of ``figure_compare_spread``: the same draws flown free and under
    each controller.

    Attributes
    ----------
    scenario_name : str
        The nominal scenario's name (the panel's title).
    runs : int
        Draws N.
    labels : tuple of str
        The run kinds in drawing order (free, then the controllers).
    failures : mapping of str to int
        Label -> draws that failed.
    completed : mapping of str to mapping of str to ndarray
        Label -> measure (at least ``peak_q1`` and ``rms_q1``) -> the completed draws'
        values [m].
    """

    scenario_name: str
    runs: int
    labels: tuple[str, ...]
    failures: Mapping[str, int]
    completed: Mapping[str, Mapping[str, np.ndarray]]


def figure_compare_spread(
    spreads: Sequence[ControllerSpread], *, fig: Figure | None = None
) -> Figure:
    """``tetherheli compare --montecarlo``'s box plots: peak and RMS q1 per run kind over
    the completed draws (whiskers at the 5th and 95th percentiles), one row of panels per
    Monte Carlo, the failures counted in the tick labels; into ``fig`` if given.

    Parameters
    ----------
    spreads : sequence of ControllerSpread
        The Monte Carlos, at least one.
    fig : Figure, optional
        An empty figure to draw into (default: a new one).

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn.
    """
    if fig is None:
        fig = new_figure(figsize=(9.0, 3.2 * len(spreads)))
    else:
        fig = _empty(fig)
    axes = fig.subplots(len(spreads), 2, squeeze=False)
    for row, mc in zip(axes, spreads, strict=True):
        labels = [f"{lab}\n{mc.failures[lab]}/{mc.runs} failed" for lab in mc.labels]
        for ax, metric in zip(row, ("peak_q1", "rms_q1"), strict=True):
            data = [mc.completed[lab][metric] for lab in mc.labels]
            ax.boxplot(data, whis=(5, 95), showfliers=True)
            ax.set_xticks(range(1, len(labels) + 1), labels, fontsize=8)
            ax.set_ylabel(f"{metric} [m]")
            ax.set_title(f"{mc.scenario_name}, N = {mc.runs} (whiskers p5-p95)", fontsize=9)
            ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    return fig
