#pragma once
// What the Python module's bindings share (python/gmwm_module.cc, python/multi_signal_bindings.cc):
// the JSON text a result is built from, Ctrl-C during a study, and numpy arrays as signals.
#include <atomic>
#include <chrono>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "gmwm/engine/error.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/wavelet_variance.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/report/json_output.h"
#include "gmwm/robust/robust_wv.h"

namespace gmwm::python {

namespace py = pybind11;
using gmwm::report::Json;

// A JSON document as the text the CLI writes (report::dump_json: the same renderer, floats
// with 17 significant digits); the Python package builds its typed results from it and
// keeps it for to_json().
std::string to_python(const Json& j);

// How often the interpreter's main thread looks for a signal while the library computes
// (Ctrl-C): often enough that KeyboardInterrupt comes well within a second, rarely enough
// that taking the GIL costs nothing next to the work.
constexpr auto kSignalCheckInterval = std::chrono::milliseconds(50);

// A study that Ctrl-C can stop. Python runs its signal handlers only on the main thread
// and only when that thread calls PyErr_CheckSignals, while the library's progress
// callbacks come from TBB's worker threads. So the study runs on a thread of its own (the
// GIL released) and this thread, every kSignalCheckInterval, takes the GIL briefly and
// calls PyErr_CheckSignals. When a handler raises (KeyboardInterrupt), `cancel` is set; the
// progress callbacks the study was given (cancellation_point) then throw gmwm::Cancelled
// at their next call, which unwinds the study's parallel loops, and the handler's
// exception is raised here. `study(progress)` gets that progress callback to install.
template <class Study>
auto run_cancellable(Study&& study) -> decltype(study(std::function<void(int, int)>())) {
  using Result = decltype(study(std::function<void(int, int)>()));
  auto cancel = std::make_shared<std::atomic<bool>>(false);
  const std::function<void(int, int)> cancellation_point = [cancel](int, int) {
    if (cancel->load(std::memory_order_relaxed)) throw gmwm::Cancelled();
  };
  bool interrupted = false;
  std::future<Result> done;
  {
    py::gil_scoped_release release;
    done = std::async(std::launch::async, [&] { return study(cancellation_point); });
    while (done.wait_for(kSignalCheckInterval) != std::future_status::ready) {
      py::gil_scoped_acquire acquire;
      if (PyErr_CheckSignals() != 0) {
        // The handler's exception stays set on this thread while the study winds down.
        interrupted = true;
        cancel->store(true);
        break;
      }
    }
    done.wait();
  }
  if (interrupted) {
    try {
      done.get();  // gmwm::Cancelled, or a result that came first: either way, interrupted
    } catch (...) {
    }
    throw py::error_already_set();
  }
  return done.get();
}

// A 1-D float64 view of one series (copied when not contiguous float64).
std::vector<double> series_of(const py::handle& obj, const char* what);

// The library's check that a WV can be used (underflow, overflow), naming the column.
void check_wv_range(const std::string& name, const gmwm::WaveletVariance& wv, std::span<const double> x);

// Columns: a 1-D array (one column), a 2-D array (samples x columns, as a file's columns),
// a pandas DataFrame (its columns; `labels` receives their labels) or a sequence of 1-D arrays.
std::vector<std::vector<double>> columns_of(const py::handle& obj, std::vector<std::string>* labels = nullptr);

// The rate given with data (freq): refused when missing or outside the readers' range.
double given_rate(std::optional<double> freq);
/// first_level= as the CLI's --first-level: 'auto' or a whole number 1..62 (a Python int, a
/// numpy integer or its digits); InputError naming the argument otherwise.
int first_level_argument(const py::object& value);
gmwm::report::ColumnInfo info(const std::string& name, std::size_t n, std::optional<double> freq,
                              const std::string& unit);

// The columns' names: `names` when given, else the labels the data carried (`found`, a
// DataFrame's), else x1, x2, ...
std::vector<std::string> names_for(std::size_t k, const std::vector<std::string>& names,
                                   const std::vector<std::string>& found = {});

// The columns as the signal set a file would give ("<array>", the rate when known).
gmwm::io::SignalSet signal_set_of(std::vector<std::vector<double>> cols, const std::vector<std::string>& labels,
                                  std::optional<double> freq);

// The robust WV settings of `--robust [--eff E] [--estimator NAME] [--no-spike-screen]` with the
// WV's alpha and levels; nullopt when not robust (robust::robust_wv_options: every face's checks).
std::optional<gmwm::robust::RobustWvOptions> robust_options(bool robust, std::optional<double> eff,
                                                            const std::optional<std::string>& estimator, double alpha,
                                                            int levels, bool spike_screen);

gmwm::OmegaKind omega_kind(const std::string& s);

// The classical WV's settings of a study: alpha and levels (0: all), the levels refused as
// the CLI's --levels beyond what the set's samples give.
gmwm::WvOptions wv_levels(double alpha, int levels, const gmwm::io::SignalSet& set);

// The Kalman table's rate (--kf-rate): the given one, checked, else the data's rate.
double kalman_rate(std::optional<double> kf_rate, const gmwm::io::SignalSet& set);

/// The joint fit and selection over replicates, the export and the fleet: their m.def.
void add_multi_signal_functions(py::module_& m);
// gmwm.read and the timing of an index (read_bindings.cc).
void add_read_functions(py::module_& m);
// gmwm.stability (stability_bindings.cc).
void add_stability_functions(py::module_& m);
// gmwm.fit_curve (curve_bindings.cc).
void add_curve_functions(py::module_& m);
// The functions bound in their own files: each add_*_functions above, in that order.
void add_other_files_functions(py::module_& m);

}  // namespace gmwm::python
