"""Typed results of wv, allan, fit and select (docs/cli.md, "JSON"), built from the
library's JSON text; each keeps the parsed document (`.document`) and the text
(`.to_json()`)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Iterator, Mapping

import numpy as np

from ._common import (BoolArray, FloatArray, HasParameters, IntArray, JsonResult, bools, built, continuous, floats, g, ints, num, opt_int, parameters, present, strings)
from ._types import (AllanDeviation, ContinuousParameter, FitQuality, GoodnessOfFit, Kalman, NoiseFigures, Parameter)
from ._json_text import item_texts


@dataclass(frozen=True, eq=False)
class WvLevels:
    """A wavelet variance level by level, as arrays: `level` (1, 2, ...), `tau` (samples),
    `tau_seconds` (NaN without a rate), `wv` (nu^2), its interval `ci_low`, `ci_high`, the
    number of wavelet `coefficients` and each level's `note` (None where it has none). The
    robust estimator's diagnostics (`classical_wv`, `robust_to_classical`, `ci_disjoint`,
    `contaminated`, `rounding_ratio`, `tail_share`) are None for a classical WV."""

    level: IntArray
    tau: FloatArray
    tau_seconds: FloatArray
    wv: FloatArray
    ci_low: FloatArray
    ci_high: FloatArray
    coefficients: IntArray
    note: tuple[str | None, ...]
    classical_wv: FloatArray | None
    robust_to_classical: FloatArray | None
    ci_disjoint: BoolArray | None
    contaminated: BoolArray | None
    rounding_ratio: FloatArray | None
    tail_share: FloatArray | None

    @classmethod
    def from_list(cls, rows: list[Mapping[str, Any]]) -> "WvLevels":
        def col(key: str) -> list[Any]:
            return [r.get(key) for r in rows]

        robust = bool(rows) and "classical_wv" in rows[0]
        return cls(ints(col("level")), floats(col("tau")), floats(col("tau_seconds")), floats(col("wv")),
                   floats(col("ci_low")), floats(col("ci_high")), ints(col("coefficients")), tuple(col("note")),
                   floats(col("classical_wv")) if robust else None,
                   floats(col("robust_to_classical")) if robust else None,
                   bools(col("ci_disjoint")) if robust else None, bools(col("contaminated")) if robust else None,
                   floats(col("rounding_ratio")) if robust else None, floats(col("tail_share")) if robust else None)

    def __len__(self) -> int:
        return len(self.level)

    def __repr__(self) -> str:
        if not len(self.level):
            return "WvLevels(empty)"
        return (f"WvLevels({len(self.level)} levels, tau {g(self.tau[0])}-{g(self.tau[-1])} samples, "
                f"wv {g(self.wv[0])} .. {g(self.wv[-1])})")


class _WvArrays:
    """`tau`, `tau_seconds`, `wv`, `ci_low`, `ci_high` of `levels`, directly."""

    levels: WvLevels

    @property
    def tau(self) -> FloatArray:
        return self.levels.tau

    @property
    def tau_seconds(self) -> FloatArray:
        return self.levels.tau_seconds

    @property
    def wv(self) -> FloatArray:
        return self.levels.wv

    @property
    def ci_low(self) -> FloatArray:
        return self.levels.ci_low

    @property
    def ci_high(self) -> FloatArray:
        return self.levels.ci_high


@dataclass(frozen=True, eq=False)
class WvResult(JsonResult, _WvArrays):
    """The wavelet variance of one column (gmwm.wv; a column of `gmwm wv --json`):
    `w.tau`, `w.wv`, `w.ci_low`, `w.ci_high` are float64 arrays (those of `w.levels`).
    A `gmwm wv --adev` column also has `unit`, `allan` and `noise_figures` (else None)."""

    name: str
    n: int
    freq: float
    estimator: str
    efficiency: float
    alpha: float
    levels: WvLevels
    small_sample: str | None
    screening: dict[str, Any] | None
    quantization: dict[str, Any] | None
    unit: str | None
    allan: AllanDeviation | None
    noise_figures: NoiseFigures | None

    @classmethod
    def _from(cls, d: Any, text: str) -> "WvResult":
        return cls(d, text, d["name"], int(d["n"]), num(d["freq"]), d["estimator"], num(d["efficiency"]),
                   num(d["alpha"]), WvLevels.from_list(d["levels"]), d.get("small_sample"), d.get("screening"),
                   d.get("quantization"), d.get("unit"), AllanDeviation.from_dict(d.get("allan")),
                   NoiseFigures.from_dict(d.get("noise_figures")))

    def __repr__(self) -> str:
        rate = "no rate" if np.isnan(self.freq) else f"freq={g(self.freq)} Hz"
        return (f"WvResult({self.name}: {self.estimator}, n={self.n}, {rate}, "
                f"{len(self.levels)} levels, wv {g(self.wv[0])} .. {g(self.wv[-1])})")


@dataclass(frozen=True, eq=False)
class AllanResult(JsonResult):
    """The data's Allan deviation and the noise figures read off it (gmwm.allan; the
    "unit", "allan" and "noise_figures" of a `gmwm wv --adev` column): `a.tau`, `a.adev`,
    `a.ci_low`, `a.ci_high` are those of `a.allan`; `a.noise_figures.N`, `.K`, `.B`."""

    unit: str | None
    allan: AllanDeviation
    noise_figures: NoiseFigures

    @classmethod
    def _from(cls, d: Any, text: str) -> "AllanResult":
        return cls(d, text, d["unit"], present(AllanDeviation.from_dict(d["allan"]), "allan"),
                   present(NoiseFigures.from_dict(d["noise_figures"]), "noise_figures"))

    @property
    def tau(self) -> FloatArray:
        return self.allan.tau

    @property
    def adev(self) -> FloatArray:
        return self.allan.adev

    @property
    def ci_low(self) -> FloatArray:
        return self.allan.ci_low

    @property
    def ci_high(self) -> FloatArray:
        return self.allan.ci_high

    def __repr__(self) -> str:
        f = self.noise_figures
        return (f"AllanResult({len(self.allan)} points, N={g(f.N.value)}, K={g(f.K.value)}, B={g(f.B.value)} "
                f"({self.unit or 'no unit'}))")


def _figures_repr(f: NoiseFigures | None) -> str:
    return "" if f is None else f", N={g(f.N.value)} {f.N.unit}"


@dataclass(frozen=True, eq=False)
class FitResult(JsonResult, HasParameters, _WvArrays):
    """A GMWM fit of one column (gmwm.fit; a column of `gmwm fit --json`): `model` with its
    values, `parameters` (`f.parameter("sigma2", "WN")`), `gof`, `status`, the data's WV
    (`levels`; `f.wv`, `f.tau`, ...) and the model's (`implied_wv`), the parameters in
    physical units (`continuous`), `kalman`, `allan` and `noise_figures`."""

    name: str
    n: int
    freq: float
    model: str | None
    model_structure: str
    parameters: tuple[Parameter, ...]
    quality: FitQuality
    objective: float
    gof: GoodnessOfFit
    status: str
    message: str
    notes: tuple[str, ...]
    evaluations: int
    omega: str
    implied_wv: FloatArray
    estimator: str
    efficiency: float
    alpha: float
    levels: WvLevels
    unit: str | None
    continuous: tuple[ContinuousParameter, ...]
    kalman: Kalman | None
    allan: AllanDeviation | None
    noise_figures: NoiseFigures | None
    small_sample: str | None = None  # robust fits: the WV's small-sample correction, said
    screening: dict[str, Any] | None = None  # robust fits: the spike screen's note and replaced samples

    @classmethod
    def _from(cls, d: Any, text: str) -> "FitResult":
        return cls(d, text, d["name"], int(d["n"]), num(d["freq"]), d["model"], d["model_structure"],
                   parameters(d["parameters"]), present(FitQuality.from_dict(d["quality"]), "quality"), num(d["objective"]),
                   GoodnessOfFit.from_dict(d["gof"]), d["status"], d["message"], strings(d["notes"]),
                   int(d["evaluations"]), d["omega"], floats(d["implied_wv"]), d["estimator"], num(d["efficiency"]),
                   num(d["alpha"]), WvLevels.from_list(d["levels"]), d.get("unit"), continuous(d.get("continuous")),
                   Kalman.from_dict(d.get("kalman")), AllanDeviation.from_dict(d.get("allan")),
                   NoiseFigures.from_dict(d.get("noise_figures")), d.get("small_sample"), d.get("screening"))

    def __repr__(self) -> str:
        return (f"FitResult({self.name}: {self.model_structure}, {self.status}, "
                f"gof p={g(self.gof.p_value, 3)}{_figures_repr(self.noise_figures)})")


@dataclass(frozen=True, eq=False)
class RankingRow(HasParameters):
    """One distinct effective model of a selection's ranking (rank 1 the chosen one):
    its objective, optimism, criterion (WVIC or BIC), GoF p-value and parameters (with
    intervals for rank 1, values only for the rest)."""

    rank: int
    model: str
    objective: float
    optimism: float
    criterion: float
    optimism_analytic: float
    optimism_bootstrap: float
    optimism_bootstrap_se: float
    rank_analytic: int | None
    rank_bootstrap: int | None
    gof_p_value: float
    status: str
    effective_parameters: int
    members: tuple[str, ...]
    member_objectives: FloatArray
    reductions: tuple[str, ...]
    parameters: tuple[Parameter, ...]
    optimism_note: str | None
    optimism_difference: float

    @classmethod
    def from_dict(cls, r: Mapping[str, Any]) -> "RankingRow":
        return cls(int(r["rank"]), r["model"], num(r["objective"]), num(r["optimism"]), num(r["criterion"]),
                   num(r["optimism_analytic"]), num(r["optimism_bootstrap"]), num(r["optimism_bootstrap_se"]),
                   opt_int(r["rank_analytic"]), opt_int(r["rank_bootstrap"]), num(r["gof_p_value"]), r["status"],
                   int(r["effective_parameters"]), strings(r["members"]), floats(r["member_objectives"]),
                   strings(r["reductions"]), parameters(r["parameters"]), r.get("optimism_note"),
                   num(r.get("optimism_difference")))

    def __repr__(self) -> str:
        return (f"RankingRow({self.rank}: {self.model}, criterion {g(self.criterion)} = objective "
                f"{g(self.objective)} + optimism {g(self.optimism)}, gof p={g(self.gof_p_value, 3)})")


@dataclass(frozen=True)
class Candidate:
    """A candidate model as fitted, and the effective model it fell onto."""

    model: str
    objective: float
    status: str
    effective: str
    reductions: tuple[str, ...]

    @classmethod
    def from_dict(cls, c: Mapping[str, Any]) -> "Candidate":
        return cls(c["model"], num(c["objective"]), c["status"], c["effective"], strings(c["reductions"]))


@dataclass(frozen=True, eq=False)
class BestFit(HasParameters):
    """A selection's chosen model fitted, in the fields of a fit: `model` with values (the
    JSON's "best_model"), `model_structure`, `parameters` (rank 1's; empty where the JSON
    gives none, as over replicates), `objective`, `gof`, `status`, `notes`, `quality` (None
    over replicates), `unit`, `continuous` ("best_continuous"), `kalman` ("best_kalman"),
    `allan` and `noise_figures`."""

    model: str | None
    model_structure: str | None
    parameters: tuple[Parameter, ...]
    objective: float
    gof: GoodnessOfFit
    status: str
    notes: tuple[str, ...]
    quality: FitQuality | None
    unit: str | None
    continuous: tuple[ContinuousParameter, ...]
    kalman: Kalman | None
    allan: AllanDeviation | None
    noise_figures: NoiseFigures | None

    @classmethod
    def from_column(cls, c: Mapping[str, Any], structure: str | None, rows: tuple[Parameter, ...]) -> "BestFit":
        b = c["best_fit"]
        return cls(c["best_model"], structure, rows, num(b["objective"]), GoodnessOfFit.from_dict(b["gof"]),
                   b["status"], strings(b.get("notes")), FitQuality.from_dict(b.get("quality")), c.get("unit"),
                   continuous(c.get("best_continuous")), Kalman.from_dict(c.get("best_kalman")),
                   AllanDeviation.from_dict(c.get("allan")), NoiseFigures.from_dict(c.get("noise_figures")))

    def __repr__(self) -> str:
        return (f"BestFit({self.model_structure}, {self.status}, gof p={g(self.gof.p_value, 3)}"
                f"{_figures_repr(self.noise_figures)})")


@dataclass(frozen=True, eq=False)
class SelectColumn(JsonResult, _WvArrays):
    """One column's model selection (a column of `gmwm select --json`): the `ranking`, the
    chosen model (`best`; with values `best_model`), its fit as `best_fit`, every
    `candidates` fit, and the data's WV (`levels`)."""

    name: str
    n: int
    freq: float
    full_model: str
    best: str | None
    best_model: str | None
    penalty: str
    omega: str
    models: int
    representation_violations: int
    ranking: tuple[RankingRow, ...]
    candidates: tuple[Candidate, ...]
    not_converged: int
    failed: int
    all_rejected: bool
    best_fit: BestFit
    estimator: str
    efficiency: float
    alpha: float
    levels: WvLevels
    unit: str | None
    allan: AllanDeviation | None
    noise_figures: NoiseFigures | None
    small_sample: str | None = None  # robust selections: the WV's small-sample correction, said
    screening: dict[str, Any] | None = None  # robust selections: the spike screen's note and replaced samples

    @classmethod
    def _from(cls, d: Any, text: str) -> "SelectColumn":
        ranking = tuple(RankingRow.from_dict(r) for r in d["ranking"])
        chosen = next((r for r in ranking if r.model == d["best"]), None)
        best_fit = BestFit.from_column(d, d["best"], chosen.parameters if chosen else ())
        return cls(d, text, d["name"], int(d["n"]), num(d["freq"]), d["full_model"], d["best"], d["best_model"],
                   d["penalty"], d["omega"], int(d["models"]), int(d["representation_violations"]), ranking,
                   tuple(Candidate.from_dict(c) for c in d["candidates"]), int(d["not_converged"]), int(d["failed"]),
                   bool(d["all_rejected"]), best_fit, d["estimator"], num(d["efficiency"]), num(d["alpha"]),
                   WvLevels.from_list(d["levels"]), d.get("unit"), best_fit.allan, best_fit.noise_figures,
                   d.get("small_sample"), d.get("screening"))

    @property
    def best_continuous(self) -> tuple[ContinuousParameter, ...]:
        return self.best_fit.continuous

    @property
    def best_kalman(self) -> Kalman | None:
        return self.best_fit.kalman

    def __repr__(self) -> str:
        return (f"SelectColumn({self.name}: best {self.best} of {len(self.ranking)} effective models, "
                f"gof p={g(self.best_fit.gof.p_value, 3)}{_figures_repr(self.noise_figures)})")


@dataclass(frozen=True, eq=False)
class SelectResult(JsonResult):
    """gmwm.select's columns (`s[0]`, `len(s)`, iteration), each a SelectColumn;
    `to_json()` is the JSON array of the columns."""

    columns: tuple[SelectColumn, ...]

    @classmethod
    def _from(cls, d: Any, text: str) -> "SelectResult":
        return cls(d, text, tuple(built(SelectColumn, t) for t in item_texts(text)))

    def __getitem__(self, k: int) -> SelectColumn:
        return self.columns[k]

    def __len__(self) -> int:
        return len(self.columns)

    def __iter__(self) -> Iterator[SelectColumn]:
        return iter(self.columns)

    def __repr__(self) -> str:
        return "SelectResult(" + ", ".join(f"{c.name}: {c.best}" for c in self.columns) + ")"


__all__ = ["WvLevels", "WvResult", "AllanResult", "FitResult", "RankingRow", "Candidate", "BestFit", "SelectColumn",
           "SelectResult"]
