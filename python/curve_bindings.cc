// gmwm.fit_curve: the curve fit study (pipeline::study_curve_fit, as `gmwm fit --curve`) on a
// curve file or on named columns (a dict or a DataFrame's); the fit column gmwm fit --curve
// --json writes for it.
#include <optional>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "gmwm/engine/choice.h"
#include "gmwm/engine/curve.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/number_text.h"
#include "gmwm/io/curve_reader.h"
#include "gmwm/engine/random.h"
#include "gmwm/io/units.h"
#include "gmwm/pipeline/curve_study.h"
#include "gmwm/report/curve_output.h"
#include "module_support.h"

namespace gmwm::python {
namespace {

// One named column of numbers as the reader takes it (any length; the curve's checks follow).
std::vector<double> numbers_of(const py::handle& obj, const std::string& name) {
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(obj);
  if (!a) {
    PyErr_Clear();  // ensure() leaves the conversion's error set
    throw gmwm::InputError("curve: " + name + ": expected a 1-D sequence of numbers");
  }
  if (a.ndim() != 1)
    throw gmwm::InputError("curve: " + name + ": expected a 1-D sequence, got " + std::to_string(a.ndim()) +
                           " dimensions");
  return {a.data(), a.data() + a.size()};
}

// The curve to fit: a file's (its one curve, or the one `column` names) or a mapping's.
gmwm::GivenCurve curve_argument(const py::object& curve, const std::optional<std::string>& column,
                                const gmwm::io::CurveReadOptions& read) {
  if (py::isinstance<py::str>(curve)) {
    gmwm::io::CurveReadOptions o = read;
    if (column) o.columns = {*column};
    const std::vector<gmwm::GivenCurve> curves = gmwm::io::read_curves(curve.cast<std::string>(), o);
    if (curves.size() == 1) return curves.front();
    std::string names;
    for (const auto& c : curves) names += (names.empty() ? "" : ", ") + c.name;
    throw gmwm::InputError(curve.cast<std::string>() + ": found " + std::to_string(curves.size()) + " curves (" +
                           names + "), expected column= to pick one");
  }
  if (!py::isinstance<py::dict>(curve))
    throw gmwm::InputError(
        "curve: expected a curve file's path or named columns (a dict or DataFrame of tau and the values)");
  std::vector<std::string> names;
  std::vector<std::vector<double>> columns;
  for (const auto& [key, value] : curve.cast<py::dict>()) {
    names.push_back(py::str(key).cast<std::string>());
    columns.push_back(numbers_of(value, names.back()));
  }
  gmwm::GivenCurve c = gmwm::io::curve_from_columns(names, columns, "curve", read);
  if (column) c.name = *column;
  return c;
}

std::string py_fit_curve(const py::object& curve, const std::string& model_spec,
                         const std::optional<std::string>& value, std::optional<double> freq,
                         const std::string& exclude_taus, const std::string& omega, double alpha, double confidence,
                         std::optional<double> record, const std::string& units, std::optional<double> kf_rate,
                         int max_evaluations, std::uint64_t seed, const std::optional<std::string>& column) {
  gmwm::io::CurveReadOptions read;
  if (value) {
    read.quantity = gmwm::parse_curve_quantity(*value);
    if (!read.quantity)
      throw gmwm::InputError("--value: " + gmwm::unknown_choice(*value, gmwm::curve_quantity_names()));
  }
  gmwm::pipeline::CurveFitStudyOptions o;
  o.model = model_spec;
  if (freq) o.freq = given_rate(freq);
  if (!exclude_taus.empty()) o.exclude = gmwm::pipeline::parse_tau_ranges(exclude_taus);
  o.fit.omega = omega_kind(omega);
  o.fit.confidence = confidence;
  if (record && !(*record > 0.0))
    throw gmwm::InputError("--record: found " + gmwm::significant(*record, 6) +
                           ", expected a record length in seconds above 0");
  o.fit.record_seconds = record.value_or(0.0);
  o.fit.fit.alpha = alpha;
  o.fit.fit.max_evaluations = max_evaluations;
  o.fit.fit.seed = seed;
  if (const std::string why = o.Validate(); !why.empty()) throw gmwm::InputError(why);
  const gmwm::GivenCurve c = curve_argument(curve, column, read);
  const std::string unit = gmwm::io::unit_of_column(gmwm::io::parse_units_spec(units), c.name);
  if (kf_rate) given_rate(kf_rate);
  const Json out = run_cancellable([&](const std::function<void(int, int)>&) {
    const gmwm::pipeline::CurveFitStudy study = gmwm::pipeline::study_curve_fit({c}, o);
    return gmwm::report::curve_fit_column_json(study, 0, unit, kf_rate.value_or(0.0));
  });
  return to_python(out);
}

}  // namespace

void add_curve_functions(py::module_& m) {
  m.def("fit_curve", &py_fit_curve, py::arg("curve"), py::arg("model"), py::kw_only(), py::arg("value") = py::none(),
        py::arg("freq") = py::none(), py::arg("exclude_taus") = "", py::arg("omega") = "model", py::arg("alpha") = 0.05,
        py::arg("confidence") = 0.95, py::arg("record") = py::none(), py::arg("units") = "",
        py::arg("kf_rate") = py::none(), py::arg("max_evaluations") = gmwm::FitOptions{}.max_evaluations,
        py::arg("seed") = gmwm::kDefaultSeed, py::arg("column") = py::none(),
        "GMWM fit of a model to a given Allan deviation, Allan variance or wavelet variance curve (a file's path, "
        "or columns by name: tau in seconds, adev/avar/wv or value, optionally ci_low and ci_high or edf), as gmwm "
        "fit --curve: the 'fit' JSON column with its 'curve' (value as --value, freq the rate of the data behind "
        "the curve, exclude_taus as --exclude-taus, record as --record, confidence as --curve-confidence)");
}

}  // namespace gmwm::python
