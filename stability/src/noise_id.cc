// The dominant power-law noise at an averaging factor (confidence.h): the lag-1
// autocorrelation method (W. J. Riley and C. A. Greenhall, "Power law noise identification
// using the lag 1 autocorrelation", Proc. 18th EFTF, 2004) on the phase decimated by m, or,
// with fewer than kMinAcfPoints points, Barnes' B1 ratio (J. A. Barnes, "Tables of bias
// functions B1 and B2 for variances based on finite samples of processes with power law
// spectral densities", NBS Technical Note 375, 1969) and the R(n) ratio (NIST SP 1065,
// section 5.6).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "gmwm/stability/confidence.h"

namespace gmwm::stability {
namespace {

// Differencing stops once the lag-1 autocorrelation's delta = r1 / (1 + r1) falls below
// this (Riley and Greenhall 2004, eq. 4: delta < 0.25 means the differenced series is
// stationary, its noise index p = -2 (delta + d)).
constexpr double kStationaryDelta = 0.25;

int difference_order(DeviationKind kind) {
  return kind == DeviationKind::kHdev || kind == DeviationKind::kOhdev || kind == DeviationKind::kHtotdev ? 3 : 2;
}

// x_0, x_m, x_2m, ...: the phase seen at tau = m tau0.
std::vector<double> decimated(std::span<const double> x, std::int64_t m) {
  std::vector<double> out;
  for (std::size_t i = 0; i < x.size(); i += static_cast<std::size_t>(m)) out.push_back(x[i]);
  return out;
}

// Removes the least-squares line a + b i (the frequency offset of phase data).
void remove_line(std::vector<double>& v) {
  const double n = static_cast<double>(v.size());
  const double mean_i = (n - 1.0) / 2.0;
  double mean_v = 0.0;
  for (const double x : v) mean_v += x;
  mean_v /= n;
  double sxy = 0.0, sxx = 0.0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const double di = static_cast<double>(i) - mean_i;
    sxy += di * (v[i] - mean_v);
    sxx += di * di;
  }
  const double slope = sxx > 0.0 ? sxy / sxx : 0.0;
  for (std::size_t i = 0; i < v.size(); ++i) v[i] -= mean_v + slope * (static_cast<double>(i) - mean_i);
}

// Riley and Greenhall's eq. (2): sum (z_t - zbar)(z_{t+1} - zbar) / sum (z_t - zbar)^2.
double lag1_autocorrelation(const std::vector<double>& z) {
  double mean = 0.0;
  for (const double v : z) mean += v;
  mean /= static_cast<double>(z.size());
  double num = 0.0, den = 0.0;
  for (std::size_t t = 0; t < z.size(); ++t) {
    const double a = z[t] - mean;
    den += a * a;
    if (t + 1 < z.size()) num += a * (z[t + 1] - mean);
  }
  return den > 0.0 ? num / den : 0.0;
}

NoiseIdentification by_autocorrelation(std::vector<double> z, int dmax) {
  remove_line(z);
  for (int d = 0;; ++d) {
    const double r1 = lag1_autocorrelation(z);
    const double delta = r1 / (1.0 + r1);
    if (delta < kStationaryDelta || d >= dmax || z.size() < 3) {
      // p = -2 (delta + d) is the phase's spectral index; the frequency's is alpha = p + 2.
      const double p = -2.0 * (delta + d);
      NoiseIdentification id;
      id.estimate = p + 2.0;
      id.alpha = static_cast<int>(std::lround(p)) + 2;
      id.method = NoiseIdMethod::kLag1Acf;
      return id;
    }
    for (std::size_t t = 0; t + 1 < z.size(); ++t) z[t] = z[t + 1] - z[t];
    z.pop_back();
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
NoiseIdentification by_b1(std::span<const double> x, const std::vector<double>& z, std::int64_t m, int dmax) {
  NoiseIdentification id;
  std::vector<double> y;  // the m-averaged frequencies (tau0 = 1)
  for (std::size_t i = 0; i + 1 < z.size(); ++i) y.push_back((z[i + 1] - z[i]) / static_cast<double>(m));
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
  const std::vector<double> z = decimated(phase, m);
  NoiseIdentification id =
      static_cast<std::int64_t>(z.size()) >= kMinAcfPoints ? by_autocorrelation(z, dmax) : by_b1(phase, z, m, dmax);
  id.alpha = std::clamp(id.alpha, 2 - 2 * dmax, 2);
  return id;
}

}  // namespace gmwm::stability
