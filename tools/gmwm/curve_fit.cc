// gmwm fit --curve: the curve fit study through the command line (curve_fit.h).
#include "curve_fit.h"

#include <iostream>

#include "gmwm/engine/choice.h"
#include "gmwm/engine/curve.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/fit.h"
#include "gmwm/io/curve_reader.h"
#include "gmwm/io/read_request.h"
#include "gmwm/pipeline/curve_study.h"
#include "gmwm/report/curve_output.h"

namespace gmwm::cli {
namespace {

// `gmwm fit`'s options that read or treat a record: none applies to a curve.
constexpr const char* kRecordOptions[] = {"INPUT",    "--topic",       "--levels",     "--memory",
                                          "--gaps",   "--data",        "--decimate",   "--decimate-filter",
                                          "--robust", "--eff",         "--estimator",  "--no-spike-screen",
                                          "--joint",  "--first-level", "--replicates", "--report"};

void refuse_record_options(const CLI::App& sub) {
  for (const char* name : kRecordOptions) {
    const CLI::Option* o = sub.get_option_no_throw(name);
    if (o && o->count() > 0)
      throw InputError(std::string(name) + " with --curve: " +
                       (std::string(name) == "--report" ? "a curve fit writes no HTML report yet"
                                                        : "a curve has no record to read (give one or the other)"));
  }
}

pipeline::CurveFitStudyOptions study_options(const CurveArgs& a, const CurveFitSettings& s,
                                             const CommonOptions& common) {
  pipeline::CurveFitStudyOptions o;
  o.model = s.model;
  o.freq = s.freq;
  if (!a.exclude_taus.empty()) o.exclude = pipeline::parse_tau_ranges(a.exclude_taus);
  o.fit.record_seconds = a.record.value_or(0.0);
  o.fit.confidence = a.confidence;
  o.fit.omega = parse_omega_kind(s.omega).value_or(OmegaKind::kModel);
  o.fit.fit.alpha = s.alpha;
  o.fit.fit.max_evaluations = s.max_evaluations;
  o.fit.fit.seed = common.seed;
  if (const std::string why = o.Validate(); !why.empty()) throw InputError(why);
  return o;
}

// Warns about each curve weighed by the shortest record, and each fit that did not converge
// or failed; the number of usable fits.
int warn_about_curves(const pipeline::CurveFitStudy& study) {
  int usable = 0;
  for (const pipeline::CurveFitColumn& c : study.columns) {
    const std::string head = c.curve.source + ": curve '" + c.curve.name + "': ";
    if (c.weights == CurveWeights::kShortestRecord)
      warn(head +
           "no interval, edf or record length: weighed as the shortest record reaching its longest tau, "
           "whose intervals bound a longer record's (--record SECONDS gives the record's own)");
    if (c.fit.status == FitStatus::kNotConverged) warn(head + "the fit did not converge: " + c.fit.message);
    if (c.fit.status == FitStatus::kFailed) warn(head + "the fit failed: " + c.fit.message);
    usable += c.fit.status != FitStatus::kFailed;
  }
  return usable;
}

}  // namespace

void add_curve_options(CLI::App& sub, CurveArgs& args) {
  sub.add_option("--curve", args.curve,
                 "Fit a given Allan deviation, Allan variance or wavelet variance curve instead of INPUT: delimited "
                 "text with a header naming tau (s) and the values, optionally ci_low, ci_high or edf "
                 "(docs/curve-fit.md); --freq is the rate of the data behind it")
      ->type_name("FILE");
  sub.add_option("--value", args.value,
                 "What the curve's values are: adev (squared to the Allan variance), avar or wv (default: from the "
                 "value column's name)")
      ->check(choice_of(curve_quantity_names()))
      ->type_name("adev|avar|wv");
  sub.add_option("--exclude-taus", args.exclude_taus,
                 "Taus of the curve (s) left out of the fit: ranges A:B, an end left empty open (':0.05,100:')")
      ->type_name("RANGES")
      ->check(CLI::Validator(
          [](const std::string& text) -> std::string {
            const std::string option = "--exclude-taus: ";  // CLI11 names the option itself
            try {
              pipeline::parse_tau_ranges(text, "--exclude-taus");
              return "";
            } catch (const InputError& e) {
              const std::string m = e.what();
              return m.rfind(option, 0) == 0 ? m.substr(option.size()) : m;
            }
          },
          "RANGES"));
  sub.add_option_function<double>(
         "--record", [&args](const double& s) { args.record = s; },
         "Length of the record behind a curve without intervals or edf, in seconds: each point's degrees of "
         "freedom (default: the shortest record reaching its longest tau)")
      ->type_name("SECONDS")
      ->transform(decimal_number([](double s) { return s > 0.0; }, "a record length in seconds above 0"));
  sub.add_option("--curve-confidence", args.confidence,
                 "Level of the curve's ci_low/ci_high intervals (0.683 for +-1 sigma error bars)")
      ->type_name("C")
      ->transform(decimal_number([](double c) { return c > 0.0 && c < 1.0; },
                                 "a confidence level strictly between 0 and 1 (0.683 for +-1 sigma bars)"))
      ->capture_default_str();
}

int run_curve_fit(const CLI::App& sub, const CurveArgs& args, const CurveFitSettings& settings,
                  const CommonOptions& common) {
  Stopwatch total;
  refuse_record_options(sub);
  declare_input(common, args.curve);
  declare_output(common, "--json", common.json);
  const pipeline::CurveFitStudyOptions options = study_options(args, settings, common);
  io::CurveReadOptions read;
  if (!args.value.empty()) read.quantity = parse_curve_quantity(args.value);
  if (settings.columns) read.columns = io::comma_list(*settings.columns);
  Stopwatch read_clock;
  const std::vector<GivenCurve> curves = io::read_curves(args.curve, read);
  const double read_seconds = read_clock.seconds();
  std::vector<std::string> units;
  for (const GivenCurve& c : curves) units.push_back(column_unit(settings.units, c.name));
  auto study = std::make_shared<const pipeline::CurveFitStudy>(pipeline::study_curve_fit(curves, options));
  const int usable = warn_about_curves(*study);
  Outcome outcome{report::curve_fit_document(args.curve, *study, units, settings.units.kf_rate),
                  {{"read", read_seconds}, {"fit", study->fit_seconds}},
                  {},
                  [study, units, kf = settings.units.kf_rate, verbose = common.verbose](const report::Json& doc) {
                    return report::curve_fit_text(doc, *study, {units, kf, verbose});
                  }};
  outcome.seconds["total"] = total.seconds();
  emit(common, std::move(outcome));
  if (usable > 0) return 0;
  std::cerr << "gmwm: error: no usable fit (every curve's fit failed)\n";
  return 1;
}

}  // namespace gmwm::cli
