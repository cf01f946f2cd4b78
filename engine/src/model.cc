#include "gmwm/engine/model.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <sstream>

#include "gmwm/engine/check.h"
#include "gmwm/engine/number_text.h"

namespace gmwm {

Model::Model(std::vector<Component> components) : components_(std::move(components)) {
  offsets_.reserve(components_.size());
  for (auto& c : components_) {
    offsets_.push_back(num_parameters_);
    if (c.given.empty())
      c.given.assign(static_cast<std::size_t>(c.process->size()), std::numeric_limits<double>::quiet_NaN());
    num_parameters_ += c.process->size();
  }
}

bool Model::fully_specified() const {
  for (const auto& c : components_)
    for (double v : c.given)
      if (std::isnan(v)) return false;
  return true;
}

Eigen::VectorXd Model::given_values() const {
  Eigen::VectorXd theta(num_parameters_);
  for (int c = 0; c < num_components(); ++c)
    for (int k = 0; k < components_[c].process->size(); ++k)
      theta(offset(c) + k) = components_[c].given[static_cast<std::size_t>(k)];
  return theta;
}

namespace {
std::span<const double> slice(const Eigen::VectorXd& theta, int off, int len) {
  return {theta.data() + off, static_cast<std::size_t>(len)};
}
}  // namespace

std::string Model::validate(const Eigen::VectorXd& theta) const {
  if (theta.size() != num_parameters_)
    return "model takes " + std::to_string(num_parameters_) + " parameters, got " + std::to_string(theta.size());
  for (int c = 0; c < num_components(); ++c) {
    const auto& p = *components_[c].process;
    std::string why = p.validate(slice(theta, offset(c), p.size()));
    if (!why.empty()) return "component " + std::to_string(c + 1) + " (" + p.name() + "): " + why;
  }
  return {};
}

Eigen::VectorXd Model::wv(const Eigen::VectorXd& theta, std::span<const double> tau) const {
  check_size_match("Model::wv", "theta", static_cast<std::size_t>(theta.size()), "parameters",
                   static_cast<std::size_t>(num_parameters_));
  Eigen::VectorXd total = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(tau.size()));
  Eigen::VectorXd part(total.size());
  for (int c = 0; c < num_components(); ++c) {
    const auto& p = *components_[c].process;
    p.wv(slice(theta, offset(c), p.size()), tau, {part.data(), tau.size()});
    total += part;
  }
  return total;
}

Eigen::MatrixXd Model::jacobian(const Eigen::VectorXd& theta, std::span<const double> tau) const {
  const auto J = static_cast<Eigen::Index>(tau.size());
  Eigen::MatrixXd jac(J, num_parameters_);
  for (int c = 0; c < num_components(); ++c) {
    const auto& p = *components_[c].process;
    p.wv_jacobian(slice(theta, offset(c), p.size()), tau, jac.middleCols(offset(c), p.size()));
  }
  return jac;
}

void Model::wv_and_jacobian(const Eigen::VectorXd& theta, std::span<const double> tau, Eigen::VectorXd& nu,
                            Eigen::MatrixXd& jac) const {
  check_size_match("Model::wv_and_jacobian", "theta", static_cast<std::size_t>(theta.size()), "parameters",
                   static_cast<std::size_t>(num_parameters_));
  const auto J = static_cast<Eigen::Index>(tau.size());
  // The components' WVs summed in wv()'s order, from zero: the same sum to the bit.
  nu = Eigen::VectorXd::Zero(J);
  jac.resize(J, num_parameters_);
  Eigen::VectorXd part(J);
  for (int c = 0; c < num_components(); ++c) {
    const auto& p = *components_[c].process;
    p.wv_and_jacobian(slice(theta, offset(c), p.size()), tau, {part.data(), tau.size()},
                      jac.middleCols(offset(c), p.size()));
    nu += part;
  }
}

std::vector<Eigen::MatrixXd> Model::hessians(const Eigen::VectorXd& theta, std::span<const double> tau) const {
  const auto J = static_cast<Eigen::Index>(tau.size());
  std::vector<Eigen::MatrixXd> out(tau.size(), Eigen::MatrixXd::Zero(num_parameters_, num_parameters_));
  for (int c = 0; c < num_components(); ++c) {
    const auto& p = *components_[c].process;
    const int k = p.size();
    Eigen::MatrixXd h(J, k * k);
    p.wv_hessian(slice(theta, offset(c), k), tau, h);
    for (Eigen::Index j = 0; j < J; ++j)
      for (int l = 0; l < k; ++l)
        for (int m = 0; m < k; ++m) out[static_cast<std::size_t>(j)](offset(c) + l, offset(c) + m) = h(j, l * k + m);
  }
  return out;
}

Eigen::VectorXd Model::to_unconstrained(const Eigen::VectorXd& theta) const {
  Eigen::VectorXd u(theta.size());
  for (int k = 0; k < num_parameters_; ++k) {
    const ParameterSpec& s = spec_of(k);
    u(k) = gmwm::to_unconstrained(s.transform, s.signed_magnitude ? std::abs(theta(k)) : theta(k));
  }
  return u;
}

Eigen::VectorXd Model::scaled(const Eigen::VectorXd& theta, double c) const {
  Eigen::VectorXd out = theta;
  for (int j = 0; j < num_components(); ++j) {
    const Process& p = *components()[static_cast<std::size_t>(j)].process;
    const std::vector<double> s = p.scaled({theta.data() + offset(j), static_cast<std::size_t>(p.size())}, c);
    for (int k = 0; k < p.size(); ++k) out(offset(j) + k) = s[static_cast<std::size_t>(k)];
  }
  return out;
}

Eigen::VectorXd Model::from_unconstrained(const Eigen::VectorXd& u) const {
  Eigen::VectorXd theta(u.size());
  for (int k = 0; k < num_parameters_; ++k) theta(k) = gmwm::from_unconstrained(spec_of(k).transform, u(k));
  return theta;
}

Eigen::VectorXd Model::dtheta_du(const Eigen::VectorXd& u) const {
  Eigen::VectorXd d(u.size());
  for (int k = 0; k < num_parameters_; ++k) d(k) = dnatural_du(spec_of(k).transform, u(k));
  return d;
}

Model Model::canonical(Eigen::VectorXd* theta, std::vector<int>* permutation) const {
  std::vector<int> order(components_.size());
  std::iota(order.begin(), order.end(), 0);
  auto key = [&](int c) {
    const auto& p = *components_[c].process;
    double sk = 0.0;
    if (p.sort_key() >= 0) {
      if (theta)
        sk = (*theta)(offset(c) + p.sort_key());
      else
        sk = components_[c].given[static_cast<std::size_t>(p.sort_key())];
      if (std::isnan(sk)) sk = std::numeric_limits<double>::infinity();
    }
    return std::make_tuple(p.canonical_rank(), p.structure(), sk);
  };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key(a) < key(b); });
  std::vector<Component> comps;
  comps.reserve(order.size());
  Eigen::VectorXd sorted(theta ? theta->size() : 0);
  int pos = 0;
  for (int c : order) {
    comps.push_back(components_[c]);
    if (theta) {
      const int k = components_[c].process->size();
      sorted.segment(pos, k) = theta->segment(offset(c), k);
      pos += k;
    }
  }
  if (theta) *theta = sorted;
  if (permutation) *permutation = order;
  return Model(std::move(comps));
}

namespace {
std::string head(const Process& p) {
  std::string s = p.name();
  if (!p.structure().empty()) {
    s += '(';
    s += p.structure();
    s += ')';
  }
  return s;
}
}  // namespace

std::string Model::to_string() const {
  std::ostringstream os;
  for (std::size_t c = 0; c < components_.size();) {
    const std::string h = head(*components_[c].process);
    std::size_t r = c + 1;
    while (r < components_.size() && head(*components_[r].process) == h) ++r;
    if (c) os << "+";
    if (r - c > 1) os << (r - c) << "*";
    os << h;
    c = r;
  }
  return os.str();
}

std::string Model::to_string(const Eigen::VectorXd& theta) const {
  std::ostringstream os;
  os.precision(17);
  for (int c = 0; c < num_components(); ++c) {
    const auto& p = *components_[c].process;
    if (c) os << "+";
    os << p.name() << "(";
    bool first = true;
    if (!p.structure().empty()) {
      os << p.structure();
      first = false;
    }
    for (int k = 0; k < p.size(); ++k) {
      os << (first ? "" : ",") << p.parameters()[static_cast<std::size_t>(k)].name << "="
         << p.to_display(k, theta(offset(c) + k));
      first = false;
    }
    os << ")";
  }
  return os.str();
}

int Model::component_of(int k) const {
  int c = 0;
  while (c + 1 < num_components() && offsets_[static_cast<std::size_t>(c + 1)] <= k) ++c;
  return c;
}

const ParameterSpec& Model::spec_of(int k) const {
  const int c = component_of(k);
  return components_[c].process->parameters()[static_cast<std::size_t>(k - offset(c))];
}

std::string Model::parameter_label(int k) const {
  const int c = component_of(k);
  return components_[c].process->name() + "[" + std::to_string(c + 1) + "]." + spec_of(k).name;
}

Model operator+(const Model& a, const Model& b) {
  std::vector<Component> c = a.components();
  c.insert(c.end(), b.components().begin(), b.components().end());
  return Model(std::move(c));
}

std::string component_text(const Model& model, int c, const Eigen::VectorXd& theta, int digits) {
  const Process& p = *model.components()[static_cast<std::size_t>(c)].process;
  std::string s = p.name() + (p.structure().empty() ? "" : "[" + p.structure() + "]") + "(";
  const auto& specs = p.parameters();
  for (std::size_t k = 0; k < specs.size(); ++k) {
    s += (k ? "," : "") + specs[k].name + "=" +
         significant(p.to_display(static_cast<int>(k), theta(model.offset(c) + static_cast<int>(k))), digits);
  }
  return s + ")";
}

}  // namespace gmwm
