"""Typed results of nav, plan and export (docs/cli.md "JSON", docs/nav.md,
docs/exports.md)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping

import numpy as np

from ._common import (BoolArray, FloatArray, IntArray, JsonResult, floats, g, num, strings)
@dataclass(frozen=True)
class NavScenario:
    """The trajectory, rates, outages ((start, end) in seconds) and initial errors."""

    trajectory: str
    imu_rate: float
    horizon: float
    fix_rate: float
    fix_sigma: float
    outages: tuple[tuple[float, float], ...]
    gravity: float
    initial: dict[str, float]
    output_interval: float
    judge_from: float

    @classmethod
    def from_dict(cls, s: Mapping[str, Any]) -> "NavScenario":
        return cls(s["trajectory"], num(s["imu_rate"]), num(s["horizon"]), num(s["fix_rate"]), num(s["fix_sigma"]),
                   tuple((num(a), num(b)) for a, b in s["outages"]), num(s["gravity"]),
                   {k: num(v) for k, v in s["initial"].items()}, num(s["output_interval"]), num(s["judge_from"]))


@dataclass(frozen=True)
class NavSummary:
    """A filter's errors at the judged time (`time`) and the largest over the run."""

    time: float
    position_rms: float
    position_3sigma: float
    velocity_rms: float
    velocity_3sigma: float
    attitude_rms: float
    attitude_3sigma: float
    nees: float
    largest_position_rms: float
    largest_nees: float


@dataclass(frozen=True, eq=False)
class NavCurves:
    """A filter's error curves against `time` (s): the true RMS errors, the 3-sigma the
    filter claims, and the NEES."""

    time: FloatArray
    position_rms: FloatArray
    position_3sigma: FloatArray
    velocity_rms: FloatArray
    velocity_3sigma: FloatArray
    attitude_rms: FloatArray
    attitude_3sigma: FloatArray
    nees: FloatArray

    def __repr__(self) -> str:
        return f"NavCurves({len(self.time)} points to {g(self.time[-1]) if len(self.time) else '-'} s)"


@dataclass(frozen=True, eq=False)
class NavMonteCarlo:
    """The Monte Carlo runs' curves (on the exact curves' time grid) and their verdict."""

    position_rms: FloatArray
    velocity_rms: FloatArray
    attitude_rms: FloatArray
    nees: FloatArray
    verdict: str

    def __repr__(self) -> str:
        return f"NavMonteCarlo({len(self.nees)} points, {self.verdict})"


@dataclass(frozen=True, eq=False)
class NavFilter:
    """One filter model against the truth: its `verdict` (consistent, optimistic, ...),
    the share of time its NEES is inside / above the band, `summary` and `curves`."""

    label: str
    source: str
    models: tuple[str, ...]
    notes: tuple[str, ...]
    verdict: str
    nees_inside: float
    nees_above: float
    nees_band: tuple[float, float]
    summary: NavSummary
    curves: NavCurves
    monte_carlo: NavMonteCarlo | None

    @classmethod
    def from_dict(cls, f: Mapping[str, Any]) -> "NavFilter":
        s, c, m = f["summary"], f["curves"], f["monte_carlo"]
        summary = NavSummary(**{k: num(s[k]) for k in NavSummary.__dataclass_fields__})
        curves = NavCurves(**{k: floats(c[k]) for k in NavCurves.__dataclass_fields__})
        mc = None if m is None else NavMonteCarlo(floats(m["position_rms"]), floats(m["velocity_rms"]),
                                                  floats(m["attitude_rms"]), floats(m["nees"]), m["verdict"])
        low, high = f["nees_band"]
        return cls(f["label"], f["source"], strings(f["models"]), strings(f["notes"]), f["verdict"],
                   num(f["nees_inside"]), num(f["nees_above"]), (num(low), num(high)), summary, curves, mc)

    def __repr__(self) -> str:
        return (f"NavFilter({self.label}: {self.verdict}, NEES inside {g(100 * self.nees_inside, 3)}%, "
                f"position rms {g(self.summary.position_rms)} m at {g(self.summary.time)} s)")


@dataclass(frozen=True, eq=False)
class NavResult(JsonResult):
    """What a noise model costs a navigation filter (gmwm.nav, `gmwm nav --json`): the
    `scenario`, the truth, one NavFilter per filter, the Monte Carlo settings (`runs`,
    `seed`; None without) and the `units` of the curves."""

    scenario: NavScenario
    truth_source: str
    truth_models: tuple[str, ...]
    filters: tuple[NavFilter, ...]
    monte_carlo: dict[str, int] | None
    units: dict[str, str]

    @classmethod
    def _from(cls, d: Any, text: str) -> "NavResult":
        return cls(d, text, NavScenario.from_dict(d["scenario"]), d["truth"]["source"], strings(d["truth"]["models"]),
                   tuple(NavFilter.from_dict(f) for f in d["filters"]), d["monte_carlo"], dict(d["units"]))

    def filter(self, label: str) -> NavFilter:
        """The filter labelled `label` (KeyError when none)."""
        for f in self.filters:
            if f.label == label:
                return f
        raise KeyError(label)

    def __repr__(self) -> str:
        return "NavResult(" + ", ".join(f"{f.label}: {f.verdict}" for f in self.filters) + ")"


@dataclass(frozen=True)
class PlanTarget:
    """A figure to pin down (N, K, B or a parameter): the record it needs (`samples`,
    `seconds`; `reachable` False when no length gives the precision)."""

    name: str
    value: float
    unit: str
    reachable: bool
    samples: int
    seconds: float
    own_samples: int
    relative_se: float
    precision_at_record: float
    basis: str
    #: Why a record of record_seconds promises no precision (None when it does).
    precision_at_record_basis: str | None = None

    def __repr__(self) -> str:
        need = f"{g(self.seconds)} s" if self.reachable else "unreachable"
        return f"PlanTarget({self.name} = {g(self.value)} {self.unit}: {need})"


@dataclass(frozen=True)
class PlanResolved:
    """The record at which the model itself is resolved, and the parameter that sets it."""

    samples: int
    seconds: float
    by: str


@dataclass(frozen=True)
class PlanColumn:
    name: str
    unit: str | None
    model: str
    freq: float
    resolved: PlanResolved
    targets: tuple[PlanTarget, ...]

    def __repr__(self) -> str:
        return f"PlanColumn({self.name}: {self.model}, " + ", ".join(repr(t) for t in self.targets) + ")"

    def target(self, name: str) -> PlanTarget:
        """The target called `name` (KeyError when none)."""
        for t in self.targets:
            if t.name == name:
                return t
        raise KeyError(name)


@dataclass(frozen=True, eq=False)
class PlanResult(JsonResult):
    """How long to record (gmwm.plan, `gmwm plan --json`): per column the record each
    target needs for `precision` at `confidence`."""

    source: str
    precision: float
    confidence: float
    record_seconds: float
    columns: tuple[PlanColumn, ...]

    @classmethod
    def _from(cls, d: Any, text: str) -> "PlanResult":
        columns = tuple(
            PlanColumn(c["name"], c["unit"], c["model"], num(c["freq"]),
                       PlanResolved(int(c["resolved"]["samples"]), num(c["resolved"]["seconds"]), c["resolved"]["by"]),
                       tuple(PlanTarget(t["name"], num(t["value"]), t["unit"], bool(t["reachable"]), int(t["samples"]),
                                        num(t["seconds"]), int(t["own_samples"]), num(t["relative_se"]),
                                        num(t["precision_at_record"]), t["basis"],
                                        t.get("precision_at_record_basis")) for t in c["targets"]))
            for c in d["columns"])
        return cls(d, text, d["source"], num(d["precision"]), num(d["confidence"]), num(d["record_seconds"]), columns)

    def __repr__(self) -> str:
        parts = [f"{c.name}: " + ", ".join(f"{t.name} {g(t.seconds, 3)} s" if t.reachable else f"{t.name} unreachable"
                                           for t in c.targets) for c in self.columns]
        return f"PlanResult(+-{g(100 * self.precision, 3)}%: " + "; ".join(parts) + ")"


@dataclass(frozen=True)
class GaussMarkov:
    """A Gauss-Markov (AR1) component in continuous units."""

    correlation_time: float
    sigma: float
    drive: float


@dataclass(frozen=True, eq=False)
class ExportColumn:
    """A column's figures as the export read them (the data's unit): N (`noise_density`),
    K (`random_walk`), its Gauss-Markov components and the `others` it cannot express."""

    name: str
    freq: float
    kind: str
    unit: str
    model: str
    noise_density: float
    random_walk: float
    gauss_markov: tuple[GaussMarkov, ...]
    others: tuple[str, ...]

    def __repr__(self) -> str:
        return f"ExportColumn({self.name}: N={g(self.noise_density)}, K={g(self.random_walk)} ({self.unit}))"


@dataclass(frozen=True)
class WrittenNoise:
    """The figures written for a sensor, in SI."""

    noise_density: float
    random_walk: float
    bias_drive: float
    bias_correlation_time: float
    bias_from_random_walk: bool

    @classmethod
    def from_dict(cls, w: Mapping[str, Any]) -> "WrittenNoise":
        return cls(num(w["noise_density"]), num(w["random_walk"]), num(w["bias_drive"]),
                   num(w["bias_correlation_time"]), bool(w["bias_from_random_walk"]))


@dataclass(frozen=True)
class ExportWritten:
    """One sensor kind's written figures: `combined` (the aggregate), and per axis (x, y,
    z) in `axes` when `per_axis` (else None)."""

    columns: tuple[str, ...]
    per_axis: bool
    combined: WrittenNoise
    axes: dict[str, WrittenNoise] | None

    def __repr__(self) -> str:
        return (f"ExportWritten({', '.join(self.columns)}: N={g(self.combined.noise_density)}, "
                f"K={g(self.combined.random_walk)}{', per axis' if self.per_axis else ''})")


@dataclass(frozen=True)
class ConsistentFor:
    """`export --consistent-for`: the inflation that keeps a WN + RW filter consistent."""

    update_rate: float
    horizon: float
    fix_sigma: float
    white_factor: float
    walk_factor: float
    verdict: str
    nees_inside: float
    smaller_factor: float
    smaller_factor_above_band: float
    reason: str
    #: The next smaller factor's verdict (optimistic), None when no inflation was needed.
    smaller_factor_verdict: str | None = None


@dataclass(frozen=True, eq=False)
class ExportResult(JsonResult):
    """The document `gmwm export ... --json` writes: the `format`, the `output` file, the
    columns read, the figures `written` per sensor kind (gyro, accel), the `warnings` and,
    with --consistent-for, `consistent_for` (else None)."""

    format: str
    output: str
    sidecar: str | None
    source: str
    aggregation: str
    inflate: float
    inflate_walk: float
    rate: float
    columns: tuple[ExportColumn, ...]
    written: dict[str, ExportWritten]
    warnings: tuple[str, ...]
    consistent_for: ConsistentFor | None
    #: The file's text and its sidecar's (basalt's header), as gmwm.export() rendered them;
    #: None for a document read with from_json (the command wrote the files itself).
    content: str | None = None
    sidecar_content: str | None = None

    @classmethod
    def _from(cls, d: Any, text: str) -> "ExportResult":
        columns = tuple(
            ExportColumn(c["name"], num(c["freq"]), c["kind"], c["unit"], c["model"], num(c["noise_density"]),
                         num(c["random_walk"]),
                         tuple(GaussMarkov(num(m["correlation_time"]), num(m["sigma"]), num(m["drive"]))
                               for m in c["gauss_markov"]), strings(c["others"]))
            for c in d["columns"])
        written = {
            k: ExportWritten(strings(w["columns"]), bool(w["per_axis"]), WrittenNoise.from_dict(w["combined"]),
                             {a: WrittenNoise.from_dict(x) for a, x in w["axes"].items()} if "axes" in w else None)
            for k, w in d["written"].items()}
        c = d.get("consistent_for")
        consistent = None if c is None else ConsistentFor(
            num(c["update_rate"]), num(c["horizon"]), num(c["fix_sigma"]), num(c["white_factor"]),
            num(c["walk_factor"]), c["verdict"], num(c["nees_inside"]), num(c["smaller_factor"]),
            num(c["smaller_factor_above_band"]), c["reason"], c.get("smaller_factor_verdict"))
        return cls(d, text, d["format"], d["output"], d["sidecar"], d["source"], d["aggregation"], num(d["inflate"]),
                   num(d["inflate_walk"]), num(d["rate"]), columns, written, strings(d["warnings"]), consistent)

    def __repr__(self) -> str:
        kinds = ", ".join(f"{k} N={g(w.combined.noise_density)} K={g(w.combined.random_walk)}"
                          for k, w in self.written.items())
        return f"ExportResult({self.format} -> {self.output}: {kinds}, inflation x{g(self.inflate)})"


@dataclass(frozen=True)
class FleetFigure:
    """N, K or B of one unit's axis: `value` with its interval [`low`, `high`] (low NaN for a
    bound) in the data's unit, and its `source` (model, data or bound)."""

    value: float
    low: float
    high: float
    source: str

    @classmethod
    def from_dict(cls, d: Mapping[str, Any] | None) -> "FleetFigure | None":
        return None if d is None else cls(num(d["value"]), num(d["low"]), num(d["high"]), d["source"])


@dataclass(frozen=True)
class FleetSpecCheck:
    """One figure of a unit's axis against its spec limit (`gmwm fleet --spec`): `value` with
    its interval [`low`, `high`] in the limit's unit (B as the Allan minimum 0.664 B when the
    limit is an in-run bias stability), the `verdict` ('pass', 'fail', 'unknown') and a `note`."""

    figure: str
    limit: float
    limit_unit: str
    limit_key: str
    limit_where: str
    value: float
    low: float
    high: float
    verdict: str
    note: str

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> "FleetSpecCheck":
        return cls(d["figure"], num(d["limit"]), d["limit_unit"], d["limit_key"], d["limit_where"], num(d["value"]),
                   num(d["low"]), num(d["high"]), d["verdict"], d["note"])


@dataclass(frozen=True)
class FleetRow:
    """One unit x axis of a fleet (or a recording that failed: `axis` empty, `status` why)."""

    unit: str
    model: str
    group: str
    path: str
    axis: str
    unit_of_data: str
    status: str
    chosen: str | None
    chosen_structure: str | None
    gof_p_value: float
    freq: float
    n: int
    N: FleetFigure | None
    K: FleetFigure | None
    B: FleetFigure | None
    seconds: float
    flags: tuple[str, ...]
    cached: bool = False
    spec: tuple[FleetSpecCheck, ...] = ()
    spec_verdict: str = ""
    spec_note: str = ""
    gap_verdict: str = ""
    gap_headline: str = ""
    gap_p_value: float = float("nan")


@dataclass(frozen=True)
class FleetFigureSummary:
    """One figure ('N', 'K' or 'B') of one axis over a group's units: its median, its
    spread as a factor (exp(MAD of the logs / 0.6745)) and the units flagged on it."""

    group: str
    axis: str
    figure: str
    units: int
    median: float
    spread: float
    flagged: tuple[str, ...]
    unit: str = ""
    out_of_spec: tuple[str, ...] = ()


@dataclass(frozen=True)
class FleetJointModel:
    """The joint model of a group's axis (`gmwm fleet --joint`): its units as replicates (the
    ones that stand out `left_out`), the selection's `recommended` model and its `model` with
    values, the typical unit's N, K, B, and the shared-theta test (`shared`: the units share
    one theta at 5%; `heterogeneity_p`, `calibration` 'bootstrap' or 'chi-square'). `status`
    says why there is none."""

    group: str
    axis: str
    units: int
    left_out: tuple[str, ...]
    status: str
    unit: str
    recommended: str | None
    model: str | None
    N: FleetFigure | None
    K: FleetFigure | None
    B: FleetFigure | None
    heterogeneity: float
    heterogeneity_p: float
    calibration: str | None
    shared: bool | None
    seconds: float

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> "FleetJointModel":
        t = d.get("replicate_test") or {}
        return cls(d["group"], d["axis"], int(d["units"]), strings(d.get("left_out", [])), d["status"], d["unit"],
                   d.get("recommended"), d.get("model"), FleetFigure.from_dict(d.get("N")),
                   FleetFigure.from_dict(d.get("K")), FleetFigure.from_dict(d.get("B")), num(t.get("heterogeneity")),
                   num(t.get("heterogeneity_p_value")), t.get("calibration"), t.get("shared"), num(d["seconds"]))


@dataclass(frozen=True, eq=False)
class FleetResult(JsonResult):
    """The document `gmwm fleet MANIFEST --json` writes (gmwm.fleet): `rows` (one per unit x
    axis), `summary` (per group, axis and figure), `failed` recordings."""

    manifest: str
    model_spec: str
    recordings: int
    failed: int
    rows: tuple[FleetRow, ...]
    summary: tuple[FleetFigureSummary, ...]
    cached: int = 0
    cache: str | None = None
    spec: str | None = None
    gap_baseline: str | None = None
    joint: tuple[FleetJointModel, ...] = ()

    @classmethod
    def _from(cls, d: Any, text: str) -> "FleetResult":
        rows = tuple(
            FleetRow(r["unit"], r["model"], r["group"], r["path"], r["axis"], r["unit_of_data"], r["status"],
                     r["chosen"], r["chosen_structure"], num(r["gof_p_value"]), num(r["freq"]), int(r["n"]),
                     FleetFigure.from_dict(r["N"]), FleetFigure.from_dict(r["K"]), FleetFigure.from_dict(r["B"]),
                     num(r["seconds"]), strings(r["flags"]), bool(r.get("cached", False)),
                     tuple(FleetSpecCheck.from_dict(c) for c in r.get("spec", ())), r.get("spec_verdict", ""),
                     r.get("spec_note", ""), (r.get("gap") or {}).get("verdict", ""),
                     (r.get("gap") or {}).get("headline", ""), num((r.get("gap") or {}).get("p_value")))
            for r in d["rows"])
        summary = tuple(
            FleetFigureSummary(s["group"], s["axis"], s["figure"], int(s["units"]), num(s["median"]),
                               num(s["spread"]), strings(s["flagged"]), s.get("unit", ""),
                               strings(s.get("out_of_spec", [])))
            for s in d["summary"])
        return cls(d, text, d["manifest"], d["model_spec"], int(d["recordings"]), int(d["failed"]), rows, summary,
                   int(d.get("cached", 0)), d.get("cache"), d.get("spec"), d.get("gap_baseline"),
                   tuple(FleetJointModel.from_dict(j) for j in d.get("joint", [])))

    def to_dataframe(self) -> Any:
        """The rows as a pandas DataFrame (N, K, B as value columns with _low and _high);
        ImportError when pandas is not installed (Debian: python3-pandas)."""
        import pandas  # optional: only this method needs it

        records = []
        for r in self.rows:
            rec = {k: getattr(r, k) for k in ("unit", "model", "group", "path", "axis", "unit_of_data", "status",
                                              "chosen_structure", "gof_p_value", "freq", "n", "seconds")}
            for name in ("N", "K", "B"):
                f = getattr(r, name)
                rec[name] = f.value if f else np.nan
                rec[name + "_low"] = f.low if f else np.nan
                rec[name + "_high"] = f.high if f else np.nan
            rec["flags"] = "; ".join(r.flags)
            rec["cached"] = r.cached
            rec["spec"] = r.spec_verdict
            rec["gap"] = r.gap_verdict
            records.append(rec)
        return pandas.DataFrame.from_records(records)

    def __repr__(self) -> str:
        flagged = sorted({r.unit for r in self.rows if r.flags})
        return (f"FleetResult({self.recordings} recordings over {self.model_spec}, {len(self.rows)} rows, "
                f"{self.failed} failed, flagged: {', '.join(flagged) if flagged else 'none'})")
