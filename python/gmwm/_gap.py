"""Typed results of gap and gap_check (docs/cli.md "JSON", docs/gap.md)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping

import numpy as np

from ._common import (BoolArray, FloatArray, HasParameters, IntArray, JsonResult, bools, built, column_texts,
                      continuous, floats, g, num, parameters, strings)
from ._types import ContinuousParameter, Parameter


@dataclass(frozen=True)
class GapBand:
    """A band of levels beyond the multiplicity-corrected z: `direction` excess or deficit,
    `peak_ratio` the largest departure (data WV / baseline WV)."""

    tau_from_seconds: float
    tau_to_seconds: float
    tau_from: float
    tau_to: float
    direction: str
    peak_ratio: float

    @classmethod
    def from_dict(cls, b: Mapping[str, Any]) -> "GapBand":
        return cls(num(b["tau_from_seconds"]), num(b["tau_to_seconds"]), num(b["tau_from"]), num(b["tau_to"]),
                   b["direction"], num(b["peak_ratio"]))

    def __repr__(self) -> str:
        return (f"GapBand({self.direction} at {g(self.tau_from_seconds)} s - {g(self.tau_to_seconds)} s, "
                f"up to {g(self.peak_ratio)}x)")


def _bands(rows: Any) -> tuple[GapBand, ...]:
    return tuple(GapBand.from_dict(b) for b in rows or ())


@dataclass(frozen=True, eq=False)
class GapLevels:
    """Per level, as arrays: `ratio` of the data's WV to the baseline's, its `z`, the
    reference band (`ref_low`, `ref_high`; analytic: `analytic_low`, `analytic_high`) and
    whether the level is `outside` it."""

    tau: FloatArray
    tau_seconds: FloatArray
    ratio: FloatArray
    z: FloatArray
    ref_low: FloatArray
    analytic_low: FloatArray
    analytic_high: FloatArray
    ref_high: FloatArray
    outside: BoolArray

    @classmethod
    def from_list(cls, rows: list[Mapping[str, Any]]) -> "GapLevels":
        def col(key: str) -> list[Any]:
            return [r[key] for r in rows]

        return cls(floats(col("tau")), floats(col("tau_seconds")), floats(col("ratio")), floats(col("z")),
                   floats(col("ref_low")), floats(col("analytic_low")), floats(col("analytic_high")),
                   floats(col("ref_high")), bools(col("outside")))

    def __len__(self) -> int:
        return len(self.tau)

    def __repr__(self) -> str:
        return f"GapLevels({len(self.tau)} levels, {int(self.outside.sum())} outside)"


@dataclass(frozen=True)
class GapWindow:
    """A (time window, level) cell that departs from the rest of the record."""

    t_from_seconds: float
    t_to_seconds: float
    first_sample: int
    last_sample: int
    tau_seconds: float
    tau: float
    ratio: float
    z: float


@dataclass(frozen=True, eq=False)
class GapSplitHalf:
    """The two halves of the record compared, per level, as arrays."""

    tau: FloatArray
    tau_seconds: FloatArray
    ratio: FloatArray
    disjoint: BoolArray

    def __repr__(self) -> str:
        return f"GapSplitHalf({len(self.tau)} levels, {int(self.disjoint.sum())} disjoint)"


@dataclass(frozen=True, eq=False)
class GapTest:
    """The comparison with the baseline (JSON "gap"): the global test, the bands, the
    levels and the window map (`windows` None when the record is too short for one)."""

    detected: bool
    p_value: float
    statistic: float
    bands: tuple[GapBand, ...]
    levels: GapLevels
    windows: tuple[GapWindow, ...] | None
    split_half: GapSplitHalf
    window_length_seconds: float

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> "GapTest":
        windows = None if d["windows"] is None else tuple(
            GapWindow(num(w["t_from_seconds"]), num(w["t_to_seconds"]), int(w["first_sample"]), int(w["last_sample"]),
                      num(w["tau_seconds"]), num(w["tau"]), num(w["ratio"]), num(w["z"])) for w in d["windows"])
        half = d["split_half"]
        split = GapSplitHalf(floats([h["tau"] for h in half]), floats([h["tau_seconds"] for h in half]),
                             floats([h["ratio"] for h in half]), bools([h["disjoint"] for h in half]))
        return cls(bool(d["detected"]), num(d["p_value"]), num(d["statistic"]), _bands(d["bands"]),
                   GapLevels.from_list(d["levels"]), windows, split, num(d["window_length_seconds"]))

    def __repr__(self) -> str:
        return f"GapTest(detected={self.detected}, p={g(self.p_value, 3)}, {len(self.bands)} bands)"


@dataclass(frozen=True)
class GapStep:
    """One effect the attribution took, in order: `effect` (WN, AR1, REPARAMETERISE, ...),
    its `detail`, its drop in the objective and its `share` of the excess removed."""

    effect: str
    detail: str
    drop: float
    share: float

    def __repr__(self) -> str:
        return f"GapStep({self.detail}: {g(100 * self.share, 3)}% of the excess)"


@dataclass(frozen=True)
class GapCandidate:
    """A candidate effect scored against its calibrated threshold."""

    effect: str
    improvement: float
    threshold: float
    optimism: float
    wvic_confirmed: bool
    cleared: bool
    model: str


@dataclass(frozen=True)
class GapEvent:
    """A bias STEP or warm-up TRANSIENT located in the series."""

    effect: str
    sample: int
    time_seconds: float
    size: float
    time_constant: float
    time_constant_seconds: float
    level: int
    statistic: float
    threshold: float


@dataclass(frozen=True)
class GapEventTest:
    statistic: float
    threshold: float


@dataclass(frozen=True)
class GapStepScan:
    """The step scan (docs/gap.md, "The step scan"): max |z| / RMS against its calibrated
    threshold, and the sample where |z| peaks."""

    statistic: float
    threshold: float
    sample: int


@dataclass(frozen=True)
class GapTrend:
    """The drift test on the record's end segments (`omega` per sample, signed)."""

    omega: float
    ci_low: float
    ci_high: float
    z: float
    threshold: float
    significant: bool


@dataclass(frozen=True)
class GapTemperature:
    """The coupling to the temperature column (wavelet covariance)."""

    coupling: float
    ci_low: float
    ci_high: float
    z: float
    threshold: float
    significant: bool


@dataclass(frozen=True, eq=False)
class Attribution(HasParameters):
    """Which effects explain the gap: the first `effect`, the `steps` taken (each with its
    share of the excess), the final `model` with its `parameters` and `physical` quantities,
    the time-domain tests (`event`, `event_test`, `drift`, `temperature`, `step_scan`; None
    when not run), the `refused` moves and every scored candidate."""

    effect: str
    steps: tuple[GapStep, ...]
    model: str
    parameters: tuple[Parameter, ...]
    physical: tuple[ContinuousParameter, ...]
    event: GapEvent | None
    event_test: GapEventTest | None
    temperature: GapTemperature | None
    drift: GapTrend | None
    refused: tuple[Any, ...]
    candidates: tuple[GapCandidate, ...]
    step_scan: GapStepScan | None = None

    @classmethod
    def from_dict(cls, a: Mapping[str, Any]) -> "Attribution":
        details, drops, shares = a["step_details"], a["step_drops"], a["step_shares"]
        steps = tuple(GapStep(e, details[k] if k < len(details) else "", num(drops[k]) if k < len(drops) else np.nan,
                              num(shares[k]) if k < len(shares) else np.nan) for k, e in enumerate(a["steps"]))
        e, et, t, dr = a["event"], a["event_test"], a["temperature"], a["drift"]
        return cls(
            a["effect"], steps, a["model"], parameters(a["parameters"]), continuous(a["physical"]),
            None if e is None else GapEvent(e["effect"], int(e["sample"]), num(e["time_seconds"]), num(e["size"]),
                                            num(e["time_constant"]), num(e["time_constant_seconds"]), int(e["level"]),
                                            num(e["statistic"]), num(e["threshold"])),
            None if et is None else GapEventTest(num(et["statistic"]), num(et["threshold"])),
            None if t is None else GapTemperature(num(t["coupling"]), num(t["ci_low"]), num(t["ci_high"]),
                                                  num(t["z"]), num(t["threshold"]), bool(t["significant"])),
            None if dr is None else GapTrend(num(dr["omega"]), num(dr["ci_low"]), num(dr["ci_high"]), num(dr["z"]),
                                             num(dr["threshold"]), bool(dr["significant"])),
            tuple(a["refused"]),
            tuple(GapCandidate(c["effect"], num(c["improvement"]), num(c["threshold"]), num(c["optimism"]),
                               bool(c["wvic_confirmed"]), bool(c["cleared"]), c["model"]) for c in a["candidates"]),
            None if a.get("step_scan") is None else GapStepScan(num(a["step_scan"]["statistic"]),
                                                                num(a["step_scan"]["threshold"]),
                                                                int(a["step_scan"]["sample"])))

    def __repr__(self) -> str:
        return f"Attribution({' -> '.join(s.effect for s in self.steps) or self.effect}: {self.model})"


@dataclass(frozen=True)
class Remaining:
    """What is left after the attribution: `closed` when the final model is not rejected."""

    closed: bool
    bands: tuple[GapBand, ...]
    levels_outside: int

    def __repr__(self) -> str:
        state = "closed" if self.closed else "open"
        return f"Remaining({state}, {len(self.bands)} bands, {self.levels_outside} levels outside)"


@dataclass(frozen=True)
class Shrinkage:
    """How much of the gap the attribution removed (objective, distance, excess, levels
    outside, p-value: before and after)."""

    objective_before: float
    objective_after: float
    null_mean: float
    null_mean_after: float
    distance_before: float
    distance_after: float
    null_distance_mean: float
    excess_before: float
    excess_after: float
    excess_removed: float
    rms_log_ratio_before: float
    rms_log_ratio_after: float
    levels_outside_before: int
    levels_outside_after: int
    p_value_before: float
    p_value_after: float

    @classmethod
    def from_dict(cls, s: Mapping[str, Any]) -> "Shrinkage":
        values: dict[str, Any] = {k: (int(s[k]) if k.startswith("levels_outside") else num(s[k]))
                                  for k in cls.__dataclass_fields__}
        return cls(**values)


@dataclass(frozen=True)
class GapNavigation:
    """The integrated error after `horizon_seconds` under the baseline and the final model."""

    horizon_seconds: float
    rms_without: float
    rms_with: float
    unit: str


@dataclass(frozen=True)
class Contamination:
    screened: bool
    levels: tuple[Any, ...]


@dataclass(frozen=True, eq=False)
class GapColumn(JsonResult):
    """One column's gap diagnosis: the `headline` (the verdict the terminal prints), the
    comparison (`gap`), the `attribution`, what `remaining`, the `shrinkage`."""

    name: str
    n: int
    freq: float
    baseline_model: str
    gap: GapTest
    attribution: Attribution
    headline: str
    contamination: Contamination
    remaining: Remaining
    shrinkage: Shrinkage
    navigation: GapNavigation
    conversions: tuple[str, ...]
    notes: tuple[str, ...]

    @classmethod
    def _from(cls, d: Any, text: str) -> "GapColumn":
        r, nv, c = d["remaining"], d["navigation"], d["contamination"]
        return cls(d, text, d["name"], int(d["n"]), num(d["freq"]), d["baseline_model"], GapTest.from_dict(d["gap"]),
                   Attribution.from_dict(d["attribution"]), d["headline"],
                   Contamination(bool(c["screened"]), tuple(c["levels"])),
                   Remaining(bool(r["closed"]), _bands(r["bands"]), int(r["levels_outside"])),
                   Shrinkage.from_dict(d["shrinkage"]),
                   GapNavigation(num(nv["horizon_seconds"]), num(nv["rms_without"]), num(nv["rms_with"]), nv["unit"]),
                   strings(d["conversions"]), strings(d["notes"]))

    @property
    def closed(self) -> bool:
        """The gap is closed: the final model is not rejected."""
        return self.remaining.closed

    @property
    def effect(self) -> str:
        return self.attribution.effect

    def __repr__(self) -> str:
        return (f"GapColumn({self.name}: {'detected' if self.gap.detected else 'no gap'}, {self.effect}, "
                f"excess removed {g(100 * self.shrinkage.excess_removed, 3)}%, "
                f"{'closed' if self.closed else 'remains'})")


@dataclass(frozen=True)
class GapAssessment:
    """The gap a model leaves: objective, levels outside, p-value, navigation error."""

    objective: float
    null_mean: float
    levels_outside: int
    p_value: float
    navigation_rms: float
    remaining: tuple[GapBand, ...]

    @classmethod
    def from_dict(cls, a: Mapping[str, Any]) -> "GapAssessment":
        return cls(num(a["objective"]), num(a["null_mean"]), int(a["levels_outside"]), num(a["p_value"]),
                   num(a["navigation_rms"]), _bands(a["remaining"]))


@dataclass(frozen=True)
class ConfigChange:
    """A field of the baseline's configuration: its `input` value and the `corrected` one."""

    field: str
    input: float
    corrected: float
    unit: str
    changed: bool


@dataclass(frozen=True)
class CorrectedColumn:
    """A column's corrected model: the part the format can hold (`expressible`), the
    `full` model, what the format cannot hold, and the gap each leaves (`gap_left`: input,
    config, full)."""

    name: str
    expressible: str | None
    full: str
    not_expressible: tuple[str, ...]
    gap_left: dict[str, GapAssessment]
    verdict: str = "written"  # what the file does with the column's figures (written, kept: ...)
    why: str = ""  # why the input's figures are kept
    warnings: tuple[str, ...] = ()  # worse than the input, or more optimistic than the data's model

    def __repr__(self) -> str:
        return f"CorrectedColumn({self.name}: {self.expressible}, {len(self.not_expressible)} not expressible)"


@dataclass(frozen=True)
class CorrectedConfig:
    """The corrected configuration in the baseline's own format (`content` is the file)."""

    format: str
    content: str
    header: tuple[str, ...]
    changes: tuple[ConfigChange, ...]
    columns: tuple[CorrectedColumn, ...]

    @classmethod
    def from_dict(cls, c: Mapping[str, Any] | None) -> "CorrectedConfig | None":
        if c is None:
            return None
        changes = tuple(ConfigChange(x["field"], num(x["input"]), num(x["corrected"]), x["unit"], bool(x["changed"]))
                        for x in c["changes"])
        columns = tuple(CorrectedColumn(x["name"], x["expressible"], x["full"], strings(x["not_expressible"]),
                                        {k: GapAssessment.from_dict(v) for k, v in x["gap_left"].items()},
                                        x.get("verdict", "written"), x.get("why", ""), strings(x.get("warnings", [])))
                        for x in c["columns"])
        return cls(c["format"], c["content"], strings(c["header"]), changes, columns)

    def __repr__(self) -> str:
        return f"CorrectedConfig({self.format}, {sum(c.changed for c in self.changes)} of {len(self.changes)} changed)"


@dataclass(frozen=True)
class CrossAxisPair:
    a: str
    b: str
    tau: float
    tau_seconds: float
    rho: float
    z: float


@dataclass(frozen=True)
class CrossAxis:
    """The cross-axis wavelet correlations tested and the significant ones."""

    tested: int
    significant: tuple[CrossAxisPair, ...]

    def __repr__(self) -> str:
        return f"CrossAxis({len(self.significant)} of {self.tested} pairs significant)"


@dataclass(frozen=True, eq=False)
class GapResult(JsonResult):
    """The sim-to-real gap document (gmwm.gap, `gmwm gap --json`): `columns` (GapColumn),
    the baseline, the cross-axis test and the `corrected` configuration (None when the
    document has none)."""

    input: str
    baseline_source: str
    replicates: int
    seed: int
    temperature_column: str | None
    cross_axis: CrossAxis
    columns: tuple[GapColumn, ...]
    corrected: CorrectedConfig | None

    @classmethod
    def _from(cls, d: Any, text: str) -> "GapResult":
        x = d["cross_axis"]
        cross = CrossAxis(int(x["tested"]), tuple(
            CrossAxisPair(p["a"], p["b"], num(p["tau"]), num(p["tau_seconds"]), num(p["rho"]), num(p["z"]))
            for p in x["significant"]))
        return cls(document=d, _text=text, input=d["input"], baseline_source=d["baseline_source"],
                   replicates=int(d["replicates"]), seed=int(d["seed"]), temperature_column=d.get("temperature_column"),
                   cross_axis=cross, columns=tuple(built(GapColumn, t) for t in column_texts(text)),
                   corrected=CorrectedConfig.from_dict(d.get("corrected")))

    def __repr__(self) -> str:
        return "GapResult(" + "; ".join(f"{c.name}: {c.effect}, {'closed' if c.closed else 'remains'}"
                                        for c in self.columns) + ")"


@dataclass(frozen=True)
class GapCheckFamily:
    """The self-check's figures for one effect family."""

    cases: int
    correct: int
    detected: int
    located: int
    median_excess_removed: float
    strength_90: float
    strength_90_crossing: str
    oracle_strength_90: float
    oracle_ratio: float


@dataclass(frozen=True)
class GapCheckCase:
    """One simulated case: the withheld effect (`truth`) and what the diagnosis `reported`."""

    truth: str
    strength: float
    injected: str
    reported: str
    detected: bool
    located: bool
    correct: bool
    excess_removed: float
    parameter_error: float
    oracle_nc: float
    oracle: str


@dataclass(frozen=True, eq=False)
class GapCheckResult(JsonResult):
    """The diagnosis' self-check (gmwm.gap_check, `gmwm gap-check --json`): `confusion`
    (truth -> reported -> count), `power` (effect -> strength -> share correctly
    attributed; strengths as floats, the JSON's keys are text), per-family figures and
    every case."""

    n: int
    replicates: int
    strengths: FloatArray
    seed: int
    cases: int
    correct: int
    false_alarms: int
    confusion: dict[str, dict[str, int]]
    power: dict[str, dict[float, float]]
    families: dict[str, GapCheckFamily]
    case_list: tuple[GapCheckCase, ...]

    @classmethod
    def _from(cls, d: Any, text: str) -> "GapCheckResult":
        families = {k: GapCheckFamily(int(f["cases"]), int(f["correct"]), int(f["detected"]), int(f["located"]),
                                      num(f["median_excess_removed"]), num(f["strength_90"]),
                                      f["strength_90_crossing"], num(f["oracle_strength_90"]), num(f["oracle_ratio"]))
                    for k, f in d["families"].items()}
        cases = tuple(GapCheckCase(c["truth"], num(c["strength"]), c["injected"], c["reported"], bool(c["detected"]),
                                   bool(c["located"]), bool(c["correct"]), num(c["excess_removed"]),
                                   num(c["parameter_error"]), num(c["oracle_nc"]), c["oracle"])
                      for c in d["case_list"])
        return cls(d, text, int(d["n"]), int(d["replicates"]), floats(d["strengths"]), int(d["seed"]),
                   int(d["cases"]), int(d["correct"]), int(d["false_alarms"]),
                   {t: {r: int(k) for r, k in row.items()} for t, row in d["confusion"].items()},
                   {t: {float(s): num(v) for s, v in row.items()} for t, row in d["power"].items()}, families, cases)

    def __repr__(self) -> str:
        return (f"GapCheckResult({self.correct} of {self.cases} cases correct, {self.false_alarms} false alarms, "
                f"n={self.n})")
