"""Pieces shared by the typed results: numbers and arrays from JSON, parameters, goodness
of fit, continuous parameters, Kalman terms, the Allan deviation and the noise figures.

JSON null (the library's NaN or infinity, or "not given") becomes NaN in a float field or
array, None elsewhere.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass
from typing import Any, Iterable, Mapping, TypeVar

import numpy as np
import numpy.typing as npt

from ._json_text import item_texts, member_text

T = TypeVar("T", bound="JsonResult")

# The arrays of the typed results: read-only numpy arrays of the document's numbers.
FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]
BoolArray = npt.NDArray[np.bool_]


X = TypeVar("X")


def present(value: X | None, what: str) -> X:
    """A part every document of its kind carries (ValueError naming it when missing)."""
    if value is None:
        raise ValueError(f"the document has no {what}")
    return value


def num(v: Any) -> float:
    """A JSON number as a float (null: NaN)."""
    return math.nan if v is None else float(v)


def opt_int(v: Any) -> int | None:
    return None if v is None else int(v)


def floats(values: Iterable[Any] | None) -> FloatArray:
    """A read-only float64 array (null: NaN)."""
    a = np.array([math.nan if v is None else v for v in (values or [])], dtype=np.float64)
    a.flags.writeable = False
    return a


def ints(values: Iterable[Any] | None) -> IntArray:
    a = np.array(list(values or []), dtype=np.int64)
    a.flags.writeable = False
    return a


def bools(values: Iterable[Any] | None) -> BoolArray:
    a = np.array(list(values or []), dtype=bool)
    a.flags.writeable = False
    return a


def strings(values: Iterable[Any] | None) -> tuple[str, ...]:
    return tuple(values or ())


def g(x: float | None, digits: int = 4) -> str:
    """A number for a repr: 4 significant digits, '-' for NaN or None."""
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    return format(x, f".{digits}g")


@dataclass(frozen=True, eq=False, repr=False)
class JsonResult:
    """A result built from the library's JSON text: `document` is the parsed JSON (nothing
    is lost), `to_json()` the text itself, unchanged."""

    document: Any
    _text: str

    def to_json(self) -> str:
        """The library's JSON text, exactly as the command writes it."""
        return self._text

    def _header(self, key: str) -> str | None:
        return self.document.get(key) if isinstance(self.document, dict) else None

    @property
    def tool(self) -> str | None:
        """"gmwm" in a whole command's document (None for one column's)."""
        return self._header("tool")

    @property
    def version(self) -> str | None:
        """The version of gmwm that wrote a whole command's document (None for one column's)."""
        return self._header("version")

    @property
    def command(self) -> str | None:
        """The command that wrote a whole document ("fit", "gap", ...; None for one column's)."""
        return self._header("command")

    @classmethod
    def from_json(cls: type[T], text: str) -> T:
        """The typed result of the library's (or the command's) JSON text."""
        return cls._from(json.loads(text), text)

    @classmethod
    def _from(cls: type[T], d: Any, text: str) -> T:
        raise NotImplementedError


def column_texts(text: str) -> list[str]:
    """The texts of a document's "columns", each as dump_json renders it alone."""
    return item_texts(member_text(text, "columns"))


def built(cls: type[T], text: str) -> T:
    return cls._from(json.loads(text), text)


@dataclass(frozen=True)
class Parameter:
    """A fitted parameter in display units (docs/cli.md "fit"): `interval` is the kind of
    [ci_low, ci_high]: two-sided, one-sided, not identified or boundary (None: not given)."""

    process: str
    component: int
    name: str
    value: float
    se: float
    ci_low: float
    ci_high: float
    interval: str | None

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> "Parameter":
        return cls(d["process"], int(d["component"]), d["name"], num(d["value"]), num(d.get("se")),
                   num(d.get("ci_low")), num(d.get("ci_high")), d.get("interval"))

    def __repr__(self) -> str:
        return (f"Parameter({self.process}[{self.component}].{self.name} = {g(self.value)} "
                f"[{g(self.ci_low)}, {g(self.ci_high)}] {self.interval or 'no interval'})")


def parameters(rows: Iterable[Mapping[str, Any]] | None) -> tuple[Parameter, ...]:
    return tuple(Parameter.from_dict(r) for r in rows or ())


class HasParameters:
    """`parameter(name, process, component)`: one row of `parameters`."""

    parameters: tuple[Parameter, ...]

    def parameter(self, name: str, process: str | None = None, component: int | None = None) -> Parameter:
        """The parameter called `name` (of `process`, of `component`); KeyError when none or
        several match."""
        found = [p for p in self.parameters if p.name == name and process in (None, p.process)
                 and component in (None, p.component)]
        if len(found) != 1:
            raise KeyError(f"{len(found)} parameters match name={name!r}, process={process!r}, "
                           f"component={component!r}")
        return found[0]


@dataclass(frozen=True)
class ContinuousParameter:
    """A parameter as a physical quantity (correlation time, noise density, ...) with its
    interval and unit; `component` is None where the JSON has none (gap's "physical")."""

    process: str
    component: int | None
    name: str
    value: float
    ci_low: float
    ci_high: float
    unit: str
    convention: str

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> "ContinuousParameter":
        return cls(d["process"], opt_int(d.get("component")), d["name"], num(d["value"]), num(d.get("ci_low")),
                   num(d.get("ci_high")), d["unit"], d["convention"])

    def __repr__(self) -> str:
        return (f"ContinuousParameter({self.process}.{self.name} = {g(self.value)} {self.unit} "
                f"[{g(self.ci_low)}, {g(self.ci_high)}])")


def continuous(rows: Iterable[Mapping[str, Any]] | None) -> tuple[ContinuousParameter, ...]:
    return tuple(ContinuousParameter.from_dict(r) for r in rows or ())


@dataclass(frozen=True)
class GoodnessOfFit:
    statistic: float
    df: float
    p_value: float
    method: str

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> "GoodnessOfFit":
        return cls(num(d["statistic"]), num(d["df"]), num(d["p_value"]), d["method"])


@dataclass(frozen=True)
class WorstLevel:
    level: int
    tau: float
    tau_seconds: float
    ratio: float
    z: float


@dataclass(frozen=True)
class FitQuality:
    """Whether the fit is rejected (p < 5%), the verdict, the levels that depart most and
    whether it is degenerate."""

    rejected: bool
    verdict: str | None
    worst_levels: tuple[WorstLevel, ...]
    degenerate: bool
    degeneracy: str | None

    @classmethod
    def from_dict(cls, d: Mapping[str, Any] | None) -> "FitQuality | None":
        if d is None:
            return None
        worst = tuple(WorstLevel(int(w["level"]), num(w["tau"]), num(w["tau_seconds"]), num(w["ratio"]), num(w["z"]))
                      for w in d["worst_levels"])
        return cls(bool(d["rejected"]), d["verdict"], worst, bool(d["degenerate"]), d["degeneracy"])

    def __repr__(self) -> str:
        return f"FitQuality(rejected={self.rejected}, degenerate={self.degenerate})"


@dataclass(frozen=True)
class KalmanTerm:
    """One Kalman-filter term: `q` the continuous spectral density, `discrete` the per-step
    variance, `transition` the state transition (None/NaN where not a state)."""

    process: str
    component: int | None
    role: str
    q: float
    q_unit: str | None
    transition: float
    discrete: float
    discrete_unit: str | None
    note: str

    def __repr__(self) -> str:
        return f"KalmanTerm({self.process}: {self.role}, q={g(self.q)} {self.q_unit})"


@dataclass(frozen=True)
class Kalman:
    filter_rate: float
    terms: tuple[KalmanTerm, ...]

    @classmethod
    def from_dict(cls, d: Mapping[str, Any] | None) -> "Kalman | None":
        if d is None:
            return None
        terms = tuple(KalmanTerm(t["process"], opt_int(t["component"]), t["role"], num(t["q"]), t["q_unit"],
                                 num(t["transition"]), num(t["discrete"]), t["discrete_unit"], t["note"])
                      for t in d["terms"])
        return cls(num(d["filter_rate"]), terms)

    def __repr__(self) -> str:
        return f"Kalman({len(self.terms)} terms at {g(self.filter_rate)} Hz)"


@dataclass(frozen=True, eq=False)
class AllanDeviation:
    """The overlapping Allan deviation on its octave grid (`tau` in seconds, `m` the
    averaging factors) with its chi-square interval; `model` the model's curve on the same
    grid, or None."""

    alpha: float
    m: IntArray
    tau: FloatArray
    adev: FloatArray
    ci_low: FloatArray
    ci_high: FloatArray
    edf: FloatArray
    model: FloatArray | None

    @classmethod
    def from_dict(cls, d: Mapping[str, Any] | None) -> "AllanDeviation | None":
        if d is None:
            return None
        return cls(num(d["alpha"]), ints(d["m"]), floats(d["tau"]), floats(d["adev"]), floats(d["ci_low"]),
                   floats(d["ci_high"]), floats(d["edf"]), None if d["model"] is None else floats(d["model"]))

    def __len__(self) -> int:
        return len(self.tau)

    def __repr__(self) -> str:
        if not len(self.tau):
            return "AllanDeviation(empty)"
        return (f"AllanDeviation({len(self.tau)} points, tau {g(self.tau[0])}-{g(self.tau[-1])} s, "
                f"smallest adev {g(float(np.nanmin(self.adev)))}{', with model' if self.model is not None else ''})")


@dataclass(frozen=True)
class FigureComponent:
    """A model component's share of a noise figure."""

    component: str
    share: float


@dataclass(frozen=True)
class Readoff:
    """One read-off of the Allan deviation (the model's or the data's): `how` says how it
    was read (the method), `status` read, extrapolated or bound (None: not available)."""

    value: float
    low: float
    high: float
    status: str | None
    tau: float
    region_from: float
    region_to: float
    how: str
    components: tuple[FigureComponent, ...]

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> "Readoff":
        return cls(**readoff_fields(d))

    @property
    def interval(self) -> tuple[float, float]:
        return (self.low, self.high)

    def __repr__(self) -> str:
        return f"Readoff({g(self.value)} [{g(self.low)}, {g(self.high)}], {self.status})"


def readoff_fields(d: Mapping[str, Any]) -> dict[str, Any]:
    return dict(value=num(d["value"]), low=num(d["low"]), high=num(d["high"]), status=d["status"],
                tau=num(d["tau"]), region_from=num(d["region_from"]), region_to=num(d["region_to"]), how=d["how"],
                components=tuple(FigureComponent(c["component"], num(c["share"])) for c in d["components"]))


@dataclass(frozen=True)
class NoiseFigure(Readoff):
    """A noise figure (N, K or B) as written: its value, interval [low, high] and unit,
    `source` (model, data or bound: whose read-off it is), `note`, and both read-offs."""

    unit: str
    source: str
    note: str
    model: Readoff
    data: Readoff

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> "NoiseFigure":
        return cls(**readoff_fields(d), unit=d["unit"], source=d["source"], note=d["note"],
                   model=Readoff.from_dict(d["model"]), data=Readoff.from_dict(d["data"]))

    def __repr__(self) -> str:
        return f"NoiseFigure({g(self.value)} {self.unit} [{g(self.low)}, {g(self.high)}], {self.source}, {self.status})"


@dataclass(frozen=True)
class NoiseFigures:
    """The IEEE 952 figures: N (JSON "white"), K ("walk") and B ("instability")."""

    N: NoiseFigure
    K: NoiseFigure
    B: NoiseFigure

    @classmethod
    def from_dict(cls, d: Mapping[str, Any] | None) -> "NoiseFigures | None":
        if d is None:
            return None
        return cls(NoiseFigure.from_dict(d["white"]), NoiseFigure.from_dict(d["walk"]),
                   NoiseFigure.from_dict(d["instability"]))

    @property
    def white(self) -> NoiseFigure:
        return self.N

    @property
    def walk(self) -> NoiseFigure:
        return self.K

    @property
    def instability(self) -> NoiseFigure:
        return self.B

    def __repr__(self) -> str:
        return (f"NoiseFigures(N={g(self.N.value)} {self.N.unit}, K={g(self.K.value)} {self.K.unit}, "
                f"B={g(self.B.value)} {self.B.unit})")
