"""gmwm: the Generalized Method of Wavelet Moments for inertial sensor noise.

The functions take numpy arrays and return typed results (frozen dataclasses with numpy
float64 arrays) built from the JSON the `gmwm` command writes for the same data and options
(docs/cli.md, "JSON"; docs/python.md walks through them):

    import numpy as np, gmwm
    x = gmwm.simulate("WN(sigma2=1e-4)+RW(gamma2=1e-9)", 2**17, freq=100)   # numpy array
    w = gmwm.wv(x, freq=100)                       # w.tau, w.tau_seconds, w.wv, w.ci_low, w.ci_high
    f = gmwm.fit(x, "WN+RW", freq=100, units="rad/s")
    f.parameters[0].value, f.parameter("gamma2").ci_high, f.gof.p_value, f.implied_wv
    f.noise_figures.N.value, f.noise_figures.N.unit   # N, K, B, Q, R with intervals and read-offs
    s = gmwm.select(np.column_stack([x, x]), "AR1+WN+RW", freq=100)   # s[0].best, s[0].ranking
    a = gmwm.allan(x, freq=100, units="rad/s")     # a.tau, a.adev, a.noise_figures.B
    g = gmwm.gap(np.column_stack([x]), freq=100, names=["gyro_x"], kalibr="imu.yaml")
                                                   # g.columns[0].headline, g.corrected.content
    n = gmwm.nav("select.json", ["truth", "wnrw", "imu.yaml*2"], outages=[(300, 360)])
                                                   # n.filters[k].verdict, n.filters[k].curves.nees
    c = gmwm.gap_check(cases=3, n=2**14, families="STEP,DR")   # c.confusion, c.power
    p = gmwm.plan(model="WN(sigma2=1e-8)+RW(gamma2=1e-14)", freq=100, unit="rad/s")
                                                   # p.columns[0].targets[k].seconds
    d = gmwm.stability(x, freq=100, kind="oadev,mdev", taus="decade")
                                                   # d.columns[0].deviations["mdev"].value
    c = gmwm.fit_curve("adev.csv", "WN+RW+AR1")    # a given Allan deviation curve: c.curve.weights
    f.to_json()                                    # the command's JSON text, unchanged
    f.document                                     # the same, parsed (every field)

    j = gmwm.fit_joint([x1, x2, x3], "AR1+WN+RW", freq=100)   # replicates: one joint model per axis
    j.columns[0].parameters, j.columns[0].replicate_test.p_value
    k = gmwm.select_joint([x1, x2, x3], "2*AR1+WN+RW", freq=100)   # k.columns[0].ranking, .recommended
    t = gmwm.fleet("fleet.csv", model="AR1+WN+RW")   # t.rows[k].N.value, t.summary, t.to_dataframe()
    e = gmwm.export(f, format="kalibr", sensor="gyro")   # e.content: the imu.yaml text; e.written

Results of the command line load the same way: every class has from_json(text) (e.g.
JointFitResult for `gmwm fit --joint --json`, ExportResult for `gmwm export --json`).

`units` is the CLI's --units everywhere: one unit ("deg/s") or kind=unit pairs
("gyro=deg/s,accel=g", each column's kind from its name); a typo is refused. plan() takes the
CLI's --unit (one unit name, validated too).

Data: a numpy array, a pandas Series or DataFrame (columns named by their labels), or a
Recording read as the command reads a file (every format it reads, the same refusals):

    imu = gmwm.read("imu.csv.gz", columns="gyro_x,gyro_y")   # .values, .names, .freq, .timing
    f = gmwm.fit(imu["gyro_x"], "WN+RW")          # the rate and the name come with it
    gyro, accel = gmwm.read_parts("d435i.bag", topic="/camera/gyro/sample,/camera/accel/sample")
                                                  # topics at different rates, each at its own

`freq` (Hz) is needed by every function that takes data: a Recording carries its rate, and a
pandas DatetimeIndex or TimedeltaIndex gives it (measured as a timestamp column, with the
same checks); an array carries no timestamps, as the CLI refuses a file without a time
column and no --freq (freq=1 reads tau in samples).

Bad input raises gmwm.InputError (a ValueError) with the command's one-line message, the
keyword argument to change named where the command names its option.
"""
from __future__ import annotations

import ast
import dataclasses
import functools
import inspect
import os
from typing import Any, Callable, ParamSpec, Sequence, TypeVar

from . import _gmwm, _signals
from ._common import (JsonResult)
from ._types import (AllanDeviation, ContinuousParameter, FigureComponent, FitQuality, GoodnessOfFit, Kalman, KalmanTerm, NoiseFigure, NoiseFigures, Parameter, Readoff, WorstLevel)
from ._types import (Attribution, ConfigChange, Contamination, CorrectedColumn, CorrectedConfig, CrossAxis,
                     CrossAxisPair, GapAssessment, GapBand, GapCandidate, GapCheckCase, GapCheckFamily, GapCheckResult,
                     GapColumn, GapEvent, GapEventTest, GapStepScan, GapLevels, GapNavigation, GapResult, GapSplitHalf, GapStep,
                     GapTemperature, GapTest, GapTrend, GapWindow, Remaining, Shrinkage)
from ._gmwm import DEFAULT_SEED, InputError, __version__, simulate
from ._types import (ConsistentFor, ExportColumn, ExportResult, ExportWritten, FleetFigure, FleetFigureSummary,
                     FleetJointModel, FleetResult, FleetRow, FleetSpecCheck, GaussMarkov, NavCurves, NavFilter,
                     NavMonteCarlo, NavResult, NavScenario, NavSummary, PlanColumn, PlanResolved, PlanResult, PlanTarget,
                     WrittenNoise)
from ._types import (Agmwm, JointFitColumn, JointFitResult, JointRankingRow, JointSelectColumn,
                     JointSelectResult, ReplicateBootstrap, ReplicateFit, ReplicateOwnFit, ReplicateTest)
from ._signals import Recording, RepeatedSamplesWarning, TimingWarning, read, read_parts
from ._curve import fit_curve
from ._types import CurveInfo
from ._types import RepeatedSamples, Timing
from ._types import Deviation, StabilityColumn, StabilityResult
from ._types import (AllanResult, BestFit, Candidate, FitResult, RankingRow, SelectColumn, SelectResult, WvLevels,
                     WvResult)


def _signature(doc: str, returns: str) -> inspect.Signature | None:
    """The signature in the first line of a pybind11 docstring, returning `returns`."""
    head = doc.split("\n", 1)[0]
    empty = inspect.Parameter.empty

    def parameter(a: ast.arg, kind: Any, default: ast.expr | None) -> inspect.Parameter:
        return inspect.Parameter(a.arg, kind, default=empty if default is None else ast.literal_eval(default),
                                 annotation=ast.unparse(a.annotation) if a.annotation else empty)

    try:
        params = head[head.index("(") + 1:head.rindex(") -> ")]
        args = ast.parse(f"def f({params}): pass").body[0].args  # type: ignore[attr-defined]
        positional = args.posonlyargs + args.args
        defaults = [None] * (len(positional) - len(args.defaults)) + list(args.defaults)
        out = [parameter(a, inspect.Parameter.POSITIONAL_OR_KEYWORD, d) for a, d in zip(positional, defaults)]
        out += [parameter(a, inspect.Parameter.KEYWORD_ONLY, d) for a, d in zip(args.kwonlyargs, args.kw_defaults)]
        return inspect.Signature(out, return_annotation=returns)
    except (ValueError, SyntaxError):
        return None


_P = ParamSpec("_P")
_R = TypeVar("_R", bound=JsonResult)


def _typed(raw: Callable[_P, str], result: type[_R],
           signals: Callable[[dict[str, Any]], None] | None = None) -> Callable[_P, _R]:
    """`raw` (returning the library's JSON text) returning `result` built from that text, with
    raw's parameters (from the module's stub, _gmwm.pyi) for type checkers. `signals` turns
    the arguments given (by name) that carry data into what raw takes: a Recording or a
    pandas time index into arrays, names and freq (_signals)."""
    doc = raw.__doc__ or ""
    name = result.__name__
    signature = _signature(doc, f"gmwm.{name}")

    @functools.wraps(raw)
    def call(*args: _P.args, **kwargs: _P.kwargs) -> _R:
        if signals is None or signature is None:
            return result.from_json(raw(*args, **kwargs))
        try:
            bound = signature.bind(*args, **kwargs)
        except TypeError:
            return result.from_json(raw(*args, **kwargs))  # raw's own message for a wrong call
        arguments = dict(bound.arguments)
        signals(arguments)
        return result.from_json(raw(**arguments))

    call.__doc__ = doc.replace(") -> str\n", f") -> gmwm.{name}\n", 1) + (
        f"\nReturns a gmwm.{name} (typed fields; .document the parsed JSON, .to_json() its text).\n")
    call.__module__ = __name__
    if signature is not None:
        call.__signature__ = signature  # type: ignore[attr-defined]
    return call


wv = _typed(_gmwm.wv, WvResult, _signals.one_series)
allan = _typed(_gmwm.allan, AllanResult, _signals.one_series)
fit = _typed(_gmwm.fit, FitResult, _signals.one_series)
select = _typed(_gmwm.select, SelectResult, _signals.columns)
gap = _typed(_gmwm.gap, GapResult, _signals.columns)
gap_check = _typed(_gmwm.gap_check, GapCheckResult)
nav = _typed(_gmwm.nav, NavResult)
fit_joint = _typed(_gmwm.fit_joint, JointFitResult, _signals.replicates)
select_joint = _typed(_gmwm.select_joint, JointSelectResult, _signals.replicates)
stability = _typed(_gmwm.stability, StabilityResult, _signals.columns)
_fleet_raw = _typed(_gmwm.fleet, FleetResult)


def fleet(manifest: str | os.PathLike[str], *, model: str, alpha: float = 0.05, seed: int = DEFAULT_SEED,
          memory: float | None = None, cache: str | os.PathLike[str] | None = "",
          scheduler: Any = None, spec: str | os.PathLike[str] | None = None,
          gap_kalibr: str | os.PathLike[str] | None = None, gap_gazebo: str | os.PathLike[str] | None = None,
          gap_datasheet: str | os.PathLike[str] | None = None, gap_imu: str = "",
          gap_replicates: int = 200, joint: bool = False, joint_draws: int = 100,
          first_level: int | str = "auto") -> FleetResult:
    """Every recording of a manifest (CSV or YAML: path, unit, model[, topic, columns, units, rate,
    group]) selected over `model` as gmwm select does: one row per unit x axis with N, K, B, the
    fleet's summary and the units that stand out (the document gmwm fleet --json writes).

    cache: the folder of records already computed (by content and options); "" (default) the
    CLI's .gmwm-cache beside the manifest, None no cache. scheduler: None runs here; a Dask
    scheduler's address ("tcp://host:8786"), a distributed.Client or a LocalCluster runs each
    recording as a task there (python3-distributed; the workers need gmwm and the files).
    spec: a yaml of datasheet limits per sensor model (the CLI's --spec): each unit's N, K, B
    checked against them (rows' "spec", "spec_verdict"; the summary's "out_of_spec").
    gap_kalibr / gap_gazebo / gap_datasheet (at most one): each recording's gap diagnosis
    against that baseline, as gmwm gap gives it (rows' "gap": verdict, headline, p_value);
    gap_imu names a Kalibr chain's IMU, gap_replicates the reference replicates.
    joint: each group's joint model per axis (its units as replicates; result.joint), the
    shared-theta test by bootstrap (joint_draws) up to 12 units, by its chi-square beyond.
    first_level: the first level each selection fits and each gap diagnosis compares (the
    CLI's --first-level): "auto" (default) above the scales a unit's held or interpolated
    samples smooth, 1 where they do not repeat; rows' "first_level" says where."""
    from . import _fleet_dask

    runner = None if scheduler is None else _fleet_dask.runner(scheduler)
    gaps = [(f, p) for f, p in (("kalibr", gap_kalibr), ("gz-sdf", gap_gazebo), ("datasheet", gap_datasheet))
            if p is not None]
    if len(gaps) > 1:
        raise InputError("fleet: give one gap baseline: gap_kalibr, gap_gazebo or gap_datasheet")
    gap_format, gap_path = gaps[0] if gaps else ("kalibr", "")
    return _fleet_raw(os.fspath(manifest), model=model, alpha=alpha, seed=seed, memory=memory,
                      cache=None if cache is None else os.fspath(cache), runner=runner,
                      spec="" if spec is None else os.fspath(spec), gap_format=gap_format,
                      gap_path=os.fspath(gap_path), gap_imu=gap_imu, gap_replicates=gap_replicates, joint=joint,
                      joint_draws=joint_draws, first_level=first_level)


def _result_document(result: Any) -> tuple[str, str]:
    """The fit/select document gmwm export reads and the file it came from ("" when none): a
    FitResult or SelectResult (wrapped as the command's document), a result's JSON text, or
    the path of a result file."""
    if isinstance(result, FitResult):
        return '{"tool": "gmwm", "command": "fit", "columns": [' + result.to_json() + ']}', ""
    if isinstance(result, SelectResult):
        return '{"tool": "gmwm", "command": "select", "columns": ' + result.to_json() + '}', ""
    if isinstance(result, str) and result.lstrip().startswith("{"):
        return result, ""
    if isinstance(result, str) and result.lstrip().startswith("["):
        raise InputError("result: JSON text of a list (a result's columns, as SelectResult.to_json() gives), expected "
                         "the result itself (a gmwm.FitResult or gmwm.SelectResult), a result document's text or its "
                         "file")
    if isinstance(result, (str, os.PathLike)):
        try:
            with open(result, encoding="utf-8") as f:
                return f.read(), os.fspath(result)
        except OSError as e:
            raise InputError(f"result {os.fspath(result)}: {e.strerror}, expected the JSON file of a gmwm fit or "
                             "gmwm select result") from None
    raise InputError("result: expected a gmwm.FitResult, a gmwm.SelectResult, a result's JSON text or its path, "
                     f"got {type(result).__name__}")


def plan(result: Any = None, *, model: str | None = None, freq: float | None = None, unit: str = "",
         precision: float = 0.1, confidence: float = 0.95, targets: Sequence[str] = (), have: float | None = None,
         columns: Sequence[str] = ()) -> PlanResult:
    """How long to record, as `gmwm plan` says: per column of a fit/select result (a
    gmwm.FitResult or gmwm.SelectResult, a result's JSON text or the path of a `--json`
    file), or for `model` (every value given) at `freq` Hz, the record length at which N, K,
    B or a parameter (`targets`: 'N', 'K', 'B', 'WN[1].sigma2', ...) reach +-`precision`
    with probability `confidence`; `have` (s) adds the precision such a record reaches.
    `unit` labels a model's figures; `columns` picks a result's."""
    document, source = (None, "") if result is None else _result_document(result)
    return PlanResult.from_json(_gmwm.plan(document, model=model, freq=freq, unit=unit, precision=precision,
                                           confidence=confidence, targets=list(targets), have=have,
                                           columns=list(columns), source_name=source))


def export(result: Any, *, format: str, output: str = "", **options: Any) -> ExportResult:
    """A fit/select result's noise parameters in a consumer's format, as `gmwm export
    RESULT --format FORMAT --output OUTPUT` writes them (nothing is written here).

    `result` is a gmwm.FitResult or gmwm.SelectResult, a result's JSON text, or the path of
    a `gmwm fit/select --json` file. `format`: kalibr, openvins, vins, orbslam3, basalt,
    gz-sdf or rotors; `output` only names the file in the document. Options as the CLI's:
    aggregate ('mean', 'worst', 'per-axis'), inflate, rate (Hz), rostopic, units, sensor
    ('gyro' or 'accel'), columns (names), consistent_for ((update rate Hz, horizon s, update
    sigma m): derives the inflation that keeps a WN + RW filter consistent), partial (True:
    a sensor without columns has its fields left out; else such a result is refused: a 0
    would be read as a perfect sensor).

    Returns a gmwm.ExportResult: the document (to_json() equals the CLI's --json without
    "run"), `content` the file's text and `sidecar_content` basalt's header (else None).
    """
    document, source_name = _result_document(result)
    text, content, sidecar = _gmwm.export(document, format=format, output=output, source_name=source_name,
                                          **options)
    return dataclasses.replace(ExportResult.from_json(text), content=content, sidecar_content=sidecar)


__all__ = [
    "wv", "allan", "fit", "select", "gap", "gap_check", "nav", "plan", "simulate", "fit_joint", "select_joint",
    "stability", "fit_curve", "CurveInfo",
    "export", "fleet", "read", "read_parts", "InputError", "DEFAULT_SEED",
    # signals in
    "Recording", "Timing", "TimingWarning", "RepeatedSamples", "RepeatedSamplesWarning",
    "__version__",
    # results of the functions
    "WvResult", "AllanResult", "FitResult", "SelectResult", "GapResult", "GapCheckResult", "NavResult", "PlanResult",
    "StabilityResult", "StabilityColumn", "Deviation",
    # documents of the command line
    "JointFitResult", "JointSelectResult", "ExportResult",
    # their parts
    "JsonResult", "WvLevels", "Parameter", "ContinuousParameter", "GoodnessOfFit", "FitQuality", "WorstLevel",
    "Kalman", "KalmanTerm", "AllanDeviation", "Readoff", "FigureComponent", "NoiseFigure", "NoiseFigures",
    "RankingRow", "Candidate", "BestFit", "SelectColumn",
    "GapColumn", "GapTest", "GapBand", "GapLevels", "GapWindow", "GapSplitHalf", "Attribution", "GapStep",
    "GapCandidate", "GapEvent", "GapEventTest", "GapStepScan", "GapTrend", "GapTemperature", "Remaining", "Shrinkage",
    "GapNavigation", "Contamination", "CorrectedConfig", "CorrectedColumn", "ConfigChange", "GapAssessment",
    "CrossAxis", "CrossAxisPair", "GapCheckFamily", "GapCheckCase",
    "NavScenario", "NavFilter", "NavSummary", "NavCurves", "NavMonteCarlo", "PlanColumn", "PlanResolved", "PlanTarget",
    "JointFitColumn", "ReplicateFit", "ReplicateOwnFit", "Agmwm", "ReplicateBootstrap", "ReplicateTest",
    "JointSelectColumn", "JointRankingRow",
    "ExportColumn", "ExportWritten", "WrittenNoise", "GaussMarkov", "ConsistentFor",
    "FleetResult", "FleetRow", "FleetFigure", "FleetFigureSummary", "FleetSpecCheck", "FleetJointModel",
]
