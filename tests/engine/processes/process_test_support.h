#pragma once
// Shared checks for the process tests (tests/engine/processes/*_test.cc).

#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "gmwm/engine/process.h"

namespace gmwm::test {

/// A process from the registry (throws what the registry throws).
std::unique_ptr<Process> make_process(const std::string& name, const std::map<std::string, long>& structural = {},
                                      const ProcessContext& context = {});

/// tau = 2^j_min .. 2^j_max.
std::vector<double> dyadic_scales(int j_max, int j_min = 1);

std::vector<double> wv_of(const Process& p, std::span<const double> theta, std::span<const double> tau);

/// The WV computed from p.generalized_autocovariance through the Haar filter of each
/// scale (process.h: Cov of zero-sum filters), O(tau^2): small scales only.
std::vector<double> wv_from_autocovariance(const Process& p, std::span<const double> theta,
                                           std::span<const double> tau);

/// Expects |actual - expected| <= rel |expected| for each element.
void expect_all_relatively_near(const std::vector<double>& actual, const std::vector<double>& expected, double rel,
                                const std::string& what);

/// Compares wv_jacobian with central differences of wv, and wv_hessian with central
/// differences of wv_jacobian, both taken in the unconstrained coordinate u_l of each
/// parameter (step 2e-5 max(|u_l|, 1); the WV varies on O(1) scales in u_l even near
/// phi = +-1) and divided by d theta_l / d u_l. Tolerance per entry,
/// derived from the step: 2 |D(h) - D(h/2)| (twice a Richardson estimate of the truncation
/// error of D(h/2), which is compared) + rounding 1e3 eps max|f| / h.
void expect_derivatives_match_finite_differences(const Process& p, std::vector<double> theta,
                                                 std::span<const double> tau);

struct SimulationCheck {
  int length = 256;  ///< samples per replicate
  int replicates = 2000;
  std::uint64_t seed = 1;
  bool stationary = true;  ///< also check the series' variance and lag-1 covariance
};

/// Simulates replicates and checks that the mean (over time and replicates) of d_t^2 and
/// d_t d_{t+1}, with d_t = x_t - x_{t-1}, match 2g(0) - 2g(1) and 2g(1) - g(0) - g(2)
/// within 3 Monte-Carlo standard errors (the SE from the spread of the per-replicate
/// means); for stationary processes the same for x_t^2 and x_t x_{t+1} against g(0), g(1).
void expect_simulated_moments_match(const Process& p, std::span<const double> theta, const SimulationCheck& check);

/// Mean over replicates of x_0^2 against g(0), within 3 standard errors.
void expect_first_sample_is_stationary(const Process& p, std::span<const double> theta, int replicates,
                                       std::uint64_t seed);

}  // namespace gmwm::test
