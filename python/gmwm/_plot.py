"""The results' .plot(): matplotlib figures of a WV, an Allan deviation, a fit with its
per-process decomposition, a selection (its ranking and the chosen fit), a gap diagnosis,
a navigation run and a fleet. matplotlib is optional: without it .plot() raises ImportError
saying how to install it. Each returns the axes it drew on; every axis is labelled with its
unit, and each series has its own colour (matplotlib's cycle C0, C1, ...)."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from . import _gmwm

if TYPE_CHECKING:
    from ._types import (AllanDeviation, FitResult, FleetResult, GapColumn, GapResult, NavResult, NoiseFigures,
                         SelectColumn, SelectResult, StabilityColumn, WvLevels, WvResult)

# The figure size of a single plot, in inches (matplotlib's default is 6.4 x 4.8).
FIGURE_SIZE = (7.0, 4.5)
# The interval bands' opacity: the points and lines stay readable through them.
BAND_ALPHA = 0.25
# Rows of a selection's ranking drawn at most (the rest are worse and crowd the labels).
MAX_RANKING_ROWS = 12


def pyplot() -> Any:
    """matplotlib.pyplot, or ImportError saying how to install it."""
    try:
        import matplotlib.pyplot as plt
    except ImportError as e:
        raise ImportError("gmwm's .plot() needs matplotlib: apt install python3-matplotlib (Debian) or "
                          "pip install matplotlib") from e
    return plt


def axes(ax: Any = None, size: tuple[float, float] = FIGURE_SIZE) -> Any:
    if ax is not None:
        return ax
    _, ax = pyplot().subplots(figsize=size)
    return ax


def _squared(unit: str | None) -> str:
    return f" [({unit})^2]" if unit else ""


def _bracket(unit: str | None) -> str:
    return f" [{unit}]" if unit else ""


def _scales(levels: WvLevels) -> tuple[Any, str]:
    """The levels' scales in seconds, or in samples when the rate is unknown."""
    if len(levels.tau_seconds) and not np.all(np.isnan(levels.tau_seconds)):
        return levels.tau_seconds, "tau [s]"
    return levels.tau, "tau [samples]"


def _wv_data(ax: Any, levels: WvLevels, label: str = "data WV") -> tuple[Any, str]:
    tau, xlabel = _scales(levels)
    ax.fill_between(tau, levels.ci_low, levels.ci_high, color="C0", alpha=BAND_ALPHA, label="interval")
    ax.loglog(tau, levels.wv, "o", color="C0", ms=4, label=label)
    ax.set_xlabel(xlabel)
    return tau, xlabel


def wv(w: WvResult, ax: Any = None) -> Any:
    ax = axes(ax)
    tau, _ = _wv_data(ax, w.levels, f"{w.estimator} WV")
    if w.levels.classical_wv is not None:
        ax.loglog(tau, w.levels.classical_wv, "x", color="C1", ms=5, label="classical WV")
    ax.set_ylabel("wavelet variance" + _squared(w.unit))
    ax.set_title(f"{w.name}: Haar wavelet variance")
    ax.legend(loc="best", fontsize=8)
    return ax


def _is(figure: Any) -> str:
    """'<' for a figure the curves only bound (as the report's guides say it), else '='."""
    return "<" if figure.status == "bound" or figure.source == "bound" else "="


def allan(a: AllanDeviation, figures: NoiseFigures | None, unit: str | None, name: str, ax: Any = None) -> Any:
    ax = axes(ax)
    ax.fill_between(a.tau, a.ci_low, a.ci_high, color="C0", alpha=BAND_ALPHA, label="interval")
    ax.loglog(a.tau, a.adev, color="C0", label="data")
    if a.model is not None:
        ax.loglog(a.tau, a.model, color="C1", label="model")
    if figures is not None:
        n, k, b = figures.N, figures.K, figures.B
        if math.isfinite(n.value):
            ax.loglog(a.tau, n.value / np.sqrt(a.tau), "--", color="C2",
                      label=f"N / sqrt(tau), N {_is(n)} {n.value:.3g} {n.unit}")
        if math.isfinite(k.value):
            ax.loglog(a.tau, k.value * np.sqrt(a.tau / 3), "-.", color="C3",
                      label=f"K sqrt(tau / 3), K {_is(k)} {k.value:.3g} {k.unit}")
        if math.isfinite(b.value):
            ax.axhline(0.664 * b.value, ls=":", color="C4", label=f"0.664 B, B {_is(b)} {b.value:.3g} {b.unit}")
        q, r = figures.Q, figures.R  # None in a document written before them
        if q is not None and math.isfinite(q.value):
            ax.loglog(a.tau, math.sqrt(3) * q.value / a.tau, "--", color="C5",
                      label=f"sqrt(3) Q / tau, Q {_is(q)} {q.value:.3g} {q.unit}")
        if r is not None and math.isfinite(r.value):
            ax.loglog(a.tau, r.value * a.tau / math.sqrt(2), "-.", color="C6",
                      label=f"R tau / sqrt(2), R {_is(r)} {r.value:.3g} {r.unit}")
    finite = a.adev[np.isfinite(a.adev) & (a.adev > 0)]
    if len(finite):
        ax.set_ylim(finite.min() / 3, finite.max() * 3)
    ax.set_xlabel("tau [s]")
    ax.set_ylabel("Allan deviation" + _bracket(unit))
    ax.set_title(f"{name}: Allan deviation" if name else "Allan deviation")
    ax.legend(loc="best", fontsize=8)
    return ax


def _model(ax: Any, model: str | None, structure: str | None, levels: WvLevels, freq: float,
           decomposition: bool) -> None:
    """The model's WV over the data's, and each component's (dashed) when asked."""
    if model is None:
        return
    tau, _ = _scales(levels)
    labels, parts = _gmwm.model_wv(model, levels.tau, freq=None if math.isnan(freq) else freq)
    ax.loglog(tau, parts.sum(axis=0), "-", color="C1", label=f"{structure or model} (fitted)")
    if decomposition and len(labels) > 1:
        for k, (label, part) in enumerate(zip(labels, parts)):
            ax.loglog(tau, part, "--", color=f"C{k + 2}", lw=1, label=label)


def _wv_and_model(ax: Any, levels: WvLevels, model: str | None, structure: str | None, freq: float,
                  unit: str | None, title: str, decomposition: bool) -> Any:
    """The data's WV with its interval, a fitted model's WV over it (and each process's)."""
    ax = axes(ax)
    _wv_data(ax, levels)
    _model(ax, model, structure, levels, freq, decomposition)
    _floor(ax, levels.ci_low)
    ax.set_ylabel("wavelet variance" + _squared(unit))
    ax.set_title(title)
    ax.legend(loc="best", fontsize=8)
    return ax


def fit(f: FitResult, ax: Any = None, decomposition: bool = True) -> Any:
    return _wv_and_model(ax, f.levels, f.model, f.model_structure, f.freq, f.unit,
                         f"{f.name}: {f.model_structure}, gof p = {f.gof.p_value:.3g}", decomposition)


def _floor(ax: Any, values: Any) -> None:
    """Components far below the data would stretch the axis: keep it near the data's range."""
    positive = values[np.isfinite(values) & (values > 0)]
    if len(positive):
        low, high = ax.get_ylim()
        ax.set_ylim(max(low, positive.min() / 100), high)


def ranking(c: SelectColumn, ax: Any = None) -> Any:
    ax = axes(ax)
    rows = c.ranking[:MAX_RANKING_ROWS]
    y = np.arange(len(rows))[::-1]
    criteria = np.array([r.criterion for r in rows])
    above = criteria - np.nanmin(criteria) if len(rows) else criteria
    chosen = np.array([r.model == c.best for r in rows], dtype=bool)
    ax.hlines(y, 0, above, color="C0", lw=1)
    ax.plot(above[~chosen], y[~chosen], "o", color="C0", label="candidate")
    ax.plot(above[chosen], y[chosen], "D", color="C1", ms=8, label="chosen")
    # Differences span from a fraction of one to many thousands: linear near 0, logarithmic beyond.
    ax.set_xscale("symlog", linthresh=1.0)
    ax.set_yticks(y, [r.model for r in rows], fontsize=8)
    ax.set_xlabel(f"{c.penalty.upper()} above the best [objective units, symlog]")
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title(f"{c.name}: ranking of {len(c.ranking)} models")
    return ax


def select_column(c: SelectColumn, ax: Any = None, ranking_ax: Any = None, decomposition: bool = True) -> Any:
    """The chosen fit over the data's WV; with no axes given, its ranking beside it."""
    if ax is None and ranking_ax is None:
        _, (ranking_ax, ax) = pyplot().subplots(1, 2, figsize=(2 * FIGURE_SIZE[0], FIGURE_SIZE[1]))
    if ranking_ax is not None:
        ranking(c, ranking_ax)
    ax = _wv_and_model(ax, c.levels, c.best_model, c.best, c.freq, c.unit, f"{c.name}: chosen {c.best}",
                       decomposition)
    return ax if ranking_ax is None else (ranking_ax, ax)


def select(s: SelectResult) -> Any:
    """One row per column: its ranking and its chosen fit."""
    fig, grid = pyplot().subplots(len(s.columns), 2, figsize=(2 * FIGURE_SIZE[0], FIGURE_SIZE[1] * len(s.columns)),
                                  squeeze=False)
    for c, (left, right) in zip(s.columns, grid):
        select_column(c, right, left)
    fig.tight_layout()
    return grid


def gap_column(c: GapColumn, ax: Any = None) -> Any:
    """The data's WV level by level against the baseline's WV and the band a recording of
    the baseline would fall in (the data's WV is its ratio to the baseline's times that WV)."""
    ax = axes(ax)
    lv = c.gap.levels
    _, parts = _gmwm.model_wv(c.baseline_model, lv.tau, freq=None if math.isnan(c.freq) else c.freq)
    baseline = parts.sum(axis=0)
    data = lv.ratio * baseline
    ax.fill_between(lv.tau_seconds, lv.ref_low, lv.ref_high, color="C0", alpha=BAND_ALPHA,
                    label="band of the baseline's recordings")
    ax.loglog(lv.tau_seconds, baseline, "-", color="C0", label="baseline's WV")
    inside = ~lv.outside
    ax.loglog(lv.tau_seconds[inside], data[inside], "o", color="C2", ms=4, label="data, inside the band")
    ax.loglog(lv.tau_seconds[lv.outside], data[lv.outside], "o", color="C3", ms=5, label="data, outside the band")
    ax.set_xlabel("tau [s]")
    ax.set_ylabel("wavelet variance [(data unit)^2]")
    ax.set_title(f"{c.name}: {c.effect}, {'gap closed' if c.closed else 'gap remains'}")
    ax.legend(loc="best", fontsize=8)
    return ax


def gap(g: GapResult) -> Any:
    """One plot per column."""
    fig, grid = pyplot().subplots(len(g.columns), 1, figsize=(FIGURE_SIZE[0], FIGURE_SIZE[1] * len(g.columns)),
                                  squeeze=False)
    for c, row in zip(g.columns, grid):
        gap_column(c, row[0])
    fig.tight_layout()
    return grid[:, 0]


def nav(n: NavResult, ax: Any = None, quantity: str = "position") -> Any:
    if quantity not in ("position", "velocity", "attitude"):
        raise ValueError(f"quantity: found {quantity!r}, expected position, velocity or attitude")
    ax = axes(ax)
    for k, f in enumerate(n.filters):
        curves = f.curves
        ax.plot(curves.time, getattr(curves, f"{quantity}_rms"), "-", color=f"C{k}", label=f"{f.label}: RMS error")
        ax.plot(curves.time, getattr(curves, f"{quantity}_3sigma"), "--", color=f"C{k}", lw=1,
                label=f"{f.label}: claimed 3 sigma")
    for start, end in n.scenario.outages:
        ax.axvspan(start, end, color="0.85", zorder=0)
    ax.set_yscale("log")
    ax.set_xlabel("time [s]")
    ax.set_ylabel(f"{quantity} error" + _bracket(n.units.get(quantity)))
    ax.set_title(f"{quantity} error against the truth (outages shaded)")
    ax.legend(loc="best", fontsize=8)
    return ax


def fleet(r: FleetResult, ax: Any = None, figure: str = "N") -> Any:
    if figure not in ("N", "K", "B", "Q", "R"):
        raise ValueError(f"figure: found {figure!r}, expected N, K, B, Q or R")
    ax = axes(ax)
    axis_names: list[str] = sorted({row.axis for row in r.rows if row.axis})
    units = sorted({row.unit for row in r.rows if row.axis})
    boxed = False  # one legend entry for the boxes
    for k, unit in enumerate(units):
        xs, ys, lows, highs, flagged = [], [], [], [], []
        for row in r.rows:
            value = getattr(row, figure)
            if row.unit != unit or not row.axis or value is None or not math.isfinite(value.value):
                continue
            xs.append(axis_names.index(row.axis) + (k - (len(units) - 1) / 2) * 0.6 / max(len(units), 1))
            ys.append(value.value)
            lows.append(value.value - value.low if math.isfinite(value.low) else 0.0)
            highs.append(value.high - value.value if math.isfinite(value.high) else 0.0)
            flagged.append(bool(row.flags))
        ax.errorbar(xs, ys, yerr=[lows, highs], fmt="o", color=f"C{k}", ms=5, capsize=2, label=unit)
        marked = [(x, y) for x, y, f in zip(xs, ys, flagged) if f]
        if marked:
            ax.plot(*zip(*marked), "s", mfc="none", mec="red", ms=11, label="_flagged" if boxed else "flagged")
            boxed = True
    ax.set_xticks(range(len(axis_names)), axis_names)
    ax.set_yscale("log")
    ax.set_ylabel(f"{figure}" + _bracket(_figure_unit(r, figure)))
    ax.set_title(f"{figure} of every unit, by axis ({r.recordings} recordings)")
    ax.legend(loc="center left", bbox_to_anchor=(1.0, 0.5), fontsize=8)
    return ax


def _figure_unit(r: FleetResult, figure: str) -> str | None:
    """The figure's unit (N: U/sqrt(Hz), K: U/s/sqrt(Hz), B: U, Q: U*s, R: U/s, as the documents
    write them) for the rows' data unit; None when the rows' units differ or are not known."""
    units = {row.unit_of_data for row in r.rows if row.axis and row.unit_of_data}
    if len(units) != 1:
        return None
    return dict(zip("NKBQR", _gmwm.figure_units(units.pop())))[figure]


def labels_of(ax: Any) -> Sequence[str]:
    """The legend's labels of an axes (the tests read them)."""
    legend = ax.get_legend()
    return [t.get_text() for t in legend.get_texts()] if legend else []


TIME_KINDS = ("tdev", "ttotdev", "mtie", "tierms")


def stability(c: "StabilityColumn", ax: Any = None, kinds: Sequence[str] | None = None) -> Any:
    chosen = list(kinds) if kinds is not None else [k for k in c.deviations if k not in TIME_KINDS]
    for k in chosen:
        if k not in c.deviations:
            raise ValueError(f"kinds: {k!r} is not among this column's deviations ({', '.join(c.deviations)})")
    units = {(k in TIME_KINDS) for k in chosen}
    if len(units) > 1:
        raise ValueError("kinds: the time deviations (tdev, ttotdev, mtie, tierms) are in the phase's unit; "
                         "plot them apart from the others")
    ax = axes(ax)
    for i, k in enumerate(chosen):
        d = c.deviations[k]
        ax.loglog(d.tau, d.value, "o-", ms=3, color=f"C{i}", label=k)
        ax.fill_between(d.tau, d.ci_low, d.ci_high, color=f"C{i}", alpha=BAND_ALPHA, lw=0)
    unit = c.unit if c.unit else "data unit"
    time_units = bool(chosen) and chosen[0] in TIME_KINDS
    ax.set_xlabel("tau [s]")
    ax.set_ylabel("deviation [" + (f"({unit})*s" if time_units else unit) + "]")
    ax.set_title(f"{c.name}: stability deviations (bands: their intervals)")
    ax.legend(loc="best", fontsize=8)
    return ax
