"""Typed documents of the studies over replicates: `gmwm fit --joint` and `gmwm select
--joint` (docs/cli.md "JSON", docs/multi-signal.md), from the command's JSON text."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping

import numpy as np

from ._common import (BoolArray, FloatArray, HasParameters, IntArray, JsonResult, built, column_texts, continuous, floats, g, num, opt_int, parameters, strings)
from ._types import (BestFit, AllanDeviation, ContinuousParameter, GoodnessOfFit, Kalman, NoiseFigures, Parameter)


@dataclass(frozen=True, eq=False)
class ReplicateOwnFit(HasParameters):
    """One recording's own fit of the model."""

    model: str
    status: str
    objective: float
    parameters: tuple[Parameter, ...]

    def __repr__(self) -> str:
        return f"ReplicateOwnFit({self.model}, {self.status})"


@dataclass(frozen=True, eq=False)
class ReplicateFit:
    """One recording ("FILE:COLUMN") of an axis: its length, its number of WV `levels` (a
    count here), its share of the joint objective and its own `fit`."""

    source: str
    n: int
    levels: int
    objective_share: float
    fit: ReplicateOwnFit

    def __repr__(self) -> str:
        return f"ReplicateFit({self.source}: n={self.n}, {self.fit.status}, objective {g(self.fit.objective)})"


@dataclass(frozen=True, eq=False)
class Agmwm:
    """The average of the replicates' own estimates (AGMWM), parameter by parameter, in
    the order of the joint fit's parameters."""

    value: FloatArray
    se: FloatArray

    def __repr__(self) -> str:
        return f"Agmwm({len(self.value)} parameters)"


@dataclass(frozen=True, eq=False)
class ReplicateBootstrap:
    """Replicate-t intervals from resamples of the replicates (display units), per
    parameter."""

    method: str
    ci_low: FloatArray
    ci_high: FloatArray
    draws: int
    exhaustive: bool

    def __repr__(self) -> str:
        return f"ReplicateBootstrap({self.method}, {self.draws} draws)"


@dataclass(frozen=True, eq=False)
class ReplicateTest:
    """The test of whether the recordings share one theta (parametric bootstrap, or its
    chi-square calibration)."""

    heterogeneity: float
    heterogeneity_p_value: float
    statistic: float
    p_value: float
    own_minimum: FloatArray
    draws: int
    calibration: str = "bootstrap"  #: 'bootstrap' or 'chi-square' (docs/multi-signal.md)
    df_heterogeneity: float = float("nan")  #: the chi-square's degrees of freedom (NaN: bootstrap)
    df_statistic: float = float("nan")

    def __repr__(self) -> str:
        return f"ReplicateTest(p={g(self.p_value, 3)}, heterogeneity p={g(self.heterogeneity_p_value, 3)})"


@dataclass(frozen=True, eq=False)
class JointFitColumn(JsonResult, HasParameters):
    """One axis fitted jointly over its recordings: the joint `model`, `parameters`, `gof`,
    each recording's own fit (`replicates`), the AGMWM beside it, the replicate bootstrap
    and test (None when absent), and the joint model's physical fields."""

    name: str
    freq: float
    replicates: tuple[ReplicateFit, ...]
    model: str
    model_structure: str
    parameters: tuple[Parameter, ...]
    agmwm: Agmwm
    objective: float
    gof: GoodnessOfFit
    status: str
    message: str
    notes: tuple[str, ...]
    replicate_bootstrap: ReplicateBootstrap | None
    replicate_test: ReplicateTest | None
    unit: str | None
    continuous: tuple[ContinuousParameter, ...]
    kalman: Kalman | None
    allan: AllanDeviation | None
    noise_figures: NoiseFigures | None

    @classmethod
    def _from(cls, d: Any, text: str) -> "JointFitColumn":
        reps = tuple(ReplicateFit(r["source"], int(r["n"]), int(r["levels"]), num(r["objective_share"]),
                                  ReplicateOwnFit(r["fit"]["model"], r["fit"]["status"], num(r["fit"]["objective"]),
                                                  parameters(r["fit"]["parameters"])))
                     for r in d["replicates"])
        b, t = d["replicate_bootstrap"], d["replicate_test"]
        boot = None if b is None else ReplicateBootstrap(b["method"], floats(b["ci_low"]), floats(b["ci_high"]),
                                                         int(b["draws"]), bool(b["exhaustive"]))
        test = None if t is None else ReplicateTest(num(t["heterogeneity"]), num(t["heterogeneity_p_value"]),
                                                    num(t["statistic"]), num(t["p_value"]), floats(t["own_minimum"]),
                                                    int(t["draws"]), t.get("calibration", "bootstrap"),
                                                    num(t.get("df_heterogeneity")), num(t.get("df_statistic")))
        return cls(d, text, d["name"], num(d["freq"]), reps, d["model"], d["model_structure"],
                   parameters(d["parameters"]),
                   Agmwm(floats([a["value"] for a in d["agmwm"]]), floats([a["se"] for a in d["agmwm"]])),
                   num(d["objective"]), GoodnessOfFit.from_dict(d["gof"]), d["status"], d["message"],
                   strings(d["notes"]), boot, test, d.get("unit"), continuous(d.get("continuous")),
                   Kalman.from_dict(d.get("kalman")), AllanDeviation.from_dict(d.get("allan")),
                   NoiseFigures.from_dict(d.get("noise_figures")))

    def __repr__(self) -> str:
        shared = "" if self.replicate_test is None else f", shared-theta p={g(self.replicate_test.p_value, 3)}"
        return (f"JointFitColumn({self.name}: {self.model_structure} over {len(self.replicates)} recordings, "
                f"{self.status}, gof p={g(self.gof.p_value, 3)}{shared})")


@dataclass(frozen=True, eq=False)
class JointFitResult(JsonResult):
    """The document `gmwm fit INPUT --joint FILE ... --json` writes: one JointFitColumn
    per axis."""

    input: str
    model_spec: str
    seed: int
    estimator: str
    columns: tuple[JointFitColumn, ...]

    @classmethod
    def _from(cls, d: Any, text: str) -> "JointFitResult":
        return cls(d, text, d["input"], d["model_spec"], int(d["seed"]), d["estimator"],
                   tuple(built(JointFitColumn, t) for t in column_texts(text)))

    def __repr__(self) -> str:
        return "JointFitResult(" + "; ".join(f"{c.name}: {c.model_structure}, {c.status}" for c in self.columns) + ")"


@dataclass(frozen=True, eq=False)
class JointRankingRow:
    """A candidate of the selection over replicates, ranked by the cross-validated WVIC
    (`cv_wvic`; `split_loss` per split), with the `effective` model it stands for (None
    where the document predates it). `parameters` is the number of parameters (a count, as
    the JSON has it)."""

    rank: int
    model: str
    effective: str | None
    parameters: int
    cv_wvic: float
    split_loss: FloatArray
    objective: float
    analytic_wvic: float
    rank_analytic: int
    bootstrap_wvic: float
    bootstrap_se: float
    rank_bootstrap: int | None
    p_not_worse: float
    equivalent: bool

    @classmethod
    def from_dict(cls, r: Mapping[str, Any]) -> "JointRankingRow":
        return cls(int(r["rank"]), r["model"], r.get("effective"), int(r["parameters"]), num(r["cv_wvic"]),
                   floats(r["split_loss"]), num(r["objective"]), num(r["analytic_wvic"]), int(r["rank_analytic"]),
                   num(r["bootstrap_wvic"]), num(r["bootstrap_se"]), opt_int(r["rank_bootstrap"]),
                   num(r["p_not_worse"]), bool(r["equivalent"]))

    def __repr__(self) -> str:
        return f"JointRankingRow({self.rank}: {self.model}, cv_wvic {g(self.cv_wvic)})"


@dataclass(frozen=True, eq=False)
class JointSelectColumn(JsonResult):
    """One axis's selection over replicates: the `ranking`, the `chosen` and `recommended`
    models, and the recommended model fitted jointly (`best_model`, `best_fit`: None when
    the document has none)."""

    name: str
    freq: float
    replicates: tuple[str, ...]
    full_model: str
    training: tuple[tuple[int, ...], ...]
    chosen: str
    recommended: str
    chosen_analytic: str
    chosen_bootstrap: str | None
    all_rejected: bool
    ranking: tuple[JointRankingRow, ...]
    best_model: str | None
    best_fit: BestFit | None
    unit: str | None
    allan: AllanDeviation | None
    noise_figures: NoiseFigures | None

    @classmethod
    def _from(cls, d: Any, text: str) -> "JointSelectColumn":
        best = BestFit.from_dict(d) if "best_fit" in d else None
        return cls(d, text, d["name"], num(d["freq"]), strings(d["replicates"]), d["full_model"],
                   tuple(tuple(int(i) for i in s) for s in d["training"]), d["chosen"], d["recommended"],
                   d["chosen_analytic"], d["chosen_bootstrap"], bool(d["all_rejected"]),
                   tuple(JointRankingRow.from_dict(r) for r in d["ranking"]), d.get("best_model"), best,
                   d.get("unit"), best.allan if best else None, best.noise_figures if best else None)

    @property
    def best_continuous(self) -> tuple[ContinuousParameter, ...]:
        """The recommended model's parameters in physical units (empty without a best fit)."""
        return self.best_fit.continuous if self.best_fit else ()

    @property
    def best_kalman(self) -> Kalman | None:
        """The recommended model's Kalman terms (None without a best fit)."""
        return self.best_fit.kalman if self.best_fit else None

    def __repr__(self) -> str:
        return (f"JointSelectColumn({self.name}: chosen {self.chosen}, recommended {self.recommended}, "
                f"{len(self.replicates)} recordings)")


@dataclass(frozen=True, eq=False)
class JointSelectResult(JsonResult):
    """The document `gmwm select INPUT --joint FILE ... --json` writes: one
    JointSelectColumn per axis."""

    input: str
    model_spec: str
    seed: int
    optimism: str
    estimator: str
    columns: tuple[JointSelectColumn, ...]

    @classmethod
    def _from(cls, d: Any, text: str) -> "JointSelectResult":
        return cls(d, text, d["input"], d["model_spec"], int(d["seed"]), d["optimism"], d["estimator"],
                   tuple(built(JointSelectColumn, t) for t in column_texts(text)))

    def __repr__(self) -> str:
        return "JointSelectResult(" + "; ".join(f"{c.name}: {c.recommended}" for c in self.columns) + ")"
