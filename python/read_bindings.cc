// gmwm.read and the timing of a pandas index: the Python face of the readers every face
// shares (io::ReadRequest, io::timing_of_stamps). A recording is handed over as a 2-D
// float64 array and a JSON text of what the file said about it (names, units, rate, timing).
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "gmwm/engine/error.h"
#include "gmwm/io/option_wording.h"
#include "gmwm/io/read_request.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/io/stamp_timing.h"
#include "gmwm/report/json_output.h"
#include "module_support.h"

namespace gmwm::python {
namespace {

// The timing JSON of the documents (report::timing_json) with its one-line summary.
Json timing_with_summary(const gmwm::io::TimingReport& t) {
  Json j = gmwm::report::timing_json(t);
  j["summary"] = gmwm::io::option_wording(t.summary(), gmwm::io::Face::kPython);
  j["rate_change"] = t.rate_change ? Json(t.rate_change_text()) : Json(nullptr);
  return j;
}

// --columns as Python gives it: None (every signal column), "a,b" (as the CLI's text) or a
// list of names and 1-based indices.
std::vector<std::string> columns_argument(const py::object& columns) {
  if (columns.is_none()) return {};
  if (py::isinstance<py::str>(columns)) return gmwm::io::column_list(columns.cast<std::string>());
  if (!py::isinstance<py::sequence>(columns))
    throw gmwm::InputError("--columns: expected a list of names or 1-based indices, or one text 'a,b,c'");
  std::vector<std::string> out;
  for (const auto& item : py::cast<py::sequence>(columns)) {
    if (py::isinstance<py::int_>(item) && !py::isinstance<py::bool_>(item))
      out.push_back(std::to_string(item.cast<long long>()));
    else if (py::isinstance<py::str>(item))
      out.push_back(item.cast<std::string>());
    else
      throw gmwm::InputError("--columns: found " + std::string(py::str(py::type::of(item).attr("__name__"))) +
                             ", expected column names or 1-based indices");
  }
  if (out.empty()) throw gmwm::InputError("--columns: found an empty list, expected names or 1-based indices");
  return out;
}

// decimate as Python gives it: any whole number (a numpy integer, 2**40) is checked against
// 1..kMaxDecimation with its own digits in the message; anything else is refused the same way
// (not pybind's TypeError for an int that does not fit).
int decimate_argument(const py::object& value) {
  const std::string expected = ", expected a whole number from 1 to " + std::to_string(gmwm::io::kMaxDecimation);
  if (PyBool_Check(value.ptr()) || PyIndex_Check(value.ptr()) == 0)
    throw gmwm::InputError("--decimate: found " + py::repr(value).cast<std::string>() + expected);
  const auto whole = py::reinterpret_steal<py::object>(PyNumber_Index(value.ptr()));
  if (!whole) throw py::error_already_set();
  int overflow = 0;
  const long long k = PyLong_AsLongLongAndOverflow(whole.ptr(), &overflow);
  if (overflow != 0 || k < 1 || k > gmwm::io::kMaxDecimation)
    throw gmwm::InputError("--decimate: found " + py::str(whole).cast<std::string>() + expected);
  return static_cast<int>(k);
}

gmwm::io::ReadRequest read_request_of(const std::string& path, const py::object& columns, std::optional<double> freq,
                                      const std::string& topic, std::optional<double> memory, const std::string& gaps,
                                      const std::string& data, const py::object& decimate,
                                      const std::string& decimate_filter) {
  gmwm::io::ReadRequest request;
  request.path = path;
  request.columns = columns_argument(columns);
  request.freq = freq;
  request.topic = topic;
  request.memory_mb = memory;
  request.spill = false;  // the values are handed over in memory, as one array
  request.gaps = gmwm::io::gap_handling_of(gaps);
  request.data = gmwm::io::data_kind_of(data);
  request.decimate = decimate_argument(decimate);
  request.decimate_filter = gmwm::io::decimation_filter_of(decimate_filter);
  return request;
}

using Record = std::tuple<py::array_t<double>, std::string>;

Record record_of(const gmwm::io::SignalSet& set, const std::string& path, std::optional<double> freq,
                 const std::string& topic, std::optional<double> memory);

Record py_read(const std::string& path, const py::object& columns, std::optional<double> freq, const std::string& topic,
               std::optional<double> memory, const std::string& gaps, const std::string& data,
               const py::object& decimate, const std::string& decimate_filter) {
  const gmwm::io::ReadRequest request =
      read_request_of(path, columns, freq, topic, memory, gaps, data, decimate, decimate_filter);
  gmwm::io::SignalSet set;
  {
    py::gil_scoped_release release;
    set = gmwm::io::read_request(request);
  }
  return record_of(set, path, freq, topic, memory);
}

std::vector<Record> py_read_parts(const std::string& path, const py::object& columns, const std::string& topic,
                                  std::optional<double> memory, const std::string& gaps, const std::string& data,
                                  const py::object& decimate, const std::string& decimate_filter) {
  const gmwm::io::ReadRequest request =
      read_request_of(path, columns, std::nullopt, topic, memory, gaps, data, decimate, decimate_filter);
  std::vector<gmwm::io::RecordPart> parts;
  {
    py::gil_scoped_release release;
    parts = gmwm::io::read_request_parts(request);
  }
  std::vector<Record> out;
  for (const gmwm::io::RecordPart& p : parts) out.push_back(record_of(p.set, path, std::nullopt, p.topic, memory));
  return out;
}

// The samples of a set read (gmwm.read, a part of gmwm.read_parts) and the JSON of the rest.
Record record_of(const gmwm::io::SignalSet& set, const std::string& path, std::optional<double> freq,
                 const std::string& topic, std::optional<double> memory) {
  // The samples on their grid, a NaN row where the stamps show one missing (the pandas idiom;
  // every function taking the values reads NaN rows as missing: io::take_nan_rows_as_missing).
  const std::size_t k = set.signals.size();
  const std::size_t observed = k ? set.signals.front().values.size() : 0;
  const std::size_t n = observed + static_cast<std::size_t>(set.missing_samples());
  if (!set.missing.empty()) {
    const double budget = memory ? *memory * 1e6 : gmwm::io::memory_budget_bytes();
    const double bytes = static_cast<double>(n) * static_cast<double>(k) * 8.0;
    if (budget > 0.0 && bytes > budget)
      throw gmwm::InputError(path + ": " +
                             gmwm::io::gaps_summary(set).substr(0, gmwm::io::gaps_summary(set).find(';')) +
                             ": their NaN rows would take " + std::to_string(static_cast<long long>(bytes / 1e6)) +
                             " MB, more than the memory; read with gaps=\"join\" to join the samples end to end");
  }
  py::array_t<double> values({n, k});
  double* dst = values.mutable_data();
  std::size_t row = 0, next = 0, run = 0;
  for (std::size_t g = 0; g < n; ++g) {
    const bool hole = run < set.missing.size() && static_cast<std::int64_t>(g) >= set.missing[run].start;
    for (std::size_t c = 0; c < k; ++c)
      dst[row * k + c] = hole ? std::numeric_limits<double>::quiet_NaN() : set.signals[c].values[next];
    ++row;
    if (!hole) ++next;
    if (hole && static_cast<std::int64_t>(g) + 1 == set.missing[run].start + set.missing[run].length) ++run;
  }
  Json meta;
  meta["path"] = set.path;
  Json names = Json::array(), units = Json::array();
  for (const gmwm::io::Signal& s : set.signals) {
    names.push_back(s.name);
    units.push_back(s.unit.empty() ? Json(nullptr) : Json(s.unit));
  }
  meta["names"] = std::move(names);
  meta["units"] = std::move(units);
  meta["freq"] = set.freq;
  meta["freq_given"] = freq.has_value();
  meta["topic"] = topic.empty() ? Json(nullptr) : Json(topic);
  meta["preset"] = set.preset.empty() ? Json(nullptr) : Json(set.preset);
  meta["delimiter"] = set.delimiter.empty() ? Json(nullptr) : Json(set.delimiter);
  meta["compressed"] = set.compressed;
  meta["conditioning"] = gmwm::io::conditioning_summary(set);
  meta["notes"] = set.notes;  // what reading left out (a topic's axes that are 0 throughout)
  Json repeated = Json::array();
  for (const gmwm::io::Signal& s : set.signals)
    if (s.repeated.detected()) repeated.push_back(gmwm::report::repeated_samples_json(s, set.freq, set.freq_known));
  meta["repeated_samples"] = std::move(repeated);
  if (set.timing) {
    meta["timing"] = timing_with_summary(*set.timing);
    const Json record = gmwm::report::record_timing_json(set);
    for (const char* key : {"missing_samples", "gap_handling", "gaps_read_as_missing"})
      meta["timing"][key] = record[key];
  } else {
    meta["timing"] = Json(nullptr);
  }
  return {values, to_python(meta)};
}

// The timing's JSON and "missing_runs": [[start, length], ...], the samples the stamps show
// missing as a file's gaps are taken (io::missing_runs_of; none when freq is given, which
// takes the samples as evenly spaced).
std::string py_stamps_timing(const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& stamps,
                             const std::string& source, const std::string& column, std::optional<double> freq) {
  if (stamps.ndim() != 1) throw gmwm::InputError(source + ": expected one timestamp a sample");
  const std::span<const std::int64_t> ns(stamps.data(), static_cast<std::size_t>(stamps.size()));
  gmwm::io::TimingReport t;
  std::vector<gmwm::MissingRun> runs;
  {
    py::gil_scoped_release release;
    t = gmwm::io::timing_of_stamps(ns, source, column, freq);
    if (!freq) runs = gmwm::io::missing_runs_of(t, source, gmwm::io::GapHandling::kCompleteWindows);
  }
  Json j = timing_with_summary(t);
  Json missing = Json::array();
  std::int64_t missing_samples = 0;
  for (const gmwm::MissingRun& r : runs) {
    missing.push_back({r.start, r.length});
    missing_samples += r.length;
  }
  j["missing_runs"] = std::move(missing);
  // As gmwm.read's timing says them (report::record_timing_json).
  j["missing_samples"] = missing_samples;
  j["gap_handling"] = freq ? Json(nullptr) : Json("windows");
  j["gaps_read_as_missing"] = !runs.empty();
  return to_python(j);
}

}  // namespace

void add_read_functions(py::module_& m) {
  m.def("read", &py_read, py::arg("path"), py::kw_only(), py::arg("columns") = py::none(), py::arg("freq") = py::none(),
        py::arg("topic") = "", py::arg("memory") = py::none(), py::arg("gaps") = "windows", py::arg("data") = "rate",
        py::arg("decimate") = 1, py::arg("decimate_filter") = "average",
        "The columns of a recording as the gmwm command reads them (delimited text, gzip, PX4 ULog, ROS 1 bag, "
        "rosbag2, MCAP): a samples x columns float64 array and the JSON text of names, units, rate and timing");
  m.def("read_parts", &py_read_parts, py::arg("path"), py::kw_only(), py::arg("columns") = py::none(), py::arg("topic"),
        py::arg("memory") = py::none(), py::arg("gaps") = "windows", py::arg("data") = "rate", py::arg("decimate") = 1,
        py::arg("decimate_filter") = "average",
        "The parts of a recording (the topics of topic 'A,B', or a table's stamp columns that each stamp their "
        "own), each read as gmwm.read reads one at its own rate: a list of (samples x columns array, JSON text) "
        "pairs");
  m.def("stamps_timing", &py_stamps_timing, py::arg("stamps"), py::kw_only(), py::arg("source"), py::arg("column"),
        py::arg("freq") = py::none(),
        "The sampling of integer-nanosecond timestamps (a pandas DatetimeIndex's asi8), measured and refused as a "
        "file's timestamp column: the JSON of the timing");
}

}  // namespace gmwm::python
