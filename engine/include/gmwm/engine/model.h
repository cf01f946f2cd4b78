#pragma once
// A latent model: a sum of independent processes. theta is the concatenation of the
// components' natural parameters in component order.

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gmwm/engine/process.h"

namespace gmwm {

struct Component {
  ProcessPtr process;
  /// Values given in the model string (natural space), NaN where not given.
  std::vector<double> given;
};

class Model {
 public:
  Model() = default;
  explicit Model(std::vector<Component> components);

  const std::vector<Component>& components() const { return components_; }
  int num_components() const { return static_cast<int>(components_.size()); }
  int num_parameters() const { return num_parameters_; }
  /// Offset of component c's parameters in theta.
  int offset(int c) const { return offsets_[static_cast<std::size_t>(c)]; }
  /// True when every parameter has a given value.
  bool fully_specified() const;
  /// The given values as a theta vector (NaN where not given).
  Eigen::VectorXd given_values() const;

  /// Empty when theta is valid for every component, else "component k (AR1): reason".
  std::string validate(const Eigen::VectorXd& theta) const;

  Eigen::VectorXd wv(const Eigen::VectorXd& theta, std::span<const double> tau) const;
  /// J x p Jacobian in natural parameters.
  Eigen::MatrixXd jacobian(const Eigen::VectorXd& theta, std::span<const double> tau) const;
  /// wv and jacobian at one point, the same to the bit as each apart (Process::wv_and_jacobian).
  void wv_and_jacobian(const Eigen::VectorXd& theta, std::span<const double> tau, Eigen::VectorXd& nu,
                       Eigen::MatrixXd& jac) const;
  /// Per level, the p x p Hessian (block-diagonal across components), stored as
  /// hess[j](l, m).
  std::vector<Eigen::MatrixXd> hessians(const Eigen::VectorXd& theta, std::span<const double> tau) const;

  /// Natural <-> unconstrained (component-wise transforms).
  Eigen::VectorXd to_unconstrained(const Eigen::VectorXd& theta) const;
  Eigen::VectorXd from_unconstrained(const Eigen::VectorXd& u) const;
  /// d theta / d u (diagonal), at u.
  Eigen::VectorXd dtheta_du(const Eigen::VectorXd& u) const;
  /// theta for the data multiplied by sqrt(c) (c > 0), component by component
  /// (Process::scaled): the WV is c times theta's.
  Eigen::VectorXd scaled(const Eigen::VectorXd& theta, double c) const;

  /// Components sorted canonically (docs/cli.md order; repeated components by their sort
  /// key, e.g. AR1 by increasing phi). Returns the permutation of components applied
  /// and permutes theta (if given) accordingly; `permutation` (if given) receives, per
  /// component of the result, its index in this model.
  Model canonical(Eigen::VectorXd* theta = nullptr, std::vector<int>* permutation = nullptr) const;

  /// "2*AR1+WN+RW" (no values).
  std::string to_string() const;
  /// "AR1(phi=0.9,sigma2=1)+WN(sigma2=0.5)" with values shown in display units, 17
  /// significant digits: usable as SPEC_WITH_VALUES.
  std::string to_string(const Eigen::VectorXd& theta) const;
  /// Names "AR1[1].phi"-like, for messages; and per parameter (component index, name).
  std::string parameter_label(int k) const;
  int component_of(int k) const;
  const ParameterSpec& spec_of(int k) const;

 private:
  std::vector<Component> components_;
  std::vector<int> offsets_;
  int num_parameters_ = 0;
};

/// Component c with its values, compact ("AR1(phi=0.16,sigma2=0.1195)", `digits`
/// significant digits, display units): for messages and tables.
std::string component_text(const Model& model, int c, const Eigen::VectorXd& theta, int digits = 4);

/// The sum of two models: a's components then b's (theta concatenates in that order,
/// a's parameters first). Not canonical: call canonical() to sort.
Model operator+(const Model& a, const Model& b);

}  // namespace gmwm
