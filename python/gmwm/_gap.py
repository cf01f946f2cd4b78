"""The methods of the typed results of gap and gap_check (docs/cli.md "JSON", docs/gap.md):
their fields and from_dict are generated from report/schema/results.json into _types.py."""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Mapping, cast

import numpy as np

from ._common import BoolArray, FloatArray, HasParameters, built, column_texts, g, num

if TYPE_CHECKING:
    from ._types import (Attribution, ConfigChange, GapBand, GapColumn, GapResult, GapStep, GapTest, Remaining,
                         Shrinkage)


class GapBandMethods:
    tau_from_seconds: float
    tau_to_seconds: float
    direction: str
    peak_ratio: float

    def __repr__(self) -> str:
        return (f"GapBand({self.direction} at {g(self.tau_from_seconds)} s - {g(self.tau_to_seconds)} s, "
                f"up to {g(self.peak_ratio)}x)")


class GapLevelsMethods:
    tau: FloatArray
    outside: BoolArray

    def __len__(self) -> int:
        return len(self.tau)

    def __repr__(self) -> str:
        return f"GapLevels({len(self.tau)} levels, {int(self.outside.sum())} outside)"


class GapSplitHalfMethods:
    tau: FloatArray
    disjoint: BoolArray

    def __repr__(self) -> str:
        return f"GapSplitHalf({len(self.tau)} levels, {int(self.disjoint.sum())} disjoint)"


class GapTestMethods:
    detected: bool
    p_value: float
    bands: tuple[GapBand, ...]

    def __repr__(self) -> str:
        return f"GapTest(detected={self.detected}, p={g(self.p_value, 3)}, {len(self.bands)} bands)"


class GapStepMethods:
    detail: str
    share: float

    def __repr__(self) -> str:
        return f"GapStep({self.detail}: {g(100 * self.share, 3)}% of the excess)"


def attribution_steps(a: Mapping[str, Any]) -> tuple[GapStep, ...]:
    """The steps, element by element from the JSON's parallel lists "steps", "step_details",
    "step_drops" and "step_shares" (a list shorter than "steps": "" or NaN)."""
    from ._types import GapStep

    details, drops, shares = a["step_details"], a["step_drops"], a["step_shares"]
    return tuple(GapStep(e, details[k] if k < len(details) else "", num(drops[k]) if k < len(drops) else np.nan,
                         num(shares[k]) if k < len(shares) else np.nan) for k, e in enumerate(a["steps"]))


class AttributionMethods(HasParameters):
    effect: str
    model: str
    steps: tuple[GapStep, ...]

    def __repr__(self) -> str:
        return f"Attribution({' -> '.join(s.effect for s in self.steps) or self.effect}: {self.model})"


class RemainingMethods:
    closed: bool
    bands: tuple[GapBand, ...]
    levels_outside: int

    def __repr__(self) -> str:
        state = "closed" if self.closed else "open"
        return f"Remaining({state}, {len(self.bands)} bands, {self.levels_outside} levels outside)"


class GapColumnMethods:
    name: str
    gap: GapTest
    attribution: Attribution
    remaining: Remaining
    shrinkage: Shrinkage

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

    def plot(self, ax: Any = None) -> Any:
        """The data's WV over the baseline's, level by level, against the reference band (the
        levels outside it in red); the axes drawn on. Needs matplotlib."""
        from . import _plot

        return _plot.gap_column(cast("GapColumn", self), ax)



class CorrectedColumnMethods:
    name: str
    expressible: str | None
    not_expressible: tuple[str, ...]

    def __repr__(self) -> str:
        return f"CorrectedColumn({self.name}: {self.expressible}, {len(self.not_expressible)} not expressible)"


class CorrectedConfigMethods:
    format: str
    changes: tuple[ConfigChange, ...]

    def __repr__(self) -> str:
        return f"CorrectedConfig({self.format}, {sum(c.changed for c in self.changes)} of {len(self.changes)} changed)"


class CrossAxisMethods:
    tested: int
    significant: tuple[Any, ...]

    def __repr__(self) -> str:
        return f"CrossAxis({len(self.significant)} of {self.tested} pairs significant)"


def gap_columns(d: Any, text: str) -> tuple[GapColumn, ...]:
    """The document's columns, each built from its own text."""
    from ._types import GapColumn

    return tuple(built(GapColumn, t) for t in column_texts(text))


class GapResultMethods:
    columns: tuple[GapColumn, ...]

    def __repr__(self) -> str:
        return "GapResult(" + "; ".join(f"{c.name}: {c.effect}, {'closed' if c.closed else 'remains'}"
                                        for c in self.columns) + ")"

    def plot(self) -> Any:
        """A figure with one plot per column (GapColumn.plot); its axes."""
        from . import _plot

        return _plot.gap(cast("GapResult", self))



def confusion_of(d: Mapping[str, Any]) -> dict[str, dict[str, int]]:
    """truth -> reported -> count."""
    return {t: {r: int(k) for r, k in row.items()} for t, row in d["confusion"].items()}


def power_of(d: Mapping[str, Any]) -> dict[str, dict[float, float]]:
    """effect -> strength -> share correctly attributed (the JSON's strengths are text keys)."""
    return {t: {float(s): num(v) for s, v in row.items()} for t, row in d["power"].items()}


class GapCheckResultMethods:
    n: int
    cases: int
    correct: int
    false_alarms: int

    def __repr__(self) -> str:
        return (f"GapCheckResult({self.correct} of {self.cases} cases correct, {self.false_alarms} false alarms, "
                f"n={self.n})")
