// A model fitted to a given curve (engine/curve.h): the curve as the WV the estimator takes,
// each point's degrees of freedom from what the curve gives, the model's Allan variance at any
// averaging time, the fit, and the refusals of what a curve cannot be.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <tuple>
#include <vector>

#include <boost/math/distributions/chi_squared.hpp>

#include "gmwm/engine/allan.h"
#include "gmwm/engine/check.h"
#include "gmwm/engine/curve.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/number_text.h"

namespace gmwm {
namespace {

GivenCurve curve_of(CurveQuantity q, std::vector<double> tau, std::vector<double> value) {
  GivenCurve c;
  c.name = "x";
  c.source = "curve";
  c.quantity = q;
  c.tau = std::move(tau);
  c.value = std::move(value);
  return c;
}

// The message of what `f` throws as InputError ("" when it throws nothing).
template <class F>
std::string refusal(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return {};
}

TEST(CurveWv, ReadsEachQuantityAsTheWaveletVarianceItStandsFor) {
  // AVAR(T) = 2 nu^2(2 T f) (statistics.md section 1): an Allan deviation of 0.1 at 0.01 s,
  // at 100 Hz, is nu^2 = 0.005 at tau = 2 samples; so is an Allan variance of 0.01; a WV's tau
  // is its Haar scale, 0.02 s.
  const CurveFitOptions o;
  for (const auto& [q, tau, value] : std::vector<std::tuple<CurveQuantity, double, double>>{
           {CurveQuantity::kAdev, 0.01, 0.1}, {CurveQuantity::kAvar, 0.01, 0.01}, {CurveQuantity::kWv, 0.02, 0.005}}) {
    const WaveletVariance w = curve_wv(curve_of(q, {tau, 40.0 * tau}, {value, value}), 100.0, o);
    EXPECT_EQ(w.tau, (std::vector<double>{2.0, 80.0})) << to_string(q);
    EXPECT_NEAR(w.wv[0], 0.005, 1e-18) << to_string(q);
    EXPECT_EQ(w.estimator, "curve");
    EXPECT_EQ(w.coefficients, (std::vector<std::int64_t>{0, 0}));
  }
}

TEST(CurveWv, TakesEtaFromTheEdfThenTheIntervalThenTheRecordThenTheShortestRecord) {
  GivenCurve c = curve_of(CurveQuantity::kAvar, {0.01, 0.02, 0.04}, {1.0, 0.5, 0.25});
  CurveFitOptions o;
  CurveWeights w{};
  // The shortest record reaching the longest averaging time, 0.04 s at 100 Hz: 8 samples, the
  // engine's eta = max((N - 2m + 1) / (2m), 1): 3.5, 1.25, 1.
  EXPECT_EQ(curve_wv(c, 100.0, o, &w).eta, (std::vector<double>{3.5, 1.25, 1.0}));
  EXPECT_EQ(w, CurveWeights::kShortestRecord);
  o.record_seconds = 10.24;  // 1024 samples
  EXPECT_EQ(curve_wv(c, 100.0, o, &w).eta, (std::vector<double>{511.5, 255.25, 127.125}));
  EXPECT_EQ(w, CurveWeights::kRecord);
  c.low = {0.9, 0.4, 0.2};
  c.high = {1.1, 0.6, 0.3};
  const WaveletVariance from_intervals = curve_wv(c, 100.0, o, &w);
  EXPECT_EQ(w, CurveWeights::kIntervals);
  EXPECT_NEAR(from_intervals.eta[0], interval_edf(0.45, 0.55, 0.95), 1e-9);
  EXPECT_EQ(from_intervals.ci_low[0], 0.45);  // the given interval, as a WV's
  c.edf = {30.0, 20.0, 10.0};
  EXPECT_EQ(curve_wv(c, 100.0, o, &w).eta, c.edf);
  EXPECT_EQ(w, CurveWeights::kEdf);
}

TEST(IntervalEdf, InvertsTheChiSquareIntervalAtItsConfidenceAndKeepsItsBounds) {
  for (double confidence : {0.95, 0.683})
    for (double eta : {1.5, 7.0, 120.0, 3e4, 5e7}) {
      const boost::math::chi_squared d(eta);
      const double a = 1.0 - confidence;
      // The interval of a value 1: [eta / q(1 - a/2), eta / q(a/2)].
      const double low = eta / boost::math::quantile(d, 1.0 - a / 2.0), high = eta / boost::math::quantile(d, a / 2.0);
      EXPECT_NEAR(interval_edf(low, high, confidence), eta, 1e-6 * eta) << confidence << ", " << eta;
    }
  EXPECT_EQ(interval_edf(0.0, 1.0, 0.95), kMinCurveEdf);  // an interval reaching 0: one degree
  EXPECT_EQ(interval_edf(1.0, 1.0 + 1e-13, 0.95), kMaxCurveEdf);
  EXPECT_THROW(interval_edf(1.0, 1.0, 0.95), InvalidArgument);
  EXPECT_THROW(interval_edf(0.5, 1.0, 1.0), InvalidArgument);
}

TEST(CurveRate, MakesTheFinestTauOneSampleOrAHundredWhenTheTausAreNoWholeMultiplesOfIt) {
  EXPECT_EQ(curve_rate(curve_of(CurveQuantity::kAdev, {0.01, 0.02, 0.05}, {1, 1, 1})), 100.0);
  EXPECT_EQ(curve_rate(curve_of(CurveQuantity::kWv, {0.02, 0.04}, {1, 1})), 100.0);  // tau = 2 samples
  // Six significant digits of a printed table are whole enough (kWholeScaleTolerance); the
  // rate keeps 12 significant digits (3.33333333333: within half a unit of the 12th, 5e-12).
  EXPECT_NEAR(curve_rate(curve_of(CurveQuantity::kAdev, {0.3, 0.9000001}, {1, 1})), 1.0 / 0.3, 5e-12);
  EXPECT_NEAR(curve_rate(curve_of(CurveQuantity::kAdev, {0.1, 0.137, 1.0}, {1, 1, 1})), kDigitisedFinestSamples / 0.1,
              1e-9);
}

TEST(ModelAllanVariance, IsTheAllanDeviationSquaredAtWholeFactorsAndSmoothBetween) {
  const Model m = parse_model("AR1(phi=0.99,sigma2=1e-4)+WN(sigma2=1e-2)+RW(gamma2=1e-8)");
  const Eigen::VectorXd theta = m.given_values();
  const std::vector<std::int64_t> factors{1, 3, 10, 333};
  const std::vector<double> adev = model_allan_deviation(m, theta, factors);
  std::vector<double> seconds;
  for (std::int64_t f : factors) seconds.push_back(static_cast<double>(f) / 50.0);
  const std::vector<double> avar = model_allan_variance(m, theta, seconds, 50.0);
  for (std::size_t k = 0; k < factors.size(); ++k) EXPECT_NEAR(avar[k], adev[k] * adev[k], 1e-13 * avar[k]);
  // Between two whole factors the continuation moves by a hair per hair of tau.
  const std::vector<double> near =
      model_allan_variance(m, theta, std::vector<double>{10.5 / 50.0, 10.5000001 / 50.0}, 50.0);
  EXPECT_NEAR(near[1], near[0], 1e-7 * near[0]);
  EXPECT_LT(near[0], avar[2]);  // falling where white noise dominates
}

TEST(CurveProblem, RefusesHostileValuesNamingThePointAndWhatWasExpected) {
  auto problem = [](std::vector<double> tau, std::vector<double> value) {
    return curve_problem(curve_of(CurveQuantity::kAdev, std::move(tau), std::move(value)));
  };
  EXPECT_EQ(problem({1, 2}, {1, 1}), "");
  EXPECT_EQ(problem({}, {}), "curve: curve 'x': found no point, expected a curve of tau and value");
  EXPECT_EQ(problem({1, NAN}, {1, 1}), "curve: tau[1]: found nan, expected a positive finite tau in seconds");
  EXPECT_EQ(problem({-1, 2}, {1, 1}), "curve: tau[0]: found -1, expected a positive finite tau in seconds");
  EXPECT_EQ(problem({1, 2, 2}, {1, 1, 1}),
            "curve: tau[2]: found tau 2 s again (tau[1]), expected each tau once, increasing");
  EXPECT_EQ(problem({1, 4, 2}, {1, 1, 1}), "curve: tau[2]: found tau 2 s after 4 s, expected taus increasing");
  EXPECT_EQ(problem({1, 2}, {1, -0.5}), "curve: value[1]: found -0.5, expected a positive finite adev");
  EXPECT_EQ(problem({1, 2}, {1, INFINITY}), "curve: value[1]: found inf, expected a positive finite adev");
  EXPECT_NE(problem({1, 2}, {1, 1e-40}).find("expected a adev whose WV lies within 1e-30 .. 1e+30"), std::string::npos);
  GivenCurve c = curve_of(CurveQuantity::kAdev, {1, 2}, {1, 1});
  c.low = {0.9, 1.1};
  c.high = {1.1, 1.2};
  EXPECT_EQ(curve_problem(c),
            "curve: low[1]: found the interval 1.1 .. 1.2 for 1, expected low < high holding the value");
  c.low = {0.9, 0.9};
  c.edf = {3, 0};
  EXPECT_EQ(curve_problem(c), "curve: edf[1]: found 0, expected degrees of freedom above 0, up to 1e+12");
  c.edf.clear();
  c.high.clear();
  EXPECT_EQ(curve_problem(c),
            "curve: curve 'x': found low without high, expected both ends of each interval or neither");
  // From a file, the point's line and the field's column.
  GivenCurve f = curve_of(CurveQuantity::kAdev, {1, 1}, {1, 1});
  f.source = "adev.csv";
  f.line = {2, 5};
  f.tau_field = {"tau_seconds", 3};
  EXPECT_EQ(curve_problem(f), "adev.csv:5:3: found tau 1 s again (line 2), expected each tau once, increasing");
}

TEST(CurveWv, RefusesATauBelowOneSampleAndARecordShorterThanTheLongestWindow) {
  const GivenCurve c = curve_of(CurveQuantity::kAdev, {0.005, 0.1}, {1, 1});
  CurveFitOptions o;
  EXPECT_EQ(refusal([&] { curve_wv(c, 100.0, o); }),
            "curve: tau[0]: found tau 0.005 s, 0.5 samples at 100 Hz, expected at least one sample (0.01 s; give the "
            "rate of the data behind the curve: --freq)");
  o.record_seconds = 0.1;
  EXPECT_EQ(refusal([&] { curve_wv(c, 1000.0, o); }),
            "--record: found 0.1 s, expected at least the longest window of curve (0.2 s: twice its longest averaging "
            "time)");
  o.record_seconds = 0.0;
  o.omega = OmegaKind::kFull;
  EXPECT_EQ(refusal([&] { curve_wv(c, 1000.0, o); }),
            "curve fit: --omega: found 'full', expected model or diag (a curve has no record to simulate or to take a "
            "covariance from)");
}

// The exact Allan variance of `spec` (every value given) at `seconds`, rate `freq`, as a curve
// with a record of `record` seconds behind it.
GivenCurve exact_curve(const std::string& spec, double freq, const std::vector<double>& seconds) {
  const Model m = parse_model(spec, {freq, true});
  return curve_of(CurveQuantity::kAvar, seconds, model_allan_variance(m, m.given_values(), seconds, freq));
}

std::vector<double> octaves(double from, int count, int per_octave) {
  std::vector<double> out;
  for (int k = 0; k < count * per_octave; ++k) out.push_back(from * std::exp2(static_cast<double>(k) / per_octave));
  return out;
}

TEST(FitCurve, RecoversAModelFromItsOwnExactCurveAndGivesNoGoodnessOfFitTest) {
  const std::string truth = "AR1(phi=0.995,sigma2=3e-4)+WN(sigma2=1)+RW(gamma2=1e-7)";
  std::vector<double> taus;
  for (double t : octaves(0.01, 17, 1)) taus.push_back(std::round(t * 100.0) / 100.0);  // whole samples
  const GivenCurve c = exact_curve(truth, 100.0, taus);
  CurveFitOptions o;
  o.record_seconds = 2621.44;
  const WaveletVariance wv = curve_wv(c, 100.0, o);
  const Model model = parse_model("WN+RW+AR1", {100.0, true});
  const FitResult r = fit_curve(wv, model, o);
  ASSERT_EQ(r.status, FitStatus::kConverged) << r.message;
  const Eigen::VectorXd expected = parse_model(truth, {100.0, true}).given_values();  // canonical: AR1, WN, RW
  for (int k = 0; k < expected.size(); ++k)
    EXPECT_NEAR(r.theta(k), expected(k), 1e-6 * expected(k)) << r.model.parameter_label(k);
  EXPECT_LT(r.objective, 1e-12);
  EXPECT_TRUE(std::isnan(r.gof.p_value));
  EXPECT_EQ(r.gof.method, "none (a given curve: the correlation of its points across taus is unknown)");
  EXPECT_EQ(r.gof.df, 17 - 4);
  EXPECT_TRUE(r.se.allFinite());
}

TEST(FitCurve, AveragingTimesThatAreNoWholeNumbersOfSamplesGiveTheFiguresOfAFinerRate) {
  // A curve measured at 1 kHz (every tau a whole number of its samples: 13, 27, 53, ... ms),
  // fitted at 100 Hz, where its taus are 1.3, 2.7, 5.3 ... samples: the continuation of the
  // closed forms between whole scales reads the same noise density, random walk and
  // Gauss-Markov time and size as the 1 kHz truth. Measured: N 2.5e-5 off (the random walk's
  // discrete 2 / tau term, statistics.md section 3, differs between the rates and white noise
  // takes it), sigma 1e-6, the correlation time and K 1e-13.
  const double fine = 1000.0, coarse = 100.0;
  const double T = 2.0, s2 = 0.03, N = 0.1, K = 3e-3;  // s, U^2, U/sqrt(Hz), U/s/sqrt(Hz)
  const double phi = std::exp(-1.0 / (fine * T));
  const std::string truth = "AR1(phi=" + significant(phi, 17) + ",sigma2=" + significant(s2 * (1 - phi * phi), 17) +
                            ")+WN(sigma2=" + significant(N * N * fine, 17) +
                            ")+RW(gamma2=" + significant(K * K / fine, 17) + ")";
  std::vector<double> taus;
  for (double t : octaves(0.013, 14, 1)) taus.push_back(std::round(t * fine) / fine);
  CurveFitOptions o;
  o.record_seconds = 4.0 * taus.back();
  const WaveletVariance wv = curve_wv(exact_curve(truth, fine, taus), coarse, o);
  const FitResult r = fit_curve(wv, parse_model("WN+RW+AR1", {coarse, true}), o);
  ASSERT_EQ(r.status, FitStatus::kConverged) << r.message;
  const Eigen::VectorXd t = r.theta;  // AR1 phi, sigma2; WN sigma2; RW gamma2 at 100 Hz
  EXPECT_NEAR(std::sqrt(t(2) / coarse), N, 1e-4 * N);
  EXPECT_NEAR(-1.0 / (coarse * std::log(t(0))), T, 1e-9 * T);
  EXPECT_NEAR(std::sqrt(t(1) / (1.0 - t(0) * t(0))), std::sqrt(s2), 1e-5 * std::sqrt(s2));
  EXPECT_NEAR(std::sqrt(t(3) * coarse), K, 1e-9 * K);
}

}  // namespace
}  // namespace gmwm
