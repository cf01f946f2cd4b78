#include "gmwm/engine/process.h"

#include <cmath>
#include <sstream>

#include "gmwm/engine/process_registry.h"

namespace gmwm {

double to_unconstrained(Transform t, double x) {
  switch (t) {
    case Transform::kLog:
      return std::log(x);
    case Transform::kAtanh:
      return std::atanh(x);
    case Transform::kIdentity:
      return x;
    case Transform::kLogitHalf: {
      const double p = 2.0 * x;
      return std::log(p / (1.0 - p));
    }
  }
  return x;
}

double from_unconstrained(Transform t, double u) {
  switch (t) {
    case Transform::kLog:
      return std::exp(u);
    case Transform::kAtanh:
      return std::tanh(u);
    case Transform::kIdentity:
      return u;
    case Transform::kLogitHalf:
      return 0.5 / (1.0 + std::exp(-u));
  }
  return u;
}

double dnatural_du(Transform t, double u) {
  switch (t) {
    case Transform::kLog:
      return std::exp(u);
    case Transform::kAtanh: {
      const double c = std::cosh(u);
      return 1.0 / (c * c);
    }
    case Transform::kIdentity:
      return 1.0;
    case Transform::kLogitHalf: {
      const double s = 1.0 / (1.0 + std::exp(-u));
      return 0.5 * s * (1.0 - s);
    }
  }
  return 1.0;
}

double d2natural_du2(Transform t, double u) {
  switch (t) {
    case Transform::kLog:
      return std::exp(u);
    case Transform::kAtanh: {
      const double th = std::tanh(u);
      return -2.0 * th * (1.0 - th * th);
    }
    case Transform::kIdentity:
      return 0.0;
    case Transform::kLogitHalf: {
      const double s = 1.0 / (1.0 + std::exp(-u));
      return 0.5 * s * (1.0 - s) * (1.0 - 2.0 * s);
    }
  }
  return 0.0;
}

std::string Process::validate(std::span<const double> theta) const {
  // The message is formatted only on failure: a stream per parameter (its locale set-up
  // and facet look-ups) was 1% of a selection's CPU, which validates every projection
  // (issue 44).
  const auto message = [](const auto&... parts) {
    std::ostringstream os;
    os.precision(17);
    (os << ... << parts);
    return os.str();
  };
  const auto& specs = parameters();
  if (theta.size() != specs.size()) return message(name(), " takes ", specs.size(), " parameters, got ", theta.size());
  for (std::size_t k = 0; k < specs.size(); ++k) {
    const double x = theta[k];
    const std::string& p = specs[k].name;
    if (!std::isfinite(x)) return message(p, " must be finite (got ", x, ")");
    switch (specs[k].transform) {
      case Transform::kLog:
        if (specs[k].signed_magnitude) {
          if (x == 0.0) return message(p, " must be non-zero (got 0)");
        } else if (!(x > 0.0)) {
          return message(p, " must be positive (got ", x, ")");
        }
        break;
      case Transform::kAtanh:
        if (!(x > -1.0 && x < 1.0)) return message(p, " must be in (-1, 1) (got ", x, ")");
        break;
      case Transform::kLogitHalf:
        if (!(x > 0.0 && x < 0.5)) return message(p, " must be in (0, 0.5) cycles/sample (got ", x, ")");
        break;
      case Transform::kIdentity:
        break;
    }
  }
  return {};
}

std::optional<std::vector<double>> Process::represent(const Process& other, std::span<const double> other_theta) const {
  if (!same_process(*this, other)) return std::nullopt;
  return std::vector<double>(other_theta.begin(), other_theta.end());
}

std::vector<SimplerForm> Process::simpler_forms(std::span<const double> theta) const {
  (void)theta;
  return {};
}

std::vector<std::vector<double>> Process::shape_family(std::span<const double> theta,
                                                       std::span<const double> tau) const {
  (void)tau;
  return {std::vector<double>(theta.begin(), theta.end())};
}

std::optional<std::vector<double>> Process::merged(std::span<const double> a, std::span<const double> b) const {
  (void)a;
  (void)b;
  return std::nullopt;
}

std::vector<double> Process::scaled(std::span<const double> theta, double c) const {
  std::vector<double> out(theta.begin(), theta.end());
  const auto& specs = parameters();
  for (std::size_t k = 0; k < out.size() && k < specs.size(); ++k)
    if (specs[k].transform == Transform::kLog) out[k] *= c;
  return out;
}

const char* to_string(ProcessRole r) {
  switch (r) {
    case ProcessRole::kWhite:
      return "white";
    case ProcessRole::kQuantization:
      return "quantization";
    case ProcessRole::kWalk:
      return "walk";
    case ProcessRole::kDrift:
      return "drift";
    case ProcessRole::kBias:
      return "bias";
    case ProcessRole::kFlicker:
      return "flicker";
    case ProcessRole::kPeriodic:
      return "periodic";
    case ProcessRole::kOther:
      return "other";
  }
  return "other";
}

bool single_per_model(ProcessRole r) {
  return r == ProcessRole::kWhite || r == ProcessRole::kQuantization || r == ProcessRole::kWalk ||
         r == ProcessRole::kDrift;
}

ProcessPtr make_process(const std::string& name, const ProcessContext& context) {
  ProcessArgs args;
  args.context = context;
  return ProcessRegistry::instance().create(name, args);
}

bool same_process(const Process& a, const Process& b) { return a.name() == b.name() && a.structure() == b.structure(); }

}  // namespace gmwm
