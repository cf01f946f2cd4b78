"""Methods of the frequency-stability results (gmwm.stability): each column's deviations
plotted with their intervals, and a table of them as a pandas DataFrame."""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Sequence, cast

from . import _plot

if TYPE_CHECKING:
    from ._types import Deviation, StabilityColumn, StabilityResult


class StabilityColumnMethods:
    name: str
    unit: str | None
    deviations: "dict[str, Deviation]"

    def __repr__(self) -> str:
        kinds = ", ".join(self.deviations)
        return f"StabilityColumn({self.name!r}: {kinds})"

    def plot(self, ax: Any = None, kinds: Sequence[str] | None = None) -> Any:
        """The deviations of `kinds` (default: every kind in the data's unit; the time
        deviations tdev, ttotdev, mtie, tierms only when asked: their unit is the phase's)
        against tau on log-log axes, each with its interval as a band."""
        return _plot.stability(cast("StabilityColumn", self), ax, kinds)

    def to_dataframe(self) -> Any:
        """One row per kind and tau: value, interval, edf, alpha, noise, noise_id, n; needs pandas."""
        import pandas  # optional: only this method needs it

        rows = []
        for kind, d in self.deviations.items():
            for i in range(len(d.tau)):
                rows.append({"kind": kind, "m": int(d.m[i]), "tau": float(d.tau[i]), "value": float(d.value[i]),
                             "ci_low": float(d.ci_low[i]), "ci_high": float(d.ci_high[i]), "edf": float(d.edf[i]),
                             "alpha": int(d.alpha[i]), "noise": d.noise[i], "noise_id": d.noise_id[i],
                             "n": int(d.n[i]), "unit": d.unit})
        return pandas.DataFrame(rows)


class StabilityResultMethods:
    columns: "tuple[StabilityColumn, ...]"

    def __repr__(self) -> str:
        return "StabilityResult(" + ", ".join(repr(c) for c in self.columns) + ")"

    def plot(self, column: int | str = 0, ax: Any = None, kinds: Sequence[str] | None = None) -> Any:
        """The plot of one column (its index or name): StabilityColumn.plot."""
        if isinstance(column, str):
            for c in self.columns:
                if c.name == column:
                    return c.plot(ax, kinds)
            raise KeyError(column)
        return self.columns[column].plot(ax, kinds)
