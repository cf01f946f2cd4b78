"""gmwm.fit_curve: a model fitted to a given Allan deviation, Allan variance or wavelet variance
curve instead of data, as `gmwm fit --curve` (docs/curve-fit.md)."""
from __future__ import annotations

import os
import warnings
from typing import Any, Mapping, Sequence

import numpy as np

from . import _gmwm
from ._types import FitResult


def _curve_argument(curve: Any) -> Any:
    """A path as text, named columns as a dict of float arrays (a DataFrame's by its labels)."""
    if isinstance(curve, (str, os.PathLike)):
        return os.fspath(curve)
    if hasattr(curve, "columns") and hasattr(curve, "to_numpy"):  # a pandas DataFrame
        return {str(c): np.asarray(curve[c], dtype=np.float64) for c in curve.columns}
    if isinstance(curve, Mapping):
        return {str(k): np.asarray(v, dtype=np.float64) for k, v in curve.items()}
    return curve  # refused by the module, in its words


def _ranges_argument(exclude_taus: str | Sequence[tuple[float | None, float | None]] | None) -> str:
    """--exclude-taus's text: as given, or (from, to) pairs in seconds (None: an open end)."""
    if exclude_taus is None:
        return ""
    if isinstance(exclude_taus, str):
        return exclude_taus
    def end(x: float | None) -> str:
        return "" if x is None else repr(float(x))  # repr reads back to the same double

    return ",".join(f"{end(lo)}:{end(hi)}" for lo, hi in exclude_taus)


def fit_curve(curve: Any, model: str, *, value: str | None = None, freq: float | None = None,
              exclude_taus: str | Sequence[tuple[float | None, float | None]] | None = None, omega: str = "model",
              alpha: float = 0.05, confidence: float = 0.95, record: float | None = None, units: str = "",
              kf_rate: float | None = None, max_evaluations: int = 3000, seed: int = _gmwm.DEFAULT_SEED,
              column: str | None = None) -> FitResult:
    """A GMWM fit of `model` to a given curve, as `gmwm fit --curve` fits it (the same FitResult as
    gmwm.fit, with its `curve`: docs/curve-fit.md).

    curve: a file's path (delimited text whose header names tau in seconds and the values, and
    optionally ci_low, ci_high or edf; `gmwm wv --adev-csv` writes one), or named columns (a dict
    or a DataFrame: "tau", "adev" (or "avar", "wv", "value"), ...). value: what the values are,
    "adev", "avar" or "wv" (the CLI's --value; default from the column's name). freq: the rate of
    the data behind the curve, which the parameters are per sample at (default: the finest tau one
    sample). exclude_taus: taus left out, the CLI's text (":0.05,100:") or (from, to) pairs in
    seconds, None an open end. record: the record's length in seconds, for a curve without
    intervals or edf (default: the shortest record reaching its longest tau, whose intervals bound
    a longer record's; a warning says so). confidence: the level of the curve's intervals (0.683
    for +-1 sigma error bars). column: the curve of a file that holds several. omega: "model" or
    "diag"; alpha, units, kf_rate, max_evaluations and seed as gmwm.fit's."""
    text = _gmwm.fit_curve(_curve_argument(curve), model, value=value, freq=freq,
                           exclude_taus=_ranges_argument(exclude_taus), omega=omega, alpha=alpha,
                           confidence=confidence, record=record, units=units, kf_rate=kf_rate,
                           max_evaluations=max_evaluations, seed=seed, column=column)
    result = FitResult.from_json(text)
    if result.curve is not None and result.curve.weights == "shortest-record":
        warnings.warn(f"{result.curve.source}: curve '{result.name}': no interval, edf or record length: weighed as "
                      "the shortest record reaching its longest tau, whose intervals bound a longer record's "
                      "(record= gives the record's own)", UserWarning, stacklevel=2)
    return result
