#include "gmwm/engine/physical.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "gmwm/engine/check.h"
#include "gmwm/engine/process.h"

namespace gmwm {
namespace {

/// A quantity depending jointly on more parameters than this is refused by
/// physical_interval (3^k evaluations; the processes here depend on at most 2).
constexpr std::size_t kMaxJointParameters = 8;

struct Factor {
  std::string text;
  bool denominator = false;
};

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

/// Factors of a unit, split at '*' and '/' outside parentheses. `invert` flips them all.
std::vector<Factor> split_factors(const std::string& unit, bool invert) {
  std::vector<Factor> out;
  std::string cur;
  bool den = false;
  int depth = 0;
  auto flush = [&] {
    std::string t = trim(cur);
    if (!t.empty()) out.push_back({t, den != invert});
    cur.clear();
  };
  for (char c : unit) {
    if (c == '(') ++depth;
    if (c == ')') --depth;
    if (depth == 0 && (c == '*' || c == '/')) {
      flush();
      den = (c == '/');
    } else {
      cur += c;
    }
  }
  flush();
  return out;
}

/// n when the factor is "s" or "s^n" (integer n), else nothing.
std::optional<int> seconds_power(const std::string& f) {
  if (f == "s") return 1;
  if (f.size() < 3 || f[0] != 's' || f[1] != '^') return std::nullopt;
  std::size_t pos = 0;
  try {
    const int n = std::stoi(f.substr(2), &pos);
    if (pos == f.size() - 2) return n;
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

std::string seconds_factor(int n) { return n == 1 ? "s" : "s^" + std::to_string(n); }

bool same_value(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

}  // namespace

double quantity_of_kind(const std::vector<PhysicalQuantity>& q, PhysicalKind kind) {
  for (const PhysicalQuantity& x : q)
    if (x.kind == kind) return x.value;
  return std::nan("");
}

std::string render_unit(const std::string& pattern, const std::string& data_unit) {
  std::vector<Factor> factors;
  for (const Factor& f : split_factors(pattern, false)) {
    if (f.text == "U") {
      for (Factor& d : split_factors(data_unit, f.denominator)) factors.push_back(std::move(d));
    } else {
      factors.push_back(f);
    }
  }
  int seconds = 0;
  std::vector<std::string> num, den;
  for (const Factor& f : factors) {
    if (f.text == "1") continue;
    if (const auto n = seconds_power(f.text)) {
      seconds += f.denominator ? -*n : *n;
    } else {
      (f.denominator ? den : num).push_back(f.text);
    }
  }
  if (seconds > 0) num.push_back(seconds_factor(seconds));
  if (seconds < 0) den.insert(den.begin(), seconds_factor(-seconds));
  std::string out;
  for (const std::string& n : num) {
    if (!out.empty()) out.push_back('*');
    out.append(n);
  }
  if (out.empty() && !den.empty()) out.push_back('1');
  for (const std::string& d : den) {
    out.push_back('/');
    out.append(d);
  }
  return out;
}

std::vector<PhysicalQuantity> Process::physical(std::span<const double> theta, double freq) const {
  check_size_match("Process::physical", "theta", theta.size(), "parameters of " + name(), parameters().size());
  check_positive("Process::physical", "freq", freq);
  return physical_impl(theta, freq);
}

std::vector<PhysicalQuantity> Process::physical_impl(std::span<const double> theta, double) const {
  std::vector<PhysicalQuantity> out;
  const auto& specs = parameters();
  for (std::size_t k = 0; k < specs.size(); ++k)
    out.push_back({specs[k].name, theta[k], "",
                   "discrete (per-sample) parameter, no standard physical counterpart: " + specs[k].meaning});
  return out;
}

std::vector<PhysicalInterval> physical_interval(const Process& process, std::span<const double> theta,
                                                std::span<const double> ci_low, std::span<const double> ci_high,
                                                double freq) {
  constexpr const char* kFn = "physical_interval";
  check_size_match(kFn, "ci_low", ci_low.size(), "theta", theta.size());
  check_size_match(kFn, "ci_high", ci_high.size(), "theta", theta.size());
  const std::vector<PhysicalQuantity> base = process.physical(theta, freq);
  const std::size_t np = theta.size(), nq = base.size();

  // Candidate values of each parameter: its bounds, plus 0 when strictly inside.
  std::vector<std::vector<double>> candidates(np);
  for (std::size_t k = 0; k < np; ++k) {
    const double lo = ci_low[k], hi = ci_high[k];
    if (lo > hi) {
      std::ostringstream req;
      req.precision(17);
      req << "at most ci_high[" << k << "] = " << hi;
      detail::throw_check(kFn, "ci_low[" + std::to_string(k) + "]", lo, req.str());
    }
    candidates[k] = {lo, hi};
    if (lo < 0.0 && hi > 0.0) candidates[k].push_back(0.0);
  }

  std::vector<double> t(theta.begin(), theta.end());
  auto evaluate = [&]() {
    std::vector<PhysicalQuantity> q = process.physical(t, freq);
    if (q.size() != nq)
      throw std::logic_error(process.name() + "::physical returned a theta-dependent number of quantities");
    return q;
  };

  // Which parameters each quantity depends on: those whose candidates change it.
  std::vector<std::vector<std::size_t>> depends(nq);
  for (std::size_t k = 0; k < np; ++k) {
    std::vector<bool> changed(nq, false);
    for (double c : candidates[k]) {
      t[k] = c;
      const auto q = evaluate();
      for (std::size_t i = 0; i < nq; ++i)
        if (!same_value(q[i].value, base[i].value)) changed[i] = true;
    }
    t[k] = theta[k];
    for (std::size_t i = 0; i < nq; ++i)
      if (changed[i]) depends[i].push_back(k);
  }

  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<PhysicalInterval> out(nq);
  for (std::size_t i = 0; i < nq; ++i) {
    const auto& dep = depends[i];
    if (dep.size() > kMaxJointParameters)
      detail::throw_check(kFn, "the number of parameters of quantity '" + base[i].name + "'",
                          static_cast<double>(dep.size()), "at most " + std::to_string(kMaxJointParameters));
    bool unknown = false;
    for (std::size_t k : dep)
      for (double c : candidates[k]) unknown = unknown || std::isnan(c);
    if (unknown) {
      out[i] = {nan, nan};
      continue;
    }
    double lo = std::isnan(base[i].value) ? INFINITY : base[i].value;
    double hi = std::isnan(base[i].value) ? -INFINITY : base[i].value;
    // Every combination of the candidates of the parameters it depends on (mixed radix).
    std::vector<std::size_t> idx(dep.size(), 0);
    while (true) {
      for (std::size_t d = 0; d < dep.size(); ++d) t[dep[d]] = candidates[dep[d]][idx[d]];
      const double v = evaluate()[i].value;
      if (!std::isnan(v)) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
      std::size_t d = 0;
      while (d < dep.size() && ++idx[d] == candidates[dep[d]].size()) idx[d++] = 0;
      if (d == dep.size()) break;
    }
    for (std::size_t k : dep) t[k] = theta[k];
    out[i] = lo <= hi ? PhysicalInterval{lo, hi} : PhysicalInterval{nan, nan};
  }
  return out;
}

}  // namespace gmwm
