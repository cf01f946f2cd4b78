// The frequency-stability deviations from phase data (deviation.h): factor checks -> one
// sum of squares per factor (the kind's differences, O(N) each) -> the deviation.
#include "gmwm/stability/deviation.h"

#include <array>
#include <cmath>
#include <string>

#include "gmwm/engine/choice.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/number_text.h"
#include "gmwm/engine/parallel.h"

namespace gmwm::stability {
namespace {

struct Named {
  DeviationKind kind;
  std::string_view name;
};
constexpr std::array<Named, 7> kKinds = {{{DeviationKind::kAdev, "adev"},
                                          {DeviationKind::kOadev, "oadev"},
                                          {DeviationKind::kMdev, "mdev"},
                                          {DeviationKind::kTdev, "tdev"},
                                          {DeviationKind::kHdev, "hdev"},
                                          {DeviationKind::kOhdev, "ohdev"},
                                          {DeviationKind::kTotdev, "totdev"}}};
constexpr std::array<DeviationKind, 7> kAll = {DeviationKind::kAdev,  DeviationKind::kOadev, DeviationKind::kMdev,
                                               DeviationKind::kTdev,  DeviationKind::kHdev,  DeviationKind::kOhdev,
                                               DeviationKind::kTotdev};

bool hadamard(DeviationKind k) { return k == DeviationKind::kHdev || k == DeviationKind::kOhdev; }

// The decades' 1-2-4 steps (Stable32's and allantools' "decade" taus).
constexpr std::array<std::int64_t, 3> kDecadeSteps = {1, 2, 4};

// Sum over i in [0, count) of (sum_k c_k x_{i + k m})^2, in long double: the squared
// differences of every overlapping estimator (c = 1, -2, 1 for the Allan variance; 1, -3,
// 3, -1 for the Hadamard), with `stride` between consecutive i (m for the non-overlapping
// ones, 1 for the overlapping).
template <std::size_t K>
long double squared_differences(std::span<const double> x, std::int64_t m, std::int64_t count, std::int64_t stride,
                                const std::array<double, K>& c) {
  long double sum = 0.0L;
  for (std::int64_t t = 0; t < count; ++t) {
    const std::int64_t i = t * stride;
    long double d = 0.0L;
    for (std::size_t k = 0; k < K; ++k)
      d += static_cast<long double>(c[k]) * x[static_cast<std::size_t>(i + static_cast<std::int64_t>(k) * m)];
    sum += d * d;
  }
  return sum;
}

constexpr std::array<double, 3> kSecond = {1.0, -2.0, 1.0};
constexpr std::array<double, 4> kThird = {-1.0, 3.0, -3.0, 1.0};

// MVAR's numerator: the inner sums of m second differences from their prefix sums.
long double modified_sum(std::span<const double> x, std::int64_t m) {
  const auto n = static_cast<std::int64_t>(x.size());
  const std::int64_t d = n - 2 * m;  // second differences x_{i+2m} - 2 x_{i+m} + x_i
  std::vector<long double> prefix(static_cast<std::size_t>(d) + 1, 0.0L);
  for (std::int64_t i = 0; i < d; ++i) {
    const auto u = static_cast<std::size_t>(i);
    prefix[u + 1] = prefix[u] + (static_cast<long double>(x[u + 2 * static_cast<std::size_t>(m)]) -
                                 2.0L * x[u + static_cast<std::size_t>(m)] + x[u]);
  }
  long double sum = 0.0L;
  for (std::int64_t j = 0; j + m <= d; ++j) {
    const long double inner = prefix[static_cast<std::size_t>(j + m)] - prefix[static_cast<std::size_t>(j)];
    sum += inner * inner;
  }
  return sum;
}

// TOTVAR's numerator: the second differences of the phase reflected at both ends, for the
// centres i = 1 .. N-2.
long double total_sum(std::span<const double> x, std::int64_t m) {
  const auto n = static_cast<std::int64_t>(x.size());
  const auto at = [&](std::int64_t i) -> long double {
    if (i < 0) return 2.0L * x.front() - x[static_cast<std::size_t>(-i)];
    if (i > n - 1) return 2.0L * x.back() - x[static_cast<std::size_t>(2 * (n - 1) - i)];
    return x[static_cast<std::size_t>(i)];
  };
  long double sum = 0.0L;
  for (std::int64_t i = 1; i <= n - 2; ++i) {
    const long double d = at(i - m) - 2.0L * at(i) + at(i + m);
    sum += d * d;
  }
  return sum;
}

// The variance of `kind` at factor m (terms(kind, N, m) >= 1).
double variance(DeviationKind kind, std::span<const double> x, std::int64_t m, double tau0) {
  const auto n = static_cast<std::int64_t>(x.size());
  const long double tau = static_cast<long double>(m) * tau0;
  const auto count = static_cast<long double>(terms(kind, n, m));
  switch (kind) {
    case DeviationKind::kAdev:
      return static_cast<double>(squared_differences(x, m, terms(kind, n, m), m, kSecond) / (2.0L * tau * tau * count));
    case DeviationKind::kOadev:
      return static_cast<double>(squared_differences(x, m, terms(kind, n, m), 1, kSecond) / (2.0L * tau * tau * count));
    case DeviationKind::kMdev:
    case DeviationKind::kTdev: {
      const long double mvar = modified_sum(x, m) / (2.0L * m * m * tau * tau * count);
      return static_cast<double>(kind == DeviationKind::kMdev ? mvar : tau * tau * mvar / 3.0L);
    }
    case DeviationKind::kHdev:
      return static_cast<double>(squared_differences(x, m, terms(kind, n, m), m, kThird) / (6.0L * tau * tau * count));
    case DeviationKind::kOhdev:
      return static_cast<double>(squared_differences(x, m, terms(kind, n, m), 1, kThird) / (6.0L * tau * tau * count));
    case DeviationKind::kTotdev:
      return static_cast<double>(total_sum(x, m) / (2.0L * tau * tau * count));
  }
  return NAN;
}

std::string text_of(double v) { return significant(v, 6); }

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

std::vector<double> phase_from_frequency(std::span<const double> y, double tau0) {
  if (!(tau0 > 0.0) || !std::isfinite(tau0))
    throw InputError("tau0: found " + text_of(tau0) + ", expected a positive, finite spacing in seconds");
  std::vector<double> x(y.size() + 1, 0.0);
  long double sum = 0.0L;
  for (std::size_t i = 0; i < y.size(); ++i) {
    if (!std::isfinite(y[i])) throw InputError("sample " + std::to_string(i) + " is not a finite number");
    sum += static_cast<long double>(y[i]) * tau0;
    x[i + 1] = static_cast<double>(sum);
  }
  return x;
}

std::int64_t min_phase_points(DeviationKind kind) { return hadamard(kind) ? 4 : 3; }

std::int64_t max_factor(DeviationKind kind, std::int64_t n) {
  if (n < min_phase_points(kind)) return 0;
  switch (kind) {
    case DeviationKind::kAdev:
    case DeviationKind::kOadev:
    case DeviationKind::kTotdev:
      return (n - 1) / 2;
    case DeviationKind::kMdev:
    case DeviationKind::kTdev:
      return n / 3;
    case DeviationKind::kHdev:
    case DeviationKind::kOhdev:
      return (n - 1) / 3;
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
      return n - 3 * m + 1;
    case DeviationKind::kHdev:
      return (n - 1) / m - 2;
    case DeviationKind::kOhdev:
      return n - 3 * m;
    case DeviationKind::kTotdev:
      return n - 2;
  }
  return 0;
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
  const std::int64_t top = max_factor(kind, phase_points);
  std::vector<std::int64_t> out;
  switch (set) {
    case TauSet::kAll:
      for (std::int64_t m = 1; m <= top; ++m) out.push_back(m);
      break;
    case TauSet::kOctave:
      for (std::int64_t m = 1; m <= top; m *= 2) out.push_back(m);
      break;
    case TauSet::kDecade:
      for (std::int64_t decade = 1; decade <= top; decade *= 10)
        for (const std::int64_t step : kDecadeSteps)
          if (step * decade <= top) out.push_back(step * decade);
      break;
  }
  return out;
}

DeviationCurve deviation(DeviationKind kind, std::span<const double> phase, double tau0,
                         std::span<const std::int64_t> m) {
  if (!(tau0 > 0.0) || !std::isfinite(tau0))
    throw InputError("tau0: found " + text_of(tau0) + ", expected a positive, finite spacing in seconds");
  const auto n = static_cast<std::int64_t>(phase.size());
  if (n < min_phase_points(kind))
    throw InputError(std::string(deviation_name(kind)) + ": found " + std::to_string(n) +
                     " phase points, expected at least " + std::to_string(min_phase_points(kind)));
  for (std::size_t i = 0; i < phase.size(); ++i)
    if (!std::isfinite(phase[i])) throw InputError("phase point " + std::to_string(i) + " is not a finite number");
  const std::int64_t top = max_factor(kind, n);
  for (const std::int64_t f : m)
    if (f < 1 || f > top)
      throw InputError(std::string(deviation_name(kind)) + ": averaging factor " + std::to_string(f) +
                       " is outside 1 .. " + std::to_string(top) + " (" + std::to_string(n) + " phase points)");
  DeviationCurve c;
  c.kind = kind;
  c.tau0 = tau0;
  c.m.assign(m.begin(), m.end());
  c.value.resize(m.size());
  gmwm::parallel_for(std::size_t{0}, m.size(),
                     [&](std::size_t k) { c.value[k] = std::sqrt(variance(kind, phase, m[k], tau0)); });
  for (const std::int64_t f : m) {
    c.tau.push_back(static_cast<double>(f) * tau0);
    c.terms.push_back(terms(kind, n, f));
  }
  return c;
}

}  // namespace gmwm::stability
