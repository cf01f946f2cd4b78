// The Python module's shared helpers (module_support.h).
#include "module_support.h"

#include <cstdint>

#include "gmwm/engine/check.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/pipeline/first_level.h"
#include "gmwm/report/json_output.h"
#include "gmwm/robust/robust_request.h"
#include "gmwm/robust/robust_wv.h"
#include "gmwm/robust/tuning.h"
#include "gmwm/engine/choice.h"

namespace gmwm::python {

std::string to_python(const Json& j) { return gmwm::report::dump_json(j); }

namespace {

// A pandas DataFrame (duck-typed: pandas is not a dependency of the module).
bool is_data_frame(const py::handle& obj) {
  return !py::isinstance<py::array>(obj) && py::hasattr(obj, "columns") && py::hasattr(obj, "iloc") &&
         py::hasattr(obj, "to_numpy");
}

// A DataFrame's column labels as text (str() of each: pandas allows any hashable).
std::vector<std::string> frame_labels(const py::handle& frame) {
  std::vector<std::string> out;
  for (const auto& label : frame.attr("columns")) out.push_back(py::str(label).cast<std::string>());
  return out;
}

}  // namespace

// A 1-D float64 view of one series (copied when not contiguous float64).
std::vector<double> series_of(const py::handle& obj, const char* what) {
  if (is_data_frame(obj)) {
    // One series: a DataFrame of one column is that column; of more, the message says which
    // functions take them all (a 2-D array said "2 dimensions", a DataFrame gave KeyError: 0).
    const std::vector<std::string> labels = frame_labels(obj);
    if (labels.size() == 1)
      return series_of(obj.attr("iloc")[py::make_tuple(py::slice(py::none(), py::none(), py::none()), 0)], what);
    throw gmwm::InputError(std::string(what) + ": found a DataFrame of " + std::to_string(labels.size()) +
                           " columns, expected one series (e.g. data['" + (labels.empty() ? "x" : labels.front()) +
                           "']); select, gap and the joint functions take every column of a DataFrame");
  }
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(obj);
  if (!a) {
    PyErr_Clear();  // ensure() leaves the conversion's error set
    throw gmwm::InputError(std::string(what) + ": expected a 1-D array of numbers");
  }
  if (a.ndim() != 1)
    throw gmwm::InputError(std::string(what) + ": expected a 1-D array, got " + std::to_string(a.ndim()) +
                           " dimensions");
  if (a.size() < gmwm::io::kMinSamples)
    throw gmwm::InputError(std::string(what) + ": found " + std::to_string(a.size()) + " samples, expected at least " +
                           std::to_string(gmwm::io::kMinSamples) +
                           " (the wavelet variance needs 4 levels, 2^4 samples)");
  std::vector<double> x(a.data(), a.data() + a.size());
  // NaN marks a missing sample (io::take_nan_rows_as_missing); an infinity is refused.
  for (std::size_t i = 0; i < x.size(); ++i)
    if (std::isinf(x[i]))
      throw gmwm::InputError(std::string(what) + ": sample " + std::to_string(i) +
                             " is not a finite number (NaN marks a missing sample; an infinity is refused)");
  // As the CLI's reader: a constant has a wavelet variance of zero, nothing to fit.
  const auto first = std::find_if(x.begin(), x.end(), [](double v) { return !std::isnan(v); });
  if (first != x.end() && std::all_of(first, x.end(), [&](double v) { return std::isnan(v) || v == *first; })) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", *first);
    throw gmwm::InputError(std::string(what) + ": found all " + std::to_string(x.size()) + " values equal to " + buf +
                           ", expected a varying signal (a constant has a wavelet variance of zero)");
  }
  return x;
}

// The library's check that a WV can be used (underflow, overflow), naming the column.
void check_wv_range(const std::string& name, const gmwm::WaveletVariance& wv, std::span<const double> x) {
  if (const std::string why = gmwm::wv_range_problem(wv, x, false); !why.empty())
    throw gmwm::InputError("column '" + name + "': " + why);
}

// Columns: a 1-D array (one column), a 2-D array (samples x columns, as a file's columns)
// or a sequence of 1-D arrays.
std::vector<std::vector<double>> columns_of(const py::handle& obj, std::vector<std::string>* labels) {
  if (is_data_frame(obj)) {
    // A DataFrame: its columns, named by their labels (as a file's header names them).
    const std::vector<std::string> found = frame_labels(obj);
    if (found.empty()) throw gmwm::InputError("data: found a DataFrame with no column, expected samples x columns");
    std::vector<std::vector<double>> out;
    for (std::size_t c = 0; c < found.size(); ++c)
      out.push_back(series_of(obj.attr("iloc")[py::make_tuple(py::slice(py::none(), py::none(), py::none()), c)],
                              ("column '" + found[c] + "'").c_str()));
    if (labels) *labels = found;
    return out;
  }
  if (py::isinstance<py::array>(obj) && py::cast<py::array>(obj).ndim() == 2) {
    auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(obj);
    if (!a) {
      PyErr_Clear();
      throw gmwm::InputError("data: expected a 2-D array of numbers (samples x columns)");
    }
    if (a.shape(1) == 0) throw gmwm::InputError("data: found no column, expected samples x columns");
    std::vector<std::vector<double>> out(static_cast<std::size_t>(a.shape(1)));
    for (py::ssize_t c = 0; c < a.shape(1); ++c) {
      py::object col = py::reinterpret_steal<py::object>(
          PyObject_GetItem(a.ptr(), py::make_tuple(py::slice(py::none(), py::none(), py::none()), c).ptr()));
      out[static_cast<std::size_t>(c)] = series_of(col, ("column " + std::to_string(c + 1)).c_str());
    }
    return out;
  }
  if (py::isinstance<py::array>(obj)) return {series_of(obj, "data")};
  if (!py::isinstance<py::sequence>(obj) || py::isinstance<py::str>(obj))
    throw gmwm::InputError("data: expected an array (samples, or samples x columns) or a list of 1-D arrays");
  std::vector<std::vector<double>> out;
  std::size_t k = 0;
  for (const auto& item : py::cast<py::sequence>(obj))
    out.push_back(series_of(item, ("column " + std::to_string(++k)).c_str()));
  if (out.empty()) throw gmwm::InputError("data: found no column, expected samples x columns");
  return out;
}

double given_rate(std::optional<double> freq) {
  // As the command line refuses a file without a timestamp column and no --freq: an array
  // carries no timing, and a result without a rate had no figure in seconds (issue 45: the
  // Python module took a missing freq silently).
  if (!freq)
    throw gmwm::InputError(gmwm::io::missing_rate_problem(
        "data", "an array carries no timestamps (a Recording, or a pandas time index, carries its rate)"));
  if (const std::string why = gmwm::io::sampling_rate_problem(*freq, "freq"); !why.empty()) throw gmwm::InputError(why);
  return *freq;
}

gmwm::report::ColumnInfo info(const std::string& name, std::size_t n, std::optional<double> freq,
                              const std::string& unit) {
  return {name, static_cast<std::int64_t>(n), given_rate(freq), true, unit};
}

std::vector<std::string> names_for(std::size_t k, const std::vector<std::string>& names,
                                   const std::vector<std::string>& found) {
  if (names.empty() && found.size() == k) return found;
  if (names.empty()) {
    std::vector<std::string> out;
    for (std::size_t i = 0; i < k; ++i) out.push_back("x" + std::to_string(i + 1));
    return out;
  }
  if (names.size() != k)
    throw gmwm::InputError("names: " + std::to_string(names.size()) + " names for " + std::to_string(k) + " columns");
  return names;
}

// The columns as the signal set a file would give ("<array>", the rate when known).
gmwm::io::SignalSet signal_set_of(std::vector<std::vector<double>> cols, const std::vector<std::string>& labels,
                                  std::optional<double> freq) {
  const gmwm::report::ColumnInfo first = info(labels.front(), cols.front().size(), freq, "");
  gmwm::io::SignalSet set;
  set.path = "<array>";
  set.freq = first.freq;
  set.freq_known = first.freq_known;
  for (std::size_t k = 0; k < cols.size(); ++k) set.signals.push_back({labels[k], std::move(cols[k]), ""});
  gmwm::io::take_nan_rows_as_missing(set, "data");
  gmwm::io::find_repeated_samples(set);  // as reading a file does: the documents say it
  // and so does a warning, as gmwm.read's (the array's columns are named by `labels`).
  for (const std::string& note : gmwm::io::repeated_samples_notes(set))
    py::module_::import("warnings")
        .attr("warn")("data: " + note, py::module_::import("gmwm._signals").attr("RepeatedSamplesWarning"), 3);
  return set;
}

// The robust WV settings of `--robust [--eff E] [--estimator NAME]`; nullopt when not robust
// (robust::robust_wv_options: the checks and messages of every face).
std::optional<gmwm::robust::RobustWvOptions> robust_options(bool robust, std::optional<double> eff,
                                                            const std::optional<std::string>& estimator, double alpha,
                                                            int levels, bool spike_screen) {
  gmwm::WvOptions wv;
  wv.alpha = alpha;
  wv.levels = levels;
  return gmwm::robust::robust_wv_options({robust, eff, estimator, !spike_screen}, wv);
}

gmwm::WvOptions wv_levels(double alpha, int levels, const gmwm::io::SignalSet& set) {
  gmwm::WvOptions o;
  o.alpha = alpha;
  o.levels = levels;
  if (const std::string why = o.Validate(); !why.empty()) throw gmwm::InputError(why);
  const auto n = set.signals.empty() ? std::int64_t{0} : static_cast<std::int64_t>(set.signals.front().values.size());
  if (const std::string why = gmwm::io::levels_problem(levels, n, "--levels"); !why.empty())
    throw gmwm::InputError(why);
  return o;
}

double kalman_rate(std::optional<double> kf_rate, const gmwm::io::SignalSet& set) {
  if (!kf_rate) return set.freq_known ? set.freq : 0.0;
  if (const std::string why = gmwm::io::sampling_rate_problem(*kf_rate, "--kf-rate"); !why.empty())
    throw gmwm::InputError(why);
  return *kf_rate;
}

gmwm::OmegaKind omega_kind(const std::string& s) {
  if (const auto k = gmwm::parse_omega_kind(s)) return *k;
  throw gmwm::InputError("--omega: " + gmwm::unknown_choice(s, gmwm::omega_kind_names()));
}

int first_level_argument(const py::object& value) {
  std::string text;
  if (py::isinstance<py::str>(value))
    text = value.cast<std::string>();
  else if (!py::isinstance<py::bool_>(value) && py::hasattr(value, "__index__"))  // int, numpy integer
    text = py::str(py::module_::import("operator").attr("index")(value)).cast<std::string>();
  const std::optional<int> level = text.empty() ? std::nullopt : gmwm::pipeline::parse_first_level(text);
  if (!level)
    throw gmwm::InputError("first_level: found " + py::repr(value).cast<std::string>() + ", expected " +
                           gmwm::pipeline::kFirstLevelExpected);
  return *level;
}

void add_other_files_functions(py::module_& m) {
  add_multi_signal_functions(m);
  add_read_functions(m);
  add_stability_functions(m);
  add_curve_functions(m);
}

}  // namespace gmwm::python
