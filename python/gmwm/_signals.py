"""Signals in: a recording read as the gmwm command reads it (gmwm.read), and the rate of a
pandas index. Every function that takes data takes a numpy array, a pandas Series or
DataFrame, or a Recording; this module turns the last two into the arrays, names and rate
the library takes, by the rules the command line follows for a file (the same readers, the
same timestamp checks, the same refusals, naming Python's keywords)."""
from __future__ import annotations

import json
import math
import os
import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from . import _gmwm
from ._common import FloatArray, g
from ._gmwm import InputError

if TYPE_CHECKING:
    from ._types import RepeatedSamples, Timing


class TimingWarning(UserWarning):
    """The timestamps of the data have gaps, samples out of order, or disagree with a given
    freq by more than 1%: the rate taken is still the median step's (or freq), but the
    samples are not evenly spaced as the wavelet variance assumes."""


class RepeatedSamplesWarning(UserWarning):
    """Some samples of a column copy the one before (held) or are an exact linear combination
    of their neighbours (interpolated), as a driver that fills a faster stream makes them: the
    fine scales are smoothed and N is read above them (Recording.repeated_samples says where)."""


class TimingMethods:
    gaps: int
    disorder: int
    given_freq: float | None
    estimated_freq: float

    @property
    def irregular(self) -> bool:
        """Gaps, samples out of order, or a given freq more than 1% from the stamps' rate."""
        disagrees = (self.given_freq is not None and self.estimated_freq > 0.0
                     and abs(self.estimated_freq - self.given_freq) > 0.01 * self.given_freq)
        return self.gaps > 0 or self.disorder > 0 or disagrees


@dataclass(frozen=True, eq=False)
class Recording:
    """The columns of a recording as the gmwm command reads them (gmwm.read): `values` a
    read-only samples x columns float64 array, `names` the columns' names, `units` the unit
    each header states (None where none), `freq` the rate in Hz (the given freq, else the
    timestamps'), `timing` what the timestamps said (None without a timestamp column).

    Every function that takes data takes a Recording: its rate is the freq, its names the
    columns' names (`rec["gyro_x"]` is the one-column recording a one-series function takes).
    """

    path: str
    names: tuple[str, ...]
    units: tuple[str | None, ...]
    freq: float
    values: FloatArray
    timing: Timing | None
    topic: str | None = None
    preset: str | None = None
    conditioning: str | None = None
    repeated_samples: tuple["RepeatedSamples", ...] = ()

    def __len__(self) -> int:
        return int(self.values.shape[0])

    def __getitem__(self, key: str | int | Sequence[str | int]) -> "Recording":
        """The recording of one column (a name or 0-based position) or of several."""
        keys = [key] if isinstance(key, (str, int)) else list(key)
        picks = [self._position(k) for k in keys]
        values = self.values[:, picks]
        values.flags.writeable = False
        return Recording(self.path, tuple(self.names[p] for p in picks), tuple(self.units[p] for p in picks),
                         self.freq, values, self.timing, self.topic, self.preset, self.conditioning,
                         tuple(r for r in self.repeated_samples if r.column in [self.names[p] for p in picks]))

    def _position(self, key: str | int) -> int:
        if isinstance(key, str):
            if key in self.names:
                return self.names.index(key)
            raise KeyError(f"{key!r}: not a column of {self.path} (its columns: {', '.join(self.names)})")
        if -len(self.names) <= key < len(self.names):
            return key % len(self.names)
        raise IndexError(f"column {key}: {self.path} has {len(self.names)} columns")

    def column(self, name: str | int) -> FloatArray:
        """One column's samples."""
        return self.values[:, self._position(name)]

    @property
    def seconds(self) -> FloatArray:
        """Each sample's time from the first, in seconds, at `freq` (the samples evenly spaced)."""
        t = np.arange(len(self), dtype=np.float64) / self.freq
        t.flags.writeable = False
        return t

    def to_dataframe(self) -> Any:
        """A pandas DataFrame of the columns, its index the seconds from the first sample."""
        import pandas  # optional: only this method needs it

        frame = pandas.DataFrame(np.array(self.values), columns=list(self.names))
        frame.index = pandas.Index(self.seconds, name="seconds")
        return frame

    def __repr__(self) -> str:
        return (f"Recording({os.path.basename(self.path)}: {len(self)} samples x {len(self.names)} columns "
                f"({', '.join(self.names)}), freq={g(self.freq)} Hz)")


def read(path: str | os.PathLike[str], *, columns: str | Sequence[str | int] | None = None,
         freq: float | None = None, topic: str | None = None, memory: float | None = None,
         gaps: str = "windows", data: str = "rate", decimate: int = 1,
         decimate_filter: str = "average") -> Recording:
    """The columns of a recording, read exactly as `gmwm fit PATH --columns ... --freq ...
    --topic ... --memory ...` reads them: delimited text (CSV, tab, whitespace; EuRoC and
    Kalibr layouts), gzip of it, PX4 ULog, ROS 1 bags, rosbag2 and MCAP.

    columns: names or 1-based indices (a list, or "a,b,c" as the CLI's text); None: every
    numeric column that is not a timestamp. freq: the rate in Hz, which takes the samples as
    evenly spaced (else the timestamps give it; a recording without either is refused).
    topic: a log's or bag's topic ("sensor_combined", "/imu0", ...). memory: MB the values may
    take (default 75% of the machine's memory); a longer record is refused, since the values
    are handed over in memory. gaps: "windows" (the default) puts a NaN row where the
    timestamps show a sample missing, and every function reads NaN rows as missing (each scale
    from the windows that hold none, as `--gaps windows`); "join" joins the samples end to
    end as if none were missing. data: "rate" (the default), "increment" (delta-angles,
    delta-velocities over one period, read as increment x rate) or "phase" (a phase or time
    error, an angle: read as its first differences x rate). decimate: keep one sample in
    K after decimate_filter, "average" (the mean of each K samples: N, K and B of the band kept
    are unchanged) or "none" (every K-th sample: the band above folds in). The Recording's
    `conditioning` says what was done (None when nothing), and its freq is the rate after it.
    Its `repeated_samples` lists the columns whose samples are held or interpolated (a
    RepeatedSamplesWarning each).

    Bad input raises gmwm.InputError with the command's one-line message, naming these
    keywords. A timing irregularity (gaps, samples out of order, a freq that disagrees with
    the stamps) is a TimingWarning."""
    values, meta_text = _gmwm.read(os.fspath(path), columns=columns, freq=freq, topic=topic or "", memory=memory,
                                   gaps=gaps, data=data, decimate=decimate, decimate_filter=decimate_filter)
    return _recording(values, meta_text)


def read_parts(path: str | os.PathLike[str], *, topic: str | Sequence[str] | None = None,
               columns: str | Sequence[str] | None = None, memory: float | None = None, gaps: str = "windows",
               data: str = "rate", decimate: int = 1, decimate_filter: str = "average") -> list[Recording]:
    """The parts of a recording, each read at its own rate (no resampling), as `gmwm
    wv|fit|select PATH [--topic A,B]` reads them: several topics of a log or bag (RealSense:
    topic=["/camera/gyro/sample", "/camera/accel/sample"], the gyroscope at 400 Hz and the
    accelerometer at 250 Hz; each Recording's `topic` set), or a table whose timestamp columns
    each stamp the columns to their right (gyro_timestamp,gyro_x,..,accel_timestamp,accel_x,..,
    a sensor's cells empty in the other's rows). A recording of one part gives a list of one.
    Each part takes the other keywords as gmwm.read does; columns are names kept from whichever
    part gives them (a part left with none is left out); no freq, since each part's rate is its
    stamps'. Refused (gmwm.InputError): a name no part gives, a name two parts give, an index."""
    topics = "" if topic is None else topic if isinstance(topic, str) else ",".join(topic)
    found = _gmwm.read_parts(os.fspath(path), columns=columns, topic=topics, memory=memory, gaps=gaps, data=data,
                             decimate=decimate, decimate_filter=decimate_filter)
    return [_recording(values, meta_text) for values, meta_text in found]


def _recording(values: FloatArray, meta_text: str) -> Recording:
    """A Recording of what _gmwm.read gives, its warnings said (as the command's are)."""
    from ._types import RepeatedSamples, Timing

    meta = json.loads(meta_text)
    values.flags.writeable = False
    timing = Timing.from_dict(meta["timing"])
    if timing is not None and timing.irregular:
        warnings.warn(f"{meta['path']}: {timing.summary}", TimingWarning, stacklevel=3)
    for note in meta["notes"]:  # what reading left out, as the command's warnings say it
        warnings.warn(f"{meta['path']}: {note}", UserWarning, stacklevel=3)
    repeated = tuple(r for r in (RepeatedSamples.from_dict(d) for d in meta["repeated_samples"]) if r is not None)
    for r in repeated:
        warnings.warn(f"{meta['path']}: {r.summary}", RepeatedSamplesWarning, stacklevel=3)
    return Recording(meta["path"], tuple(meta["names"]), tuple(meta["units"]), float(meta["freq"]), values, timing,
                     meta["topic"], meta["preset"], meta["conditioning"] or None, repeated)


def _index_timing(data: Any, freq: float | None, what: str) -> tuple[Timing | None, list[tuple[int, int]]]:
    """The timing of a pandas object's DatetimeIndex or TimedeltaIndex (None for any other
    index), measured and refused as a file's timestamp column, and the runs (start, length)
    of samples its gaps leave out, taken as gmwm.read takes a file's (none when freq is given)."""
    index: Any = getattr(data, "index", None)
    if getattr(getattr(index, "dtype", None), "kind", None) not in ("M", "m") or not hasattr(index, "asi8"):
        return None, []
    from ._types import Timing

    stamps = np.asarray(index.asi8, dtype=np.int64)
    if np.any(stamps == np.iinfo(np.int64).min):
        raise InputError(f"{what}.index: found NaT among the timestamps, expected a time for every sample")
    column = str(index.name) if index.name is not None else "index"
    found = json.loads(_gmwm.stamps_timing(stamps, source=f"{what}.index", column=column, freq=freq))
    runs = [(int(start), int(length)) for start, length in found.pop("missing_runs")]
    timing = Timing.from_dict(found)
    if timing is not None and timing.irregular:
        warnings.warn(f"{what}.index: {timing.summary}", TimingWarning, stacklevel=4)
    return timing, runs


def _with_missing_rows(data: Any, runs: list[tuple[int, int]]) -> FloatArray:
    """The values of `data` on the grid of its stamps: a NaN row for each sample missing (read
    as missing by every function, as gmwm.read's Recording is)."""
    values = np.asarray(data, dtype=np.float64)
    one = values.ndim == 1
    rows = values.reshape(len(values), -1)
    n = len(rows) + sum(length for _, length in runs)
    grid = np.full((n, rows.shape[1]), np.nan)
    observed = np.ones(n, dtype=bool)
    for start, length in runs:
        observed[start:start + length] = False
    grid[observed] = rows
    return grid[:, 0] if one else grid


def _column_labels(data: Any) -> list[str] | None:
    """A DataFrame's column labels as text (as the module names its columns), else None."""
    columns = getattr(data, "columns", None)
    return [str(c) for c in columns] if columns is not None and hasattr(data, "iloc") else None


def _rate_and_grid(data: Any, freq: float | None, what: str) -> tuple[float | None, Any]:
    """The rate a signal argument carries (the given freq, a Recording's, a time index's) and
    its values: a time index with gaps gives NaN rows where its stamps show samples missing."""
    if isinstance(data, Recording):
        return (data.freq if freq is None else freq), data
    timing, runs = _index_timing(data, freq, what)
    if runs:
        data = _with_missing_rows(data, runs)
    if freq is None and timing is not None:
        return timing.estimated_freq, data
    return freq, data


def _label_of(data: Any) -> str | None:
    """The name a one-series argument carries: a Recording's or one-column DataFrame's
    column, a Series' name."""
    if isinstance(data, Recording):
        return data.names[0] if len(data.names) == 1 else None
    columns = getattr(data, "columns", None)
    if columns is not None and hasattr(data, "iloc"):
        return str(columns[0]) if len(columns) == 1 else None
    name = getattr(data, "name", None)
    if hasattr(data, "iloc") and isinstance(name, str) and name:
        return name
    return None


def one_series(arguments: dict[str, Any]) -> None:
    """wv, allan, fit: `data` one series; its rate and its name taken from it when not given."""
    data = arguments["data"]
    if "name" not in arguments and (label := _label_of(data)) is not None:
        arguments["name"] = label
    arguments["freq"], data = _rate_and_grid(data, arguments.get("freq"), "data")
    arguments["data"] = data
    if isinstance(data, Recording):
        if len(data.names) != 1:
            raise InputError(f"data: found a recording of {len(data.names)} columns, expected one series (e.g. "
                             f"data['{data.names[0]}']); select, gap and the joint functions take every column "
                             "of a recording")
        arguments["data"] = data.values[:, 0]


def columns(arguments: dict[str, Any]) -> None:
    """select, gap: `data` the columns; their rate and names taken from a Recording."""
    given = arguments["data"]
    if isinstance(given, Recording):
        arguments.setdefault("names", list(given.names))
    arguments["freq"], data = _rate_and_grid(given, arguments.get("freq"), "data")
    if data is not given and (labels := _column_labels(given)) is not None:
        arguments.setdefault("names", labels)  # the frame's labels, kept on its grid's array
    arguments["data"] = data
    if isinstance(data, Recording):
        arguments["data"] = data.values


def replicates(arguments: dict[str, Any]) -> None:
    """fit_joint, select_joint: each replicate's columns; the rate taken from them when not
    given, and every replicate's rate the same."""
    items = list(arguments["replicates"])
    given = arguments.get("freq")
    graded = [_rate_and_grid(item, given, f"replicates[{k}]") for k, item in enumerate(items)]
    rates = [rate for rate, _ in graded]
    known = [(k, r) for k, r in enumerate(rates) if r is not None]
    if given is None and known:
        first_k, first = known[0]
        for k, r in known[1:]:
            if not math.isclose(r, first, rel_tol=0.01):
                raise InputError(f"replicates[{k}]: sampled at {g(r)} Hz, replicates[{first_k}] at {g(first)} Hz, "
                                 "expected one rate (give freq to take every replicate at it)")
        arguments["freq"] = first
    if items and isinstance(items[0], Recording):
        arguments.setdefault("names", list(items[0].names))
    if graded and graded[0][1] is not items[0] and (labels := _column_labels(items[0])) is not None:
        arguments.setdefault("names", labels)
    arguments["replicates"] = [item.values if isinstance(item, Recording) else item for _, item in graded]
