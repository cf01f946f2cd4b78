// The frequency-stability deviations from phase data (deviation.h): factor checks -> one
// sum of squares per factor (the kind's differences, O(N) each) -> the deviation. The total
// variances beyond TOTVAR, Theo1, MTIE and TIE rms have their own files (kinds_internal.h).
#include "gmwm/stability/deviation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>
#include <optional>
#include <string>

#include "gmwm/engine/choice.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/number_text.h"
#include "gmwm/engine/parallel.h"
#include "gmwm/engine/samples.h"
#include "kinds_internal.h"

namespace gmwm::stability {
namespace {

using detail::sum_of_squares;

struct Named {
  DeviationKind kind;
  std::string_view name;
};
constexpr std::array<Named, 13> kKinds = {{{DeviationKind::kAdev, "adev"},
                                           {DeviationKind::kOadev, "oadev"},
                                           {DeviationKind::kMdev, "mdev"},
                                           {DeviationKind::kTdev, "tdev"},
                                           {DeviationKind::kHdev, "hdev"},
                                           {DeviationKind::kOhdev, "ohdev"},
                                           {DeviationKind::kTotdev, "totdev"},
                                           {DeviationKind::kMtotdev, "mtotdev"},
                                           {DeviationKind::kTtotdev, "ttotdev"},
                                           {DeviationKind::kHtotdev, "htotdev"},
                                           {DeviationKind::kTheo1, "theo1"},
                                           {DeviationKind::kMtie, "mtie"},
                                           {DeviationKind::kTierms, "tierms"}}};
constexpr std::array<DeviationKind, 13> kAll = {
    DeviationKind::kAdev,    DeviationKind::kOadev,   DeviationKind::kMdev,   DeviationKind::kTdev,
    DeviationKind::kHdev,    DeviationKind::kOhdev,   DeviationKind::kTotdev, DeviationKind::kMtotdev,
    DeviationKind::kTtotdev, DeviationKind::kHtotdev, DeviationKind::kTheo1,  DeviationKind::kMtie,
    DeviationKind::kTierms};

// Theo1's factors are even and at least 10 (NIST SP 1065 eq. 30: 10 <= m <= N - 1, m even).
constexpr std::int64_t kTheo1SmallestFactor = 10;
// Theo1's averaging time is 0.75 m tau0 (NIST SP 1065 eq. 30; Stable32's "Theo1 Tau").
constexpr double kTheo1TauPerFactor = 0.75;

bool hadamard(DeviationKind k) {
  return k == DeviationKind::kHdev || k == DeviationKind::kOhdev || k == DeviationKind::kHtotdev;
}
// The smallest factor and the step between factors: Theo1's are 10, 12, 14, ...
std::int64_t smallest_factor(DeviationKind k) { return k == DeviationKind::kTheo1 ? kTheo1SmallestFactor : 1; }
std::int64_t factor_step(DeviationKind k) { return k == DeviationKind::kTheo1 ? 2 : 1; }

// The decades' 1-2-4 steps (Stable32's and allantools' "decade" taus).
constexpr std::array<std::int64_t, 3> kDecadeSteps = {1, 2, 4};

// The squared second differences x_{i+2m} - 2 x_{i+m} + x_i (the Allan variances) or third
// differences x_{i+3m} - 3 x_{i+2m} + 3 x_{i+m} - x_i (the Hadamard), summed over `count` i
// spaced `stride` apart (m for the non-overlapping estimators, 1 for the overlapping).
double second_differences(std::span<const double> x, std::int64_t m, std::int64_t count, std::int64_t stride) {
  const double* p0 = x.data();
  return sum_of_squares(
      count,
      [=](std::int64_t t) {
        const double* p = p0 + t * stride;
        return p[2 * m] - 2.0 * p[m] + p[0];
      },
      detail::reads_at(x, 0, m, 3, stride), stride);
}
double third_differences(std::span<const double> x, std::int64_t m, std::int64_t count, std::int64_t stride) {
  const double* p0 = x.data();
  return sum_of_squares(
      count,
      [=](std::int64_t t) {
        const double* p = p0 + t * stride;
        return p[3 * m] - 3.0 * p[2 * m] + 3.0 * p[m] - p[0];
      },
      detail::reads_at(x, 0, m, 4, stride), stride);
}

// MDEV's pieces start from a direct sum of m second differences; beyond this factor that
// start would cost more than an eighth of a piece's work, and the pieces run in turn instead,
// each continuing the last one's sum.
constexpr std::int64_t kLargestRestartedFactor = detail::kPieceTerms / 8;

// MVAR's numerator: the sum over j < N - 3m + 1 of S_j^2, S_j the sum of the m second
// differences d_i = x_{i+2m} - 2 x_{i+m} + x_i, i = j .. j + m - 1, each S_{j+1} from S_j
// (d_{j+m} in, d_j out: O(1) a term, on the scale of the differences whatever N), in pieces
// that read the phase where they are and release it behind them (a phase in a file).
double modified_sum(std::span<const double> x, std::int64_t m) {
  const double* p = x.data();
  const std::int64_t count = static_cast<std::int64_t>(x.size()) - 3 * m + 1;
  const auto second = [=](std::int64_t i) { return p[i + 2 * m] - 2.0 * p[i + m] + p[i]; };
  const detail::Reads reads = detail::reads_at(x, 0, m, 4, 1);
  const auto start = [&](std::int64_t j) {  // S_j directly (m up to N / 3: released as it goes)
    double s = 0.0;
    for (std::int64_t from = j; from < j + m; from += detail::kPieceTerms) {
      const std::int64_t to = std::min(j + m, from + detail::kPieceTerms);
      for (std::int64_t i = from; i < to; ++i) s += second(i);
      if ((to - j) % (detail::kReleasePieces * detail::kPieceTerms) == 0) reads.release(j, to);
    }
    return s;
  };
  const auto run = [&](std::int64_t first, std::int64_t last, double& s) {  // S_first in, S_last out
    double sum = 0.0;
    for (std::int64_t j = first; j < last; ++j) {
      sum += s * s;
      if (j + 1 < count) s += second(j + m) - second(j);
    }
    return sum;
  };
  if (m <= kLargestRestartedFactor)
    return detail::sum_in_pieces(count, detail::kPieceTerms, reads, [&](std::int64_t first, std::int64_t last) {
      double s = start(first);
      return run(first, last, s);
    });
  double s = start(0), sum = 0.0;
  for (std::int64_t first = 0; first < count; first += detail::kPieceTerms) {
    const std::int64_t last = std::min(count, first + detail::kPieceTerms);
    sum += run(first, last, s);
    if ((first / detail::kPieceTerms + 1) % detail::kReleasePieces == 0 || last == count)
      reads.release(std::max<std::int64_t>(0, last - detail::kReleasePieces * detail::kPieceTerms), last);
  }
  return sum;
}

// TOTVAR's numerator: the second differences of the phase reflected at both ends, for the
// centres i = 1 .. N-2 (the interior m .. N-1-m reads no reflection; m <= (N - 1) / 2, so a
// centre's differences reflect at one end at most).
double total_sum(std::span<const double> x, std::int64_t m) {
  const auto n = static_cast<std::int64_t>(x.size());
  const double* p = x.data();
  const auto at = [=](std::int64_t i) -> double {
    if (i < 0) return 2.0 * p[0] - p[-i];
    if (i > n - 1) return 2.0 * p[n - 1] - p[2 * (n - 1) - i];
    return p[i];
  };
  // Centres m .. n-1-m read no reflection (i - m >= 0, i + m <= n - 1).
  const std::int64_t lo = std::min(m, n - 1);
  const std::int64_t hi = std::max(lo, n - m);  // one past the last
  // Centres [from, to) near an end, reading where `reads` says (the reflected read runs backwards).
  const auto centres = [&](std::int64_t from, std::int64_t to, detail::Reads reads) {
    return sum_of_squares(
        to - from,
        [=](std::int64_t t) {
          const std::int64_t i = from + t;
          return at(i - m) - 2.0 * at(i) + at(i + m);
        },
        reads);
  };
  detail::Reads left = detail::reads_at(x, 1, m, 2, 1), interior = detail::reads_at(x, lo - m, m, 3, 1),
                right = detail::reads_at(x, hi - m, m, 2, 1);
  if (left.x != nullptr) {
    left.read[2] = {m - 1, -1};  // at(i - m) = 2 x_0 - x_{m-i}
    left.count = 3;
    right.read[2] = {2 * (n - 1) - hi - m, -1};  // at(i + m) = 2 x_{N-1} - x_{2(N-1)-i-m}
    right.count = 3;
  }
  const double inside = sum_of_squares(
      hi - lo,
      [=](std::int64_t t) {
        const double* c = p + lo + t;
        return c[m] - 2.0 * c[0] + c[-m];
      },
      interior);
  return centres(1, lo, left) + inside + centres(hi, n - 1, right);
}

// The variance of `kind` at factor m (terms(kind, N, m) >= 1).
double variance(DeviationKind kind, std::span<const double> x, std::int64_t m, double tau0) {
  const auto n = static_cast<std::int64_t>(x.size());
  const double tau = static_cast<double>(m) * tau0;
  const std::int64_t count = terms(kind, n, m);
  const double scale = tau * tau * static_cast<double>(count);
  switch (kind) {
    case DeviationKind::kAdev:
      return second_differences(x, m, count, m) / (2.0 * scale);
    case DeviationKind::kOadev:
      return second_differences(x, m, count, 1) / (2.0 * scale);
    case DeviationKind::kMdev:
    case DeviationKind::kTdev: {
      const double mvar = modified_sum(x, m) / (2.0 * static_cast<double>(m) * static_cast<double>(m) * scale);
      return kind == DeviationKind::kMdev ? mvar : tau * tau * mvar / 3.0;
    }
    case DeviationKind::kHdev:
      return third_differences(x, m, count, m) / (6.0 * scale);
    case DeviationKind::kOhdev:
      return third_differences(x, m, count, 1) / (6.0 * scale);
    case DeviationKind::kTotdev:
      return total_sum(x, m) / (2.0 * scale);
    case DeviationKind::kMtotdev:
    case DeviationKind::kTtotdev: {
      const double mtotvar = detail::modified_total_variance(x, m, tau0);
      return kind == DeviationKind::kMtotdev ? mtotvar : tau * tau * mtotvar / 3.0;
    }
    case DeviationKind::kHtotdev:  // Stable32 reads OHVAR at m = 1 (kinds_internal.h)
      return m == 1 ? third_differences(x, m, count, 1) / (6.0 * scale) : detail::hadamard_total_variance(x, m, tau0);
    case DeviationKind::kTheo1:
      return detail::theo1_variance(x, m, tau0);
    case DeviationKind::kMtie:
    case DeviationKind::kTierms:
      break;
  }
  return NAN;
}

// The deviation of `kind` at factor m: the square root of its variance, or MTIE and TIE rms.
double deviation_at(DeviationKind kind, std::span<const double> x, std::int64_t m, double tau0) {
  if (kind == DeviationKind::kMtie) return detail::max_time_interval_error(x, m);
  if (kind == DeviationKind::kTierms) return detail::time_interval_error_rms(x, m);
  return std::sqrt(variance(kind, x, m, tau0));
}

std::string text_of(double v) { return significant(v, 6); }

// The phase's spread from its first point beyond which its squared differences, summed over
// up to 1e9 terms, could overflow (above) or lose every digit to underflow (below): a double
// holds 1.8e308 and its normal numbers start at 2.2e-308, and the squares of differences of
// up to 8 x the spread, times 1e9 terms, stay inside that range for spreads in [1e-100, 1e100].
constexpr double kLargestSafeSpread = 1e100;
constexpr double kSmallestSafeSpread = 1e-100;

struct Scaled {
  Samples phase;        // the phase over its spread (empty: read as it is)
  double factor = 1.0;  // what the deviations are multiplied by
};

// One pass over the phase: its spread from the first point (the largest |x_i - x_0|), NaN
// when a point is not finite. Four lanes of extremes, so that the pass vectorizes and carries
// no chain from one point to the next (a running std::max kept in memory was 70% of an ADEV
// at 1e5 points); NaN and infinity are caught by summing (x_i - x_0) * 0, which is 0 for
// every finite point and NaN for any other.
// The lanes' extremes of x - x0 and their sum of (x - x0) * 0 over a stretch of the phase.
struct Extent {
  std::array<double, detail::kLanes> lo{}, hi{}, bad{};
  void add(const double* p, std::int64_t n, double x0) {
    std::int64_t i = 0;
    for (; i + detail::kLanes <= n; i += detail::kLanes)
      for (int l = 0; l < detail::kLanes; ++l) {
        const auto k = static_cast<std::size_t>(l);
        const double v = p[i + l] - x0;
        lo[k] = v < lo[k] ? v : lo[k];
        hi[k] = v > hi[k] ? v : hi[k];
        bad[k] += v * 0.0;
      }
    for (; i < n; ++i) {
      const double v = p[i] - x0;
      lo[0] = v < lo[0] ? v : lo[0];
      hi[0] = v > hi[0] ? v : hi[0];
      bad[0] += v * 0.0;
    }
  }
};

double spread_or_nan(std::span<const double> x) {
  const double x0 = x.front();
  std::vector<Extent> part(1);
  // Extremes and sums of zeros are exact, so neither the pieces nor their order change the
  // result: in parallel pieces in memory, block by block for a phase in a file (released
  // behind the pass: samples.h).
  if (gmwm::detail::in_sample_file(x.data(), x.size())) {
    gmwm::for_each_block(x, [&](std::span<const double> b, std::size_t) {
      part[0].add(b.data(), static_cast<std::int64_t>(b.size()), x0);
    });
  } else {
    const auto n = static_cast<std::int64_t>(x.size());
    part.resize(static_cast<std::size_t>((n + detail::kPieceTerms - 1) / detail::kPieceTerms));
    gmwm::parallel_for(std::size_t{0}, part.size(), [&](std::size_t k) {
      const auto first = static_cast<std::int64_t>(k) * detail::kPieceTerms;
      part[k].add(x.data() + first, std::min(detail::kPieceTerms, n - first), x0);
    });
  }
  double spread = 0.0, check = 0.0;
  for (const Extent& e : part)
    for (std::size_t k = 0; k < e.lo.size(); ++k) {
      spread = std::max({spread, -e.lo[k], e.hi[k]});
      check += e.bad[k];
    }
  return check == 0.0 ? spread : NAN;
}

// Checks every point finite (InputError naming the first that is not) and scales a phase
// whose spread is outside the safe range.
Scaled checked_scaled_phase(std::span<const double> x) {
  const double spread = spread_or_nan(x);
  if (std::isnan(spread))
    for (std::size_t i = 0; i < x.size(); ++i)
      if (!std::isfinite(x[i])) throw InputError("phase point " + std::to_string(i) + " is not a finite number");
  if (std::isnan(spread))  // finite points whose differences overflow
    throw InputError("phase: points differ by more than a double holds (1.8e308)");
  Scaled s;
  if (spread == 0.0 || (spread <= kLargestSafeSpread && spread >= kSmallestSafeSpread)) return s;
  s.factor = spread;
  // In a temporary file when the phase is in one (samples.h), else in memory.
  const bool file = gmwm::detail::in_sample_file(x.data(), x.size());
  std::optional<SampleFileWriter> writer;
  if (file) writer.emplace();
  std::vector<double> memory;
  gmwm::for_each_block(x, [&](std::span<const double> part, std::size_t) {
    std::vector<double> block(part.size());
    for (std::size_t i = 0; i < part.size(); ++i) block[i] = (part[i] - x.front()) / spread;
    if (file)
      writer->append(block.data(), block.size());
    else
      memory.insert(memory.end(), block.begin(), block.end());
  });
  s.phase = file ? writer->finish() : Samples(std::move(memory));
  return s;
}

}  // namespace

std::span<const DeviationKind> deviation_kinds() { return kAll; }

std::string_view deviation_name(DeviationKind kind) {
  for (const Named& k : kKinds)
    if (k.kind == kind) return k.name;
  return "unknown";
}

std::optional<DeviationKind> deviation_from_name(std::string_view name) {
  for (const Named& k : kKinds)
    if (k.name == name) return k.kind;
  return std::nullopt;
}

DeviationKind deviation_of(const std::string& text) {
  if (const auto k = deviation_from_name(text)) return *k;
  std::vector<std::string> names;
  for (const Named& k : kKinds) names.emplace_back(k.name);
  throw InputError("--kind: " + unknown_choice(text, names));
}

std::int64_t min_phase_points(DeviationKind kind) {
  switch (kind) {
    case DeviationKind::kTheo1:
      return kTheo1SmallestFactor + 1;
    case DeviationKind::kMtie:
    case DeviationKind::kTierms:
      return 2;
    default:
      return hadamard(kind) ? 4 : 3;
  }
}

std::int64_t max_factor(DeviationKind kind, std::int64_t n) {
  if (n < min_phase_points(kind)) return 0;
  switch (kind) {
    case DeviationKind::kAdev:
    case DeviationKind::kOadev:
    case DeviationKind::kTotdev:
      return (n - 1) / 2;
    case DeviationKind::kMdev:
    case DeviationKind::kTdev:
    case DeviationKind::kMtotdev:
    case DeviationKind::kTtotdev:
      return n / 3;
    case DeviationKind::kHdev:
    case DeviationKind::kOhdev:
    case DeviationKind::kHtotdev:
      return (n - 1) / 3;
    case DeviationKind::kTheo1:
      return (n - 1) / 2 * 2;  // the largest even factor below N
    case DeviationKind::kMtie:
    case DeviationKind::kTierms:
      return n - 1;
  }
  return 0;
}

std::int64_t terms(DeviationKind kind, std::int64_t n, std::int64_t m) {
  switch (kind) {
    case DeviationKind::kAdev:
      return (n - 1) / m - 1;
    case DeviationKind::kOadev:
      return n - 2 * m;
    case DeviationKind::kMdev:
    case DeviationKind::kTdev:
    case DeviationKind::kMtotdev:
    case DeviationKind::kTtotdev:
      return n - 3 * m + 1;
    case DeviationKind::kHdev:
      return (n - 1) / m - 2;
    case DeviationKind::kOhdev:
    case DeviationKind::kHtotdev:
      return n - 3 * m;
    case DeviationKind::kTotdev:
      return n - 2;
    case DeviationKind::kTheo1:
      return (n - m) * (m / 2);
    case DeviationKind::kMtie:
    case DeviationKind::kTierms:
      return n - m;
  }
  return 0;
}

double factor_work(DeviationKind kind, std::int64_t n, std::int64_t m) {
  const auto points = static_cast<double>(n);
  switch (kind) {
    case DeviationKind::kAdev:
    case DeviationKind::kHdev:
      return points / static_cast<double>(std::max<std::int64_t>(m, 1));
    case DeviationKind::kTheo1: {
      // Its (N - m) m / 2 terms summed directly (about two points' time each) up to m = 256;
      // beyond, through correlations, about 7 log2(m)^2 points' time a point (13 ms a factor
      // near m = 16000 on 65537 points, against OADEV's 0.14 ns a point; tools/bench/RESULTS.md).
      constexpr double kDirectTermWork = 2.0, kCorrelationWork = 7.0;
      constexpr std::int64_t kLargestDirect = 256;
      const auto mm = static_cast<double>(m);
      if (m <= kLargestDirect) return points * kDirectTermWork * mm / 2.0;
      return points * kCorrelationWork * std::log2(mm) * std::log2(mm);
    }
    default:
      return points;
  }
}

bool in_time_units(DeviationKind kind) {
  return kind == DeviationKind::kTdev || kind == DeviationKind::kTtotdev || kind == DeviationKind::kMtie ||
         kind == DeviationKind::kTierms;
}

double averaging_time(DeviationKind kind, std::int64_t m, double tau0) {
  return (kind == DeviationKind::kTheo1 ? kTheo1TauPerFactor : 1.0) * static_cast<double>(m) * tau0;
}

std::string_view tau_set_name(TauSet set) {
  switch (set) {
    case TauSet::kAll:
      return "all";
    case TauSet::kOctave:
      return "octave";
    case TauSet::kDecade:
      return "decade";
  }
  return "unknown";
}

std::optional<TauSet> tau_set_from_name(std::string_view name) {
  for (const TauSet s : {TauSet::kAll, TauSet::kOctave, TauSet::kDecade})
    if (tau_set_name(s) == name) return s;
  return std::nullopt;
}

std::vector<std::int64_t> factors(TauSet set, DeviationKind kind, std::int64_t phase_points) {
  const std::int64_t top = max_factor(kind, phase_points), smallest = smallest_factor(kind);
  std::vector<std::int64_t> out;
  switch (set) {
    case TauSet::kAll:
      for (std::int64_t m = smallest; m <= top; m += factor_step(kind)) out.push_back(m);
      break;
    case TauSet::kOctave:
      // MTIE's are Stable32's windows of 2^k points (m = 2^k - 1); Theo1's start at 10.
      for (std::int64_t m = smallest; m <= top; m = kind == DeviationKind::kMtie ? 2 * m + 1 : 2 * m) out.push_back(m);
      break;
    case TauSet::kDecade:
      for (std::int64_t decade = 1; decade <= top; decade *= 10)
        for (const std::int64_t step : kDecadeSteps)
          if (step * decade <= top && step * decade >= smallest) out.push_back(step * decade);
      break;
  }
  return out;
}

DeviationCurve deviation(DeviationKind kind, std::span<const double> phase, double tau0,
                         std::span<const std::int64_t> m, const FactorProgress& progress) {
  if (!(tau0 > 0.0) || !std::isfinite(tau0))
    throw InputError("tau0: found " + text_of(tau0) + ", expected a positive, finite spacing in seconds");
  const auto n = static_cast<std::int64_t>(phase.size());
  if (n < min_phase_points(kind))
    throw InputError(std::string(deviation_name(kind)) + ": found " + std::to_string(n) +
                     " phase points, expected at least " + std::to_string(min_phase_points(kind)));
  const std::int64_t top = max_factor(kind, n), smallest = smallest_factor(kind);
  for (const std::int64_t f : m)
    if (f < smallest || f > top || (f - smallest) % factor_step(kind) != 0)
      throw InputError(std::string(deviation_name(kind)) + ": averaging factor " + std::to_string(f) + " is outside " +
                       (factor_step(kind) == 1 ? "" : "the even factors ") + std::to_string(smallest) + " .. " +
                       std::to_string(top) + " (" + std::to_string(n) + " phase points)");
  DeviationCurve c;
  c.kind = kind;
  c.tau0 = tau0;
  c.m.assign(m.begin(), m.end());
  c.value.resize(m.size());
  // Every deviation is linear in the phase: one far from 1 is read scaled to 1 and scaled back.
  const Scaled scaled = checked_scaled_phase(phase);
  const std::span<const double> x = scaled.phase.empty() ? phase : std::span<const double>(scaled.phase);
  // A phase in a temporary file is released after each factor (the pieces release the pages
  // they pass; this, the few a piece's ends share with the next).
  const bool file = gmwm::detail::in_sample_file(x.data(), x.size());
  std::mutex told;  // progress is told one factor at a time
  std::size_t done = 0;
  gmwm::parallel_for(std::size_t{0}, m.size(), [&](std::size_t k) {
    c.value[k] = deviation_at(kind, x, m[k], tau0) * scaled.factor;
    if (file) gmwm::detail::release_file_pages(x.data(), x.data() + x.size());
    if (progress) {
      const std::lock_guard<std::mutex> lock(told);
      progress(++done, m.size());
    }
  });
  for (const std::int64_t f : m) {
    c.tau.push_back(averaging_time(kind, f, tau0));
    c.terms.push_back(terms(kind, n, f));
  }
  return c;
}

}  // namespace gmwm::stability
