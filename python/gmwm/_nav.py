"""The methods of the typed results of nav, plan, export and fleet (docs/cli.md "JSON",
docs/nav.md, docs/exports.md, docs/fleet.md): their fields and from_dict are generated from
report/schema/results.json into _types.py."""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Mapping, cast

import numpy as np

from ._common import FloatArray, g, num

if TYPE_CHECKING:
    from ._types import (ExportWritten, FleetResult, FleetRow, NavFilter, NavResult, NavSummary, PlanColumn,
                         PlanTarget, WrittenNoise)


def outages_of(s: Mapping[str, Any]) -> tuple[tuple[float, float], ...]:
    """The outages as (start, end) in seconds."""
    return tuple((num(a), num(b)) for a, b in s["outages"])


class NavCurvesMethods:
    time: FloatArray

    def __repr__(self) -> str:
        return f"NavCurves({len(self.time)} points to {g(self.time[-1]) if len(self.time) else '-'} s)"


class NavMonteCarloMethods:
    nees: FloatArray
    verdict: str

    def __repr__(self) -> str:
        return f"NavMonteCarlo({len(self.nees)} points, {self.verdict})"


class NavFilterMethods:
    label: str
    verdict: str
    nees_inside: float
    summary: NavSummary

    def __repr__(self) -> str:
        return (f"NavFilter({self.label}: {self.verdict}, NEES inside {g(100 * self.nees_inside, 3)}%, "
                f"position rms {g(self.summary.position_rms)} m at {g(self.summary.time)} s)")


class NavResultMethods:
    filters: tuple[NavFilter, ...]

    def filter(self, label: str) -> NavFilter:
        """The filter labelled `label` (KeyError when none)."""
        for f in self.filters:
            if f.label == label:
                return f
        raise KeyError(label)

    def __repr__(self) -> str:
        return "NavResult(" + ", ".join(f"{f.label}: {f.verdict}" for f in self.filters) + ")"

    def plot(self, ax: Any = None, quantity: str = "position") -> Any:
        """Each filter's true RMS error and the 3 sigma it claims against time (`quantity`:
        position, velocity or attitude), the outages shaded; the axes drawn on."""
        from . import _plot

        return _plot.nav(cast("NavResult", self), ax, quantity)



class PlanTargetMethods:
    name: str
    value: float
    unit: str
    reachable: bool
    seconds: float

    def __repr__(self) -> str:
        need = f"{g(self.seconds)} s" if self.reachable else "unreachable"
        return f"PlanTarget({self.name} = {g(self.value)} {self.unit}: {need})"


class PlanColumnMethods:
    name: str
    model: str
    targets: tuple[PlanTarget, ...]

    def __repr__(self) -> str:
        return f"PlanColumn({self.name}: {self.model}, " + ", ".join(repr(t) for t in self.targets) + ")"

    def target(self, name: str) -> PlanTarget:
        """The target called `name` (KeyError when none)."""
        for t in self.targets:
            if t.name == name:
                return t
        raise KeyError(name)


class PlanResultMethods:
    precision: float
    columns: tuple[PlanColumn, ...]

    def __repr__(self) -> str:
        parts = [f"{c.name}: " + ", ".join(f"{t.name} {g(t.seconds, 3)} s" if t.reachable else f"{t.name} unreachable"
                                           for t in c.targets) for c in self.columns]
        return f"PlanResult(+-{g(100 * self.precision, 3)}%: " + "; ".join(parts) + ")"


class ExportColumnMethods:
    name: str
    noise_density: float
    random_walk: float
    unit: str

    def __repr__(self) -> str:
        return f"ExportColumn({self.name}: N={g(self.noise_density)}, K={g(self.random_walk)} ({self.unit}))"


class ExportWrittenMethods:
    columns: tuple[str, ...]
    per_axis: bool
    combined: WrittenNoise

    def __repr__(self) -> str:
        return (f"ExportWritten({', '.join(self.columns)}: N={g(self.combined.noise_density)}, "
                f"K={g(self.combined.random_walk)}{', per axis' if self.per_axis else ''})")


class ExportResultMethods:
    format: str
    output: str
    inflate: float
    written: dict[str, ExportWritten]

    def __repr__(self) -> str:
        kinds = ", ".join(f"{k} N={g(w.combined.noise_density)} K={g(w.combined.random_walk)}"
                          for k, w in self.written.items())
        return f"ExportResult({self.format} -> {self.output}: {kinds}, inflation x{g(self.inflate)})"


class FleetResultMethods:
    recordings: int
    model_spec: str
    failed: int
    rows: tuple[FleetRow, ...]

    def to_dataframe(self) -> Any:
        """The rows as a pandas DataFrame (N, K, B, Q, R as value columns with _low and _high);
        ImportError when pandas is not installed (Debian: python3-pandas)."""
        import pandas  # optional: only this method needs it

        records = []
        for r in self.rows:
            rec = {k: getattr(r, k) for k in ("unit", "model", "group", "path", "axis", "unit_of_data", "status",
                                              "chosen_structure", "gof_p_value", "freq", "n", "seconds")}
            for name in ("N", "K", "B", "Q", "R"):
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

    def plot(self, ax: Any = None, figure: str = "N") -> Any:
        """`figure` (N, K, B, Q or R) of every unit by axis with its interval, one colour per unit,
        the flagged ones boxed in red; the axes drawn on. Needs matplotlib."""
        from . import _plot

        return _plot.fleet(cast("FleetResult", self), ax, figure)

