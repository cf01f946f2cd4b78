// gmwm.stability: the frequency-stability study (pipeline::study_stability, as `gmwm
// stability`, hat=True its --hat) on arrays, a Recording or a DataFrame; the document gmwm
// stability --json writes (without "run").
#include <optional>
#include <string>
#include <vector>

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "gmwm/engine/error.h"
#include "gmwm/io/read_request.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/io/units.h"
#include "gmwm/pipeline/stability_study.h"
#include "gmwm/report/stability_output.h"
#include "module_support.h"

namespace gmwm::python {
namespace {

// --kind as Python gives it: "oadev,mdev" (the CLI's text) or a list of names.
std::vector<gmwm::stability::DeviationKind> kinds_argument(const py::object& kind) {
  std::vector<std::string> names;
  if (py::isinstance<py::str>(kind))
    names = gmwm::io::comma_list(kind.cast<std::string>());
  else
    for (const py::handle k : kind) names.push_back(py::str(k).cast<std::string>());
  std::vector<gmwm::stability::DeviationKind> out;
  for (const std::string& n : names) out.push_back(gmwm::stability::deviation_of(n));
  return out;
}

// --taus as Python gives it: a set's name, or averaging times in seconds.
void taus_argument(const py::object& taus, gmwm::pipeline::StabilityStudyOptions& o) {
  if (py::isinstance<py::str>(taus)) {
    const std::string name = taus.cast<std::string>();
    const auto set = gmwm::stability::tau_set_from_name(name);
    if (!set)
      throw gmwm::InputError("taus: found '" + name +
                             "', expected all, octave, decade or averaging times in seconds ([1, 10, 100])");
    o.taus = *set;
    return;
  }
  if (!py::isinstance<py::sequence>(taus) || py::len(taus) == 0)
    throw gmwm::InputError("taus: expected all, octave, decade or a non-empty list of averaging times in seconds");
  for (const py::handle t : taus)
    o.tau_list.push_back(py::float_(py::reinterpret_borrow<py::object>(t)).cast<double>());
}

std::string py_stability(const py::object& data, const py::object& kind, const py::object& taus,
                         std::optional<double> freq, const std::vector<std::string>& names, const std::string& units,
                         bool phase, double confidence, const std::string& intervals, std::optional<int> noise_alpha,
                         bool hat) {
  std::vector<std::string> found;
  std::vector<std::vector<double>> cols = columns_of(data, &found);
  const std::vector<std::string> labels = names_for(cols.size(), names, found);
  const gmwm::io::UnitsSpec spec = gmwm::io::parse_units_spec(units);
  std::vector<std::string> column_units;
  for (const std::string& label : labels) column_units.push_back(gmwm::io::unit_of_column(spec, label));
  gmwm::io::SignalSet set = signal_set_of(std::move(cols), labels, freq);
  if (phase) {
    gmwm::io::take_phase_as_rate(set, "data");
    gmwm::io::find_repeated_samples(set);  // of the rates the study reads, as the command finds them
  }
  gmwm::pipeline::StabilityStudyOptions o;
  o.kinds = kinds_argument(kind);
  taus_argument(taus, o);
  o.intervals.confidence = confidence;
  const auto method = gmwm::stability::interval_method_from_name(intervals);
  if (!method) throw gmwm::InputError("intervals: found '" + intervals + "', expected stable32 or exact");
  o.intervals.method = *method;
  o.intervals.noise_alpha = noise_alpha;
  o.three_cornered_hat = hat;
  if (const std::string why = o.Validate(); !why.empty()) throw gmwm::InputError(why);
  const Json out = run_cancellable([&](const std::function<void(int, int)>& cancellation_point) {
    o.progress = cancellation_point;  // after each factor: Ctrl-C stops a long study there
    return gmwm::report::stability_document(set, gmwm::pipeline::study_stability(set, o), o, column_units);
  });
  return to_python(out);
}

}  // namespace

void add_stability_functions(py::module_& m) {
  m.def("stability", &py_stability, py::arg("data"), py::kw_only(), py::arg("kind") = "oadev",
        py::arg("taus") = "octave", py::arg("freq") = py::none(), py::arg("names") = std::vector<std::string>{},
        py::arg("units") = "", py::arg("phase") = false, py::arg("confidence") = gmwm::stability::kStable32Confidence,
        py::arg("intervals") = "stable32", py::arg("noise_alpha") = py::none(), py::arg("hat") = false,
        "The frequency-stability deviations of each column (kind: 'adev', 'oadev', 'mdev', 'tdev', 'hdev', "
        "'ohdev', 'totdev', 'mtotdev', 'ttotdev', 'htotdev', 'theo1', 'mtie', 'tierms', a comma list or a list; taus: "
        "'octave', 'decade', 'all' or averaging times in "
        "seconds), the columns read as rates or fractional frequency (phase=True: as phase or time error), each "
        "with its chi-square interval at `confidence` (Stable32's one sigma by default; intervals: 'stable32' "
        "or 'exact' quantiles; noise_alpha: one noise exponent for every tau instead of identifying it); hat=True: "
        "the three-cornered hat of three columns recorded together, each column's own deviation separated from "
        "what the three share (its 'hat'): the document gmwm stability --json writes");
}

}  // namespace gmwm::python
