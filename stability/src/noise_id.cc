// The dominant power-law noise at an averaging factor (confidence.h): the lag-1
// autocorrelation method (W. J. Riley and C. A. Greenhall, "Power law noise identification
// using the lag 1 autocorrelation", Proc. 18th EFTF, 2004) on the phase decimated by m, or,
// with fewer than kMinAcfPoints points, Barnes' B1 ratio (J. A. Barnes, "Tables of bias
// functions B1 and B2 for variances based on finite samples of processes with power law
// spectral densities", NBS Technical Note 375, 1969) and the R(n) ratio (NIST SP 1065,
// section 5.6).
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "gmwm/engine/samples.h"
#include "gmwm/stability/confidence.h"
#include "kinds_internal.h"

namespace gmwm::stability {
namespace {

// Differencing stops once the lag-1 autocorrelation's delta = r1 / (1 + r1) falls below
// this (Riley and Greenhall 2004, eq. 4: delta < 0.25 means the differenced series is
// stationary, its noise index p = -2 (delta + d)).
constexpr double kStationaryDelta = 0.25;

int difference_order(DeviationKind kind) {
  return kind == DeviationKind::kHdev || kind == DeviationKind::kOhdev || kind == DeviationKind::kHtotdev ? 3 : 2;
}

// The lag-1 autocorrelation of the series s(t), t in [0, n) (Riley and Greenhall's eq. 2:
// sum (s_t - sbar)(s_{t+1} - sbar) / sum (s_t - sbar)^2), in one pass without a copy: the
// sums of s - s(0) (a shift that keeps the squares on the scale of the series' spread, not
// of its offset), centred afterwards.
// `passed(t)` is called as the pass goes (Behind: a phase in a file released behind it).
template <class S, class P>
double lag1_autocorrelation(std::int64_t n, const S& s, P& passed) {
  const double shift = s(0);
  double sum = 0.0, squares = 0.0, products = 0.0, previous = 0.0;
  for (std::int64_t t = 0; t < n; ++t) {
    passed(t);
    const double v = s(t) - shift;
    sum += v;
    squares += v * v;
    if (t > 0) products += previous * v;
    previous = v;
  }
  const double nn = static_cast<double>(n), mean = sum / nn;
  const double first = 0.0, last = previous;  // s(0) - shift and s(n - 1) - shift
  // sum_{t<n-1} (a_t - mean)(a_{t+1} - mean) = products - mean (2 sum - first - last) + (n - 1) mean^2
  const double num = products - mean * (2.0 * sum - first - last) + (nn - 1.0) * mean * mean;
  const double den = squares - nn * mean * mean;
  return den > 0.0 ? num / den : 0.0;
}

// Every this many phase points a pass over the decimated phase has crossed (8 MB), the pages
// behind it are released when the phase lives in a temporary file (samples.h): a pass over a
// record of any length then holds memory that does not grow with it, and the releases' TLB
// shootdowns stay rare.
constexpr std::int64_t kReleaseEvery = std::int64_t{1} << 20;

// Releases the phase behind a pass reading x_{t m} (nothing for a phase in memory).
struct Behind {
  const double* x;
  std::int64_t points, m;
  bool file;
  std::int64_t done = 0;
  Behind(std::span<const double> phase, std::int64_t factor)
      : x(phase.data()),
        points(static_cast<std::int64_t>(phase.size())),
        m(factor),
        file(gmwm::detail::in_sample_file(phase.data(), phase.size())) {}
  void operator()(std::int64_t t) {
    if (!file) return;
    if (t < done) done = 0;  // a new pass
    if ((t - done) * m < kReleaseEvery) return;
    detail::release_around(x, points, done * m, t * m);
    done = t;
  }
};

// The phase decimated by m (z_t = x_{tm}, t < points), less its least-squares line (the
// frequency offset), then differenced d times. Differencing after the line's removal is
// differencing z itself less a constant (d = 1) or nothing (d >= 2), which the
// autocorrelation's mean removes: the d-th difference of z is read directly.
struct DecimatedSeries {
  const double* x;
  std::int64_t m;
  double mean = 0.0, slope = 0.0, centre = 0.0;  // the line: mean + slope (t - centre)

  DecimatedSeries(std::span<const double> phase, std::int64_t factor, std::int64_t points)
      : x(phase.data()), m(factor), centre((static_cast<double>(points) - 1.0) / 2.0) {
    // One pass: sum z and sum (t - centre) z (the centred times sum to zero, so the slope is
    // their ratio to sum (t - centre)^2 = n (n^2 - 1) / 12).
    const double z0 = z(0);
    double sum = 0.0, sxy = 0.0;
    Behind passed(phase, factor);
    for (std::int64_t t = 0; t < points; ++t) {
      passed(t);
      const double v = z(t) - z0;
      sum += v;
      sxy += (static_cast<double>(t) - centre) * v;
    }
    const double n = static_cast<double>(points);
    mean = z0 + sum / n;
    const double sxx = n * (n * n - 1.0) / 12.0;
    slope = sxx > 0.0 ? sxy / sxx : 0.0;
  }
  double z(std::int64_t t) const { return x[t * m]; }
  double detrended(std::int64_t t) const { return z(t) - mean - slope * (static_cast<double>(t) - centre); }
  double difference(int d, std::int64_t t) const {
    static constexpr std::array<std::array<double, 4>, 3> kWeights = {
        {{-1.0, 1.0, 0.0, 0.0}, {1.0, -2.0, 1.0, 0.0}, {-1.0, 3.0, -3.0, 1.0}}};
    const auto& w = kWeights[static_cast<std::size_t>(d - 1)];
    double v = 0.0;
    for (int k = 0; k <= d; ++k) v += w[static_cast<std::size_t>(k)] * z(t + k);
    return v;
  }
};

NoiseIdentification by_autocorrelation(std::span<const double> x, std::int64_t m, std::int64_t points, int dmax) {
  const DecimatedSeries series(x, m, points);
  Behind passed(x, m);
  for (int d = 0;; ++d) {
    const std::int64_t n = points - d;
    const double r1 = d == 0 ? lag1_autocorrelation(
                                   n, [&](std::int64_t t) { return series.detrended(t); }, passed)
                             : lag1_autocorrelation(
                                   n, [&](std::int64_t t) { return series.difference(d, t); }, passed);
    const double delta = r1 / (1.0 + r1);
    if (delta < kStationaryDelta || d >= dmax || n < 3) {
      // p = -2 (delta + d) is the phase's spectral index; the frequency's is alpha = p + 2.
      const double p = -2.0 * (delta + d);
      NoiseIdentification id;
      id.estimate = p + 2.0;
      id.alpha = static_cast<int>(std::lround(p)) + 2;
      id.method = NoiseIdMethod::kLag1Acf;
      return id;
    }
  }
}

// Barnes' B1(N, mu): the expected ratio of the N-sample standard variance to the two-sample
// (Allan) variance of a noise whose Allan variance goes as tau^mu.
double b1_theory(double n, int mu) {
  if (mu == 0) return n * std::log(n) / (2.0 * (n - 1.0) * std::numbers::ln2);
  return n * (1.0 - std::pow(n, mu)) / (2.0 * (n - 1.0) * (1.0 - std::pow(2.0, mu)));
}

// R(n) = MVAR / AVAR expected for white PM (1 / m) and flicker PM (SP 1065 Table 6 with the
// measurement bandwidth f_h = 1 / (2 tau0): 2 pi f_h tau = pi m).
double rn_white_pm(double m) { return 1.0 / m; }
double rn_flicker_pm(double m) {
  constexpr double kPi2 = std::numbers::pi * std::numbers::pi;
  const double avar = (1.038 + 3.0 * std::log(std::numbers::pi * m)) / (4.0 * kPi2);
  const double mvar = 3.0 * std::log(256.0 / 27.0) / (8.0 * kPi2);
  return mvar / avar;
}

// White (2) or flicker (1) PM by R(n), where MDEV reaches m; flicker PM, the wider interval,
// beyond.
int white_or_flicker_pm(std::span<const double> x, std::int64_t m) {
  const auto n = static_cast<std::int64_t>(x.size());
  if (m > max_factor(DeviationKind::kMdev, n)) return 1;
  const std::int64_t f[] = {m};
  const double mdev = deviation(DeviationKind::kMdev, x, 1.0, f).value[0];
  const double oadev = deviation(DeviationKind::kOadev, x, 1.0, f).value[0];
  const double md = static_cast<double>(m);
  const double bound = std::sqrt(rn_white_pm(md) * rn_flicker_pm(md));
  return oadev > 0.0 && (mdev * mdev) / (oadev * oadev) <= bound ? 2 : 1;
}

// B1 = s^2 / AVAR of the m-averaged frequencies, both from the same values (Barnes' ratio:
// the N-sample variance over the two-sample variance of N frequencies at tau).
NoiseIdentification by_b1(std::span<const double> x, std::int64_t m, std::int64_t points, int dmax) {
  NoiseIdentification id;
  std::vector<double> y;  // the m-averaged frequencies (tau0 = 1): differences of the decimated phase
  for (std::int64_t i = 0; i + 1 < points; ++i)
    y.push_back((x[static_cast<std::size_t>((i + 1) * m)] - x[static_cast<std::size_t>(i * m)]) /
                static_cast<double>(m));
  if (y.size() < 3) return id;  // two Allan differences at least
  const double n = static_cast<double>(y.size());
  double mean = 0.0;
  for (const double v : y) mean += v;
  mean /= n;
  double var = 0.0, avar = 0.0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    var += (y[i] - mean) * (y[i] - mean);
    if (i + 1 < y.size()) avar += (y[i + 1] - y[i]) * (y[i + 1] - y[i]);
  }
  var /= n - 1.0;
  avar /= 2.0 * (n - 1.0);
  if (!(avar > 0.0)) return id;
  const double b1 = var / avar;
  // mu (AVAR ~ tau^mu) from -2 (PM) up to 1 (random-walk FM) for the Allan family, 2
  // (flicker-walk FM) for the Hadamard (Barnes' B1 holds for mu <= 2: random-run FM is read
  // as flicker walk); boundaries at the geometric means of neighbouring B1s.
  const int mu_max = dmax == 2 ? 1 : 2;
  int mu = -2;
  while (mu < mu_max && b1 > std::sqrt(b1_theory(n, mu) * b1_theory(n, mu + 1))) ++mu;
  id.method = NoiseIdMethod::kB1;
  if (mu == -2) {
    id.alpha = white_or_flicker_pm(x, m);
    id.method = NoiseIdMethod::kB1Rn;
  } else {
    id.alpha = -mu - 1;  // mu = -1 white FM (0), 0 flicker FM (-1), 1 random-walk FM (-2), ...
  }
  return id;
}

}  // namespace

std::string_view noise_id_method_name(NoiseIdMethod method) {
  switch (method) {
    case NoiseIdMethod::kLag1Acf:
      return "acf";
    case NoiseIdMethod::kB1:
      return "b1";
    case NoiseIdMethod::kB1Rn:
      return "b1+rn";
    case NoiseIdMethod::kDefault:
      return "default";
    case NoiseIdMethod::kFixed:
      return "fixed";
  }
  return "unknown";
}

std::string_view noise_name(int alpha) {
  switch (alpha) {
    case 2:
      return "white PM";
    case 1:
      return "flicker PM";
    case 0:
      return "white FM";
    case -1:
      return "flicker FM";
    case -2:
      return "random-walk FM";
    case -3:
      return "flicker-walk FM";
    case -4:
      return "random-run FM";
    default:
      return "unknown";
  }
}

NoiseIdentification identify_noise(DeviationKind kind, std::span<const double> phase, std::int64_t m) {
  const int dmax = difference_order(kind);
  const std::int64_t points = (static_cast<std::int64_t>(phase.size()) - 1) / m + 1;  // x_0, x_m, x_2m, ...
  NoiseIdentification id =
      points >= kMinAcfPoints ? by_autocorrelation(phase, m, points, dmax) : by_b1(phase, m, points, dmax);
  id.alpha = std::clamp(id.alpha, 2 - 2 * dmax, 2);
  return id;
}

}  // namespace gmwm::stability
