"""The methods of the typed results of wv, allan, fit and select (docs/cli.md, "JSON"): their
fields and from_dict are generated from report/schema/results.json into _types.py; each
result keeps the parsed document (`.document`) and the text (`.to_json()`)."""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Iterator, Mapping, cast

import numpy as np

from ._common import FloatArray, HasParameters, built, g, parameters
from ._json_text import item_texts

if TYPE_CHECKING:
    from ._types import (AllanDeviation, BestFit, ContinuousParameter, FitResult, GoodnessOfFit, Kalman,
                         NoiseFigures, Parameter, SelectColumn, SelectResult, WvLevels, WvResult)


class WvLevelsMethods:
    level: Any
    tau: FloatArray
    wv: FloatArray

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


class WvResultMethods(_WvArrays):
    name: str
    n: int
    freq: float
    estimator: str

    def __repr__(self) -> str:
        rate = "no rate" if np.isnan(self.freq) else f"freq={g(self.freq)} Hz"
        return (f"WvResult({self.name}: {self.estimator}, n={self.n}, {rate}, "
                f"{len(self.levels)} levels, wv {g(self.wv[0])} .. {g(self.wv[-1])})")

    def plot(self, ax: Any = None) -> Any:
        """The WV with its interval against tau (the classical WV beside a robust one); the
        axes drawn on (a new figure without `ax`). Needs matplotlib."""
        from . import _plot

        return _plot.wv(cast("WvResult", self), ax)



class AllanResultMethods:
    unit: str | None
    allan: AllanDeviation
    noise_figures: NoiseFigures

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
        more = "".join(f", {name}={g(x.value)}" for name, x in (("Q", f.Q), ("R", f.R)) if x is not None)
        return (f"AllanResult({len(self.allan)} points, N={g(f.N.value)}, K={g(f.K.value)}, B={g(f.B.value)}{more} "
                f"({self.unit or 'no unit'}))")

    def plot(self, ax: Any = None) -> Any:
        """The Allan deviation with its interval and the N, K, B, Q, R lines; the axes drawn on."""
        from . import _plot

        return _plot.allan(self.allan, self.noise_figures, self.unit, "", ax)



def _figures_repr(f: NoiseFigures | None) -> str:
    return "" if f is None else f", N={g(f.N.value)} {f.N.unit}"


class FitResultMethods(HasParameters, _WvArrays):
    name: str
    model_structure: str
    status: str
    gof: GoodnessOfFit
    noise_figures: NoiseFigures | None

    def __repr__(self) -> str:
        return (f"FitResult({self.name}: {self.model_structure}, {self.status}, "
                f"gof p={g(self.gof.p_value, 3)}{_figures_repr(self.noise_figures)})")

    def plot(self, ax: Any = None, decomposition: bool = True) -> Any:
        """The data's WV with its interval, the fitted model's WV and (`decomposition`) each
        process's; the axes drawn on (a new figure without `ax`). Needs matplotlib."""
        from . import _plot

        return _plot.fit(cast("FitResult", self), ax, decomposition)



class RankingRowMethods(HasParameters):
    rank: int
    model: str
    objective: float
    optimism: float
    criterion: float
    gof_p_value: float

    def __repr__(self) -> str:
        return (f"RankingRow({self.rank}: {self.model}, criterion {g(self.criterion)} = objective "
                f"{g(self.objective)} + optimism {g(self.optimism)}, gof p={g(self.gof_p_value, 3)})")


def best_structure(c: Mapping[str, Any]) -> str | None:
    """The chosen model's structure: a selection's "best" (a joint selection's best fit's model)."""
    if "best" in c:
        best: str | None = c["best"]
        return best
    model: str | None = c["best_fit"]["model"]
    return model


def best_parameters(c: Mapping[str, Any]) -> tuple[Parameter, ...]:
    """The chosen model's parameters: rank 1's row of a selection's ranking (the row whose model
    is "best"); none over replicates, whose JSON gives none."""
    chosen = next((r for r in c.get("ranking") or () if r["model"] == c.get("best")), None)
    return parameters(chosen["parameters"]) if chosen is not None else ()


def best_fit_of(c: Mapping[str, Any]) -> BestFit:
    from ._types import BestFit

    return BestFit.from_dict(c)


class BestFitMethods(HasParameters):
    model_structure: str | None
    status: str
    gof: GoodnessOfFit
    noise_figures: NoiseFigures | None

    def __repr__(self) -> str:
        return (f"BestFit({self.model_structure}, {self.status}, gof p={g(self.gof.p_value, 3)}"
                f"{_figures_repr(self.noise_figures)})")


class SelectColumnMethods(_WvArrays):
    name: str
    best: str | None
    ranking: tuple[Any, ...]
    best_fit: BestFit
    noise_figures: NoiseFigures | None

    @property
    def best_continuous(self) -> tuple[ContinuousParameter, ...]:
        return self.best_fit.continuous

    @property
    def best_kalman(self) -> Kalman | None:
        return self.best_fit.kalman

    def __repr__(self) -> str:
        return (f"SelectColumn({self.name}: best {self.best} of {len(self.ranking)} effective models, "
                f"gof p={g(self.best_fit.gof.p_value, 3)}{_figures_repr(self.noise_figures)})")

    def plot(self, ax: Any = None, ranking_ax: Any = None, decomposition: bool = True) -> Any:
        """The chosen model's WV (and each process's) over the data's; without axes, a new
        figure with the ranking beside it (returns both axes). Needs matplotlib."""
        from . import _plot

        return _plot.select_column(cast("SelectColumn", self), ax, ranking_ax, decomposition)



def select_columns(d: Any, text: str) -> tuple[SelectColumn, ...]:
    """gmwm.select's columns, each built from its own text (its to_json() the column alone)."""
    from ._types import SelectColumn

    return tuple(built(SelectColumn, t) for t in item_texts(text))


class SelectResultMethods:
    columns: tuple[SelectColumn, ...]

    def __getitem__(self, k: int) -> SelectColumn:
        return self.columns[k]

    def __len__(self) -> int:
        return len(self.columns)

    def __iter__(self) -> Iterator[SelectColumn]:
        return iter(self.columns)

    def __repr__(self) -> str:
        return "SelectResult(" + ", ".join(f"{c.name}: {c.best}" for c in self.columns) + ")"

    def plot(self) -> Any:
        """A figure with one row per column: its ranking and its chosen fit (the axes' grid)."""
        from . import _plot

        return _plot.select(cast("SelectResult", self))

