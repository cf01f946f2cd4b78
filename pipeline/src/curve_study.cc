// The curve fit study as named stages: each curve as a WV at its rate, checked against the
// model -> fits of the points kept (in parallel) -> the model at every point, noise figures.
#include "gmwm/pipeline/curve_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <charconv>
#include <cstdlib>

#include "gmwm/engine/error.h"
#include "gmwm/engine/number_text.h"
#include "gmwm/engine/parallel.h"
#include "gmwm/io/read_request.h"
#include "gmwm/io/signal_reader.h"

namespace gmwm::pipeline {
namespace {

std::string num(double x) { return significant(x, 6); }

// x in the shortest text that reads back to it ("0.05", not 0.050000000000000003; "100").
std::string shortest(double x) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x);
  return ec == std::errc() ? std::string(buf, end) : significant(x, 17);
}

// One end of a range: empty (open) or a finite number from 0.
std::optional<double> range_end(const std::string& text, bool& ok) {
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  ok = ok && end == text.c_str() + text.size() && std::isfinite(v) && v >= 0.0 &&
       text.find_first_of("xXnNiI") == std::string::npos;  // no hex floats, nan or inf
  return v;
}

// The points of `wv` marked in `keep`.
WaveletVariance kept_points(const WaveletVariance& wv, const std::vector<bool>& keep) {
  WaveletVariance out = wv;
  out.tau.clear();
  out.wv.clear();
  out.ci_low.clear();
  out.ci_high.clear();
  out.variance.clear();
  out.eta.clear();
  out.coefficients.clear();
  out.notes.clear();
  for (std::size_t k = 0; k < keep.size(); ++k) {
    if (!keep[k]) continue;
    out.tau.push_back(wv.tau[k]);
    out.wv.push_back(wv.wv[k]);
    out.ci_low.push_back(wv.ci_low[k]);
    out.ci_high.push_back(wv.ci_high[k]);
    out.variance.push_back(wv.variance[k]);
    out.eta.push_back(wv.eta[k]);
    out.coefficients.push_back(wv.coefficients[k]);
    out.notes.push_back(wv.notes[k]);
  }
  return out;
}

// Refuses a model with more parameters than the points kept, or a process that needs whole
// scales (ARMA) on a tau that is no whole number of samples.
void check_model_on_points(const CurveFitColumn& c, const Model& model) {
  const GivenCurve& curve = c.curve;
  const auto kept = static_cast<int>(std::count(c.fitted.begin(), c.fitted.end(), true));
  const int p = model.num_parameters();
  if (kept < p) {
    const int left_out = static_cast<int>(curve.size()) - kept;
    throw InputError(curve.source + ": curve '" + curve.name + "': found " + std::to_string(kept) + " points to fit" +
                     (left_out > 0 ? " (" + std::to_string(left_out) + " left out by --exclude-taus)" : "") +
                     ", expected at least " + std::to_string(p) + " for the " + std::to_string(p) + " parameters of " +
                     model.to_string());
  }
  for (const Component& comp : model.components()) {
    if (!comp.process->needs_whole_scales()) continue;
    for (std::size_t k = 0; k < curve.size(); ++k) {
      const double m = 0.5 * c.wv.tau[k];
      if (c.fitted[k] && m != std::round(m))
        throw InputError(curve_place(curve, k, curve.tau_field) + "found tau " + num(curve.tau[k]) + " s, " + num(m) +
                         " samples at " + num(c.freq) + " Hz, expected a whole number: " + comp.process->name() +
                         " sums over whole lags (give --freq at which every tau is one)");
    }
  }
}

// A curve's WV at its rate, the points kept, and the model bound there (checked against them).
CurveFitColumn prepared(const GivenCurve& curve, const CurveFitStudyOptions& o, Model& model) {
  CurveFitColumn c;
  c.curve = curve;
  c.freq = o.freq.value_or(curve_rate(curve));
  if (const std::string why = io::sampling_rate_problem(c.freq, "the rate"); !why.empty())
    throw InputError(curve.source + ": " + why + " (from the curve's finest tau: give --freq)");
  c.wv = curve_wv(curve, c.freq, o.fit, &c.weights);
  for (std::size_t k = 0; k < curve.size(); ++k) {
    bool keep = true;
    for (const TauRange& r : o.exclude) keep = keep && !r.holds(curve.tau[k]);
    c.fitted.push_back(keep);
    const double m = 0.5 * c.wv.tau[k];
    c.whole_samples = c.whole_samples && m == std::round(m);
  }
  model = o.model.bind(ProcessContext{c.freq, true});
  check_model_on_points(c, model);
  return c;
}

// Why a curve without intervals, edf or record length has the intervals it has.
std::string shortest_record_note(const CurveFitColumn& c) {
  return "the curve gives no interval, edf or record length: its points are weighed as the shortest record "
         "reaching its longest averaging time (" +
         num(static_cast<double>(c.wv.n) / c.freq) +
         " s) weighs them, and the intervals are that record's, an upper bound on a longer one's (--record "
         "SECONDS gives the record's own)";
}

// The fit of the kept points, its implied WV at every point and its misfits named by point.
void fit_column(CurveFitColumn& c, const Model& model, const CurveFitStudyOptions& o) {
  c.fit = fit_curve(kept_points(c.wv, c.fitted), model, o.fit);
  std::vector<int> point;  // the 1-based point of each fitted level
  for (std::size_t k = 0; k < c.fitted.size(); ++k)
    if (c.fitted[k]) point.push_back(static_cast<int>(k) + 1);
  for (LevelMisfit& m : c.fit.misfits) m.level = point[static_cast<std::size_t>(m.level - 1)];
  const bool usable = c.fit.status != FitStatus::kFailed && c.fit.theta.size() == c.fit.model.num_parameters() &&
                      c.fit.theta.allFinite();
  if (!usable) return;
  c.fit.implied_wv = c.fit.model.wv(c.fit.theta, c.wv.tau);
  if (has_sign_from_series(c.fit)) c.fit.notes.push_back("a curve holds no drift's sign: DR's omega is given positive");
  ReadoffOptions ro;
  ro.alpha = o.fit.fit.alpha;
  c.figures = noise_figure_report(curve_allan_deviation(c.wv, c.freq, c.fitted), c.fit.model, c.fit.theta,
                                  &c.fit.covariance, ro);
  if (c.weights == CurveWeights::kShortestRecord) c.fit.notes.push_back(shortest_record_note(c));
  if (!c.whole_samples)
    c.fit.notes.push_back("the curve's taus are not whole numbers of samples at " + num(c.freq) +
                          " Hz: the noise figures read the model's Allan deviation at the nearest whole ones");
}

}  // namespace

std::vector<TauRange> parse_tau_ranges(const std::string& text, const std::string& option) {
  std::vector<TauRange> out;
  for (const std::string& part : io::comma_list(text)) {
    const auto colon = part.find(':');
    bool ok = !part.empty() && part.find(':', colon == std::string::npos ? 0 : colon + 1) == std::string::npos;
    TauRange r;
    if (colon == std::string::npos) {
      const auto t = range_end(part, ok);
      r.from = r.to = t.value_or(0.0);
    } else {
      r.from = range_end(part.substr(0, colon), ok).value_or(0.0);
      r.to = range_end(part.substr(colon + 1), ok).value_or(std::numeric_limits<double>::infinity());
    }
    if (!ok || r.to < r.from)
      throw InputError(option + ": found '" + part +
                       "', expected taus in seconds: T, or a range A:B with A <= B (an end left empty is open: "
                       "':0.05', '100:'), comma-separated");
    out.push_back(r);
  }
  if (out.empty()) throw InputError(option + ": found no range, expected taus in seconds such as ':0.05,100:'");
  return out;
}

std::string tau_ranges_text(const std::vector<TauRange>& ranges) {
  std::string out;
  for (const TauRange& r : ranges) {
    out += out.empty() ? "" : ",";
    if (r.from == r.to)
      out += shortest(r.from);
    else
      out += (r.from > 0.0 ? shortest(r.from) : "") + ":" + (std::isfinite(r.to) ? shortest(r.to) : "");
  }
  return out;
}

std::string CurveFitStudyOptions::Validate() const {
  if (model.empty()) return "the model is empty";
  if (freq)
    if (std::string why = io::sampling_rate_problem(*freq, "--freq"); !why.empty()) return why;
  return fit.Validate();
}

CurveFitStudy study_curve_fit(const std::vector<GivenCurve>& curves, const CurveFitStudyOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError(why);
  CurveFitStudy study;
  study.model_spec = options.model.text();
  study.seed = options.fit.fit.seed;
  study.omega = options.fit.omega;
  study.freq_given = options.freq.has_value();
  study.exclude = options.exclude;
  study.confidence = options.fit.confidence;
  study.record_seconds = options.fit.record_seconds;
  std::vector<Model> models(curves.size());
  for (std::size_t k = 0; k < curves.size(); ++k) study.columns.push_back(prepared(curves[k], options, models[k]));
  const auto start = std::chrono::steady_clock::now();
  gmwm::parallel_for(std::size_t{0}, study.columns.size(),
                     [&](std::size_t k) { fit_column(study.columns[k], models[k], options); });
  study.fit_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return study;
}

}  // namespace gmwm::pipeline
