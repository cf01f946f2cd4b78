#include "gmwm/engine/repeated_samples.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <vector>

#include <Eigen/Dense>
#include <boost/math/distributions/normal.hpp>

#include "gmwm/engine/number_text.h"

namespace gmwm {
namespace {

// The record is read for a pattern in blocks of this many samples (5 s at 400 Hz), at most
// kInspectBlocks of them spread over the record (a driver's pattern holds throughout; the
// least squares of 36 positions a block were half of the detection's cost with 8).
constexpr std::int64_t kBlockSamples = 2048;
constexpr int kInspectBlocks = 4;
// The longest pattern looked for: 250 Hz on 400 Hz stamps repeats every 8 samples (the
// rates of RealSense's accelerometer and gyroscope: 63/250 and 200/400 Hz).
constexpr int kMaxPeriod = 8;
// A linear relation is exact when what it leaves is below this share of the steps'
// variance (doubles and values printed to 9 digits leave 1e-14..1e-10) plus kRoundingAllowance
// times what rounding to the quantum leaves of an exact relation, q^2/12 (1 + sum beta^2):
// natural records leave 0.3-0.6 of their steps' variance (the ADIS16405 axes, coarsest at
// about one quantum of step noise, leave 0.46), interpolated and re-rounded ones 1.
constexpr double kExactResidual = 1e-6;
constexpr double kRoundingAllowance = 2.0;
// A position whose sample equals a neighbour this often is held, not interpolated.
constexpr double kHeldPositionShare = 0.9;
// Three samples on a line, read on rounded data only when the second differences spread
// over this many quanta (their density near zero is then flat enough to be read from the
// shell 2 < |d2| / q <= 6 beside it).
constexpr double kMinQuantaForCollinear = 8.0;
// Off a lattice, three samples are on a line when the second difference is within this
// share of their size: doubles hold a value computed from stamps to about 1e-12 of it
// (the interpolation's fraction carries the stamp's rounding), float32 (ROS messages) to
// 6e-8 (kFloat32Collinear: four of its units in the last place).
constexpr double kDoubleCollinear = 1e-9;
constexpr double kFloat32Collinear = 2.4e-7;
// A record whose values are all float32 numbers, checked on this many samples.
constexpr std::int64_t kFloat32Check = 4096;
// Interpolation by p makes a share (p - 2) / p of the samples collinear with their
// neighbours: p = 2 / (1 - share), bounded here.
constexpr double kMaxSamplesPerMeasurement = 64.0;
// How far a measured samples-a-measurement may be from a whole number and count as it.
constexpr double kWholeSlack = 0.15;
// Rounding alone explains no held sample when P_0 is this close to 1 (a signal that
// barely moves): the held share is not read.
constexpr double kMaxReadableZeroShare = 0.9;
// The chance that two samples round alike when they are independent around the local
// level (white noise a fraction of a quantum, where the triangle model's uniform phase
// fails: 0.47 for 0.52 observed at 0.7 quanta of step noise), from blocks of this many
// samples, at most kLevelBlocks of them spread over the record.
constexpr std::int64_t kLevelBlockSamples = 64;
constexpr std::int64_t kLevelBlocks = 1024;

// The record, and the part of it the shares are read from: all of it up to kSampledBlocks
// blocks, else that many blocks spread over it, end to end (their joins add one step in
// kBlockSamples). The shares move by 0.003 (a binomial sd) at most; where, and the pattern,
// are read on the record itself.
constexpr std::int64_t kSampledBlocks = 16;

struct Series {
  const double* x;
  std::int64_t n;
};

double phi(double z) { return std::exp(-0.5 * z * z) / std::sqrt(2.0 * M_PI); }

// P(step = k quanta) for continuous steps of sd s quanta and two uniform rounding errors.
double lattice_probability(int k, double s) {
  if (s > 100.0) return phi(k / s) / s;  // the triangle no longer matters (and G cancels)
  const boost::math::normal_distribution<double> unit;
  auto G = [&](double x) { return x * boost::math::cdf(unit, x / s) + s * phi(x / s); };
  return std::max(0.0, G(k + 1.0) - 2.0 * G(k) + G(k - 1.0));
}

// The steps' continuous sd (quanta) whose share of one-quantum steps among the non-zero
// ones is r1: P_1 / (1 - P_0) decreases from 1 as s grows.
double lattice_sd(double r1) {
  auto ratio = [](double s) {
    return 2.0 * lattice_probability(1, s) / std::max(1e-300, 1.0 - lattice_probability(0, s));
  };
  double lo = std::log(1e-3), hi = std::log(1e8);
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (ratio(std::exp(mid)) > r1 ? lo : hi) = mid;
  }
  return std::exp(0.5 * (lo + hi));
}

struct HeldCount {
  std::int64_t zero = 0, one = 0, nonzero = 0;
};

HeldCount count_steps(const double* x, std::int64_t from, std::int64_t to, double q) {
  HeldCount c;
  for (std::int64_t t = std::max<std::int64_t>(from, 1); t < to; ++t) {
    const double d = x[t] - x[t - 1];
    if (d == 0.0) {
      ++c.zero;
      continue;
    }
    ++c.nonzero;
    c.one += q > 0.0 && std::abs(std::abs(d) / q - 1.0) < 0.5;
  }
  return c;
}

double share(std::int64_t part, std::int64_t whole) {
  return whole > 0 ? static_cast<double>(part) / static_cast<double>(whole) : 0.0;
}

// Blocks over the whole record: the first and last sample of the blocks whose share
// (from `block_share`) reaches the claim.
template <class Share>
std::pair<std::int64_t, std::int64_t> where(std::int64_t n, Share block_share) {
  std::int64_t first = -1, last = -1;
  for (std::int64_t b = 0; b < n; b += kBlockSamples) {
    const std::int64_t e = std::min(n, b + kBlockSamples);
    if (block_share(b, e) < RepeatedSamples::kMinRepeatedShare) continue;
    if (first < 0) first = b;
    last = e - 1;
  }
  return {std::max<std::int64_t>(first, 0), std::max<std::int64_t>(last, 0)};
}

// Sum over values of P(value)^2 within blocks of kLevelBlockSamples (the unbiased
// (sum c_k^2 - m) / (m (m - 1)) of the counts c_k), averaged: P_0 when consecutive samples
// are independent given the local level. Copies leave the counts' shares as they are.
double independent_zero_share(const double* x, std::int64_t n, double quantum) {
  const std::int64_t blocks = std::min(kLevelBlocks, n / kLevelBlockSamples);
  if (blocks == 0) return 0.0;
  double total = 0.0;
  std::vector<double> k(static_cast<std::size_t>(kLevelBlockSamples));
  for (std::int64_t i = 0; i < blocks; ++i) {
    const std::int64_t b = blocks == 1 ? 0 : i * (n - kLevelBlockSamples) / (blocks - 1);
    for (std::int64_t t = 0; t < kLevelBlockSamples; ++t)
      k[static_cast<std::size_t>(t)] = std::round(x[b + t] / quantum);
    std::sort(k.begin(), k.end());
    double sum_sq = 0.0;
    for (std::size_t a = 0; a < k.size();) {
      std::size_t e = a;
      while (e < k.size() && k[e] == k[a]) ++e;
      sum_sq += static_cast<double>(e - a) * static_cast<double>(e - a);
      a = e;
    }
    const auto m = static_cast<double>(kLevelBlockSamples);
    total += (sum_sq - m) / (m * (m - 1.0));
  }
  return total / static_cast<double>(blocks);
}

void find_held(Series sample, Series record, const Quantization& q, RepeatedSamples& r) {
  const double quantum = q.detected ? q.quantum : 0.0;
  const auto [x, n] = sample;
  const HeldCount c = count_steps(x, 0, n, quantum);
  if (c.nonzero == 0) return;  // a constant: nothing measured to repeat
  r.zero_step_share = share(c.zero, n - 1);
  double p0 = 0.0;
  // The larger of the two models: the triangle's (steps independent of where the sample
  // sits in its quantum: exact for a random walk) and the independent samples' (white noise
  // under a quantum); copies change neither's reading.
  if (quantum > 0.0)
    p0 = std::max(lattice_probability(0, lattice_sd(share(c.one, c.nonzero))), independent_zero_share(x, n, quantum));
  r.expected_zero_step_share = p0;
  if (p0 > kMaxReadableZeroShare) return;
  auto held = [&](std::int64_t zero, std::int64_t steps) {
    return std::max(0.0, (share(zero, steps) - p0) / (1.0 - p0));
  };
  r.held_share = held(c.zero, n - 1);
  if (!r.held()) return;
  std::tie(r.first, r.last) = where(record.n, [&](std::int64_t b, std::int64_t e) {
    const HeldCount bc = count_steps(record.x, b, e, quantum);
    return held(bc.zero, bc.zero + bc.nonzero);
  });
}

// Samples collinear with both neighbours (steps either side non-zero) beyond what
// rounding explains, in [from, to).
double collinear_share(const double* x, std::int64_t from, std::int64_t to, double quantum, double relative) {
  std::int64_t near = 0, shell = 0, counted = 0;
  for (std::int64_t t = std::max<std::int64_t>(from, 1); t + 1 < to; ++t) {
    const double a = x[t] - x[t - 1], b = x[t + 1] - x[t];
    if (a == 0.0 || b == 0.0) continue;  // held, counted as such
    ++counted;
    const double d2 = std::abs(b - a);
    const double tol =
        quantum > 0.0 ? 2.0 * quantum : relative * (std::abs(x[t - 1]) + std::abs(x[t]) + std::abs(x[t + 1]));
    near += d2 <= tol * (1.0 + 1e-9);
    shell += quantum > 0.0 && d2 > tol * (1.0 + 1e-9) && d2 <= 6.0 * quantum * (1.0 + 1e-9);
  }
  // On the lattice |d2| <= 2q takes 5 values and the shell 8: a flat density gives 5/8.
  const double expected = quantum > 0.0 ? 5.0 / 8.0 * static_cast<double>(shell) : 0.0;
  return std::max(0.0, share(near, counted) - share(static_cast<std::int64_t>(expected), counted));
}

double second_difference_sd(const double* x, std::int64_t n) {
  double s = 0.0;
  std::int64_t m = 0;
  for (std::int64_t t = 1; t + 1 < n; ++t, ++m) {
    const double d2 = x[t + 1] - 2.0 * x[t] + x[t - 1];
    s += d2 * d2;
  }
  return m > 0 ? std::sqrt(s / static_cast<double>(m)) : 0.0;
}

// In the block [b, e): is position c of period P an exact linear combination of its four
// nearest neighbours (and not a copy of one)?
enum class Position { kFree, kExact, kHeld };

Position position_kind(const double* x, std::int64_t b, std::int64_t e, int P, int c, double quantum, double step_var) {
  // The samples t in [b + 2, e - 2) with t = c mod P, regressed on their four nearest
  // neighbours with an intercept (both sides centred): the 4x4 normal equations.
  const std::int64_t t0 = b + 2;
  const std::int64_t first = t0 + ((c - t0 % P) % P + P) % P;
  using Row = Eigen::Matrix<double, 4, 1>;
  const auto row = [x](std::int64_t t) { return Row(x[t - 2], x[t - 1], x[t + 1], x[t + 2]); };
  std::int64_t m = 0, copies = 0;
  Row mean = Row::Zero();
  double y_mean = 0.0;
  for (std::int64_t t = first; t + 2 < e; t += P, ++m) {
    mean += row(t);
    y_mean += x[t];
    copies += x[t] == x[t - 1] || x[t] == x[t + 1];
  }
  if (m < 16) return Position::kFree;
  if (share(copies, m) >= kHeldPositionShare) return Position::kHeld;
  mean /= static_cast<double>(m);
  y_mean /= static_cast<double>(m);
  Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
  Row v = Row::Zero();
  double yy = 0.0;
  for (std::int64_t t = first; t + 2 < e; t += P) {
    const Row r = row(t) - mean;
    const double y = x[t] - y_mean;
    A.noalias() += r * r.transpose();
    v += r * y;
    yy += y * y;
  }
  // The residual y'y - v'beta of the centred sums: exact to about 1e-16 y'y, far below the
  // kExactResidual (1e-6) of the steps' variance that an exact relation must reach.
  const Row beta = A.colPivHouseholderQr().solve(v);
  const double resid = std::max(0.0, yy - v.dot(beta)) / static_cast<double>(m);
  const double rounding = quantum * quantum / 12.0 * (1.0 + beta.squaredNorm());
  return resid <= kExactResidual * step_var + kRoundingAllowance * rounding ? Position::kExact : Position::kFree;
}

double step_variance(const double* x, std::int64_t b, std::int64_t e) {
  double s = 0.0, s2 = 0.0;
  for (std::int64_t t = b + 1; t < e; ++t) {
    const double d = x[t] - x[t - 1];
    s += d;
    s2 += d * d;
  }
  const double m = static_cast<double>(e - b - 1);
  return m > 1 ? (s2 - s * s / m) / (m - 1) : 0.0;
}

// The block's pattern: the period with the largest share of exact positions, none at
// period 1 (a smooth signal is exact everywhere at period 1), and whether any position of
// any period copies a neighbour.
struct BlockPattern {
  int period = 0;
  double share = 0.0;
  bool held_positions = false;
};

BlockPattern block_pattern(const double* x, std::int64_t b, std::int64_t e, double quantum) {
  BlockPattern out;
  const double step_var = step_variance(x, b, e);
  if (!(step_var > 0.0)) return out;
  if (position_kind(x, b, e, 1, 0, quantum, step_var) != Position::kFree) return out;
  for (int P = 2; P <= kMaxPeriod; ++P) {
    int exact = 0;
    for (int c = 0; c < P; ++c) {
      const Position kind = position_kind(x, b, e, P, c, quantum, step_var);
      exact += kind == Position::kExact;
      out.held_positions = out.held_positions || kind == Position::kHeld;
    }
    const double s = static_cast<double>(exact) / P;
    if (s > out.share + 1e-12) out.share = s, out.period = P;
  }
  return out;
}

// Returns whether the periodic pattern leaves copies unexplained: positions that copy a
// neighbour (true also when no pattern was found).
bool find_periodic(const double* x, std::int64_t n, double quantum, double held_bound, RepeatedSamples& r) {
  const std::int64_t blocks = std::min<std::int64_t>(kInspectBlocks, n / kBlockSamples);
  if (blocks == 0) return true;
  bool held_positions = false;
  std::map<int, int> periods;
  double total = 0.0;
  std::int64_t first = -1, last = -1;
  for (std::int64_t k = 0; k < blocks; ++k) {
    const std::int64_t b = blocks == 1 ? 0 : k * (n - kBlockSamples) / (blocks - 1);
    const BlockPattern pattern = block_pattern(x, b, b + kBlockSamples, quantum);
    total += pattern.share;
    held_positions = held_positions || pattern.held_positions;
    if (pattern.share < RepeatedSamples::kMinRepeatedShare) continue;
    ++periods[pattern.period];
    if (first < 0) first = b;
    last = b + kBlockSamples - 1;
  }
  const double s = total / static_cast<double>(blocks);
  if (s < RepeatedSamples::kMinRepeatedShare || s + 1e-12 < r.interpolated_share) return true;
  r.interpolated_share = s;
  r.period =
      std::max_element(periods.begin(), periods.end(), [](auto& a, auto& c) { return a.second < c.second; })->first;
  r.first = first;
  r.last = last;
  // The period bounds the samples a measurement (2 for 200 -> 400 Hz, 8 for 250 -> 400 Hz)
  // more tightly than collinear triples do; copies found before stay.
  r.samples_per_measurement = std::max(held_bound, static_cast<double>(r.period));
  return held_positions;
}

bool float32_values(const double* x, std::int64_t n) {
  for (std::int64_t t = 0; t < std::min(n, kFloat32Check); ++t)
    if (static_cast<double>(static_cast<float>(x[t])) != x[t]) return false;
  return true;
}

void find_interpolated(Series sample, Series record, const Quantization& q, RepeatedSamples& r) {
  const auto [x, n] = sample;
  const double quantum = q.detected ? q.quantum : 0.0;
  const double held_bound = r.samples_per_measurement;
  if (quantum == 0.0 || second_difference_sd(x, n) >= kMinQuantaForCollinear * quantum) {
    const double relative = float32_values(x, n) ? kFloat32Collinear : kDoubleCollinear;
    const double s = collinear_share(x, 0, n, quantum, relative);
    if (s >= RepeatedSamples::kMinRepeatedShare) {
      r.interpolated_share = s;
      r.period = 1;
      std::tie(r.first, r.last) = where(
          record.n, [&](std::int64_t b, std::int64_t e) { return collinear_share(record.x, b, e, quantum, relative); });
      r.samples_per_measurement =
          std::max(held_bound, std::min(kMaxSamplesPerMeasurement, 2.0 / std::max(1e-12, 1.0 - s)));
    }
  }
  // Interpolating between two equal measurements makes zero steps too, scattered: copies
  // keep their positions in the pattern. Without such positions the zero steps are the
  // interpolation's (said in zero_step_share, not claimed as held). A slow measurement with
  // no period (three on a line) cannot tell the two apart: both are said.
  if (!find_periodic(record.x, record.n, quantum, held_bound, r) && r.held()) {
    r.held_share = 0.0;
    r.samples_per_measurement = static_cast<double>(r.period);
  }
}

// The whole repetition p a share read from the data stands for: a share puts p = 2 at
// 1.93-2.07; within kWholeSlack of a whole p it is that p, otherwise the next one up (the
// bias grows with p).
int whole_repetition(double samples_per_measurement) {
  const double nearest = std::round(samples_per_measurement);
  return static_cast<int>(
      std::abs(samples_per_measurement - nearest) <= kWholeSlack ? nearest : std::ceil(samples_per_measurement));
}

int first_clean_level(double samples_per_measurement, bool interpolated) {
  const int p = whole_repetition(samples_per_measurement);
  if (p <= 1) return 1;
  int level = 1;
  while (level < 30 &&
         repetition_wv_shortfall(p, std::int64_t{1} << level, interpolated) > RepeatedSamples::kAffectedWvBias)
    ++level;
  return level;
}

// A share as a percentage: whole from 10%, one decimal below.
std::string percent(double share) {
  const double p = 100.0 * share;
  std::ostringstream os;
  os.setf(std::ios::fixed);
  os.precision(p >= 10.0 ? 0 : 1);
  os << p << "%";
  return os.str();
}

}  // namespace

double repetition_wv_shortfall(int p, std::int64_t tau, bool interpolated) {
  if (p <= 1 || tau < 2) return 0.0;
  const std::int64_t half = tau / 2;
  double total = 0.0;
  std::vector<double> w;
  for (int phase = 0; phase < p; ++phase) {
    w.assign(static_cast<std::size_t>((tau + phase) / p + 2), 0.0);
    for (std::int64_t i = 0; i < tau; ++i) {
      const double h = (i < half ? 1.0 : -1.0) / static_cast<double>(tau);
      const std::int64_t t = i + phase, k = t / p;
      const double f = interpolated ? static_cast<double>(t % p) / p : 0.0;
      w[static_cast<std::size_t>(k)] += h * (1.0 - f);
      w[static_cast<std::size_t>(k + 1)] += h * f;
    }
    for (double v : w) total += v * v;
  }
  const double ideal = static_cast<double>(p) / static_cast<double>(tau);  // white noise of variance 1 a measurement
  return 1.0 - total / p / ideal;
}

RepeatedSamples detect_repeated_samples(const double* x, std::int64_t n) {
  RepeatedSamples r;
  if (n < 4) return r;
  std::vector<double> gathered;
  if (n > kSampledBlocks * kBlockSamples) {
    gathered.reserve(static_cast<std::size_t>(kSampledBlocks * kBlockSamples));
    for (std::int64_t k = 0; k < kSampledBlocks; ++k) {
      const std::int64_t b = k * (n - kBlockSamples) / (kSampledBlocks - 1);
      gathered.insert(gathered.end(), x + b, x + b + kBlockSamples);
    }
  }
  const Series record{x, n};
  const Series sample = gathered.empty() ? record : Series{gathered.data(), static_cast<std::int64_t>(gathered.size())};
  const Quantization q = detect_quantization(sample.x, sample.n);
  find_held(sample, record, q, r);
  if (r.held()) r.samples_per_measurement = 1.0 / std::max(1.0 / kMaxSamplesPerMeasurement, 1.0 - r.held_share);
  const RepeatedSamples held = r;
  find_interpolated(sample, record, q, r);
  if (held.held() && r.interpolated()) {  // both: where spans the two
    r.first = std::min(r.first, held.first);
    r.last = std::max(r.last, held.last);
  }
  if (r.detected()) r.first_clean_level = first_clean_level(r.samples_per_measurement, r.interpolated());
  return r;
}

std::string repeated_samples_text(const RepeatedSamples& r, const std::string& name, double freq) {
  if (!r.detected()) return "";
  std::ostringstream os;
  os << name << ": ";
  if (r.held()) {
    os << percent(r.held_share) << " of the samples copy the one before (held; " << percent(r.zero_step_share)
       << " of the steps are zero";
    if (r.expected_zero_step_share > 0.0) os << ", rounding explains " << percent(r.expected_zero_step_share);
    os << ")";
  }
  if (r.held() && r.interpolated()) os << " and ";
  if (r.interpolated()) {
    os << percent(r.interpolated_share) << (r.held() ? "" : " of the samples")
       << " are an exact linear combination of their neighbours (interpolated";
    if (r.period > 1) os << ", a pattern every " << r.period << " samples";
    os << ")";
  }
  os << ", from sample " << r.first << " to " << r.last << ": about " << significant(r.samples_per_measurement, 2)
     << " samples a measurement at most";
  const auto tau = static_cast<double>(std::int64_t{1} << r.first_clean_level);
  os << "; the WV below tau = " << significant(tau, 6) << " samples";
  if (freq > 0.0) os << " (" << significant(tau / freq, 3) << " s)";
  os << " is smoothed";
  if (r.first_clean_level > 2) os << " (levels 1-" << r.first_clean_level - 1 << ")";
  os << ": read N above it";
  return os.str();
}

int first_fit_level(const RepeatedSamples& r, const WaveletVariance& wv) {
  if (!r.detected()) return 1;
  const int p = whole_repetition(r.samples_per_measurement);
  const int first = first_level(wv), last = first + wv.levels() - 1;
  if (p <= 1 || wv.eta.size() != wv.tau.size()) return std::max(r.first_clean_level, first);
  for (int level = std::max(r.first_clean_level, first); level <= last; ++level) {
    const auto j = static_cast<std::size_t>(level - first);
    const double se = std::sqrt(2.0 / wv.eta[j]);
    const double bias = repetition_wv_shortfall(p, static_cast<std::int64_t>(wv.tau[j]), r.interpolated());
    if (std::abs(bias) <= RepeatedSamples::kFitBiasOfStandardError * se) return level;
  }
  return last;
}

}  // namespace gmwm
