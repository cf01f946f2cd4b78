"""Pieces shared by the typed results: numbers and arrays from JSON, parameters, goodness
of fit, continuous parameters, Kalman terms, the Allan deviation and the noise figures.

JSON null (the library's NaN or infinity, or "not given") becomes NaN in a float field or
array, None elsewhere.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Iterable, Mapping, TypeVar

import numpy as np
import numpy.typing as npt

from ._json_text import item_texts, member_text

if TYPE_CHECKING:
    from ._types import KalmanTerm, NoiseFigure, Parameter

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


# The methods of the typed results (their fields, JSON keys and from_dict are generated from
# report/schema/results.json into _types.py; each mixin names the fields it reads).


class ParameterMethods:
    process: str
    component: int
    name: str
    value: float
    ci_low: float
    ci_high: float
    interval: str | None

    def __repr__(self) -> str:
        return (f"Parameter({self.process}[{self.component}].{self.name} = {g(self.value)} "
                f"[{g(self.ci_low)}, {g(self.ci_high)}] {self.interval or 'no interval'})")


def parameters(rows: Iterable[Mapping[str, Any]] | None) -> tuple["Parameter", ...]:
    from ._types import Parameter

    return tuple(Parameter.from_dict(r) for r in rows or ())


class HasParameters:
    """`parameter(name, process, component)`: one row of `parameters`."""

    parameters: tuple["Parameter", ...]

    def parameter(self, name: str, process: str | None = None, component: int | None = None) -> "Parameter":
        """The parameter called `name` (of `process`, of `component`); KeyError when none or
        several match."""
        found = [p for p in self.parameters if p.name == name and process in (None, p.process)
                 and component in (None, p.component)]
        if len(found) != 1:
            raise KeyError(f"{len(found)} parameters match name={name!r}, process={process!r}, "
                           f"component={component!r}")
        return found[0]


class ContinuousParameterMethods:
    process: str
    name: str
    value: float
    ci_low: float
    ci_high: float
    unit: str

    def __repr__(self) -> str:
        return (f"ContinuousParameter({self.process}.{self.name} = {g(self.value)} {self.unit} "
                f"[{g(self.ci_low)}, {g(self.ci_high)}])")


class FitQualityMethods:
    rejected: bool
    degenerate: bool

    def __repr__(self) -> str:
        return f"FitQuality(rejected={self.rejected}, degenerate={self.degenerate})"


class KalmanTermMethods:
    process: str
    role: str
    q: float
    q_unit: str | None

    def __repr__(self) -> str:
        return f"KalmanTerm({self.process}: {self.role}, q={g(self.q)} {self.q_unit})"


class KalmanMethods:
    filter_rate: float
    terms: tuple["KalmanTerm", ...]

    def __repr__(self) -> str:
        return f"Kalman({len(self.terms)} terms at {g(self.filter_rate)} Hz)"


class AllanDeviationMethods:
    tau: FloatArray
    adev: FloatArray
    model: FloatArray | None

    def __len__(self) -> int:
        return len(self.tau)

    def __repr__(self) -> str:
        if not len(self.tau):
            return "AllanDeviation(empty)"
        return (f"AllanDeviation({len(self.tau)} points, tau {g(self.tau[0])}-{g(self.tau[-1])} s, "
                f"smallest adev {g(float(np.nanmin(self.adev)))}{', with model' if self.model is not None else ''})")


class ReadoffMethods:
    value: float
    low: float
    high: float
    status: str | None

    @property
    def interval(self) -> tuple[float, float]:
        return (self.low, self.high)

    def __repr__(self) -> str:
        return f"Readoff({g(self.value)} [{g(self.low)}, {g(self.high)}], {self.status})"


class NoiseFigureMethods:
    value: float
    low: float
    high: float
    status: str | None
    unit: str
    source: str

    def __repr__(self) -> str:
        return f"NoiseFigure({g(self.value)} {self.unit} [{g(self.low)}, {g(self.high)}], {self.source}, {self.status})"


class NoiseFiguresMethods:
    N: "NoiseFigure"
    K: "NoiseFigure"
    B: "NoiseFigure"
    Q: "NoiseFigure | None"
    R: "NoiseFigure | None"

    @property
    def white(self) -> "NoiseFigure":
        return self.N

    @property
    def walk(self) -> "NoiseFigure":
        return self.K

    @property
    def instability(self) -> "NoiseFigure":
        return self.B

    @property
    def quantization(self) -> "NoiseFigure | None":
        return self.Q

    @property
    def ramp(self) -> "NoiseFigure | None":
        return self.R

    def __repr__(self) -> str:
        more = "".join(f", {name}={g(f.value)} {f.unit}" for name, f in (("Q", self.Q), ("R", self.R)) if f is not None)
        return (f"NoiseFigures(N={g(self.N.value)} {self.N.unit}, K={g(self.K.value)} {self.K.unit}, "
                f"B={g(self.B.value)} {self.B.unit}{more})")
